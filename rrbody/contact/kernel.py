"""The plane step: one compiled call per step for all bodies of a space, whichever engine steps them
(pymunk's plugin :class:`rrbody.engine.plugin.plane.PlaneFriction`, the MuJoCo adapter
:mod:`rrbody.mujoco_adapter.plane`). This module is the force pass over the bodies (:func:`plane_step`:
the read mapped to the adapter's rows, then the loads, friction and the rest of each body in passes);
one body's step is :mod:`rrbody.contact.body`, the operator acting in it (the rest rule, static
friction) :mod:`rrbody.contact.rest`, a body's friction and its limiter :mod:`rrbody.contact.accel`.

Everything here is numba-compiled and works on flat arrays the adapter owns, so a step costs one
compiled call whatever the number of bodies (no per-body Python). Units: SI; per unit mass the
force is m/s^2 and the torque m^2/s^2. The arrays' layouts and the column names are
:mod:`rrbody.contact.columns` (imported here, as ``kernel.MASS`` etc.).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact import body as B
from rrbody.contact import rest as R

# (kernel.body_accel and kernel.limited: the plugin's readers)
from rrbody.contact.accel import accel_at, body_accel, limited  # noqa: F401
from rrbody.contact.columns import *  # noqa: F403 (the columns, here and as kernel.MASS etc. for every reader)
from rrbody.contact.lean import NO_REFCOUNT


@njit(cache=True)
def find_row(lookup: np.ndarray, key: np.int64) -> int:
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
            rowmap[i] = find_row(lookup, key)
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
    static friction that needs the limit-set test (:func:`~rrbody.contact.rest.held`, whose small linear solves
    allocate) is left to a second loop here, which steps it again from the start.
    """
    if got.shape[0] > cache.shape[1]:
        return -2  # the caller enlarges the cache and calls again
    if not plane_check(got, ids, lookup, cache, bodies.shape[0]):
        return -1
    rowmap = cache[ROWMAP]
    work = np.empty((got.shape[0], _N_WORK))  # (one allocation per step, small next to the pass: not worth a cache)
    n_stop, n_defer = _sweep(got, rowmap, bodies, shapes, geo, tables, t, dt, out, active, noise, work)
    if n_defer:
        for i in range(got.shape[0]):
            j = rowmap[i]
            if j >= 0 and bodies[j, DEFERRED] > 0.0:
                bodies[j, DEFERRED] = 0.0
                out[i, 0] = got[i, 4]
                out[i, 1] = got[i, 5]
                out[i, 2] = got[i, 6]
                n_stop += B.step_one(i, j, got, bodies, shapes, geo, tables, t, dt, out, active, noise)
    return n_stop




@njit(cache=True, **NO_REFCOUNT)
def plane_idle(got: np.ndarray, ids: np.ndarray, lookup: np.ndarray, cache: np.ndarray, bodies: np.ndarray, dt: float,
               out: np.ndarray, active: np.ndarray) -> bool:
    """Whether :func:`plane_step` (same arguments) would change nothing: every plugin body of the read
    exactly at rest and held as it was (:func:`rrbody.contact.body.idle`), no active load. If so, writes
    ``out`` as plane_step would (zero for the plugin bodies, a body's own force and torque for the
    others), having changed nothing else but ``cache`` as plane_step's check does, and returns True: the
    caller skips plane_step, whose answer would be 0. Else False, having changed nothing but ``cache``.

    The check costs a few loads per body; a scene at rest (gym-pusht's T between pushes) then skips
    plane_step's passes, its work array and its limit-set loop (about 0.8 of 1.1 us per step for one
    body, measured)."""
    if active.shape[0] > 0 or got.shape[0] > cache.shape[1]:
        return False
    if not plane_check(got, ids, lookup, cache, bodies.shape[0]):
        return False
    rowmap = cache[ROWMAP]
    for i in range(got.shape[0]):
        j = rowmap[i]
        if j >= 0 and not B.idle(i, j, got, bodies, dt):
            return False
    for i in range(got.shape[0]):
        if rowmap[i] >= 0:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
            out[i, 2] = 0.0
        else:
            out[i, 0] = got[i, 4]
            out[i, 1] = got[i, 5]
            out[i, 2] = got[i, 6]
    return True


#: columns of :func:`_sweep`'s work array (a row per row of the read): the angle friction is evaluated at
#: (rad), its cosine and sine, the velocity (m/s, world) and spin (rad/s) it is evaluated at, and the
#: friction there (per unit mass, world: :func:`rrbody.contact.accel.accel_at`)
_W_ALPHA, _W_COS, _W_SIN, _W_EVAL_VX, _W_EVAL_VY, _W_EVAL_SPIN, _W_ACCEL_X, _W_ACCEL_Y, _W_ACCEL_SPIN = range(9)
_N_WORK = 9


@njit(cache=True, **NO_REFCOUNT)
def _sweep(got: np.ndarray, rowmap: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
           tables: np.ndarray, t: float, dt: float, out: np.ndarray, active: np.ndarray, noise: np.ndarray,
           work: np.ndarray) -> tuple[int, int]:
    """:func:`plane_step`'s loop over the space's bodies: ``out`` starts from each body's own force and
    torque, and every plugin body gets its step (what :func:`~rrbody.contact.body.step_one` does, in passes) unless it
    needs the limit-set test (marked DEFERRED). Returns the bodies the rest rule stopped and the bodies deferred.

    Three passes over the bodies, each body's numbers kept in ``work``: the loads (:func:`~rrbody.contact.body.load`; a
    body at rest under static friction is left to the limit-set loop at once),
    then the friction where it is evaluated, disks first and then the other bodies (one kind of wrench
    per tight loop: the evaluations of consecutive bodies, independent, overlap in the CPU), then the
    rest (:func:`~rrbody.contact.body.settle`: limiter, rest rule, state). Measured against one pass doing all three per
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
        static, _, resting, _ = R.modes(i, j, got, bodies)
        if static and resting:
            # at rest under static friction: the limit-set loop steps it from the start (the test of its
            # load, whose small linear solves allocate)
            bodies[j, DEFERRED] = 1.0
            n_defer += 1
            continue
        (work[i, _W_ALPHA], work[i, _W_COS], work[i, _W_SIN], work[i, _W_EVAL_VX], work[i, _W_EVAL_VY],
         work[i, _W_EVAL_SPIN]) = B.load(i, j, got, bodies, dt, out, active, noise)
    for disks in (True, False):
        for i in range(n):
            j = rowmap[i]
            if j < 0 or (bodies[j, TABLE_KIND] == TABLE_CIRCLE) != disks or not R.evaluated(i, j, got, bodies):
                continue
            work[i, _W_ACCEL_X], work[i, _W_ACCEL_Y], work[i, _W_ACCEL_SPIN] = accel_at(
                j, work[i, _W_COS], work[i, _W_SIN], work[i, _W_EVAL_VX], work[i, _W_EVAL_VY], work[i, _W_EVAL_SPIN],
                bodies, shapes, geo, tables)
    for i in range(n):
        j = rowmap[i]
        if j < 0 or bodies[j, DEFERRED] > 0.0:
            continue
        r = B.settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, R.no_held, R.no_break, True, work[i, _W_ALPHA],
                    work[i, _W_COS], work[i, _W_SIN], work[i, _W_EVAL_VX], work[i, _W_EVAL_VY], work[i, _W_EVAL_SPIN],
                    True, work[i, _W_ACCEL_X], work[i, _W_ACCEL_Y], work[i, _W_ACCEL_SPIN])
        if r == DEFER:
            bodies[j, DEFERRED] = 1.0
            n_defer += 1
        else:
            n_stop += r
    return n_stop, n_defer
