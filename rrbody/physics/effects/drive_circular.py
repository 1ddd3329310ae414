"""Effect ``circular drive``: the pivot P moves on a circle of radius d at rate omega (the impulsive start,
docs/physics.md).

Its term in the driven body's equation, per unit mass, is the torque about P of the inertial force
of the accelerating pivot: omega^2 l d sin(phi - omega t) (m^2/s^2), with the CM at
r = P - l (cos phi, sin phi). Parameters: p[OMEGA] (rad/s), p[D] (m), p[L] (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P

__all__ = ["torque", "rod_velocity", "sincos_psi", "sincos_shifted", "sincos_small", "sincos_reduced", "NEAR",
           "REDUCED_MAX", "frame", "kinematics"]

NAME = "circular"

#: Largest angle increment |d| (rad) that :func:`sincos_small` serves; beyond it :func:`sincos_shifted`
#: calls the library's sin and cos. A DOP853 step turns psi by up to h |phi' - omega| at its last
#: stage: ~1.4 rad at the loosest tolerances of the fast-driving case (omega 300 rad/s), so most
#: stages of every tested run stay below it.
NEAR: float = 1.6
# sin(d) = d * sum a_i z^i and cos(d) = sum b_i z^i, z = d^2, on |d| <= NEAR: Chebyshev fits in z
# (mpmath.chebyfit at 40 digits; fit error 3e-19 and 9e-21 there, below double rounding). Evaluated
# in float64 they are within 2 ulp of 1 (4.4e-16) of sin and cos on the whole interval (tests/test_drive_trig.py).
_SA = (1.0, -0.16666666666666666, 0.008333333333333144, -0.00019841269841193616, 2.7557319208663986e-06,
       -2.5052106654800232e-08, 1.6058928945337649e-10, -7.642713622967296e-13, 2.7182554823331695e-15)
_CB = (1.0, -0.5, 0.04166666666666666, -0.0013888888888888425, 2.4801587301469337e-05, -2.7557319206772035e-07,
       2.0876755458184194e-09, -1.1470661422295163e-11, 4.776675193348862e-14, -1.5101383905649875e-16)


@njit(cache=True, inline="always")
def torque(sin_psi: float, p: np.ndarray) -> float:
    """Drive torque about P per unit mass (m^2/s^2) given sin(phi - omega t)."""
    w = p[P.OMEGA]
    return w * w * p[P.L] * p[P.D] * sin_psi


@njit(cache=True, inline="always")
def rod_velocity(sin_psi: float, cos_psi: float, phid: float, p: np.ndarray) -> tuple[float, float]:
    """CM velocity (m/s) in the rod frame (e, e_perp) of CM -> P, e = (cos phi, sin phi):
    (d w sin psi, d w cos psi - l phi') with psi = phi - omega t (what the driven right-hand sides
    use: no world-frame angle, and the speed is a sum of squares that does not cancel)."""
    dw = p[P.D] * p[P.OMEGA]
    return dw * sin_psi, dw * cos_psi - p[P.L] * phid


@njit(cache=True, inline="always")
def sincos_small(d: float) -> tuple[float, float]:
    """(sin d, cos d) for |d| <= NEAR (rad), to 2 ulp of 1: two polynomials in d^2, evaluated in
    Estrin's scheme (depth 4 instead of Horner's 9) because a Runge-Kutta stage waits for them."""
    z = d * d
    z2 = z * z
    z4 = z2 * z2
    a = _SA
    b = _CB
    sp = ((a[0] + z * a[1]) + z2 * (a[2] + z * a[3])) + z4 * (((a[4] + z * a[5]) + z2 * (a[6] + z * a[7]))
                                                          + z4 * a[8])
    cp = ((b[0] + z * b[1]) + z2 * (b[2] + z * b[3])) + z4 * (((b[4] + z * b[5]) + z2 * (b[6] + z * b[7]))
                                                          + z4 * (b[8] + z * b[9]))
    return d * sp, cp


@njit(cache=True, inline="always")
def sincos_shifted(psi: float, d: float, s0: float, c0: float) -> tuple[float, float]:
    """(sin psi, cos psi) of an angle psi = psi0 + d (rad) whose base psi0 has sine and cosine
    s0, c0: by the angle-addition formulas with :func:`sincos_small` where |d| <= NEAR, else (or
    for d = NaN: no base) the library's sin and cos of ``psi`` itself."""
    if abs(d) <= NEAR:  # False for NaN
        sd, cd = sincos_small(d)
        return s0 * cd + c0 * sd, c0 * cd - s0 * sd
    return math.sin(psi), math.cos(psi)


#: Cody-Waite split of pi/2 (fdlibm's pio2_1, pio2_2, pio2_2t): the first two have 33 significant
#: bits, so k times them is exact for |k| < 2^20
_P1, _P2, _P3 = 1.57079632673412561417e+00, 6.07710050630396597660e-11, 2.02226624879595063154e-21
#: largest |x| (rad) :func:`sincos_reduced` reduces itself (k = x 2/pi below 2^19); beyond, the library
REDUCED_MAX: float = 8.0e5


@njit(cache=True, inline="always")
def sincos_reduced(x: float) -> tuple[float, float]:
    """(sin x, cos x) of any angle x (rad): x = k pi/2 + r with |r| <= pi/4 (Cody-Waite, exact
    products), then :func:`sincos_small` of r and the quadrant k mod 4 chosen without a branch (a
    body's quadrant is random from one body to the next: a branch would be mispredicted). Within
    2 ulp of 1 plus the reduction's rounding (tests/test_drive_trig.py); |x| > REDUCED_MAX or NaN: the
    library's. The plugin's step evaluates one pair per body with it."""
    if not abs(x) <= REDUCED_MAX:
        return math.sin(x), math.cos(x)
    k = math.floor(x * (2.0 / math.pi) + 0.5)
    r = ((x - k * _P1) - k * _P2) - k * _P3
    sr, cr = sincos_small(r)
    q = int(k) & 3
    odd = q & 1
    a = cr if odd else sr  # sin x is +-sin r for even quadrants, +-cos r for odd ones
    b = sr if odd else cr
    return (1.0 - (q & 2)) * a, (1.0 - ((q + 1) & 2)) * b


@njit(cache=True, inline="always")
def sincos_psi(t: float, phi: float, p: np.ndarray, d: float, s0: float, c0: float) -> tuple[float, float]:
    """(sin psi, cos psi) of the drive phase psi = phi - omega t (rad) at time t (s).

    A Runge-Kutta stage knows its psi as psi0 + d, psi0 the step's start (whose sine and cosine
    s0, c0 it computed once) and d = h (sum of the stage weights times phi') - omega c h: then
    the angle-addition formulas (:func:`sincos_shifted`) replace two library calls, which reduce
    psi (|psi| reaches 1e4 rad in long runs) by 2 pi first. They are also more accurate: d is
    exact to rounding, where phi - omega t rounds to ulp(|psi|), 2e-12 rad at 1e4. Where no such
    base exists pass d = NaN (or |d| > NEAR): the library's sin and cos of phi - omega t."""
    return sincos_shifted(phi - p[P.OMEGA] * t, d, s0, c0)


@njit(cache=True, inline="always")
def frame(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """(cos wt, sin wt, cos phi, sin phi) and the CM velocity (vx, vy) (m/s, world frame):
    r = P - l e(phi), r' = P' - l phi' e_perp(phi), e_perp = (-sin, cos)."""
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    cw = math.cos(w * t)
    sw = math.sin(w * t)
    cp = math.cos(phi)
    sp = math.sin(phi)
    return cw, sw, cp, sp, -d * w * sw + l * phid * sp, d * w * cw - l * phid * cp


@njit(cache=True, inline="always")
def kinematics(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """CM position (m) and velocity (m/s) and P position (m), world frame, for the driven body."""
    cw, sw, cp, sp, vx, vy = frame(t, phi, phid, p)
    px = p[P.D] * cw
    py = p[P.D] * sw
    return px - p[P.L] * cp, py - p[P.L] * sp, vx, vy, px, py
