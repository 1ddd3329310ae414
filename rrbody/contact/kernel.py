"""The compiled heart of :class:`rrbody.engine.plugin.PlaneFriction`: one call per step for all bodies.

Everything here is numba-compiled and works on flat arrays the plugin owns, so a step costs one
compiled call whatever the number of bodies (no per-body Python). Units: SI; per unit mass the
force is m/s^2 and the torque m^2/s^2.

The arrays' layouts and the column names are :mod:`rrbody.contact.columns` (imported here, as
``kernel.MASS`` etc.); a body's friction and its limiter are :mod:`rrbody.contact.accel`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# (kernel.body_accel and kernel.limited: the plugin's readers)
from rrbody.contact.accel import (accel_at, body_accel, limited, limited_at, prefetch_at,  # noqa: F401
                                 reads_footprint_table)
from rrbody.contact.columns import *  # noqa: F403 (the columns, here and as kernel.MASS etc. for every reader)
from rrbody.contact.feet import feet_step
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.physics.effects import active as act
from rrbody.physics.effects.drive_circular import sincos_reduced
from rrbody.physics.limit import at_rest


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
def plane_check(got: np.ndarray, ids: np.ndarray, lookup: np.ndarray, cache: np.ndarray, n_plugin: int) -> bool:
    """Map every body of the space to its plugin row and check the plugin bodies' state; True if the
    step may go on: every plugin body is in the space (``n_plugin`` of them) and its angle, velocity
    and spin (``got`` columns 0-3) are finite. Changes nothing but ``cache``.

    ``cache[ROWMAP, i]`` is the plugin row of ``got`` row i, valid while ``cache[ROW_ID, i] == ids[i]``:
    the binary search runs only for rows whose body changed (the space's order is stable between
    steps), and the caller zeroes row ROW_ID whenever ``lookup`` changes (ids are pointers, never 0)."""
    rowmap = cache[ROWMAP]
    seen = cache[ROW_ID]
    n_seen = 0
    n_bad = 0
    first = -1
    for i in range(got.shape[0]):
        key = ids[i]
        if seen[i] != key:
            rowmap[i] = _find(lookup, key)
            seen[i] = key
        if rowmap[i] < 0:
            continue
        n_seen += 1
        if not (math.isfinite(got[i, 0]) and math.isfinite(got[i, 1]) and math.isfinite(got[i, 2])
                and math.isfinite(got[i, 3])):
            n_bad += 1
            if first < 0:
                first = i
    cache[STATUS, SEEN] = n_seen
    cache[STATUS, BAD] = n_bad
    cache[STATUS, FIRST_BAD] = first
    return n_bad == 0 and n_seen == n_plugin


@njit(cache=True)
def _driver(j: int, bodies: np.ndarray, t: float, dt: float) -> None:
    """The kinematic driver's position and velocity for the step from t to t + dt (s): its position
    update lands it exactly on P(t + dt) = d (cos, sin)(omega (t + dt)); its velocity, which the joint
    gives P, is P'(t + dt/2 + dt/2) plus the centripetal term w^2 dt/2 (P - CM) that pymunk's straight
    drift of a rotating body omits (staggered scheme), or P'(t + dt) (plain)."""
    t1 = t - bodies[j, T0] + dt
    w = bodies[j, OMG]
    d = bodies[j, DD]
    c1 = math.cos(w * t1)
    s1 = math.sin(w * t1)
    if bodies[j, STAG] > 0.0:
        th = w * (t1 + 0.5 * dt)
        ca = math.cos(bodies[j, EA])
        sa = math.sin(bodies[j, EA])
        c = 0.5 * dt * bodies[j, EW] * bodies[j, EW]
        vx = -d * w * math.sin(th) + c * (ca * bodies[j, ANX] - sa * bodies[j, ANY])
        vy = d * w * math.cos(th) + c * (sa * bodies[j, ANX] + ca * bodies[j, ANY])
    else:
        vx = -d * w * s1
        vy = d * w * c1
    bodies[j, DVX] = vx
    bodies[j, DVY] = vy
    bodies[j, DPX] = d * c1 - dt * vx
    bodies[j, DPY] = d * s1 - dt * vy


@njit(cache=True, inline="always")
def _slow_enough(i: int, j: int, vx: float, vy: float, w: float, dt: float, bodies: np.ndarray,
                 out: np.ndarray) -> bool:
    """The rest rule's test: every point of body j slower than the deceleration friction leaves along
    the motion (mu g, less the pull of the other forces in ``out[i]`` along it: a tilt's, the user's)
    times dt. Evaluated only where the limiter already cut the friction impulse."""
    speed = math.hypot(vx, vy)
    decel = bodies[j, COEFF]
    if speed > 0.0:  # (the direction first: m * speed underflows to 0 for a subnormal speed)
        decel -= (out[i, 0] * (vx / speed) + out[i, 1] * (vy / speed)) / bodies[j, MASS]
    return speed + abs(w) * bodies[j, REACH] <= decel * dt


@njit(cache=True)
def _held(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
          out: np.ndarray) -> bool:
    """Whether static friction holds the load in ``out[i]`` (every force but friction: the user's,
    the tilt's) on dry body j at rest at angle alpha: it lies in the contact's limit surface
    (:func:`rrbody.physics.limit.at_rest`). The answer for the last load is kept: the same load at
    the same angle needs no new test."""
    m = bodies[j, MASS]
    lx = out[i, 0] / m
    ly = out[i, 1] / m
    lt = out[i, 2] / m
    if lx == bodies[j, HX] and ly == bodies[j, HY] and lt == bodies[j, HT] and alpha == bodies[j, HA] \
            and bodies[j, HELD] >= 0.0:
        return bodies[j, HELD] > 0.0
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    _, _, _, held = at_rest(shapes, geo, int(bodies[j, S0]), int(bodies[j, S1]), ca * lx + sa * ly,
                            -sa * lx + ca * ly, lt, bodies[j, IPM], bodies[j, MUS], 0.0)
    bodies[j, HELD] = 1.0 if held else 0.0
    bodies[j, HX] = lx
    bodies[j, HY] = ly
    bodies[j, HT] = lt
    bodies[j, HA] = alpha
    return held


@njit(cache=True)
def _hold_or_break(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
                   out: np.ndarray) -> None:
    """Dry body j at rest under the load in ``out[i]``: static friction cancels it while it is held
    (the body stays exactly at rest), else ``out[i]`` becomes the break-away wrench of the
    maximum-dissipation rule (:func:`rrbody.physics.limit.at_rest`, kinetic friction). A load whose
    force alone is beyond static friction (:func:`_may_hold`) breaks away without the limit-set test,
    whose answer is known (as in :func:`_friction`)."""
    if _may_hold(j, bodies, out[i, 0], out[i, 1]) and _held(i, j, alpha, bodies, shapes, geo, out):
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
        return
    m = bodies[j, MASS]
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    lx = out[i, 0] / m
    ly = out[i, 1] / m
    ax, ay, aw, _ = at_rest(shapes, geo, int(bodies[j, S0]), int(bodies[j, S1]), ca * lx + sa * ly,
                            -sa * lx + ca * ly, out[i, 2] / m, bodies[j, IPM], 0.0, bodies[j, COEFF])
    out[i, 0] = m * (ca * ax - sa * ay)
    out[i, 1] = m * (sa * ax + ca * ay)
    out[i, 2] = m * bodies[j, IPM] * aw


@njit(cache=True)
def plane_step(got: np.ndarray, ids: np.ndarray, lookup: np.ndarray, cache: np.ndarray, bodies: np.ndarray,
               shapes: np.ndarray, geo: np.ndarray, tables: np.ndarray, t: float, dt: float, out: np.ndarray,
               active: np.ndarray, noise: np.ndarray) -> int:
    """One step of plane friction for every plugin body in a space, from the plugin's time t (s).

    ``got`` has a row per body of the space (pymunk.batch order: angle, vx, vy, w, fx, fy, torque),
    ``ids`` their ids. First :func:`plane_check`: if a plugin body is missing from the space or its
    state is not finite, returns -1 having changed nothing but ``cache`` (-2, having changed nothing,
    if ``cache`` has fewer columns than the space has bodies). Otherwise writes the forces and torques
    to apply into ``out`` (rows fx, fy, torque: the user's own plus friction), flags the bodies the
    rest rule acts on (column STOP) and returns their count. Velocities are read as belonging to the
    half step (the staggered scheme of docs/engine.md): friction acts at the predicted angle
    alpha + w dt with the velocity extrapolated from the last two steps. ``active`` (a row per plugin
    body, or none) and ``noise`` (this step's standard normal numbers) carry the active bodies'
    propulsion, drag and Langevin noise (:mod:`rrbody.physics.effects.active`), a load like the tilt's.

    :func:`_sweep` steps the bodies in three passes, compiled without numba's reference counting (the
    counting of each array passed to a per-body call took half of a frictionless step, measured). A body under
    static friction that needs the limit-set test (:func:`_held`, whose small linear solves
    allocate) is left to a second loop here, which steps it again from the start.
    """
    if got.shape[0] > cache.shape[1]:
        return -2  # the caller enlarges the cache and calls again
    if not plane_check(got, ids, lookup, cache, bodies.shape[0]):
        return -1
    rowmap = cache[ROWMAP]
    work = np.empty((got.shape[0], _N_WORK))  # (one allocation per step, ~0.2 us: not worth a cache)
    n_stop, n_defer = _sweep(got, rowmap, bodies, shapes, geo, tables, t, dt, out, active, noise, work)
    if n_defer:
        for i in range(got.shape[0]):
            j = rowmap[i]
            if j >= 0 and bodies[j, DEFR] > 0.0:
                bodies[j, DEFR] = 0.0
                out[i, 0] = got[i, 4]
                out[i, 1] = got[i, 5]
                out[i, 2] = got[i, 6]
                n_stop += _one(i, j, got, bodies, shapes, geo, tables, t, dt, out, active, noise)
    return n_stop


@njit(cache=True, inline="always")
def _extrapolated(i: int, j: int, got: np.ndarray, bodies: np.ndarray, dt: float) -> tuple[float, float, float]:
    """The velocity (m/s, world) and spin (rad/s) friction and the active drag are evaluated at for body
    j (row i of the read): the staggered scheme's extrapolation to the half step from the last two
    steps, or the velocity read (no history yet, or the plain scheme)."""
    vx = got[i, 1]
    vy = got[i, 2]
    w = got[i, 3]
    gap = bodies[j, GAP]
    if gap > 0.0 and bodies[j, STAG] > 0.0:
        g = 0.5 * dt / gap
        return vx + g * (vx - bodies[j, PVX]), vy + g * (vy - bodies[j, PVY]), w + g * (w - bodies[j, PW])
    return vx, vy, w


@njit(cache=True, inline="always")
def _static(j: int, bodies: np.ndarray) -> bool:
    """Whether static friction acts on body j: dry, and governed by the rest rule (not a driven
    body: its joint holds it)."""
    return bodies[j, MUS] > 0.0 and bodies[j, SNAP] > 0.0 and bodies[j, LAW] == LAW_DRY


@njit(cache=True, **NO_REFCOUNT)
def _no_held(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
             out: np.ndarray) -> bool:
    """:func:`_sweep`'s stand-in for :func:`_held` (it defers the bodies that would call it)."""
    return False


@njit(cache=True, **NO_REFCOUNT)
def _no_break(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
              out: np.ndarray) -> None:
    """:func:`_sweep`'s stand-in for :func:`_hold_or_break`."""
    return


#: columns of :func:`_sweep`'s work array (a row per row of the read): the angle friction is evaluated at
#: (rad), its cosine and sine, the velocity (m/s, world) and spin (rad/s) it is evaluated at, and the
#: friction there (per unit mass, world: :func:`rrbody.contact.accel.accel_at`)
_W_ALPHA, _W_CA, _W_SA, _W_EX, _W_EY, _W_EW, _W_AX, _W_AY, _W_AW = range(9)
#: footprint-table bodies whose coefficients the friction pass asks for ahead of their evaluation
AHEAD = 4


@njit(cache=True, inline="always")
def _next_tabled(k: int, n: int, rowmap: np.ndarray, got: np.ndarray, bodies: np.ndarray) -> int:
    """The first body k' >= k whose friction the second pass evaluates from a footprint table, or n."""
    while k < n:
        j = rowmap[k]
        if j >= 0 and reads_footprint_table(j, bodies) and _evaluated(k, j, got, bodies):
            return k
        k += 1
    return n


@njit(cache=True, inline="always")
def _fetch(k: int, rowmap: np.ndarray, bodies: np.ndarray, tables: np.ndarray, work: np.ndarray) -> None:
    """Start bringing in the table block body k's evaluation (accel_at, from ``work``) will read."""
    prefetch_at(rowmap[k], work[k, _W_CA], work[k, _W_SA], work[k, _W_EX], work[k, _W_EY], work[k, _W_EW], bodies,
                tables)
_N_WORK = 9


@njit(cache=True, **NO_REFCOUNT)
def _sweep(got: np.ndarray, rowmap: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
           tables: np.ndarray, t: float, dt: float, out: np.ndarray, active: np.ndarray, noise: np.ndarray,
           work: np.ndarray) -> tuple[int, int]:
    """:func:`plane_step`'s loop over the space's bodies: ``out`` starts from each body's own force and
    torque, and every plugin body gets its step (what :func:`_one` does, in passes) unless it needs the
    limit-set test (marked DEFR). Returns the bodies the rest rule stopped and the bodies deferred.

    Three passes over the bodies, each body's numbers kept in ``work``: the loads (:func:`_load`; a
    body at rest under static friction is left to the limit-set loop at once),
    then the friction where it is evaluated, disks first and then the other bodies (one kind of wrench
    per tight loop: the evaluations of consecutive bodies, independent, overlap in the CPU), then the
    rest (:func:`_settle`: limiter, rest rule, state). Measured against one pass doing all three per
    body (interleaved, 1,000 active bodies in their colliding box, the compiled call between pymunk's
    steps): 103-117 -> 91-102 us. The results are the same bits: the same functions of the same
    numbers."""
    n_stop = 0
    n_defer = 0
    n = got.shape[0]
    for i in range(n):
        out[i, 0] = got[i, 4]
        out[i, 1] = got[i, 5]
        out[i, 2] = got[i, 6]
        j = rowmap[i]
        if j < 0:
            continue
        static, _, resting, _ = _modes(i, j, got, bodies)
        if static and resting:
            # at rest under static friction: the limit-set loop steps it from the start (the test of its
            # load, whose small linear solves allocate)
            bodies[j, DEFR] = 1.0
            n_defer += 1
            continue
        (work[i, _W_ALPHA], work[i, _W_CA], work[i, _W_SA], work[i, _W_EX], work[i, _W_EY],
         work[i, _W_EW]) = _load(i, j, got, bodies, dt, out, active, noise)
    for disks in (True, False):
        p = 0  # where the search for the next footprint-table body to fetch for resumes
        fetched = 0  # footprint-table bodies fetched and not yet evaluated
        for i in range(n):
            j = rowmap[i]
            if j < 0 or (bodies[j, TKIND] == TABLE_CIRCLE) != disks or not _evaluated(i, j, got, bodies):
                continue
            if reads_footprint_table(j, bodies):
                # this body's block and those of the AHEAD such bodies after it on their way (one call
                # site each: every inlined copy of the look-up is compiled again)
                while fetched <= AHEAD:
                    p = _next_tabled(p, n, rowmap, got, bodies)
                    if p == n:
                        break
                    _fetch(p, rowmap, bodies, tables, work)
                    p += 1
                    fetched += 1
                fetched -= 1
            work[i, _W_AX], work[i, _W_AY], work[i, _W_AW] = accel_at(
                j, work[i, _W_CA], work[i, _W_SA], work[i, _W_EX], work[i, _W_EY], work[i, _W_EW], bodies, shapes,
                geo, tables)
    for i in range(n):
        j = rowmap[i]
        if j < 0 or bodies[j, DEFR] > 0.0:
            continue
        r = _settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, _no_held, _no_break, True, work[i, _W_ALPHA],
                    work[i, _W_CA], work[i, _W_SA], work[i, _W_EX], work[i, _W_EY], work[i, _W_EW], True,
                    work[i, _W_AX], work[i, _W_AY], work[i, _W_AW])
        if r == DEFER:
            bodies[j, DEFR] = 1.0
            n_defer += 1
        else:
            n_stop += r
    return n_stop, n_defer


@njit(cache=True, inline="always")
def _may_hold(j: int, bodies: np.ndarray, fx: float, fy: float) -> bool:
    """False if static friction cannot hold the load force (fx, fy) (N, world) on dry body j: its
    magnitude per unit mass is above mu_s g cos(tilt) (MUS), the largest force static friction gives
    (:func:`rrbody.physics.limit.at_rest` tests the same before its limit-set test, on the body-frame
    components). The margin 1e-12 covers the rotation's rounding (a few ulps), so a False here is a
    False there: the test is skipped, with its deferral, only where its answer is known. Active bodies
    whose propulsion beats static friction then never wait for it (in a jammed cluster, half of
    1,000 bodies were deferred every step)."""
    m = bodies[j, MASS]
    lx = fx / m
    ly = fy / m
    mus = bodies[j, MUS]
    return lx * lx + ly * ly <= mus * mus * (1.0 + 1e-12)


@njit(cache=True, inline="always")
def _modes(i: int, j: int, got: np.ndarray, bodies: np.ndarray) -> tuple[bool, float, bool, bool]:
    """Body j's (row i of the read) standing in this step: whether static friction acts on it
    (:func:`_static`), its rest-rule flag STOP, whether it is at rest (velocity and spin read exactly
    zero) and whether it turns on a held foot (:mod:`rrbody.contact.feet`; after a stop the rest rule
    zeroes the residue first)."""
    static = _static(j, bodies)
    was = bodies[j, STOP]
    resting = got[i, 1] == 0.0 and got[i, 2] == 0.0 and got[i, 3] == 0.0
    feet = static and bodies[j, FEET] > 0.0 and was == 0.0 and not resting
    return static, was, resting, feet


@njit(cache=True, inline="always")
def _evaluated(i: int, j: int, got: np.ndarray, bodies: np.ndarray) -> bool:
    """Whether :func:`_friction` evaluates body j's friction at its extrapolated velocity: not at rest
    (kinetic friction has no direction) nor turning on a held foot."""
    _, _, resting, feet = _modes(i, j, got, bodies)
    return not (resting or feet)


@njit(cache=True, inline="always")
def _load(i, j, got, bodies, dt, out, active, noise):  # noqa: ANN001, ANN202
    """Add the loads on plugin body j (row i of the read) to ``out[i]``, which holds its own force and
    torque: the tilt's pull and the active load. Returns the angle friction and the active load are
    evaluated at (rad), its cosine and sine, and the velocity friction and the drag act at
    (:func:`_extrapolated`)."""
    # a tilted plane: gravity's in-plane part acts at the centre of gravity in every step
    out[i, 0] += bodies[j, MASS] * bodies[j, GTX]
    out[i, 1] += bodies[j, MASS] * bodies[j, GTY]
    # the angle friction and the active load are evaluated at (pymunk moves the pose first)
    alpha = got[i, 0] + got[i, 3] * dt
    sa, ca = sincos_reduced(alpha)  # (a third faster than the library's pair, to 2 ulp)
    ex, ey, ew = _extrapolated(i, j, got, bodies, dt)  # the velocity friction and the drag act at
    if active.shape[0] > 0:  # self-propulsion, a medium's drag and noise: a load as well
        fa, fb, fc = act.load(j, ca, sa, ex, ey, ew, bodies[j, MASS], bodies[j, IPM], dt, active, noise)
        out[i, 0] += fa
        out[i, 1] += fb
        out[i, 2] += fc
    return alpha, ca, sa, ex, ey, ew


@njit(cache=True, inline="always")
def _settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break, defer,  # noqa: ANN001, ANN202
            alpha, ca, sa, ex, ey, ew, have, ax, ay, aw):
    """Body j's friction on top of the loads in ``out[i]`` (:func:`_friction`; with ``have``, its
    evaluation at (ex, ey, ew) is (ax, ay, aw) already); the friction added is kept (FFX, FFY, FFT).
    Returns 1 if the rest rule stops it, DEFER if it was deferred (nothing kept), else 0."""
    lx = out[i, 0]
    ly = out[i, 1]
    lt = out[i, 2]
    n = _friction(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break, defer, alpha, ca, sa,
                  ex, ey, ew, have, ax, ay, aw)
    if n == DEFER:
        return n
    # what friction added to the load is the friction this step applies
    bodies[j, FFX] = out[i, 0] - lx
    bodies[j, FFY] = out[i, 1] - ly
    bodies[j, FFT] = out[i, 2] - lt
    return n


@njit(cache=True, inline="always")
def _one(i, j, got, bodies, shapes, geo, tables, t, dt, out, active, noise):  # noqa: ANN001, ANN202
    """One plugin body's whole step in the limit-set loop (row ``i`` of the read, row ``j`` of
    ``bodies``), ``out[i]`` holding its own force and torque: the tilt's pull and the active load are
    added, then friction, static friction's limit-set test included (:func:`_held`,
    :func:`_hold_or_break`); the friction added is kept (FFX, FFY, FFT). Returns 1 if the rest rule
    stops it."""
    alpha, ca, sa, ex, ey, ew = _load(i, j, got, bodies, dt, out, active, noise)
    return _settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, _held, _hold_or_break, False, alpha, ca, sa,
                   ex, ey, ew, False, 0.0, 0.0, 0.0)


@njit(cache=True, inline="always")
def _stop(i: int, j: int, was: float, static: bool, vx: float, vy: float, w: float, dt: float, bodies: np.ndarray,
          out: np.ndarray) -> None:
    """The rest rule stops body j (row i of the read) in this step, its load held if ``static``: the
    positions still move with this step's velocity (as the exact motion would, to O(mu g dt^2)); the
    impulse cancels it, and the next step (``was`` > 0) sets the rounding residue exactly to zero."""
    if static:  # the load is held: at rest, no force but the stopping impulse
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
    if was > 0.0:
        bodies[j, STOP] = ZEROED
        bodies[j, PVX] = 0.0
        bodies[j, PVY] = 0.0
        bodies[j, PW] = 0.0
        return
    bodies[j, STOP] = STOPPING
    out[i, 0] -= bodies[j, MASS] * vx / dt
    out[i, 1] -= bodies[j, MASS] * vy / dt
    out[i, 2] -= bodies[j, MASS] * bodies[j, IPM] * w / dt


@njit(cache=True, inline="always")
def _commit(j: int, bodies: np.ndarray, vx: float, vy: float, w: float, alpha: float, ew: float, t: float,
            dt: float) -> None:
    """Body j's state for the next step: this step's velocity (the history the next extrapolates
    from), the angle and spin friction is evaluated at, and a driven body's driver."""
    bodies[j, STOP] = 0.0
    bodies[j, PVX] = vx
    bodies[j, PVY] = vy
    bodies[j, PW] = w
    bodies[j, GAP] = dt
    bodies[j, EA] = alpha
    bodies[j, EW] = ew
    if bodies[j, DRV] > 0.0:
        _driver(j, bodies, t, dt)


@njit(cache=True, inline="always")
def _evaluate(i, j, ca, sa, vx, vy, w, ex, ey, ew, dt, was, bodies, shapes, geo, tables, out,  # noqa: ANN001, ANN202
              have, ax0, ay0, aw0):
    """Friction (ax, ay, alpha_dot) of body j at the velocity (ex, ey, ew), its limiter's factor s
    (:func:`limited`, under the load in ``out[i]``) and whether the rest rule may stop the body in this
    step: every point slower than the deceleration friction leaves, where the limiter cut the impulse
    or, the step after a stop, where what is left is rounding (friction, in its dead band, may then
    give no impulse to limit). With ``have``, (ax0, ay0, aw0) is the friction at (ex, ey, ew) already.
    Changes no state."""
    m0 = bodies[j, MASS]
    if have:
        ax, ay, aw, s = limited_at(ax0, ay0, aw0, j, ca, sa, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo, tables,
                                   out[i, 0] / m0, out[i, 1] / m0, out[i, 2] / (m0 * bodies[j, IPM]))
    else:
        ax, ay, aw, s = limited(j, ca, sa, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo, tables, out[i, 0] / m0,
                                out[i, 1] / m0, out[i, 2] / (m0 * bodies[j, IPM]))
    stop = (s < 1.0 or was == STOPPING) and bodies[j, SNAP] > 0.0 and bodies[j, LAW] == LAW_DRY \
        and _slow_enough(i, j, vx, vy, w, dt, bodies, out)
    return ax, ay, aw, s, stop


@njit(cache=True, inline="always")
def _friction(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break,  # noqa: ANN001, ANN202
              defer, alpha, ca, sa, ex, ey, ew, have, ax0, ay0, aw0):
    """Add this step's friction on plugin body ``j`` (row ``i`` of the space's read) to ``out[i]``, which
    holds the load (the user's force and torque, and a tilt's pull); 1 if the rest rule stops it.
    Inlined (a call would pass its arrays on the stack for every body); ``held`` and ``hold_or_break``
    are :func:`_held` and :func:`_hold_or_break` (the limit-set loop, :func:`_one`) or, with ``defer``,
    :func:`_sweep`'s stand-ins; ``alpha`` (rad) is the angle friction is evaluated at, ``ca``, ``sa`` its
    cosine and sine, (ex, ey, ew) the velocity (:func:`_extrapolated`); with ``have``, the friction there
    is (ax0, ay0, aw0) already. With ``defer`` (the lean sweep, which hands the bodies at rest under
    static friction to the limit-set loop itself, before their loads), a body about to stop under a load
    static friction may hold, or on a held foot whose spin runs out in this step, returns DEFER having
    changed nothing, for the caller to step it again without ``defer``. A body on feet otherwise takes
    its step here: turning on a held foot, or sliding (measured, 1,000 sliding disks on three point feet:
    3.3x the cost of uniform disks per step while every such body was deferred, 1.7x since)."""
    static, was, resting, feet = _modes(i, j, got, bodies)
    vx = got[i, 1]
    vy = got[i, 2]
    w = got[i, 3]
    m0 = bodies[j, MASS]
    ax = ay = aw = 0.0
    s = 1.0
    stop = False
    # on feet: a foot at rest is held by static friction while the body turns about it. Everything up
    # to _commit changes no state (feet_step and the evaluation read none of what it writes), so a body
    # that needs the limit-set test can still be deferred, and the same numbers come out either way
    if not (resting or feet):
        ax, ay, aw, s, stop = _evaluate(i, j, ca, sa, vx, vy, w, ex, ey, ew, dt, was, bodies, shapes, geo,
                                        tables, out, have, ax0, ay0, aw0)
        if stop and static and defer and _may_hold(j, bodies, out[i, 0], out[i, 1]):
            return DEFER  # (a load static friction cannot hold needs no test: the body slides on, below)
    foot = -1
    fx = fy = tq = 0.0
    runs_out = False
    if feet:
        # near the spin's stop the extrapolated spin passes zero before the spin does: the current one then
        fex, fey, few = (vx, vy, w) if ew * w <= 0.0 else (ex, ey, ew)
        # (pymunk moves the pose with the velocity read, from got[i, 0] to alpha, then updates the
        # velocity, which moves the pose in the next step: its lever halfway through that one)
        foot, fx, fy, tq = feet_step(shapes, int(bodies[j, S0]), int(bodies[j, S1]), alpha, alpha + 0.5 * w * dt,
                                     got[i, 0] + 0.5 * w * dt, vx, vy, w, fex, fey, few, out[i, 0] / m0,
                                     out[i, 1] / m0, out[i, 2] / m0,
                                     bodies[j, COEFF], bodies[j, MUS], bodies[j, IPM], bodies[j, VEPS], dt,
                                     bodies[j, REACH], int(bodies[j, PIN]) - 1)
        # held, its spin runs out in this step: the whole body at rest where static friction holds its
        # load (the limit-set test), else, on a tilt, it swings back (the usual friction below)
        runs_out = foot >= 0 and w * (w + dt * (out[i, 2] / m0 + tq) / bodies[j, IPM]) <= 0.0
        if runs_out and defer:
            return DEFER
        if runs_out or foot == -1:
            ax, ay, aw, s, stop = _evaluate(i, j, ca, sa, vx, vy, w, fex, fey, few, dt, was, bodies, shapes, geo,
                                            tables, out, False, 0.0, 0.0, 0.0)
            # (the same test as in the branch above; one test after both branches compiled the L-shapes'
            # table look-up differently: results one ulp apart, measured)
            if stop and static and defer and _may_hold(j, bodies, out[i, 0], out[i, 1]):
                return DEFER
    _commit(j, bodies, vx, vy, w, alpha, ew, t, dt)
    if resting:
        # at rest: kinetic friction has no direction; static friction holds the load or lets go
        if static:
            hold_or_break(i, j, got[i, 0], bodies, shapes, geo, out)
        return 0
    if feet:
        if runs_out:
            bodies[j, PIN] = 0.0
            if held(i, j, got[i, 0], bodies, shapes, geo, out):
                _stop(i, j, was, static, vx, vy, w, dt, bodies, out)
                return 1
        elif foot != -1:
            bodies[j, PIN] = foot + 1.0 if foot >= 0 else 0.0
            out[i, 0] += m0 * fx
            out[i, 1] += m0 * fy
            out[i, 2] += m0 * tq
            return 0
        bodies[j, PIN] = 0.0
    if stop and (not static or held(i, j, got[i, 0], bodies, shapes, geo, out)):
        # every point slower than decel dt: friction stops the body within this step (if a load
        # acts, only where static friction then holds it; else it slides on)
        _stop(i, j, was, static, vx, vy, w, dt, bodies, out)
        return 1
    m = bodies[j, MASS] * s
    out[i, 0] += m * ax
    out[i, 1] += m * ay
    out[i, 2] += m * bodies[j, IPM] * aw
    return 0
