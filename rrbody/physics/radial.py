"""Exact dry-friction wrench on a planar contact with a radial pressure: a ring and a Hertz disk.

Pure numba kernels (no imports from the rest of rrbody, like :mod:`rrbody.physics.icr`). Units and
frames: everything in the body frame; ``a`` (m) the contact radius, (ux, uy) (m/s) the velocity of
the contact centre, ``w`` (rad/s) the spin, so that v(s) = u + w z x s at s (m) from the centre.
Returned per unit normal load and per unit mu g (the caller multiplies by mu g): the force
(fx, fy) = -Int p v/|v| dA (dimensionless) and the torque about the contact centre
tq = Int (s x f)_z (m), with Int p dA = 1.

Method
------
For w != 0 the field is a rotation about c = z x u / w, r = |c| = |u|/|w|, x = r/a, and an element
feels -sgn(w) z x e, e = (s - c)/|s - c|. With G = <e>_p = g c/r (symmetry) the force is
F = -sgn(w) z x G = g u/|u| (g <= 0: always against u), and tq = -sgn(w) a S, S = <s . e>_p / a >= 0.

Ring (all load on |s| = a): with theta = pi + 2 phi, |s - c| = a (1 + x) sqrt(1 - m sin^2 phi),
m = 4x/(1+x)^2, giving g = [(1-x) K - (1+x) E]/(pi x), S = [(1-x) K + (1+x) E]/pi. These lose
digits (g as x -> 0, S as x -> inf, both near x = 1 where K diverges); the Landen transformation
(1-x) K(m) = (1-x^2) K(x), (1+x) E(m) = 2 E(x) - (1-x^2) K(x) (modulus k = x < 1) removes that:
for x < 1, g = -(2/pi) x Q, S = (2/pi) E; for x > 1 the duality g(x) = -S(1/x),
S(x) = -g(1/x) gives g = -(2/pi) E, S = (2/pi) Q / x; with k'^2 = 1 - k^2 and the Carlson forms
(DLMF 19.25.1) E(k) = P + Q, P = k'^2 RD(0, k'^2, 1)/3, Q = (E - k'^2 K)/k^2 = k'^2 RD(0, 1, k'^2)/3,
sums of positive terms, full relative accuracy everywhere. At x = 1: g = -2/pi, S = 2/pi (Q -> 1, P -> 0).

Hertz (p = 3/(2 pi a^2) sqrt(1 - rho^2/a^2)): lines through c at angle psi from c/r, s = c + t n,
chord half-length^2 h2 = 1 - x^2 sin^2 psi (units of a). The radial integrals are exact:
Int t p dt = -(3/4) x cos(psi) h2 and Int t^2 p dt = (3/16) h2^2 + (3/4) x^2 cos^2(psi) h2, and
s . e = sgn(t) (x cos psi + t), so the cos^2 terms cancel in S::

    g = -(3/4) x Int cos^2(psi) h2 dpsi,   S = (3/16) Int h2^2 dpsi,   psi in [-psi1, psi1],

psi1 = pi/2 (x <= 1: g = -(3 pi/8) x (1 - x^2/4), S = (3 pi/16)(1 - x^2 + 3 x^4/8)) or asin(1/x)
(x > 1: non-negative entire integrands, Gauss-Legendre in psi/psi1, converged to ~1e-16 at 16 nodes).

Near translation (|w| a <= TRANSLATION_EPS |u|, w = 0 included): F = -u/|u|,
tq = -(w/|u|) <|s|^2 - (s . u/|u|)^2>_p (a^2/2 ring, a^2/5 Hertz), exact to O((w a/|u|)^2) < 1e-16.
Elements slower than v_eps are ignored only at rest (|u| <= v_eps and |w| a <= v_eps: zero wrench).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["ring_wrench", "hertz_wrench", "carlson_rf", "carlson_rd"]

#: |w| a / |u| at or below which the translation expansion is used (its relative error is O(ratio^2))
TRANSLATION_EPS: float = 1e-8
#: Gauss-Legendre nodes on [-1, 1] for the Hertz integrals outside the disk (16: converged, measured
#: 12 -> 5e-13, 16 -> 6e-16 at x = 1); the integrands are even, so only the positive half is kept
_GL_N: int = 16
_t, _wt = np.polynomial.legendre.leggauss(_GL_N)
_GL_T: np.ndarray = np.ascontiguousarray(_t[_GL_N // 2:])
_GL_W: np.ndarray = np.ascontiguousarray(_wt[_GL_N // 2:])
del _t, _wt

_TWO_PI_INV: float = 2.0 / math.pi
# Carlson duplication stops when every argument is within ERRTOL of the mean: the truncated Taylor
# tail then errs by ~ERRTOL^6 (2.4e-16 for RF, 1.1e-17 for RD; Numerical Recipes 3rd ed. 6.12)
_RF_TOL: float = 0.0025
_RD_TOL: float = 0.0015
_MAX_ITER: int = 100  # a guard only: the spread shrinks 4x per step, ~1e-300 -> ERRTOL in < 60 steps


@njit(cache=True)
def carlson_rf(x: float, y: float, z: float) -> float:
    """Carlson's RF(x, y, z) = (1/2) Int_0^inf dt / sqrt((t+x)(t+y)(t+z)); x, y, z >= 0, at most one zero."""
    for _ in range(_MAX_ITER):
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
        ave = (x + y + z) / 3.0
        dx = (ave - x) / ave
        dy = (ave - y) / ave
        dz = (ave - z) / ave
        if max(abs(dx), abs(dy), abs(dz)) <= _RF_TOL:
            break
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / math.sqrt(ave)


@njit(cache=True)
def carlson_rd(x: float, y: float, z: float) -> float:
    """Carlson's RD(x, y, z) = (3/2) Int_0^inf dt / ((t+z) sqrt((t+x)(t+y)(t+z))); x, y >= 0, x + y > 0,
    z > 0 (z below ~1e-205 overflows, as z^(-3/2) does)."""
    s = 0.0
    fac = 1.0
    for _ in range(_MAX_ITER):
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        s += fac / (sz * (z + lam))
        fac *= 0.25
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
        ave = 0.2 * (x + y + 3.0 * z)
        dx = (ave - x) / ave
        dy = (ave - y) / ave
        dz = (ave - z) / ave
        if max(abs(dx), abs(dy), abs(dz)) <= _RD_TOL:
            break
    ea = dx * dy
    eb = dz * dz
    ec = ea - eb
    ed = ea - 6.0 * eb
    ee = ed + ec + ec
    c3 = 9.0 / 22.0
    c4 = 3.0 / 26.0
    tail = (1.0 + ed * (-3.0 / 14.0 + 0.25 * c3 * ed - 1.5 * c4 * dz * ee)
            + dz * (ee / 6.0 + dz * (-c3 * ec + dz * c4 * ea)))
    return 3.0 * s + fac * tail / (ave * math.sqrt(ave))


@njit(cache=True)
def _ring_gs(u, wa):  # noqa: ANN001
    """(g, S) of the ring for x = r/a = u/wa (see the module docstring), wa > 0."""
    if u == wa:  # x = 1 exactly: K and RD(0, 0, 1) diverge, g and S have these limits
        return -_TWO_PI_INV, _TWO_PI_INV
    k = min(u, wa) / max(u, wa)  # the Landen modulus min(x, 1/x) < 1
    kp2 = (1.0 - k) * (1.0 + k)  # no cancellation: 1 - k is exact near k = 1 (Sterbenz)
    p = kp2 * carlson_rd(0.0, kp2, 1.0) / 3.0
    q = kp2 * carlson_rd(0.0, 1.0, kp2) / 3.0  # kp2 >= 2.2e-16 here: no overflow
    if u < wa:
        return -_TWO_PI_INV * k * q, _TWO_PI_INV * (p + q)
    return -_TWO_PI_INV * (p + q), _TWO_PI_INV * k * q


@njit(cache=True)
def _hertz_gs(u, wa):  # noqa: ANN001
    """(g, S) of the Hertz disk for x = r/a = u/wa (see the module docstring), wa > 0."""
    x = u / wa
    x2 = x * x
    if x <= 1.0:
        return -0.375 * math.pi * x * (1.0 - 0.25 * x2), 0.1875 * math.pi * (1.0 - x2 + 0.375 * x2 * x2)
    psi1 = math.asin(wa / u)
    ig = 0.0
    isq = 0.0
    for i in range(_GL_T.shape[0]):
        sp = math.sin(psi1 * _GL_T[i])
        cp = math.cos(psi1 * _GL_T[i])
        h2 = (1.0 - x * sp) * (1.0 + x * sp)  # factored: small near the chord ends without cancelling
        ig += _GL_W[i] * cp * cp * h2
        isq += _GL_W[i] * h2 * h2
    # psi1: [-psi1, psi1] mapped onto [-1, 1]; times 2: the even integrands summed over half the nodes
    return -1.5 * x * psi1 * ig, 0.375 * psi1 * isq


@njit(cache=True)
def _assemble(a, ux, uy, w, u, g, s):  # noqa: ANN001
    """Wrench from (g, S): F = g u/|u| (g <= 0), tq = -sgn(w) a S."""
    if u > 0.0:
        fx = g * ux / u
        fy = g * uy / u
    else:  # pure spin: c at the centre, g = 0
        fx = 0.0
        fy = 0.0
    return fx, fy, -math.copysign(a * s, w)


@njit(cache=True)
def _radial(hertz: bool, a: float, ux: float, uy: float, w: float, v_eps: float) -> tuple[float, float, float]:
    """The ring's (hertz False) or the Hertz patch's wrench: zero at rest, the translation expansion
    near translation (the profile's <|s|^2 - (s . u/|u|)^2> = a^2/2 or a^2/5), else the exact forms."""
    u = math.hypot(ux, uy)
    wa = abs(w) * a
    if u <= v_eps and wa <= v_eps:
        return 0.0, 0.0, 0.0
    if wa <= TRANSLATION_EPS * u:
        return -ux / u, -uy / u, -(w / u) * (0.2 if hertz else 0.5) * a * a
    g, s = _hertz_gs(u, wa) if hertz else _ring_gs(u, wa)
    return _assemble(a, ux, uy, w, u, g, s)


@njit(cache=True)
def ring_wrench(a: float, ux: float, uy: float, w: float, v_eps: float) -> tuple[float, float, float]:
    """Dry wrench (fx, fy, tq) per unit load and mu g of a ring of radius a (m), load uniform on it.

    (ux, uy) (m/s) the contact centre's velocity, w (rad/s) the spin, body frame; tq (m) about the
    centre. Zero at rest (|u| <= v_eps and |w| a <= v_eps, m/s)."""
    return _radial(False, a, ux, uy, w, v_eps)


@njit(cache=True)
def hertz_wrench(a: float, ux: float, uy: float, w: float, v_eps: float) -> tuple[float, float, float]:
    """Dry wrench (fx, fy, tq) per unit load and mu g of a Hertz contact of radius a (m),
    p = 3/(2 pi a^2) sqrt(1 - rho^2/a^2).

    (ux, uy) (m/s) the contact centre's velocity, w (rad/s) the spin, body frame; tq (m) about the
    centre. Zero at rest (|u| <= v_eps and |w| a <= v_eps, m/s)."""
    return _radial(True, a, ux, uy, w, v_eps)
