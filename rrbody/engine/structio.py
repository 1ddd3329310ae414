"""The plugin's per-step read and write of its own bodies straight from their Chipmunk structs.

:class:`rrbody.engine.batchio.BatchIO` reads every body of the space through ``pymunk.batch`` and
writes every body's force back (about 15 us each way per 1,000 bodies, measured). :class:`StructIO`
reads and writes only the plugin's bodies, in the plugin's row order, at the offsets
:func:`rrbody.engine.bodymem.layout` found and checked: two compiled loops of a few loads or stores
per body. It hands :func:`rrbody.contact.kernel.plane_step` the same columns ``BatchIO`` does (angle,
vx, vy, spin, fx, fy, torque), so the kernel and its checks are the same on both routes.

What it leaves to ``BatchIO`` (the plugin decides per step, :meth:`PlaneFriction.step`):

- a body no longer in the space (its struct's ``space`` field is not this space): the bulk read
  then finds it missing and the plugin refuses the step with its usual message;
- a space with sleeping enabled (``space.sleep_time_threshold`` finite): pymunk's force setter
  also wakes a sleeping body (``cpBodyActivate``), which a raw store does not; without sleeping
  that call only resets an idle timer nobody reads;
- a pymunk whose body layout the probe could not establish (``layout()`` is None).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit

from rrbody.engine.bodymem import (ANGLE, FX, FY, SPACE, SPIN, TORQUE, VX, VY, address, addresses, f64_at, i64_at,
                                   layout, set_f64)
from rrbody.contact.lean import NO_REFCOUNT

__all__ = ["StructIO", "gather", "scatter"]


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
        self._members = -1
        self._addr = np.zeros(0, dtype=np.int64)
        self._got = np.zeros((0, 7))
        self._out = np.zeros((0, 3))
        self._ids = np.zeros(0, dtype=np.int64)

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(got, ids, out) as :meth:`BatchIO.read` gives them, for the plugin's bodies in row order; None
        if one of them is not in the space (the caller then reads the space in bulk)."""
        pf = self._pf
        if self._members != pf.members:  # membership changed: the addresses again (O(n), once per change)
            self._addr = addresses(pf._list)
            n = self._addr.shape[0]
            self._got = np.zeros((n, 7))
            self._out = np.zeros((n, 3))
            self._ids = pf._idrows.view.copy()
            self._members = pf.members
        if gather(self._addr, self._offs, self._space, self._got) >= 0:
            return None
        return self._got, self._ids, self._out

    def write_forces(self) -> None:
        """Set every plugin body's force (N, at its centre of gravity) and torque (N m) from ``out``."""
        scatter(self._addr, self._offs, self._out)
