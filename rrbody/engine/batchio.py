"""Bulk reads and writes of a pymunk space's bodies through ``pymunk.batch`` (pymunk >= 7).

One read per step fetches (angle, velocity, spin, force, torque) and the id of every body of the
space; one write sets every body's force and torque. ``pymunk.batch`` is marked experimental by
pymunk; its public functions allocate a C struct and resolve flags on every call (about 1.5 us
each, measured), so this class keeps that struct and the C iterator between calls and calls the
same C functions directly. If a future pymunk drops those names, it falls back to the public
functions (same data, slower); ``tests/test_plugin.py`` checks both routes agree.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["BatchIO", "READ_COLUMNS", "POSE_COLUMNS", "body_uid"]

#: columns of the array :meth:`BatchIO.read` returns (pymunk.batch writes fields in this order)
READ_COLUMNS = ("angle", "vx", "vy", "spin", "fx", "fy", "torque")
#: the columns of a reader made with ``poses=True`` (the recorder's): position, angle, velocity, spin
POSE_COLUMNS = ("x", "y", "angle", "vx", "vy", "spin")


def body_uid(body: Any) -> int:
    """A pymunk body's id (a pointer, uintptr) as the int64 with the same bits, as :meth:`BatchIO.read`
    reads the ids."""
    uid = int(body.id)
    return uid - (1 << 64) if uid >= 1 << 63 else uid


class BatchIO:
    """Reader and force writer for all bodies of ``space`` (order: pymunk's iteration order); with
    ``poses`` a reader of :data:`POSE_COLUMNS` instead (its forces are not to be written)."""

    def __init__(self, space: Any, *, lean: bool = True, poses: bool = False) -> None:
        import pymunk.batch as pb

        F = pb.BodyFields
        self._pb = pb
        self._space = space
        if poses:
            self._read_fields = F.BODY_ID | F.POSITION | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY
            self._width = len(POSE_COLUMNS)
        else:
            self._read_fields = F.BODY_ID | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY | F.FORCE | F.TORQUE
            self._width = len(READ_COLUMNS)
        self._write_fields = F.FORCE | F.TORQUE
        self._gbuf = pb.Buffer()
        self._sbuf = pb.Buffer()
        self._n = -1
        if pb.ffi.sizeof("uintptr_t") != 8:  # pragma: no cover - 32-bit platforms
            raise ValueError("rrbody's PlaneFriction needs a 64-bit pymunk (uintptr_t of 8 bytes)")
        self._fptr: Any = None
        self._iptr: Any = None
        self.lean = False
        if lean:
            try:
                ffi, lib = pb.ffi, pb.lib
                self._ffi, self._lib, self._sp = ffi, lib, space._space
                self._each = lib.cpSpaceEachBody
                self._fn_get = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
                self._fn_set = ffi.addressof(lib, "pmSpaceBodySetIteratorFuncBatched")
                self._gdata = ffi.new("pmBatchedData *")
                self._gdata.fields = self._read_fields.value
                self._gdata.floatArray = self._gbuf._float_arr
                self._gdata.intArray = self._gbuf._int_arr
                self._sdata = ffi.new("pmBatchedData *")
                self._sdata.fields = self._write_fields.value
                self._sdata.intArray = self._sbuf._int_arr
                self.lean = True
            except (AttributeError, TypeError):  # pragma: no cover - depends on the pymunk version
                self.lean = False

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(got, ids, out): ``got`` (n x 7, READ_COLUMNS; n x 6, POSE_COLUMNS, for a pose reader) and ``ids``
        (n, int64 view of the uintptr ids) of every body in the space, and the (n x 3) array of (fx, fy,
        torque) that :meth:`write_forces` will set."""
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
        if n:
            self._sbuf.set_float_buf(self._out)
            if self.lean:
                self._sdata.floatArray = self._sbuf._float_arr

    def write_forces(self) -> None:
        """Set every body's force (N, at its centre of gravity) and torque (N m) from ``out``."""
        if self._n <= 0:
            return
        if self.lean:
            self._sbuf._float_arr.num = 0
            self._each(self._sp, self._fn_set, self._sdata)
        else:
            self._pb.set_space_bodies(self._space, self._write_fields, self._sbuf)
