"""Friction laws and the friction wrench shared by both integrator paths.

``Friction`` is the validated description; the ``@njit`` kernels below are pure array functions
(parameters travel as arguments) called by the ODE right-hand side and by the pymunk per-step hook.

Units (per unit mass, world frame): forces in m/s^2, torques in m^2/s^2.

Laws
----
- ``dry`` (Coulomb): f = -mu g v_hat for each mass element; the direction of a zero velocity is
  taken as zero force (the self-consistent limit at an impulsive start, SPEC section 2).
- ``viscous``: f = -gamma v, gamma in 1/s. The paper's "viscous" curve (Eq. 2 without the square
  root) is gamma numerically equal to k = mu g / d.
- ``none``: no friction; no kernel is called at all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from . import _params as P
from ._checks import MAX_FRICTION, check_choice, check_nonnegative, check_positive
from ._icr import icr_wrench

__all__ = ["Friction", "LAWS", "LAW_CODES", "point_force", "sampled_wrench", "body_wrench"]

LAWS: tuple[str, ...] = ("dry", "viscous", "none")
LAW_CODES: dict[str, int] = {"none": 0, "dry": 1, "viscous": 2}


@dataclass(frozen=True)
class Friction:
    """A friction law and its coefficient.

    ``coeff`` is mu*g in m/s^2 for ``dry`` and gamma in 1/s for ``viscous`` (ignored for ``none``).
    Build it from the paper's ``k = mu g / d`` with :meth:`from_k`, or from ``mu`` and ``g`` with
    :meth:`from_mu`.
    """

    law: str = "dry"
    coeff: float = 0.0

    def __post_init__(self) -> None:
        check_choice("friction", self.law, LAWS)
        object.__setattr__(self, "coeff", check_nonnegative("friction coefficient", self.coeff, hi=MAX_FRICTION))
        if self.law == "none":
            object.__setattr__(self, "coeff", 0.0)

    @classmethod
    def from_k(cls, law: str, k: float, d: float) -> "Friction":
        """From k = mu g / d (1/s^2) and the drive radius d (m). Viscous: gamma = k (paper convention)."""
        check_choice("friction", law, LAWS)
        k = check_nonnegative("k", k, unit="1/s^2", hi=MAX_FRICTION)
        return cls(law, k * d if law == "dry" else k)

    @classmethod
    def from_mu(cls, law: str, mu: float, g: float = 9.81, d: float = 1.0) -> "Friction":
        """From the friction coefficient mu, gravity g (m/s^2) and, for the viscous convention, d (m)."""
        mu = check_nonnegative("mu", mu, hi=1e3)
        g = check_positive("g", g, unit="m/s^2", hi=1e6)
        return cls.from_k(law, mu * g / d, d)

    @property
    def code(self) -> int:
        return LAW_CODES[self.law]

    @property
    def active(self) -> bool:
        """False when no friction kernel needs to run."""
        return self.law != "none" and self.coeff > 0.0

    def k(self, d: float) -> float:
        """The paper's friction parameter for drive radius d: mu g / d (dry) or gamma (viscous)."""
        return self.coeff / d if self.law == "dry" else self.coeff


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
