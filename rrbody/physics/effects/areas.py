"""Registration of the area-integration methods: the one place that maps a code to its module.

The code is a run-time choice (``p[BODY]``): the composed right-hand side calls the extended-body
code once per evaluation and this function picks the method (:mod:`rrbody.physics.effects`).

Frames: every method works in the BODY frame (CM velocity in, force out, both body-frame
components), where the body's geometry is fixed, so a method needs no trigonometric call and the
caller rotates at most once: the driven right-hand side goes from its rod frame to the body frame
by a constant angle (:mod:`rrbody.physics.dynamics`). :func:`body_wrench` is the world-frame
wrapper (one cos/sin of the body angle and two rotations) for callers holding world-frame
velocities: the free body, :mod:`rrbody.physics.wrench`, the render path.

Adding a method: a module with ``wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)
-> (Fbx, Fby, tau_cm)`` in the body frame (see :mod:`.area_point`; ``lp``: the law's further parameters,
:mod:`rrbody.physics.effects.laws`), a name in :data:`rrbody.model.laws.AREA_METHODS` (its code) with the laws that
have a form for it in the law table, and one branch in :func:`body_frame_wrench`. The methods' codes are the law
table's order of their names: an unknown code cannot come from a bound scene (the final branch).
"""

from __future__ import annotations

import math

from numba import njit

from rrbody.physics.effects import AREAS, area_contact, area_icr, area_point, area_sampled, area_table

__all__ = ["body_frame_wrench", "body_wrench", "POINT", "SAMPLED", "ICR", "TABLE", "CONTACT"]

POINT, SAMPLED, ICR, TABLE, CONTACT = AREAS["point"], AREAS["sampled"], AREAS["icr"], AREAS["table"], AREAS["contact"]


@njit(cache=True, inline="always")
def body_frame_wrench(area, law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm): friction force (m/s^2, body frame) and torque about the CM (m^2/s^2) per
    unit mass by area method ``area`` and law ``law`` with coefficient ``coeff`` and further parameters
    ``lp`` (:mod:`rrbody.physics.effects.laws`) (CM velocity (vbx, vby) m/s in the body frame, spin rad/s)."""
    if area == TABLE:
        return area_table.wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)
    if area == ICR:
        return area_icr.wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)
    if area == SAMPLED:
        return area_sampled.wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)
    if area == CONTACT:
        return area_contact.wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)
    # POINT (a bound scene's p[BODY] is one of AREAS: rrbody.physics.bind.area_model)
    return area_point.wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp)


@njit(cache=True, inline="always")
def body_wrench(area, law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fx, Fy, tau_cm): :func:`body_frame_wrench` in the world frame: body angle ``alpha`` (rad),
    CM velocity (vx, vy) (m/s, world), spin (rad/s); force (m/s^2, world frame), torque about the
    CM (m^2/s^2) per unit mass."""
    if area == POINT:
        # the laws are isotropic: a point mass needs no rotation (and its results stay bit-identical)
        return area_point.wrench(law, S, ra, rb, nq, icm, vx, vy, spin, coeff, v_eps, lp)
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    fbx, fby, tau = body_frame_wrench(area, law, S, ra, rb, nq, icm, ca * vx + sa * vy, -sa * vx + ca * vy, spin,
                                      coeff, v_eps, lp)
    return ca * fbx - sa * fby, sa * fbx + ca * fby, tau
