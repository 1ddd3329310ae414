"""The friction wrench kernels shared by both integrator paths (compiled, pure array functions).

Parameters travel as arguments (no closures), so one compiled function serves every scene; the
ODE right-hand side and the pymunk per-step hook call the same functions.

Units (per unit mass, world frame): forces in m/s^2, torques in m^2/s^2. Law codes: 0 none,
1 dry, 2 viscous (:data:`rrbody.model.friction.LAW_CODES`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P
from rrbody.physics.icr import icr_wrench

__all__ = ["point_force", "sampled_wrench", "body_wrench"]


@njit(cache=True, inline="always")
def point_force(vx: float, vy: float, law: int, coeff: float, v_eps: float) -> tuple[float, float]:
    """Friction force per unit mass (m/s^2) on a mass element moving with velocity (vx, vy) m/s.

    Dry friction at |v| <= v_eps returns zero: the direction of a vanishing velocity is undefined
    and the impulsive start's self-consistent limit is zero torque (SPEC section 2).
    """
    if law == 1:
        speed = math.hypot(vx, vy)
        if speed <= v_eps:
            return 0.0, 0.0
        return -coeff * vx / speed, -coeff * vy / speed
    if law == 2:
        return -coeff * vx, -coeff * vy
    return 0.0, 0.0


@njit(cache=True)
def sampled_wrench(samples: np.ndarray, alpha: float, vx: float, vy: float, spin: float,
                   law: int, coeff: float, v_eps: float) -> tuple[float, float, float]:
    """Force (m/s^2) and torque about the CM (m^2/s^2) per unit mass from area samples.

    ``samples`` has rows (x_b, y_b, w): body-frame offsets from the CM (m) and mass fractions
    summing to 1. ``alpha`` is the body angle (rad), (vx, vy) the CM velocity and ``spin`` the
    angular velocity (rad/s). Element velocity: v_cm + spin z x rho.
    """
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    fx_t = 0.0
    fy_t = 0.0
    tau = 0.0
    for i in range(samples.shape[0]):
        rx = ca * samples[i, 0] - sa * samples[i, 1]
        ry = sa * samples[i, 0] + ca * samples[i, 1]
        w = samples[i, 2]
        fx, fy = point_force(vx - spin * ry, vy + spin * rx, law, coeff, v_eps)
        fx_t += w * fx
        fy_t += w * fy
        tau += w * (rx * fy - ry * fx)
    return fx_t, fy_t, tau


@njit(cache=True, inline="always")
def body_wrench(p: np.ndarray, S: np.ndarray, alpha: float, vx: float, vy: float,
                spin: float) -> tuple[float, float, float]:
    """Friction force (m/s^2) and torque about the CM (m^2/s^2) per unit mass for the scene's body.

    Dispatches on the area model in ``p`` (see :mod:`rrbody._params`): a point mass feels the law
    at its CM; a sampled body sums its elements ``S``; an ellipse or disk with the
    instantaneous-centre model uses the quadrature of :mod:`rrbody._icr`.
    """
    law = int(p[P.LAW])
    coeff = p[P.COEFF]
    v_eps = p[P.VEPS]
    model = int(p[P.BODY])
    if model == P.BODY_POINT:
        fx, fy = point_force(vx, vy, law, coeff, v_eps)
        return fx, fy, 0.0
    if model == P.BODY_ICR:
        return icr_wrench(p[P.RA], p[P.RB], int(p[P.NQ]), alpha, vx, vy, spin, law, coeff, v_eps, p[P.ICM])
    return sampled_wrench(S, alpha, vx, vy, spin, law, coeff, v_eps)
