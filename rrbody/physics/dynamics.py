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

__all__ = ["rhs", "driven_rhs", "driven_kinematics", "jacobian", "SYSTEM_DRIVEN", "SYSTEM_FREE"]

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


@njit(cache=True)
def _driven_point_jacobian(t, y, p, J, fx):  # noqa: ANN001
    """Analytic J = df/dy and fx = df/dt of :func:`driven_rhs` for a point mass (the stiff case).

    With psi = phi - w t, the CM velocity in the frame (e, e_perp) of CM -> P is
    (v_e, v_p) = (d w sin psi, d w cos psi - l phi'); phi'' = (w^2 l d sin psi - l f_p) / I_P with
    f_p = -c v_p / |v| (dry) or -c v_p (viscous). d/dt = -w d/dphi at fixed phi'. Inside the
    zero-speed dead band the friction (and its derivative) is zero, as in the right-hand side.
    """
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    ip = p[P.IP]
    psi = y[0] - w * t
    s = math.sin(psi)
    c = math.cos(psi)
    dtq_dphi = w * w * l * d * c
    dtq_dphid = 0.0
    law = int(p[P.LAW])
    coeff = p[P.COEFF]
    ve = d * w * s
    vp = d * w * c - l * y[1]
    # derivatives of (v_e, v_p): d/dphi = (d w c, -d w s), d/dphi' = (0, -l)
    if law == 1:
        sp2 = ve * ve + vp * vp
        speed = math.sqrt(sp2)
        if speed > p[P.VEPS]:
            inv3 = 1.0 / (sp2 * speed)
            dg_dve = -vp * ve * inv3
            dg_dvp = ve * ve * inv3
            # torque -= l f_p = +l c g, g = v_p / |v|
            dtq_dphi += l * coeff * (dg_dve * d * w * c - dg_dvp * d * w * s)
            dtq_dphid += l * coeff * (-l * dg_dvp)
    elif law == 2:
        dtq_dphi += l * coeff * (-d * w * s)
        dtq_dphid += l * coeff * (-l)
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = dtq_dphi / ip
    J[1, 1] = dtq_dphid / ip
    fx[0] = 0.0
    fx[1] = -w * dtq_dphi / ip


@njit(cache=True)
def jacobian(system, t, y, p, S, f0, J, fx):  # noqa: ANN001
    """J = df/dy and fx = df/dt at (t, y) for the equations of ``system``; f0 = f(t, y).

    Analytic for the driven point mass; elsewhere one-sided finite differences with steps
    sqrt(eps) times the component's size (the Rosenbrock step only needs J to O(h) accuracy for
    its order, since the method is of W-type order 4 only with the exact J: the finite-difference
    error, ~1e-8 relative, sits far below the tolerances the stiff method is used at).
    """
    if system == SYSTEM_DRIVEN and p[P.BODY] == P.BODY_POINT:
        _driven_point_jacobian(t, y, p, J, fx)
        return
    n = y.shape[0]
    yp = y.copy()
    fp = np.empty(n)
    for j in range(n):
        dj = 1.5e-8 * max(abs(y[j]), 1.0)
        yp[j] = y[j] + dj
        rhs(system, t, yp, p, S, fp)
        for i in range(n):
            J[i, j] = (fp[i] - f0[i]) / dj
        yp[j] = y[j]
    dt = 1.5e-8 * max(abs(t), 1.0)
    rhs(system, t + dt, y, p, S, fp)
    for i in range(n):
        fx[i] = (fp[i] - f0[i]) / dt
