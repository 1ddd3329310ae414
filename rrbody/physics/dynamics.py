"""Right-hand sides of the equations of motion (compiled, pure functions of (t, y, p, S)).

Driven body (SPEC section 2), state y = (phi, phi') with phi the angle of CM -> P (rad):

    (I_cm/m + l^2) phi'' = omega^2 l d sin(phi - omega t) + tau_P / m

The body angle is alpha = phi - beta, so the same state serves l = 0 (P at the CM), where phi is
simply the body angle shifted by beta. tau_P is the friction torque about P (world frame).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P
from rrbody.physics.wrench import body_wrench, point_force

__all__ = ["rhs", "driven_rhs", "driven_kinematics", "SYSTEM_DRIVEN", "SYSTEM_FREE"]

SYSTEM_DRIVEN = 0  # y = (phi, phi')
SYSTEM_FREE = 1    # y = (x, y, alpha, vx, vy, spin): a free body (see free_rhs)


@njit(cache=True, inline="always")
def driven_kinematics(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """CM position (m) and velocity (m/s) and P position (m), world frame, for the driven body."""
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    cw = math.cos(w * t)
    sw = math.sin(w * t)
    cp = math.cos(phi)
    sp = math.sin(phi)
    px = d * cw
    py = d * sw
    # r = P - l e(phi); r' = P' - l phi' e_perp(phi), e_perp = (-sin, cos)
    x = px - l * cp
    y = py - l * sp
    vx = -d * w * sw + l * phid * sp
    vy = d * w * cw - l * phid * cp
    return x, y, vx, vy, px, py


@njit(cache=True, inline="always")
def driven_rhs(t, y, p, S, out):  # noqa: ANN001 (numba signature)
    """out = (phi', phi'') for the circularly driven body."""
    phi = y[0]
    phid = y[1]
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    if p[P.BODY] == P.BODY_POINT:
        # friction acts at the CM only: work in the frame (e, e_perp) of CM -> P, where the CM
        # velocity is (d w sin psi, d w cos psi - l phi') with psi = phi - w t: two trig calls,
        # and the speed is a sum of squares (no cancelling square root at the phi0 = pi start)
        psi = phi - w * t
        s = math.sin(psi)
        c = math.cos(psi)
        torque = w * w * l * d * s
        if p[P.LAW] != 0.0:
            _, f_perp = point_force(d * w * s, d * w * c - l * phid, int(p[P.LAW]), p[P.COEFF], p[P.VEPS])
            torque -= l * f_perp  # (r - P) x F with r - P = -l e
        out[0] = phid
        out[1] = torque / p[P.IP]
        return
    # extended body: four trig calls per evaluation: sin(phi - wt) from the angle-difference identity (the
    # absolute error, ~ulp(phi), is the same as evaluating sin at the rounded difference)
    cw = math.cos(w * t)
    sw = math.sin(w * t)
    cp = math.cos(phi)
    sp = math.sin(phi)
    torque = w * w * l * d * (sp * cw - cp * sw)
    if p[P.LAW] != 0.0:
        vx = -d * w * sw + l * phid * sp
        vy = d * w * cw - l * phid * cp
        fx, fy, tau_cm = body_wrench(p, S, phi - p[P.BETA], vx, vy, phid)
        # torque about P: tau_cm + (r - P) x F with r - P = -l e(phi)
        torque += tau_cm - l * (cp * fy - sp * fx)
    out[0] = phid
    out[1] = torque / p[P.IP]


@njit(cache=True)
def free_rhs(t, y, p, S, out):  # noqa: ANN001
    """Free body, y = (x, y, alpha, vx, vy, spin) (m, rad, m/s, rad/s): friction alone.

    A point mass (I_cm = 0) keeps its spin constant: it has no rotational inertia to decelerate.
    """
    out[0] = y[3]
    out[1] = y[4]
    out[2] = y[5]
    fx, fy, tau = 0.0, 0.0, 0.0
    if p[P.LAW] != 0.0:
        fx, fy, tau = body_wrench(p, S, y[2], y[3], y[4], y[5])
    out[3] = fx
    out[4] = fy
    out[5] = tau / p[P.ICM] if p[P.ICM] > 0.0 else 0.0


@njit(cache=True, inline="always")
def rhs(system, t, y, p, S, out):  # noqa: ANN001
    """Dispatch to the equations of ``system`` (SYSTEM_DRIVEN or SYSTEM_FREE)."""
    if system == SYSTEM_DRIVEN:
        driven_rhs(t, y, p, S, out)
    else:
        free_rhs(t, y, p, S, out)
