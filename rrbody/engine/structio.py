"""The plugin's per-step read and write of its own bodies straight from their Chipmunk structs.

:class:`rrbody.engine.batchio.BatchIO` reads every body of the space through ``pymunk.batch`` and
writes every body's force back (about 15 us each way per 1,000 bodies, measured). :class:`StructIO`
reads and writes only the plugin's bodies, in the plugin's row order, at the offsets
:func:`rrbody.engine.bodymem.layout` found and checked: two compiled loops of a few loads or stores
per body. It hands :func:`rrbody.contact.kernel.plane_step` the same columns ``BatchIO`` does (angle,
vx, vy, spin, fx, fy, torque), so the kernel and its checks are the same on both routes.

:meth:`StructIO.step` makes the read, the kernel and the write one compiled call (:func:`struct_step`),
without numba's reference counting: a Python call of the kernel costs about 1 us for its
arguments alone (numba wraps each array it is handed in a counted handle; 0.15 us without), and three
calls per step cost more than the friction of a few bodies (inside gym-pusht's loop, measured: the
read 1.3 us, the kernel's call 2.4, the write 0.7, per physics step). The numbers are the kernel's:
:func:`struct_step` calls the same compiled :func:`~rrbody.contact.kernel.plane_step` on the same
arrays (``tests/test_plugin_io.py`` steps a scene both ways and compares the bits).

After an idle step the plugin's next step starts with :func:`struct_still` instead, a compiled call of
two numbers (the address of its keys, dt) that repeats that step if nothing it read has changed: at
rest, inside gym-pusht's loop, it costs about 0.3 us per physics step against 2.3 us for
:func:`struct_step`'s eighteen arguments (measured; each array argument's unboxing reads its own header).
The keys are int64 byte addresses (the bodies' structs, the space's sleeping threshold, and the data of
the reader's own record and forces, ``ndarray.ctypes.data``), made with the plugin's plan and kept alive
with it.

What it leaves to ``BatchIO`` (the plugin decides per step, :meth:`PlaneFriction.step`):

- a body no longer in the space (its struct's ``space`` field is not this space): the bulk read
  then finds it missing and the plugin refuses the step with its usual message;
- a space with sleeping enabled (``space.sleep_time_threshold`` finite): pymunk's force setter
  also wakes a sleeping body (``cpBodyActivate``), which a raw store does not; without sleeping
  that call only resets an idle timer nobody reads. The compiled call reads the threshold from the
  space's struct (:func:`rrbody.engine.bodymem.sleep_offset`, probed and checked like the body
  layout; 0.5 us less per step than pymunk's property), or :meth:`StructIO.step` reads the property
  where the probe failed;
- a pymunk whose body layout the probe could not establish (``layout()`` is None).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from rrbody.contact import kernel as K
from rrbody.contact.active import NO_ACTIVE
from rrbody.contact.body import same_bits
from rrbody.contact.lean import NO_REFCOUNT, fast_entry
from rrbody.engine.bodymem import (
    ANGLE,
    FX,
    FY,
    SPACE,
    SPIN,
    TORQUE,
    VX,
    VY,
    address,
    addresses,
    f64_at,
    i64_at,
    layout,
    set_f64,
    sleep_offset,
)

__all__ = ["StructIO", "gather", "scatter", "struct_step", "struct_still", "still_entry", "GONE", "ASLEEP", "IDLE"]

#: :func:`struct_step`'s answer when a plugin body is not in the space (nothing read is used, nothing written)
GONE = -3
#: :func:`struct_step`'s answer when the space has sleeping enabled (nothing read, nothing written)
ASLEEP = -1
#: :func:`struct_step`'s answer when it skipped plane_step as idle (forces written, no body stopped; the
#: record of what it read kept for :func:`struct_still`)
IDLE = -4


@njit(cache=True, **NO_REFCOUNT)
def gather(addr: np.ndarray, offs: np.ndarray, space: int, got: np.ndarray) -> int:
    """Row k of ``got`` (angle, vx, vy, spin, fx, fy, torque; rad, m/s, rad/s, N, N m) from the body
    struct at ``addr[k]``. Returns -1, or the first k whose body is not in ``space`` (an address)."""
    for k in range(addr.shape[0]):
        a = addr[k]
        if i64_at(a + offs[SPACE]) != space:
            return k
        got[k, 0] = f64_at(a + offs[ANGLE])
        got[k, 1] = f64_at(a + offs[VX])
        got[k, 2] = f64_at(a + offs[VY])
        got[k, 3] = f64_at(a + offs[SPIN])
        got[k, 4] = f64_at(a + offs[FX])
        got[k, 5] = f64_at(a + offs[FY])
        got[k, 6] = f64_at(a + offs[TORQUE])
    return -1


@njit(cache=True, **NO_REFCOUNT)
def scatter(addr: np.ndarray, offs: np.ndarray, out: np.ndarray) -> None:
    """Set the force (N, world frame) and torque (N m) of the body struct at ``addr[k]`` to row k of ``out``."""
    for k in range(addr.shape[0]):
        a = addr[k]
        set_f64(a + offs[FX], out[k, 0])
        set_f64(a + offs[FY], out[k, 1])
        set_f64(a + offs[TORQUE], out[k, 2])


#: the struct fields of a body in the order of a row of ``got`` (and of the snapshot, :func:`struct_still`)
_READ = (ANGLE, VX, VY, SPIN, FX, FY, TORQUE)


#: the head of :func:`struct_still`'s keys: the count n of bodies, the space's address, the address of its
#: sleeping threshold (0: not read), the byte addresses of the record's and of the forces' data (C-ordered
#: float64, n + 1 rows of 7 and n rows of 3), the count of struct offsets; then the offsets, then the n
#: bodies' addresses (:meth:`StructIO.plan` makes them)
K_N, K_SPACE, K_SLEEP, K_SNAP, K_OUT, K_NOFF, K_HEAD = range(7)


@njit(cache=True, **NO_REFCOUNT)
def struct_still(keys: int, dt: float) -> bool:
    """Whether this step is the last one again: that step was idle (:func:`struct_step` kept its read in
    its record, ``snap``), the space's sleeping is off (the threshold inf, as :func:`struct_step` reads
    it), and every plugin body is still in the space, its angle, velocity, spin, force and torque the
    same bits (a zero's sign included), with the same ``dt`` (s). Then
    :func:`~rrbody.contact.kernel.plane_idle` would say True again and write the same forces: its answer
    depends on nothing else that can change while the record stands (the rows it reads are written only
    by steps that are not idle and by the plugin's own methods, which clear the record:
    :meth:`StructIO.forget`; the plugin calls this only where no body is active). Writes the forces
    (``out``) as that step did and returns True, having read a few numbers per body and none of the
    kernel's arrays. Else returns False having changed nothing.

    ``keys`` is the byte address of an int64 array in the layout of :data:`K_HEAD`, which holds the
    addresses of everything the call reads: the plugin calls it on its own, before :func:`struct_step`
    and only after an idle step, and a call of two numbers costs less than one of many arrays (each
    array argument's unboxing reads its own header, cold inside gym-pusht's loop; measured there per
    physics step: 0.27 us steady and 1.0 us on the first step after gym-pusht's observation with the
    keys as an array, against 0.73 and 1.96 us with the seven arguments it had)."""
    n = i64_at(keys + 8 * K_N)
    snap, out = i64_at(keys + 8 * K_SNAP), i64_at(keys + 8 * K_OUT)
    offs = keys + 8 * K_HEAD  # (the address of the struct offsets)
    body = offs + 8 * i64_at(keys + 8 * K_NOFF)  # (and of the bodies' addresses)
    if f64_at(snap + 56 * n) != 1.0 or f64_at(snap + 56 * n + 8) != dt:  # (its last row: 1, dt)
        return False
    sleep_at = i64_at(keys + 8 * K_SLEEP)
    if sleep_at != 0 and f64_at(sleep_at) != math.inf:
        return False
    space = i64_at(keys + 8 * K_SPACE)
    for k in range(n):
        a = i64_at(body + 8 * k)
        if i64_at(a + i64_at(offs + 8 * SPACE)) != space:
            return False
        for c in range(7):
            if not same_bits(f64_at(a + i64_at(offs + 8 * _READ[c])), f64_at(snap + 56 * k + 8 * c)):
                return False
    for k in range(n):
        a = i64_at(body + 8 * k)
        set_f64(a + i64_at(offs + 8 * FX), f64_at(out + 24 * k))
        set_f64(a + i64_at(offs + 8 * FY), f64_at(out + 24 * k + 8))
        set_f64(a + i64_at(offs + 8 * TORQUE), f64_at(out + 24 * k + 16))
    return True


@njit(cache=True, **NO_REFCOUNT)
def struct_step(addr: np.ndarray, offs: np.ndarray, space: int, sleep_at: int, got: np.ndarray, ids: np.ndarray,
                lookup: np.ndarray, cache: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
                tables: np.ndarray, out: np.ndarray, active: np.ndarray, noise: np.ndarray, snap: np.ndarray, t: float,
                dt: float) -> int:
    """:func:`gather`, :func:`rrbody.contact.kernel.plane_step` (from the plugin's time t, s, by dt, s;
    skipped where :func:`~rrbody.contact.kernel.plane_idle` finds it would change nothing) and, if it
    stepped, :func:`scatter`, in one call. Returns plane_step's answer (the bodies the rest rule acts on, or
    -1 / -2 having written nothing), :data:`IDLE` where it skipped plane_step (its forces written, no
    body stopped), :data:`GONE` if a body is not in ``space``, or :data:`ASLEEP` if the float64 at
    address ``sleep_at`` (the space's sleeping threshold, s; 0: the caller checked it) is not inf.
    ``snap`` (n + 1 rows of 7) is the record of an idle step, for :func:`struct_still`: the rows of
    ``got`` and, in its last row, 1 and dt; its last row starts with 0 after any other step."""
    n_rows = addr.shape[0]
    snap[n_rows, 0] = 0.0
    if sleep_at != 0 and f64_at(sleep_at) != math.inf:
        return ASLEEP
    if gather(addr, offs, space, got) >= 0:
        return GONE
    if K.plane_idle(got, ids, lookup, cache, bodies, dt, out, active):
        # every body at rest and held as it was: plane_step would change nothing (its forces are in out)
        for k in range(n_rows):  # (a loop: a slice assignment needs numba's reference counting)
            for c in range(7):
                snap[k, c] = got[k, c]
        snap[n_rows, 0] = 1.0
        snap[n_rows, 1] = dt
        scatter(addr, offs, out)
        return IDLE
    # (plane_step allocates its work array: it keeps its reference counting, which needs none from here)
    n = K.plane_step(got, ids, lookup, cache, bodies, shapes, geo, tables, t, dt, out, active, noise)
    if n >= 0:
        scatter(addr, offs, out)
    return n


def still_entry() -> Any:
    """:func:`struct_still`'s compiled entry point (:func:`~rrbody.contact.lean.fast_entry`), found on the
    keys of no body and a blank record (the call says False and changes nothing)."""
    blank = np.zeros((1, 7))
    keys = np.array([0, 0, 0, blank.ctypes.data, blank.ctypes.data, 0], dtype=np.int64)
    entry, _ = fast_entry(struct_still, keys.ctypes.data, 1.0)
    return entry


class StructIO:
    """Reader and force writer for the bodies of plugin ``pf`` (a PlaneFriction), in its row order,
    through their structs. Construct it only where ``layout()`` is not None."""

    def __init__(self, pf: Any) -> None:
        offs = layout()
        if offs is None:
            raise ValueError("the body layout of this pymunk is unknown: use BatchIO")
        self._pf = pf
        self._offs = offs
        self._space = address(pf.space._space)
        off = sleep_offset()
        # where the compiled call reads the space's sleeping threshold (0: step() reads pymunk's property)
        self._sleep_at = 0 if off is None else self._space + off
        self._members = -1
        self._entry: Any = None  # struct_step's compiled entry point (fast_entry), found on the first step
        self._still_entry: Any = None  # struct_still's, found with the first plan
        self._addr = np.zeros(0, dtype=np.int64)
        self._got = np.zeros((0, 7))
        self._out = np.zeros((0, 3))
        self._snap = np.zeros((1, 7))  # struct_step's record of an idle step, for struct_still
        self._ids = np.zeros(0, dtype=np.int64)

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(got, ids, out) as :meth:`BatchIO.read` gives them, for the plugin's bodies in row order; None
        if one of them is not in the space (the caller then reads the space in bulk)."""
        if self._members != self._pf.members:
            self._relink()
        if gather(self._addr, self._offs, self._space, self._got) >= 0:
            return None
        return self._got, self._ids, self._out

    def _relink(self) -> None:
        """After the plugin's membership changed: the bodies' addresses and the arrays (O(n), once per change)."""
        pf = self._pf
        self._addr = addresses(pf.bodies_by_row)
        n = self._addr.shape[0]
        self._got = np.zeros((n, 7))
        self._out = np.zeros((n, 3))
        self._snap = np.zeros((n + 1, 7))
        self._ids = pf.row_ids.copy()
        self._members = pf.members

    def step(self, plane: tuple[np.ndarray, ...], t: float, dt: float, act: tuple[np.ndarray, np.ndarray]) -> int:
        """The plugin's step from its time ``t`` by ``dt`` (s): read, kernel and write in one call
        (:func:`struct_step`, its answer; :data:`IDLE` is a step taken). ``plane``: the plugin's own arrays
        of the kernel (id lookup, row cache, rows, shapes, geo, tables, in
        :func:`~rrbody.contact.kernel.plane_step`'s order), ``act`` the active rows and this step's noise.
        Any other negative answer wrote nothing: the plugin then takes its separate calls, which refuse the
        step, enlarge the row cache and go on, or (:data:`ASLEEP`, nothing read: a space with sleeping
        enabled) take the bulk route."""
        if self._sleep_at == 0 and self._pf.space.sleep_time_threshold != math.inf:
            return ASLEEP
        if self._members != self._pf.members:
            self._relink()
        args = (*self._head(plane), self._out, *act, self._snap, t, dt)  # (t, dt last: the plan's call appends them)
        if self._entry is None:
            self._entry, n = fast_entry(struct_step, *args)  # runs this step once
            return int(n)
        return self._entry(*args)

    def _head(self, plane: tuple[np.ndarray, ...]) -> tuple[Any, ...]:
        """:func:`struct_step`'s first arguments (this reader's, then ``plane``'s)."""
        return (self._addr, self._offs, self._space, self._sleep_at, self._got, self._ids, *plane)

    def plan(self, plane: tuple[np.ndarray, ...]) -> tuple[Any, tuple[Any, ...], tuple[Any, ...]] | None:
        """The plugin's next steps while nothing changes: (entry, args, (still, at, keys, snap, out)) with
        ``entry(*args, t, dt)`` the call :meth:`step` would make for ``plane`` (the same arrays) and no
        active bodies, and ``still(at, dt)`` the call of :func:`struct_still` on this reader's record
        (True: the step is taken, as the idle step before it; ``at`` is the address of ``keys``
        (:meth:`keys`), kept alive with ``snap`` and ``out``, whose addresses it holds). None where
        :meth:`step` must run instead: before its first call, and where the compiled calls cannot read the
        sleeping threshold themselves. Valid until the plugin's membership or any of its arrays changes
        (the plugin drops it then)."""
        if self._entry is None or self._sleep_at == 0 or self._members != self._pf.members:
            return None
        if self._still_entry is None:
            self._still_entry = still_entry()
        # the still call's address of its keys, which hold the record's and the forces' addresses: the plan
        # keeps the three arrays alive with it
        keys = self.keys()
        still = (self._still_entry, keys.ctypes.data, keys, self._snap, self._out)
        return self._entry, (*self._head(plane), self._out, *NO_ACTIVE, self._snap), still

    def keys(self) -> np.ndarray:
        """:func:`struct_still`'s keys for this reader's bodies, record and forces (valid while these
        arrays are this reader's: until its membership changes)."""
        head = [self._addr.shape[0], self._space, self._sleep_at, self._snap.ctypes.data, self._out.ctypes.data,
                self._offs.shape[0]]
        return np.concatenate((np.array(head, dtype=np.int64), self._offs, self._addr), dtype=np.int64)

    def forget(self) -> None:
        """Clear the record of the last idle step (:func:`struct_still` then says False until
        :func:`struct_step` makes one again): the plugin calls it whenever it writes a row, changes its
        arrays or steps outside :func:`struct_step`."""
        self._snap[-1, 0] = 0.0

    def write_forces(self) -> None:
        """Set every plugin body's force (N, at its centre of gravity) and torque (N m) from ``out``."""
        scatter(self._addr, self._offs, self._out)
