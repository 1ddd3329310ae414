"""The recorder's copy kernels (:class:`rrbody.render.recorder.Recorder`): one frame of the filmed
bodies, in one compiled call, either read straight from their structs (:func:`capture_direct`) or
picked from the space's bulk read (:func:`capture_rows`); both add the plugin's velocity at its
time and its friction.

``pymunk.batch`` reads every body of a space, field by field, with a bounds check per number (about
14 us per 1,000 bodies for position, angle, velocity and spin, measured); the recorder needs only
the bodies it films, and their state is six numbers in each body's C struct. :func:`layout` finds
where those numbers lie in pymunk's ``cpBody`` (an opaque type to pymunk's Python side) by probing
a body whose state is set through pymunk's own setters, then checks the offsets on a second probe
after a step, and :func:`capture_direct` reads them (:mod:`rrbody.engine.bodymem`; about 2 us per
1,000 bodies). If the probe does not find every number exactly once, or the check fails (a pymunk
whose Chipmunk lays the struct out otherwise), :func:`layout` returns None and the recorder keeps
``pymunk.batch``; ``tests/test_recorder.py`` checks that both routes store the same frames, bit for
bit. A body removed from the space reads a null ``space`` field, which :func:`capture_direct`
reports instead of reading on.

The kernels are compiled without numba's reference counting (:mod:`rrbody.engine.lean`): with it,
each body's call of the shared :func:`_motion` counted its two arrays, and a capture of 1,000
bodies took 21 us instead of 2 (measured)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit

from rrbody.engine.bodymem import address, f64_at, i64_at
from rrbody.engine.kernel import FFT, FFX, FFY, GAP, N_BODY, PVX, PVY, PW, STAG
from rrbody.engine.lean import NO_REFCOUNT

__all__ = ["capture_rows", "capture_direct", "layout"]

#: bytes of a body's struct the probe searches (Chipmunk's cpBody is larger; every field read lies within)
_WINDOW = 256


@njit(cache=True, inline="always", **NO_REFCOUNT)
def _motion(out: np.ndarray, k: int, vx: float, vy: float, w: float, bodies: np.ndarray, j: int) -> None:
    """Columns 3-8 of filmed body ``k``'s row: its velocity and spin at the plugin's time, and the
    plugin's friction of its last step (``j``: its row in the plugin's ``bodies``, or -1: none)."""
    if j >= 0:
        if bodies[j, GAP] > 0.0 and bodies[j, STAG] > 0.0:
            # the staggered scheme's velocity after a step belongs to half a step later: the mean
            # with the one before is the velocity at the plugin's time (PlaneFriction.velocity)
            vx = 0.5 * (bodies[j, PVX] + vx)
            vy = 0.5 * (bodies[j, PVY] + vy)
            w = 0.5 * (bodies[j, PW] + w)
        out[k, 6] = bodies[j, FFX]
        out[k, 7] = bodies[j, FFY]
        out[k, 8] = bodies[j, FFT]
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
    (byte offsets ``offs``: :func:`rrbody.engine.bodymem.layout`). Returns -1, or the index of the
    first filmed body no longer in ``space`` (the frame is then incomplete: the caller raises)."""
    out = store[frame]
    motion = out.shape[1] >= 9
    ox, oy, oa, ovx, ovy, ow, osp = offs[0], offs[1], offs[2], offs[3], offs[4], offs[5], offs[6]
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


def _probe(values: tuple[float, float, float, float, float, float], step: bool) -> tuple[Any, Any, np.ndarray]:
    """A space with one body set to ``values`` (x, y, angle, vx, vy, spin) through pymunk's setters
    (its centre of gravity off its origin), optionally stepped; returns (space, body, its first bytes)."""
    import pymunk
    from pymunk._chipmunk import ffi

    space = pymunk.Space()
    body = pymunk.Body()
    shape = pymunk.Circle(body, 0.1, (0.3, -0.2))
    shape.density = 1.0
    space.add(body, shape)
    x, y, a, vx, vy, w = values
    body.position, body.angle, body.velocity, body.angular_velocity = (x, y), a, (vx, vy), w
    if step:
        space.step(0.01)
    return space, body, np.frombuffer(bytes(ffi.buffer(body._body, _WINDOW)), dtype=np.uint8)


def _getters(body: Any) -> list[float]:
    """x, y, angle, vx, vy, spin of ``body`` through pymunk's own getters."""
    p, v = body.position, body.velocity
    return [p.x, p.y, body.angle, v.x, v.y, body.angular_velocity]


def _find() -> np.ndarray | None:
    """The offsets :func:`layout` returns, or None (a number found other than exactly once, or the check failed)."""
    space, body, raw = _probe((1.25, -2.5, 0.625, 3.5, 4.75, -1.375), step=True)
    f = raw.view(np.float64)
    i = raw.view(np.int64)
    offs = []
    for v in _getters(body):
        hit = np.flatnonzero(f == v)
        if len(hit) != 1:
            return None
        offs.append(8 * int(hit[0]))
    hit = np.flatnonzero(i == address(space._space))
    if len(hit) != 1:
        return None
    offs.append(8 * int(hit[0]))
    out = np.array(offs, dtype=np.int64)
    # the check, through the capture's own kernel: other values in another space are read exactly,
    # and a body removed from its space reads as removed
    space2, body2, _ = _probe((-7.0625, 0.40625, -2.25, -0.3125, 9.5, 6.125), step=True)
    where = np.array([address(body2._body)], dtype=np.int64)
    frame = np.zeros((1, 1, 9))
    args = (where, out, address(space2._space), np.zeros((0, N_BODY)), np.full(1, -1, dtype=np.int64), frame, 0)
    if capture_direct(*args) != -1 or frame[0, 0, :6].tolist() != _getters(body2):
        return None
    space2.remove(body2, *body2.shapes)
    if capture_direct(*args) != 0:
        return None
    return out


_layout: Any = False  # not probed yet


def layout() -> np.ndarray | None:
    """Byte offsets (int64 array: x, y, angle, vx, vy, spin, space; the order :func:`capture_direct`
    reads) of a body's state in pymunk's ``cpBody``, found and checked once per process; None where
    they cannot be trusted."""
    global _layout
    if _layout is False:
        try:
            _layout = _find()
        except Exception:  # pragma: no cover - any surprise in pymunk's internals: keep pymunk.batch
            _layout = None
    return _layout
