"""Effect ``point``: friction acts at the CM only (a point mass, or any body reduced to its CM).

Wrench per unit mass: the law's force at the CM velocity, no torque about the CM.
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects.laws import element_force

__all__ = ["wrench"]

NAME = "point"


@njit(cache=True, inline="always")
def wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps):  # noqa: ANN001 (numba)
    """(Fx, Fy, tau_cm): force (m/s^2, world frame) and torque about the CM (m^2/s^2) per unit mass."""
    fx, fy = element_force(law, vx, vy, coeff, v_eps)
    return fx, fy, 0.0
