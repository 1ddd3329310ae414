"""Reading chosen pymunk bodies' state straight from their Chipmunk structs (the recorder's capture).

``pymunk.batch`` reads every body of a space, field by field, with a bounds check per number (about
14 us per 1,000 bodies for position, angle, velocity and spin, measured); the recorder needs only
the bodies it films, and their state is six numbers in each body's C struct. :func:`layout` finds
where those numbers lie in pymunk's ``cpBody`` (an opaque type to pymunk's Python side) by probing
a body whose state is set through pymunk's own setters, then checks the offsets on a second probe
after a step; :func:`read_pose` reads them in compiled code (about 2 us per 1,000 bodies). If the
probe does not find every number exactly once, or the check fails (a pymunk whose Chipmunk lays
the struct out otherwise), :func:`layout` returns None and the recorder keeps ``pymunk.batch``.
``tests/test_recorder.py`` checks the two routes give the same frames, bit for bit.

The addresses are those of bodies the caller keeps alive (the recorder holds its bodies), so a
read never touches freed memory; a body removed from the space reads a null ``space`` field, which
the reader reports instead of reading it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import types
from numba.extending import intrinsic

__all__ = ["layout", "address", "read_pose", "X", "Y", "ANGLE", "VX", "VY", "SPIN", "SPACE"]

#: indices into :func:`layout`'s array of byte offsets: position (of the body's origin; m), angle
#: (rad), velocity of the centre of gravity (m/s), spin (rad/s), and the body's space (a pointer)
X, Y, ANGLE, VX, VY, SPIN, SPACE = range(7)
#: bytes of a body's struct the probe searches (Chipmunk's cpBody is larger; every field read lies within)
_WINDOW = 256

_layout: Any = False  # not probed yet


def address(cdata: Any) -> int:
    """The address of a pymunk C object (``body._body``, ``space._space``) as an int64."""
    from pymunk._chipmunk import ffi

    a = int(ffi.cast("uintptr_t", cdata))
    return a - (1 << 64) if a >= 1 << 63 else a


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
    p, v = body.position, body.velocity
    return [p.x, p.y, body.angle, v.x, v.y, body.angular_velocity]


def _find() -> np.ndarray | None:
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
    # the check: other values in another space: the offsets read them all exactly, and a body
    # removed from its space reads as removed
    space2, body2, _ = _probe((-7.0625, 0.40625, -2.25, -0.3125, 9.5, 6.125), step=True)
    where = np.array([address(body2._body)], dtype=np.int64)
    check = np.empty((1, 6))
    if read_pose(where, out, address(space2._space), check) != -1 or check[0].tolist() != _getters(body2):
        return None
    space2.remove(body2, *body2.shapes)
    if read_pose(where, out, address(space2._space), check) != 0:
        return None
    return out


def layout() -> np.ndarray | None:
    """Byte offsets (int64 array, indexed by :data:`X` ... :data:`SPACE`) of a body's state in
    pymunk's ``cpBody``, found and checked once per process; None where they cannot be trusted."""
    global _layout
    if _layout is False:
        try:
            _layout = _find()
        except Exception:  # pragma: no cover - any surprise in pymunk's internals: keep pymunk.batch
            _layout = None
    return _layout


@intrinsic
def _f64_at(typingctx: Any, addr: Any) -> Any:
    """The float64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.DoubleType())))
    return types.float64(types.int64), codegen


@intrinsic
def _i64_at(typingctx: Any, addr: Any) -> Any:
    """The int64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.IntType(64))))
    return types.int64(types.int64), codegen


@njit(cache=True)
def read_pose(addr: np.ndarray, offs: np.ndarray, space: int, out: np.ndarray) -> int:
    """Rows (x, y, angle, vx, vy, spin) of the bodies at ``addr`` into ``out`` (rows x >= 6), with
    ``offs`` from :func:`layout`; returns -1, or the index of the first body whose space is not
    ``space`` (its row and those after it are not written)."""
    ox, oy, oa, ovx, ovy, ow, osp = offs[0], offs[1], offs[2], offs[3], offs[4], offs[5], offs[6]
    for k in range(addr.shape[0]):
        a = addr[k]
        if _i64_at(a + osp) != space:
            return k
        out[k, 0] = _f64_at(a + ox)
        out[k, 1] = _f64_at(a + oy)
        out[k, 2] = _f64_at(a + oa)
        out[k, 3] = _f64_at(a + ovx)
        out[k, 4] = _f64_at(a + ovy)
        out[k, 5] = _f64_at(a + ow)
    return -1
