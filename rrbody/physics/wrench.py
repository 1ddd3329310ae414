"""Friction wrench kernels for callers that hold a parameter vector (the engine path, tests).

The effects themselves live in :mod:`rrbody.physics.effects` (one module per law and per area
method); these wrappers decode the law and area codes of ``p`` at run time, which is right for a
per-step engine hook and for set-up code. The ODE loop instead has the law compiled in
(:mod:`rrbody.physics.dynamics`).

Units (per unit mass, world frame: these wrap the body-frame area methods with one rotation,
:func:`rrbody.physics.areas.body_wrench`): forces in m/s^2, torques about the CM in m^2/s^2. Law codes:
the law table's, :data:`rrbody.model.laws.LAW_CODES` (0 none, 1 dry, 2 viscous); ``lp`` the law's further
parameters per unit mass (:mod:`rrbody.physics.effects.laws`; the default: none).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.physics import params as P
from rrbody.physics.areas import SAMPLED
from rrbody.physics.areas import body_wrench as _area_wrench
from rrbody.physics.effects.laws import NO_PARAMS, element_force, law_params

__all__ = ["point_force", "sampled_wrench", "body_wrench"]


@njit(cache=True)
def point_force(vx: float, vy: float, law: int, coeff: float, v_eps: float,
                lp: tuple[float, ...] = NO_PARAMS) -> tuple[float, float]:
    """Friction force per unit mass (m/s^2) of law ``law`` on an element moving with (vx, vy) m/s;
    dry friction at |v| <= v_eps is zero (the impulsive start, docs/physics.md)."""
    return element_force(law, vx, vy, coeff, v_eps, lp)


@njit(cache=True)
def sampled_wrench(samples: np.ndarray, alpha: float, vx: float, vy: float, spin: float,
                   law: int, coeff: float, v_eps: float,
                   lp: tuple[float, ...] = NO_PARAMS) -> tuple[float, float, float]:
    """Force (m/s^2) and torque about the CM (m^2/s^2) per unit mass from area samples (rows x_b,
    y_b, w): body angle ``alpha`` (rad), CM velocity (vx, vy) (m/s), ``spin`` (rad/s)."""
    return _area_wrench(SAMPLED, law, samples, 0.0, 0.0, 0, 0.0, alpha, vx, vy, spin, coeff, v_eps, lp)


@njit(cache=True)
def body_wrench(p: np.ndarray, S: np.ndarray, alpha: float, vx: float, vy: float,
                spin: float) -> tuple[float, float, float]:
    """Friction force (m/s^2) and torque about the CM (m^2/s^2) per unit mass for the body of ``p``
    (law and area method decoded from p[LAW], p[BODY]; see :mod:`rrbody.physics.params`)."""
    return _area_wrench(int(p[P.BODY]), int(p[P.LAW]), S, p[P.RA], p[P.RB], int(p[P.NQ]), p[P.ICM], alpha,
                        vx, vy, spin, p[P.COEFF], p[P.VEPS], law_params(p))
