"""The compiled heart of :class:`rrbody.engine.plugin.PlaneFriction`: one call per step for all bodies.

Everything here is numba-compiled and works on flat arrays the plugin owns, so a step costs one
compiled call whatever the number of bodies (no per-body Python). Units: SI; per unit mass the
force is m/s^2 and the torque m^2/s^2; ``mug`` is mu g (m/s^2).

Array layouts (columns)
-----------------------
``bodies`` (float, one row per plugin body): MASS (kg), IPM = I/m (m^2), MUG (m/s^2), REACH (m:
largest distance of the footprint from the centre of gravity), SNAP (1.0: the rest rule applies),
S0, S1 (its rows in ``shapes``), then the state: PVX, PVY, PW (the velocity one step back, m/s,
rad/s), GAP (s between it and the current one; 0 = no history yet), STOP (1.0 if the rest rule
stopped it in the last step).
``geo``: the polygons' vertices (x, y, 0) followed by their far-field rules (x, y, w), m and m^2.
``lookup``: row 0 the plugin bodies' ids (int64 view of pymunk's uintptr ids) sorted, row 1 their rows.
``shapes`` (float, per shape): BODY (its body's row), KIND (0 circle, 1 polygon), WEIGHT (its share of
the load), CX, CY (circle centre or polygon centroid, body frame from the centre of gravity, m),
RAD (circle radius, or the polygon's largest vertex distance from its centroid, m), AREA (m^2),
MXX, MXY, MYY (polygon second moment about the centre of gravity / area, m^2), V0, V1 (vertex rows),
Q0, Q1 (far-field rule rows).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from rrbody.physics.icr import icr_wrench
from rrbody.physics.polygon import polygon_wrench

MASS, IPM, MUG, REACH, SNAP, S0, S1, PVX, PVY, PW, GAP, STOP = range(12)
N_BODY = 12
BODY, KIND, WEIGHT, CX, CY, RAD, AREA, MXX, MXY, MYY, V0, V1, Q0, Q1 = range(14)
N_SHAPE = 14
KIND_CIRCLE = 0.0
KIND_POLYGON = 1.0
#: Gauss nodes of the instantaneous-centre quadrature for a disk (rrbody.physics.area.icr_nodes: <= 6e-12)
DISK_NODES = 24


@njit(cache=True)
def body_accel(j: int, alpha: float, vx: float, vy: float, w: float, bodies: np.ndarray, shapes: np.ndarray,
               geo: np.ndarray) -> tuple[float, float, float]:
    """Friction (ax, ay, alpha_dot) of body ``j`` with angle ``alpha`` (rad), centre-of-gravity velocity
    (vx, vy) (m/s, world) and spin ``w`` (rad/s): force per unit mass (m/s^2, world) and the angular
    acceleration (rad/s^2)."""
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    vbx = ca * vx + sa * vy  # body frame
    vby = -sa * vx + ca * vy
    fx = 0.0
    fy = 0.0
    tq = 0.0
    for k in range(int(bodies[j, S0]), int(bodies[j, S1])):
        ox = shapes[k, CX]
        oy = shapes[k, CY]
        wt = shapes[k, WEIGHT]
        if shapes[k, KIND] == KIND_CIRCLE:
            # the disk's own centre moves with v + w z x o; the kernel gives the torque about it
            gx, gy, gt = icr_wrench(shapes[k, RAD], shapes[k, RAD], DISK_NODES, 0.0, vbx - w * oy, vby + w * ox, w,
                                    1, 1.0, 0.0, 0.0)
            gt += ox * gy - oy * gx
        else:
            gx, gy, gt = polygon_wrench(geo, int(shapes[k, V0]), int(shapes[k, V1]), shapes[k, AREA], ox, oy,
                                        shapes[k, RAD], shapes[k, MXX], shapes[k, MXY], shapes[k, MYY], geo,
                                        int(shapes[k, Q0]), int(shapes[k, Q1]), vbx, vby, w, 0.0)
        fx += wt * gx
        fy += wt * gy
        tq += wt * gt
    mug = bodies[j, MUG]
    return mug * (ca * fx - sa * fy), mug * (sa * fx + ca * fy), mug * tq / bodies[j, IPM]


@njit(cache=True)
def limited(j: int, alpha: float, vx: float, vy: float, w: float, ex: float, ey: float, ew: float, dt: float,
            bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray) -> tuple[float, float, float, float]:
    """Friction (ax, ay, alpha_dot) at the velocity (ex, ey, ew) and the factor s in [0, 1] that keeps
    the impulse dt s (ax, ay, alpha_dot) from carrying the kinetic energy of the current velocity
    (vx, vy, w) past its minimum along the impulse: no chatter, and never a gain in energy."""
    ax, ay, aw = body_accel(j, alpha, ex, ey, ew, bodies, shapes, geo)
    ipm = bodies[j, IPM]
    num = -(vx * ax + vy * ay + ipm * w * aw)
    den = dt * (ax * ax + ay * ay + ipm * aw * aw)
    if den > 0.0 and num < den:
        if ex != vx or ey != vy or ew != w:
            # near a stop the extrapolated velocity is unreliable: use the current one
            return limited(j, alpha, vx, vy, w, vx, vy, w, dt, bodies, shapes, geo)
        return ax, ay, aw, max(num / den, 0.0)
    return ax, ay, aw, 1.0


@njit(cache=True)
def _find(lookup: np.ndarray, key: np.int64) -> int:
    """The plugin row of the body with id ``key``, or -1 (binary search in lookup[0])."""
    lo = 0
    hi = lookup.shape[1]
    while lo < hi:
        mid = (lo + hi) // 2
        if lookup[0, mid] < key:
            lo = mid + 1
        else:
            hi = mid
    if lo < lookup.shape[1] and lookup[0, lo] == key:
        return lookup[1, lo]
    return -1


@njit(cache=True)
def plane_step(got: np.ndarray, ids: np.ndarray, lookup: np.ndarray, bodies: np.ndarray, shapes: np.ndarray,
               geo: np.ndarray, dt: float, out: np.ndarray) -> int:
    """One step of plane friction for every plugin body in a space.

    ``got`` has a row per body of the space (pymunk.batch order: angle, vx, vy, w, fx, fy, torque),
    ``ids`` their ids. Writes the forces and torques to apply into ``out`` (rows fx, fy, torque: the
    user's own plus friction), flags the bodies that stop this step (column STOP) and returns their
    count. Velocities are read as belonging to the half step (the staggered scheme of
    docs/engine.md): friction acts at the predicted angle alpha + w dt with the velocity extrapolated
    from the last two steps.
    """
    n_stop = 0
    for i in range(got.shape[0]):
        out[i, 0] = got[i, 4]
        out[i, 1] = got[i, 5]
        out[i, 2] = got[i, 6]
        j = _find(lookup, ids[i])
        if j < 0:
            continue
        bodies[j, STOP] = 0.0
        vx = got[i, 1]
        vy = got[i, 2]
        w = got[i, 3]
        alpha = got[i, 0] + w * dt
        gap = bodies[j, GAP]
        if gap > 0.0:
            g = 0.5 * dt / gap
            ex = vx + g * (vx - bodies[j, PVX])
            ey = vy + g * (vy - bodies[j, PVY])
            ew = w + g * (w - bodies[j, PW])
        else:
            ex = vx
            ey = vy
            ew = w
        bodies[j, PVX] = vx
        bodies[j, PVY] = vy
        bodies[j, PW] = w
        bodies[j, GAP] = dt
        if vx == 0.0 and vy == 0.0 and w == 0.0:
            continue  # at rest: zero friction (kinetic friction has no direction at zero speed)
        ax, ay, aw, s = limited(j, alpha, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo)
        if s < 1.0 and bodies[j, SNAP] > 0.0 \
                and math.hypot(vx, vy) + abs(w) * bodies[j, REACH] <= bodies[j, MUG] * dt:
            # every point slower than mu g dt: friction stops the body within this step
            bodies[j, STOP] = 1.0
            n_stop += 1
            bodies[j, PVX] = 0.0
            bodies[j, PVY] = 0.0
            bodies[j, PW] = 0.0
            continue
        m = bodies[j, MASS] * s
        out[i, 0] += m * ax
        out[i, 1] += m * ay
        out[i, 2] += m * bodies[j, IPM] * aw
    return n_stop


def fast_entry(dispatcher: Any, *args: Any) -> Any:
    """Call ``dispatcher(*args)`` once and return the compiled entry point for these argument types.

    Calling the entry point skips numba's per-call type dispatch (about 0.3 us of the ~1 us a
    many-argument call costs, measured); the arrays passed later must have the same types. Falls
    back to the dispatcher itself if numba's internals differ."""
    dispatcher(*args)
    try:
        sig = tuple(dispatcher.typeof_pyval(a) for a in args)
        return dispatcher.overloads[sig].entry_point
    except (AttributeError, KeyError, TypeError):  # pragma: no cover - numba internals
        return dispatcher
