"""A plugin body's friction and its limiter (:mod:`rrbody.contact.kernel`'s per-body evaluation): the
wrench of its footprint (exact, or from a wrench table), per unit mass in the world frame, and the
factor that keeps an impulse of it from overshooting. Units: SI; columns :mod:`rrbody.contact.columns`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.contact.columns import (
    FRICTION_COEFF,
    INERTIA_PER_MASS,
    LAW,
    LAW_DRY,
    LAW_PARAMS,
    LOAD_MEAN_X,
    LOAD_MEAN_Y,
    LOAD_SPREAD,
    SHAPE_END,
    SHAPE_FIRST,
    SLIP_EPS,
    TABLE_CIRCLE,
    TABLE_FOOTPRINT,
    TABLE_KIND,
    TABLE_START,
)
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.effects.drive_circular import sincos_reduced
from rrbody.physics.effects.laws import law_params_at
from rrbody.physics.footprint_quad import footprint_law_wrench
from rrbody.physics.footprint_table import footprint_table_wrench
from rrbody.physics.icr_table import table_wrench_body

__all__ = ["body_accel", "accel_at", "limited", "limited_at"]


@njit(cache=True, **NO_REFCOUNT)
def body_accel(j: int, alpha: float, vx: float, vy: float, w: float, bodies: np.ndarray, shapes: np.ndarray,
               geo: np.ndarray, tables: np.ndarray) -> tuple[float, float, float]:
    """Friction (ax, ay, alpha_dot) of body ``j`` with angle ``alpha`` (rad), centre-of-gravity velocity
    (vx, vy) (m/s, world) and spin ``w`` (rad/s): force per unit mass (m/s^2, world) and the angular
    acceleration (rad/s^2)."""
    sa, ca = sincos_reduced(alpha)  # as the step evaluates it
    return accel_at(j, ca, sa, vx, vy, w, bodies, shapes, geo, tables)


@njit(cache=True, inline="always")
def accel_at(j: int, ca: float, sa: float, vx: float, vy: float, w: float, bodies: np.ndarray, shapes: np.ndarray,
           geo: np.ndarray, tables: np.ndarray) -> tuple[float, float, float]:
    """:func:`body_accel` at the angle whose cosine and sine are ``ca``, ``sa`` (the kernel's step has
    them already, for the active load). Inlined where it is called."""
    c = bodies[j, FRICTION_COEFF]
    if c == 0.0:
        return 0.0, 0.0, 0.0
    vbx = ca * vx + sa * vy  # body frame
    vby = -sa * vx + ca * vy
    law = bodies[j, LAW]
    if law != LAW_DRY:
        # every other law: its own footprint form from the law table, as the ODE path's contact method takes it
        # (viscous: every element feels -gamma v(s), linear, so the footprint's mean position and spread
        # suffice), or the quadrature of its element force (rrbody.physics.footprint_quad); the law "none" has
        # FRICTION_COEFF 0 (returned above)
        fx, fy, tq = footprint_law_wrench(law, shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]),
                                   bodies[j, LOAD_MEAN_X], bodies[j, LOAD_MEAN_Y], bodies[j, LOAD_SPREAD], vbx, vby, w,
                                   c, bodies[j, SLIP_EPS], law_params_at(bodies, j, LAW_PARAMS))
        return ca * fx - sa * fy, sa * fx + ca * fy, tq / bodies[j, INERTIA_PER_MASS]
    # dry friction: the footprint kernel, or a wrench table of it
    tk = bodies[j, TABLE_KIND]
    if tk == TABLE_CIRCLE:
        fx, fy, tq = _circle(j, vbx, vby, w, bodies, shapes, tables)
    elif tk == TABLE_FOOTPRINT:
        fx, fy, tq = footprint_table_wrench(tables, int(bodies[j, TABLE_START]), shapes, geo,
                                            int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), vbx, vby, w,
                                            bodies[j, SLIP_EPS])
    else:
        fx, fy, tq = footprint_wrench(shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), vbx, vby, w,
                                      bodies[j, SLIP_EPS])
    return c * (ca * fx - sa * fy), c * (sa * fx + ca * fy), c * tq / bodies[j, INERTIA_PER_MASS]


@njit(cache=True, inline="always")
def _circle(j: int, vbx: float, vby: float, w: float, bodies: np.ndarray, shapes: np.ndarray,
            tables: np.ndarray) -> tuple[float, float, float]:
    """Dry friction per unit load and mu g of body j, one disk under a radial pressure profile (its one
    footprint row: uniform, a ring or Hertz's), from that profile's disk table (within 1e-10 of the exact
    wrench, :mod:`rrbody.physics.icr_table`; no trigonometric call, one square root): velocity (m/s)
    body frame, the force dimensionless, the torque about the centre of gravity in m."""
    k = int(bodies[j, SHAPE_FIRST])
    ox = shapes[k, C.CENTRE_X]
    oy = shapes[k, C.CENTRE_Y]
    r = shapes[k, C.RADIUS_A]
    # the disk centre's velocity, the table's wrench about it, moved to the centre of gravity
    fx, fy, tq = table_wrench_body(tables[int(bodies[j, TABLE_START]):], r, r, vbx - w * oy, vby + w * ox, w, 1.0,
                                   bodies[j, SLIP_EPS])
    wt = shapes[k, C.LOAD_SHARE]
    return wt * fx, wt * fy, wt * (tq + ox * fy - oy * fx)


@njit(cache=True, **NO_REFCOUNT)
def limited(j: int, ca: float, sa: float, vx: float, vy: float, w: float, ex: float, ey: float, ew: float, dt: float,
            bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray, tables: np.ndarray, lx: float, ly: float,
            lw: float) -> tuple[float, float, float, float]:
    """Friction (ax, ay, alpha_dot) at the angle whose cosine and sine are ``ca``, ``sa`` and the
    velocity (ex, ey, ew), and the factor s in [0, 1] that keeps
    the impulse dt s (ax, ay, alpha_dot) from carrying the kinetic energy of the velocity after the
    load's impulse, (vx, vy, w) + dt (lx, ly, lw) (the other forces per unit mass, m/s^2, and their
    angular acceleration, rad/s^2), past its minimum along the friction impulse: no chatter, and
    friction never gains energy."""
    ax, ay, aw = accel_at(j, ca, sa, ex, ey, ew, bodies, shapes, geo, tables)
    return limited_at(ax, ay, aw, j, ca, sa, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo, tables, lx, ly, lw)


@njit(cache=True, inline="always")
def limited_at(ax: float, ay: float, aw: float, j: int, ca: float, sa: float, vx: float, vy: float, w: float,
               ex: float, ey: float, ew: float, dt: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
               tables: np.ndarray, lx: float, ly: float, lw: float) -> tuple[float, float, float, float]:
    """:func:`limited` given its first evaluation, the friction (ax, ay, alpha_dot) at (ex, ey, ew)
    (:func:`accel_at`'s, which the kernel's step evaluates for all bodies before it limits any)."""
    ipm = bodies[j, INERTIA_PER_MASS]
    ux = vx + dt * lx
    uy = vy + dt * ly
    uw = w + dt * lw
    num = -(ux * ax + uy * ay + ipm * uw * aw)
    den = dt * (ax * ax + ay * ay + ipm * aw * aw)
    if den > 0.0 and num < den:
        if ex != vx or ey != vy or ew != w:
            # near a stop the extrapolated velocity is unreliable: use the current one
            return limited(j, ca, sa, vx, vy, w, vx, vy, w, dt, bodies, shapes, geo, tables, lx, ly, lw)
        return ax, ay, aw, max(num / den, 0.0)
    return ax, ay, aw, 1.0
