"""Raw access to pymunk's C structs in compiled code: an object's address, the float64 or int64 at a
byte address, a float64 stored there, and where a body's state lies in pymunk's ``cpBody``
(:func:`layout`), for the recorder's capture (:mod:`rrbody.engine.recording.capture`) and the plugin's reads
and writes (:mod:`rrbody.engine.memory.structio`); and where a space keeps its sleeping threshold in
pymunk's ``cpSpace`` (:func:`sleep_offset`), which the plugin's compiled step reads each step.

``pymunk.batch`` reads every body of a space field by field, with a bounds check per number (about
15 us per 1,000 bodies, and as much to write their forces back, measured); a body's state is a
few numbers in its C struct. :func:`layout` finds where they lie in pymunk's ``cpBody`` (an opaque
type to pymunk's Python side) by probing a body whose state is set through pymunk's own setters,
then checks the offsets on a second probe: read through a compiled reader, written through
:func:`set_f64` and read back through pymunk's getters, and a body removed from its space must read
a null ``space`` field. If the probe does not find every number exactly once, or the check fails (a
pymunk whose Chipmunk lays the struct out otherwise), :func:`layout` returns None and the callers
keep ``pymunk.batch``.

The addresses must be those of objects the caller keeps alive (the recorder and the plugin hold
their bodies), so an access never touches freed memory.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import types
from numba.extending import intrinsic

from rrbody._private import private_allowed

__all__ = ["address", "addresses", "f64_at", "i64_at", "set_f64", "layout", "sleep_offset", "X", "Y", "ANGLE", "VX",
           "VY", "SPIN", "SPACE", "FX", "FY", "TORQUE"]

#: the entries of :func:`layout`'s offsets: position (m), angle (rad), velocity (m/s), spin (rad/s),
#: the body's space (a pointer; null once removed), force (N) and torque (N m)
X, Y, ANGLE, VX, VY, SPIN, SPACE, FX, FY, TORQUE = range(10)
#: bytes of a body's struct the probe searches (Chipmunk's cpBody is larger; every field used lies within)
_WINDOW = 256


def address(cdata: Any) -> int:
    """The address of a pymunk C object (``body._body``, ``space._space``) as an int64."""
    from pymunk._chipmunk import ffi

    a = int(ffi.cast("uintptr_t", cdata))
    return a - (1 << 64) if a >= 1 << 63 else a


def addresses(bodies: Any) -> np.ndarray:
    """The addresses of pymunk bodies' structs (int64 array, in the order given)."""
    return np.array([address(b._body) for b in bodies], dtype=np.int64)


@intrinsic
def f64_at(typingctx: Any, addr: Any) -> Any:
    """The float64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.DoubleType())))
    return types.float64(types.int64), codegen


@intrinsic
def i64_at(typingctx: Any, addr: Any) -> Any:
    """The int64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.IntType(64))))
    return types.int64(types.int64), codegen


@intrinsic
def set_f64(typingctx: Any, addr: Any, value: Any) -> Any:
    """Store the float64 ``value`` at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        builder.store(args[1], builder.inttoptr(args[0], ir.PointerType(ir.DoubleType())))
        return context.get_dummy_value()
    return types.none(types.int64, types.float64), codegen


@njit(cache=True)
def _read(a: int, offs: np.ndarray, out: np.ndarray) -> None:
    """The float64 fields of the struct at ``a`` (every entry of ``offs`` but SPACE) into ``out``."""
    for k in range(offs.shape[0]):
        out[k] = f64_at(a + offs[k]) if k != SPACE else float(i64_at(a + offs[k]))


@njit(cache=True)
def _write(a: int, off: int, value: float) -> None:
    set_f64(a + off, value)


def _probe(values: tuple[float, ...], step: bool) -> tuple[Any, Any, np.ndarray]:
    """A space with one body set to ``values`` (x, y, angle, vx, vy, spin, fx, fy, torque) through
    pymunk's setters (its centre of gravity off its origin), the force and torque set after the
    optional step (a step clears them); returns (space, body, its first bytes)."""
    import pymunk
    from pymunk._chipmunk import ffi

    space = pymunk.Space()
    body = pymunk.Body()
    shape = pymunk.Circle(body, 0.1, (0.3, -0.2))
    shape.density = 1.0
    space.add(body, shape)
    x, y, a, vx, vy, w, fx, fy, tq = values
    body.position, body.angle, body.velocity, body.angular_velocity = (x, y), a, (vx, vy), w
    if step:
        space.step(0.01)
    body.force, body.torque = (fx, fy), tq
    return space, body, np.frombuffer(bytes(ffi.buffer(body._body, _WINDOW)), dtype=np.uint8)


def _getters(body: Any) -> list[float]:
    """x, y, angle, vx, vy, spin, fx, fy, torque of ``body`` through pymunk's own getters."""
    p, v, f = body.position, body.velocity, body.force
    return [p.x, p.y, body.angle, v.x, v.y, body.angular_velocity, f.x, f.y, body.torque]


def _find() -> np.ndarray | None:
    """The offsets :func:`layout` returns, or None (a number found other than exactly once, or the check failed)."""
    space, body, raw = _probe((1.25, -2.5, 0.625, 3.5, 4.75, -1.375, 5.125, -6.0625, 7.03125), step=True)
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
    offs.insert(SPACE, 8 * int(hit[0]))
    out = np.array(offs, dtype=np.int64)
    # the check: other values in another space are read exactly, written values read back through
    # pymunk's getters, and a body removed from its space reads as removed
    space2, body2, _ = _probe((-7.0625, 0.40625, -2.25, -0.3125, 9.5, 6.125, -0.875, 3.25, -1.5), step=True)
    a = address(body2._body)
    got = np.zeros(out.shape[0])
    _read(a, out, got)
    want = _getters(body2)
    if np.delete(got, SPACE).tolist() != want or int(got[SPACE]) != address(space2._space):
        return None
    for k, v in ((FX, 0.0625), (FY, -0.1875), (TORQUE, 2.5)):
        _write(a, int(out[k]), v)
    if [body2.force.x, body2.force.y, body2.torque] != [0.0625, -0.1875, 2.5]:
        return None
    space2.remove(body2, *body2.shapes)
    _read(a, out, got)
    if int(got[SPACE]) == address(space2._space):
        return None
    return out


_layout: Any = False  # not probed yet


def layout() -> np.ndarray | None:
    """Byte offsets (an int64 array indexed by X, Y, ANGLE, VX, VY, SPIN, SPACE, FX, FY, TORQUE) of a
    body's state in pymunk's ``cpBody``, found and checked once per process; None where they cannot
    be trusted."""
    global _layout
    if not private_allowed():  # RRBODY_NO_PRIVATE: the public reads take over (rrbody._private)
        return None
    if _layout is False:
        try:
            _layout = _find()
        except Exception:  # pragma: no cover - any surprise in pymunk's internals: keep pymunk.batch
            _layout = None
    return _layout


def _find_sleep() -> int | None:
    """:func:`sleep_offset`'s answer, or None (the value found other than exactly once, or the check failed)."""
    import pymunk
    from pymunk._chipmunk import ffi

    space = pymunk.Space()
    space.sleep_time_threshold = 1234.5625  # exact in binary, nothing else of a new space holds it
    raw = np.frombuffer(bytes(ffi.buffer(space._space, _WINDOW)), dtype=np.float64)
    hit = np.flatnonzero(raw == 1234.5625)
    if len(hit) != 1:
        return None
    off = 8 * int(hit[0])
    # the check, on another space: every value set through pymunk's setter reads back here, and
    # nothing else it is given (idle speed, damping, collision slop) lands there
    other = pymunk.Space()
    a = address(other._space)
    got = np.zeros(1)
    for v in (0.5, math.inf, 7.25, math.inf):
        other.sleep_time_threshold = v
        other.idle_speed_threshold, other.damping, other.collision_slop = 3.0, 0.75, 0.125
        _read(a, np.array([off], dtype=np.int64), got)
        if got[0] != v or other.sleep_time_threshold != v:
            return None
    return off


_sleep: Any = False  # not probed yet


def sleep_offset() -> int | None:
    """Byte offset of ``sleepTimeThreshold`` (s; inf: sleeping off, pymunk's default) in pymunk's
    ``cpSpace``, found and checked once per process, so that compiled code reads what
    ``space.sleep_time_threshold`` would return; None where it cannot be trusted (the caller then
    reads the property)."""
    global _sleep
    if not private_allowed():  # RRBODY_NO_PRIVATE: the public property (rrbody._private)
        return None
    if _sleep is False:
        try:
            _sleep = _find_sleep()
        except Exception:  # pragma: no cover - any surprise in pymunk's internals: keep the property
            _sleep = None
    return _sleep
