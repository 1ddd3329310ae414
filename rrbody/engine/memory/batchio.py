"""Bulk reads and writes of a pymunk space's bodies: through ``pymunk.batch``, or body by body.

One read per step fetches (angle, velocity, spin, force, torque) and the id of every body of the
space; one write sets every body's force and torque. Two routes (:data:`ROUTES`), the same numbers
on each (``tests/test_plugin_io.py`` steps a scene on every route and compares the bits):

- ``"bulk"``: ``pymunk.batch``'s public functions (``pymunk.batch`` is marked experimental by pymunk),
  numpy views on its own buffers (docs/versions.md);
- ``"per-body"``: each body's public properties (``angle``, ``velocity``, ``angular_velocity``,
  ``force``, ``torque``; one Python call each). pymunk 6.6-6.10's ``pymunk.batch`` reads no force
  or torque and writes nothing: there a force reader takes this route. (Where the struct layout is
  proven, :mod:`rrbody.engine.memory.structio` serves the plugin's bodies on every pymunk, so this route
  only carries a space with sleeping enabled, or a pymunk whose layout the probe could not prove.)

A pose reader (``poses=True``, the recorder's) needs only positions, angles and velocities, which
``pymunk.batch`` reads from 6.6 on.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["BatchIO", "READ_COLUMNS", "POSE_COLUMNS", "ROUTES", "body_uid", "rows_of", "batch_reads"]

#: columns of the array :meth:`BatchIO.read` returns (pymunk.batch writes fields in this order)
READ_COLUMNS = ("angle", "vx", "vy", "spin", "fx", "fy", "torque")
#: the columns of a reader made with ``poses=True`` (the recorder's): position, angle, velocity, spin
POSE_COLUMNS = ("x", "y", "angle", "vx", "vy", "spin")
#: the routes to the bodies, fastest first (``BatchIO(route=...)``; :attr:`BatchIO.route` is the one taken)
ROUTES = ("bulk", "per-body")


def body_uid(body: Any) -> int:
    """A pymunk body's id (a pointer, uintptr) as the int64 with the same bits, as :meth:`BatchIO.read`
    reads the ids."""
    uid = int(body.id)
    return uid - (1 << 64) if uid >= 1 << 63 else uid


def rows_of(keys: np.ndarray, rows: np.ndarray, want: np.ndarray) -> np.ndarray:
    """The row of each id of ``want`` (:func:`body_uid`) in a table of ids ``keys`` (sorted) and their
    ``rows``; -1 where it is absent (vectorised: O(len(want) log len(keys)))."""
    out = np.full(len(want), -1, dtype=np.int64)
    if len(keys):
        pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
        hit = keys[pos] == want
        out[hit] = rows[pos[hit]]
    return out


def batch_reads(poses: bool = False) -> bool:
    """Whether this pymunk's ``pymunk.batch`` serves a reader: with ``poses``, of positions, angles and
    velocities (pymunk >= 6.6); else also of forces and torques, which it must write back too
    (pymunk >= 6.11)."""
    try:
        import pymunk.batch as pb
    except ImportError:  # a pymunk before 6.6
        return False
    if poses:
        return hasattr(pb, "get_space_bodies")
    return hasattr(pb.BodyFields, "FORCE") and hasattr(pb.BodyFields, "TORQUE") \
        and hasattr(pb, "set_space_bodies") and hasattr(pb.Buffer, "set_float_buf")


class BatchIO:
    """Reader and force writer for all bodies of ``space`` (order: pymunk's iteration order); with
    ``poses`` a reader of :data:`POSE_COLUMNS` instead (its forces are not to be written).

    ``route``: one of :data:`ROUTES`, or None for the fastest this pymunk offers. The route taken is
    :attr:`route`; a route this pymunk cannot take raises ValueError, naming it."""

    def __init__(self, space: Any, *, poses: bool = False, route: str | None = None) -> None:
        if route is not None and route not in ROUTES:
            raise ValueError(f"route must be one of {', '.join(map(repr, ROUTES))} or None, got {route!r}")
        self._space = space
        self._poses = poses
        self._width = len(POSE_COLUMNS) if poses else len(READ_COLUMNS)
        self._n = -1
        self._bodies: list[Any] = []  # the per-body route's bodies of the last read, in its row order
        batched = batch_reads(poses)
        if route is None:
            route = "bulk" if batched else "per-body"
        elif route != "per-body" and not batched:
            raise ValueError(f"route {route!r} needs a pymunk.batch that reads "
                             f"{'poses' if poses else 'and writes forces'}"
                             f" (pymunk >= {'6.6' if poses else '6.11'}); this is pymunk {_pymunk_version()}: use "
                             f"route='per-body'")
        self.route = route
        if route == "per-body":
            return
        import pymunk.batch as pb

        F = pb.BodyFields
        self._pb = pb
        if poses:
            self._read_fields = F.BODY_ID | F.POSITION | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY
            self._write_fields = None  # a pose reader writes nothing
        else:
            self._read_fields = F.BODY_ID | F.ANGLE | F.VELOCITY | F.ANGULAR_VELOCITY | F.FORCE | F.TORQUE
            self._write_fields = F.FORCE | F.TORQUE
        self._gbuf = pb.Buffer()
        self._sbuf = pb.Buffer()
        if pb.ffi.sizeof("uintptr_t") != 8:  # pragma: no cover - 32-bit platforms
            raise ValueError("rrbody's PlaneFriction needs a 64-bit pymunk (uintptr_t of 8 bytes)")
        self._fptr: Any = None
        self._iptr: Any = None

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(got, ids, out): ``got`` (n x 7, READ_COLUMNS; n x 6, POSE_COLUMNS, for a pose reader) and ``ids``
        (n, int64 view of the uintptr ids) of every body in the space, and the (n x 3) array of (fx, fy,
        torque) that :meth:`write_forces` will set."""
        if self.route == "per-body":
            return self._read_each()
        fa = self._gbuf._float_arr
        ia = self._gbuf._int_arr
        self._gbuf.clear()
        self._pb.get_space_bodies(self._space, self._read_fields, self._gbuf)
        n = ia.num
        if n != self._n or fa.arr != self._fptr or ia.arr != self._iptr:
            self._rebuild(n)
        return self._got, self._ids, self._out

    def _rebuild(self, n: int) -> None:
        """New numpy views on pymunk's arrays (after their memory moved or the body count changed)."""
        ffi = self._pb.ffi
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

    def _read_each(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`read` on the per-body route: every body of the space through its public properties."""
        bodies = list(self._space.bodies)
        n = len(bodies)
        if n != self._n:
            self._n = n
            self._got = np.zeros((n, self._width))
            self._ids = np.zeros(n, dtype=np.int64)
            self._out = np.zeros((n, 3))
        got, ids = self._got, self._ids
        for k, b in enumerate(bodies):
            ids[k] = body_uid(b)
            v = b.velocity
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
            # the bodies of the last read, in its rows (the plugin writes after reading, in the same step);
            # pymunk's setters, as pymunk.batch's writer calls them (they also wake a sleeping body)
            for b, (fx, fy, tq) in zip(self._bodies, self._out.tolist()):
                b.force = (fx, fy)
                b.torque = tq
        else:
            self._pb.set_space_bodies(self._space, self._write_fields, self._sbuf)


def _pymunk_version() -> str:
    """The installed pymunk's version as its package metadata gives it (pymunk 6.6.0 reports 6.6.2
    as ``pymunk.version``)."""
    from importlib.metadata import version

    return version("pymunk")
