"""Effect ``point``: friction acts at the CM only (a point mass, or any body reduced to its CM).

Wrench per unit mass: the law's force at the CM velocity, no torque about the CM.
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects.laws import element_force

__all__ = ["wrench"]

NAME = "point"


@njit(cache=True, inline="always")
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm): force (m/s^2) and torque about the CM (m^2/s^2) per unit mass at CM
    velocity (vbx, vby) (m/s). Body frame like every area method; the laws are isotropic, so
    any frame works (the world-frame wrapper skips the rotation for this method)."""
    fx, fy = element_force(law, vbx, vby, coeff, v_eps, lp)
    return fx, fy, 0.0
