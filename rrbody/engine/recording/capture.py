"""The recorder's copy kernels (its tape, :class:`rrbody.engine.recording.tape.Tape`): one frame of the filmed
bodies, in one compiled call, either read straight from their structs (:func:`capture_direct`) or
picked from the space's bulk read (:func:`capture_rows`); both add the plugin's velocity at its
time and its friction.

``pymunk.batch`` reads every body of a space, field by field, with a bounds check per number (about
14 us per 1,000 bodies for position, angle, velocity and spin, measured); the recorder needs only
the bodies it films, and their state is six numbers in each body's C struct, which
:func:`capture_direct` reads where :func:`rrbody.engine.memory.bodymem.layout` found them (about 2 us per
1,000 bodies). Where the layout is unknown the recorder keeps ``pymunk.batch``;
``tests/test_recorder.py`` checks that both routes store the same frames, bit for bit. A body
removed from the space reads a null ``space`` field, which :func:`capture_direct` reports instead of
reading on.

The kernels are compiled without numba's reference counting (:mod:`rrbody.contact.lean`): with it,
each body's call of the shared :func:`_motion` counted its two arrays, and a capture of 1,000
bodies took 21 us instead of 2 (measured)."""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.contact.kernel import (
    FRICTION_FX,
    FRICTION_FY,
    FRICTION_TORQUE,
    PREV_GAP,
    PREV_SPIN,
    PREV_VX,
    PREV_VY,
    STAGGERED,
    STOP,
)
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.engine.memory.bodymem import ANGLE, SPACE, SPIN, VX, VY, X, Y, f64_at, i64_at, layout

__all__ = ["capture_rows", "capture_direct", "layout"]


@njit(cache=True, inline="always", **NO_REFCOUNT)
def _motion(out: np.ndarray, k: int, vx: float, vy: float, w: float, bodies: np.ndarray, j: int) -> None:
    """Columns 3-8 of filmed body ``k``'s row: its velocity and spin at the plugin's time, and the
    plugin's friction of its last step (``j``: its row in the plugin's ``bodies``, or -1: none)."""
    if j >= 0:
        if bodies[j, STOP] > 0.0 and vx == 0.0 and vy == 0.0 and w == 0.0:
            pass  # stopped by the rest rule within the last step, nothing left: at rest (PlaneFriction.velocity)
        elif bodies[j, PREV_GAP] > 0.0 and bodies[j, STAGGERED] > 0.0:
            # the staggered scheme's velocity after a step belongs to half a step later: the mean
            # with the one before is the velocity at the plugin's time (PlaneFriction.velocity)
            vx = 0.5 * (bodies[j, PREV_VX] + vx)
            vy = 0.5 * (bodies[j, PREV_VY] + vy)
            w = 0.5 * (bodies[j, PREV_SPIN] + w)
        out[k, 6] = bodies[j, FRICTION_FX]
        out[k, 7] = bodies[j, FRICTION_FY]
        out[k, 8] = bodies[j, FRICTION_TORQUE]
    else:
        out[k, 6] = 0.0
        out[k, 7] = 0.0
        out[k, 8] = 0.0
    out[k, 3] = vx
    out[k, 4] = vy
    out[k, 5] = w


@njit(cache=True, **NO_REFCOUNT)
def capture_rows(got: np.ndarray, ids: np.ndarray, want: np.ndarray, rows: np.ndarray, bodies: np.ndarray,
                 prow: np.ndarray, store: np.ndarray, frame: int) -> bool:
    """One frame from the space's bulk read ``got`` (rows x, y, angle, vx, vy, spin; ``ids`` their
    ids) into ``out = store[frame]`` (one row per filmed body: x, y, angle and, if ``out`` has 9
    columns, vx, vy, spin at the plugin's time and the friction of its last step; the store is
    passed whole: no view is made per call). ``rows``: each filmed body's row in ``got`` (found by
    the caller; ``want`` their ids, to check it); ``prow``: its row in ``bodies`` (the plugin's), or
    -1. Returns False if ``rows`` no longer points at the filmed bodies (the space changed: the
    caller finds them again and calls again; what was written meanwhile is overwritten then)."""
    out = store[frame]
    m = got.shape[0]
    motion = out.shape[1] >= 9
    for k in range(want.shape[0]):
        r = rows[k]
        if r < 0 or r >= m or ids[r] != want[k]:
            return False
        out[k, 0] = got[r, 0]
        out[k, 1] = got[r, 1]
        out[k, 2] = got[r, 2]
        if motion:
            _motion(out, k, got[r, 3], got[r, 4], got[r, 5], bodies, prow[k])
    return True


@njit(cache=True, **NO_REFCOUNT)
def capture_direct(addr: np.ndarray, offs: np.ndarray, space: int, bodies: np.ndarray, prow: np.ndarray,
                   store: np.ndarray, frame: int) -> int:
    """One frame, as :func:`capture_rows` writes it, read from the filmed bodies' structs at ``addr``
    (byte offsets ``offs``: :func:`rrbody.engine.memory.bodymem.layout`). Returns -1, or the index of the
    first filmed body no longer in ``space`` (the frame is then incomplete: the caller raises)."""
    out = store[frame]
    motion = out.shape[1] >= 9
    ox, oy, oa, ovx, ovy, ow, osp = offs[X], offs[Y], offs[ANGLE], offs[VX], offs[VY], offs[SPIN], offs[SPACE]
    for k in range(addr.shape[0]):
        a = addr[k]
        if i64_at(a + osp) != space:
            return k
        out[k, 0] = f64_at(a + ox)
        out[k, 1] = f64_at(a + oy)
        out[k, 2] = f64_at(a + oa)
        if motion:
            _motion(out, k, f64_at(a + ovx), f64_at(a + ovy), f64_at(a + ow), bodies, prow[k])
    return -1
