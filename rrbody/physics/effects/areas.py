"""Registration of the area-integration methods: the one place that maps a code to its module.

The code is a compile-time constant in every composed right-hand side, so the branches are resolved
when the kernel is compiled. Adding a method: a module with ``wrench`` (see :mod:`.area_point`), a
code in :data:`rrbody.physics.effects.AREAS` and one branch here.
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects import AREAS, area_icr, area_point, area_sampled, area_table

__all__ = ["body_wrench", "POINT", "SAMPLED", "ICR", "TABLE"]

POINT, SAMPLED, ICR, TABLE = AREAS["point"], AREAS["sampled"], AREAS["icr"], AREAS["table"]


@njit(cache=True, inline="always")
def body_wrench(area, law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps):  # noqa: ANN001 (numba)
    """(Fx, Fy, tau_cm): friction force (m/s^2, world frame) and torque about the CM (m^2/s^2) per
    unit mass by area method ``area`` and law ``law`` (body angle alpha rad, CM velocity m/s, spin rad/s)."""
    if area == TABLE:
        return area_table.wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps)
    if area == ICR:
        return area_icr.wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps)
    if area == SAMPLED:
        return area_sampled.wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps)
    return area_point.wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps)
