"""Bulk reads and writes of a pymunk space's bodies through ``pymunk.batch`` (pymunk >= 6.11), or body
by body through pymunk's public properties where ``pymunk.batch`` cannot (pymunk 6.6-6.10).

One read per step fetches (angle, velocity, spin, force, torque) and the id of every body of the
space; one write sets every body's force and torque. ``pymunk.batch`` is marked experimental by
pymunk; its public functions allocate a C struct and resolve flags on every call (about 1.5 us
each, measured), so this class keeps that struct and the C iterator between calls and calls the
same C functions directly (the *lean* route). If a pymunk lacks those names, it falls back to the
public functions (the *bulk* route: same data, slower). pymunk 6.6-6.10's ``pymunk.batch`` reads
no force or torque and writes nothing: there the *per-body* route reads and writes each body
through ``Body.angle``, ``.velocity``, ``.angular_velocity``, ``.force`` and ``.torque`` (the same
numbers, one Python call each: for a space of many bodies the struct route of
:mod:`rrbody.engine.structio` is what keeps such a pymunk fast). ``tests/test_plugin_io.py`` checks
that every route steps a scene bit for bit as the others do (docs/versions.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["BatchIO", "READ_COLUMNS", "POSE_COLUMNS", "ROUTES", "body_uid", "batch_writes"]

#: the routes a BatchIO takes to the bodies (``BatchIO.route``): pymunk.batch's C iterator kept between
#: calls, pymunk.batch's public functions, or each body's public properties
ROUTES = ("lean", "bulk", "per-body")

#: columns of the array :meth:`BatchIO.read` returns (pymunk.batch writes fields in this order)
READ_COLUMNS = ("angle", "vx", "vy", "spin", "fx", "fy", "torque")
#: the columns of a reader made with ``poses=True`` (the recorder's): position, angle, velocity, spin
POSE_COLUMNS = ("x", "y", "angle", "vx", "vy", "spin")


def body_uid(body: Any) -> int:
    """A pymunk body's id (a pointer, uintptr) as the int64 with the same bits, as :meth:`BatchIO.read`
    reads the ids."""
    uid = int(body.id)
    return uid - (1 << 64) if uid >= 1 << 63 else uid


def batch_writes() -> bool:
    """Whether this pymunk's ``pymunk.batch`` reads a body's force and torque and writes them (pymunk
    >= 6.11; 6.6-6.10 only read positions and velocities)."""
    import pymunk.batch as pb

    return hasattr(pb.BodyFields, "FORCE") and hasattr(pb, "set_space_bodies") and hasattr(pb.Buffer, "set_float_buf")


class BatchIO:
    """Reader and force writer for all bodies of ``space`` (order: pymunk's iteration order); with
    ``poses`` a reader of :data:`POSE_COLUMNS` instead (its forces are not to be written).

    ``route`` asks for a route (:data:`ROUTES`; None: the fastest this pymunk offers); the route taken
    is :attr:`route`. A route this pymunk cannot take raises ValueError."""

    def __init__(self, space: Any, *, lean: bool = True, poses: bool = False, route: str | None = None) -> None:
        import pymunk.batch as pb

        if route is not None and route not in ROUTES:
            raise ValueError(f"route must be one of {', '.join(ROUTES)} or None, got {route!r}")
        self._pb = pb
        self._space = space
        self._n = -1
        self.lean = False
        self._bodies: list[Any] = []
        if route == "per-body" or (route is None and not poses and not batch_writes()):
            # pymunk 6.6-6.10: pymunk.batch reads no force or torque and writes nothing
            self.route = "per-body"
            self._width = len(POSE_COLUMNS) if poses else len(READ_COLUMNS)
            self._poses = poses
            return
        if not poses and not batch_writes():
            raise ValueError(f"route {route!r} needs a pymunk.batch that writes forces (pymunk >= 6.11), "
                             f"this is pymunk {_version()}: use route='per-body'")
        F = pb.BodyFields
        if poses:
            self._read_fields = F.BODY_ID | F.POSITION | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY
            self._width = len(POSE_COLUMNS)
        else:
            self._read_fields = F.BODY_ID | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY | F.FORCE | F.TORQUE
            self._width = len(READ_COLUMNS)
        # a pose reader writes nothing (and pymunk 6.6-6.10's batch has no FORCE field to name)
        self._write_fields = None if poses else F.FORCE | F.TORQUE
        self._gbuf = pb.Buffer()
        self._sbuf = pb.Buffer()
        if pb.ffi.sizeof("uintptr_t") != 8:  # pragma: no cover - 32-bit platforms
            raise ValueError("rrbody's PlaneFriction needs a 64-bit pymunk (uintptr_t of 8 bytes)")
        self._fptr: Any = None
        self._iptr: Any = None
        if lean and route != "bulk":
            try:
                ffi, lib = pb.ffi, pb.lib
                self._ffi, self._lib, self._sp = ffi, lib, space._space
                self._each = lib.cpSpaceEachBody
                self._fn_get = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
                self._gdata = ffi.new("pmBatchedData *")
                self._gdata.fields = self._read_fields.value
                self._gdata.floatArray = self._gbuf._float_arr
                self._gdata.intArray = self._gbuf._int_arr
                if not poses:
                    self._fn_set = ffi.addressof(lib, "pmSpaceBodySetIteratorFuncBatched")
                    self._sdata = ffi.new("pmBatchedData *")
                    self._sdata.fields = self._write_fields.value
                    self._sdata.intArray = self._sbuf._int_arr
                self.lean = True
            except (AttributeError, TypeError):  # depends on the pymunk version; route="bulk" takes this path
                self.lean = False
        if route == "lean" and not self.lean:
            raise ValueError(f"route 'lean' is not available on pymunk {_version()}: use route='bulk'")
        self.route = "lean" if self.lean else "bulk"

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(got, ids, out): ``got`` (n x 7, READ_COLUMNS; n x 6, POSE_COLUMNS, for a pose reader) and ``ids``
        (n, int64 view of the uintptr ids) of every body in the space, and the (n x 3) array of (fx, fy,
        torque) that :meth:`write_forces` will set."""
        if self.route == "per-body":
            return self._read_each()
        fa = self._gbuf._float_arr
        ia = self._gbuf._int_arr
        if self.lean:
            fa.num = 0
            ia.num = 0
            self._each(self._sp, self._fn_get, self._gdata)
        else:
            self._gbuf.clear()
            self._pb.get_space_bodies(self._space, self._read_fields, self._gbuf)
        n = ia.num
        if n != self._n or fa.arr != self._fptr or ia.arr != self._iptr:
            self._rebuild(n)
        return self._got, self._ids, self._out

    def _rebuild(self, n: int) -> None:
        """New numpy views on pymunk's arrays (after their memory moved or the body count changed)."""
        from pymunk.batch import ffi

        fa = self._gbuf._float_arr
        ia = self._gbuf._int_arr
        self._n, self._fptr, self._iptr = n, fa.arr, ia.arr
        w = self._width
        if n == 0:
            self._got = np.zeros((0, w))
            self._ids = np.zeros(0, dtype=np.int64)
        else:
            self._got = np.frombuffer(ffi.buffer(fa.arr, 8 * w * n), dtype=np.float64).reshape(n, w)
            # ids are pointers (uintptr_t); read as int64, the type the kernel's lookup table uses
            self._ids = np.frombuffer(ffi.buffer(ia.arr, 8 * n), dtype=np.int64)
        self._out = np.zeros((n, 3))
        if n and self._write_fields is not None:
            self._sbuf.set_float_buf(self._out)
            if self.lean:
                self._sdata.floatArray = self._sbuf._float_arr

    def _read_each(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`read` body by body, through pymunk's public properties (the per-body route)."""
        bodies = list(self._space.bodies)
        n = len(bodies)
        if n != self._n:
            self._n = n
            self._got = np.zeros((n, self._width))
            self._ids = np.zeros(n, dtype=np.int64)
            self._out = np.zeros((n, 3))
        got, ids = self._got, self._ids
        for k, b in enumerate(bodies):
            v = b.velocity
            ids[k] = body_uid(b)
            if self._poses:
                p = b.position
                got[k] = (p.x, p.y, b.angle, v.x, v.y, b.angular_velocity)
            else:
                f = b.force
                got[k] = (b.angle, v.x, v.y, b.angular_velocity, f.x, f.y, b.torque)
        self._bodies = bodies
        return got, ids, self._out

    def write_forces(self) -> None:
        """Set every body's force (N, at its centre of gravity) and torque (N m) from ``out``."""
        if self._n <= 0:
            return
        if self.route == "per-body":
            # the bodies of the last read, in its order (a write always follows its read in the same step)
            for b, (fx, fy, tq) in zip(self._bodies, self._out.tolist()):
                b.force = (fx, fy)
                b.torque = tq
            return
        if self.lean:
            self._sbuf._float_arr.num = 0
            self._each(self._sp, self._fn_set, self._sdata)
        else:
            self._pb.set_space_bodies(self._space, self._write_fields, self._sbuf)


def _version() -> str:
    import pymunk

    return str(pymunk.version)
