"""The plugin's per-step read and write of its own bodies straight from their Chipmunk structs.

:class:`rrbody.engine.memory.batchio.BatchIO` reads every body of the space through ``pymunk.batch`` and
writes every body's force back (about 15 us each way per 1,000 bodies, measured). :class:`StructIO`
reads and writes only the plugin's bodies, in the plugin's row order, at the offsets
:func:`rrbody.engine.memory.bodymem.layout` found and checked: two compiled loops of a few loads or stores
per body. It hands :func:`rrbody.contact.kernel.plane_step` the same columns ``BatchIO`` does (angle,
vx, vy, spin, fx, fy, torque), so the kernel and its checks are the same on both routes.

:meth:`StructIO.step` makes the read, the kernel and the write one compiled call (:func:`struct_step`),
without numba's reference counting: a Python call of the kernel costs about 1 us for its
arguments alone (numba wraps each array it is handed in a counted handle; 0.15 us without), and three
calls per step cost more than the friction of a few bodies (inside gym-pusht's loop, measured: the
read 1.3 us, the kernel's call 2.4, the write 0.7, per physics step). The numbers are the kernel's:
:func:`struct_step` calls the same compiled :func:`~rrbody.contact.kernel.plane_step` on the same
arrays (``tests/test_plugin_io.py`` steps a scene both ways and compares the bits).

What it leaves to ``BatchIO`` (the plugin decides per step, :meth:`PlaneFriction.step`):

- a body no longer in the space (its struct's ``space`` field is not this space): the bulk read
  then finds it missing and the plugin refuses the step with its usual message;
- a space with sleeping enabled (``space.sleep_time_threshold`` finite): pymunk's force setter
  also wakes a sleeping body (``cpBodyActivate``), which a raw store does not; without sleeping
  that call only resets an idle timer nobody reads. The compiled call reads the threshold from the
  space's struct (:func:`rrbody.engine.memory.bodymem.sleep_offset`, probed and checked like the body
  layout; 0.5 us less per step than pymunk's property), or :meth:`StructIO.step` reads the property
  where the probe failed;
- a pymunk whose body layout the probe could not establish (``layout()`` is None).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit, typeof

from rrbody.contact import kernel as K
from rrbody.contact.columns import NO_ACTIVE
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.engine.memory.bodymem import (
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

__all__ = ["StructIO", "gather", "scatter", "struct_step", "GONE", "ASLEEP", "IDLE"]

#: :func:`struct_step`'s answer when a plugin body is not in the space (nothing read is used, nothing written)
GONE = -3
#: :func:`struct_step`'s answer when the space has sleeping enabled (nothing read, nothing written)
ASLEEP = -1
#: :func:`struct_step`'s answer when it skipped plane_step as idle (forces written, no body stopped)
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


@njit(cache=True, **NO_REFCOUNT)
def struct_step(addr: np.ndarray, offs: np.ndarray, space: int, sleep_at: int, got: np.ndarray, ids: np.ndarray,
                lookup: np.ndarray, cache: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
                tables: np.ndarray, out: np.ndarray, active: np.ndarray, noise: np.ndarray, t: float, dt: float) -> int:
    """:func:`gather`, :func:`rrbody.contact.kernel.plane_step` (from the plugin's time t, s, by dt, s;
    skipped where :func:`~rrbody.contact.kernel.plane_idle` finds it would change nothing) and, if it
    stepped, :func:`scatter`, in one call. Returns plane_step's answer (the bodies the rest rule acts on, or
    -1 / -2 having written nothing), :data:`IDLE` where it skipped plane_step (its forces written, no
    body stopped), :data:`GONE` if a body is not in ``space``, or :data:`ASLEEP` if the float64 at
    address ``sleep_at`` (the space's sleeping threshold, s; 0: the caller checked it) is not inf."""
    if sleep_at != 0 and f64_at(sleep_at) != math.inf:
        return ASLEEP
    if gather(addr, offs, space, got) >= 0:
        return GONE
    if K.plane_idle(got, ids, lookup, cache, bodies, dt, out, active):
        # every body at rest and held as it was: plane_step would change nothing (its forces are in out)
        scatter(addr, offs, out)
        return IDLE
    # (plane_step allocates its work array: it keeps its reference counting, which needs none from here)
    n = K.plane_step(got, ids, lookup, cache, bodies, shapes, geo, tables, t, dt, out, active, noise)
    if n >= 0:
        scatter(addr, offs, out)
    return n


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
        self._typed = False  # struct_step compiled for these argument types (on the first step)
        self._addr = np.zeros(0, dtype=np.int64)
        self._got = np.zeros((0, 7))
        self._out = np.zeros((0, 3))
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
        args = (*self._head(plane), self._out, *act, t, dt)  # (t, dt last: the plan's call appends them)
        if not self._typed:
            # plane_step compiled first, with its own options: numba 0.59 would compile it inside struct_step's
            # typing with struct_step's (no reference counting), which its work array needs
            K.plane_step.compile(tuple(typeof(a) for a in (self._got, self._ids, *plane, float(t), float(dt),
                                                           self._out, *act)))
            self._typed = True
        return int(struct_step(*args))

    def _head(self, plane: tuple[np.ndarray, ...]) -> tuple[Any, ...]:
        """:func:`struct_step`'s first arguments (this reader's, then ``plane``'s)."""
        return (self._addr, self._offs, self._space, self._sleep_at, self._got, self._ids, *plane)

    def plan(self, plane: tuple[np.ndarray, ...]) -> tuple[Any, tuple[Any, ...]] | None:
        """The plugin's next steps while nothing changes: (struct_step, args), ``struct_step(*args, t, dt)`` the call
        :meth:`step` would make for ``plane`` (the same arrays) and no active bodies. None where :meth:`step`
        must run instead: before its first call, and where the compiled call cannot read the sleeping
        threshold itself. Valid until the plugin's membership or any of its arrays changes (the plugin drops
        it then)."""
        if not self._typed or self._sleep_at == 0 or self._members != self._pf.members:
            return None
        return struct_step, (*self._head(plane), self._out, *NO_ACTIVE)

    def write_forces(self) -> None:
        """Set every plugin body's force (N, at its centre of gravity) and torque (N m) from ``out``."""
        scatter(self._addr, self._offs, self._out)
