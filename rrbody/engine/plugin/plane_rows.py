"""The plugin's table of bodies: which pymunk bodies feel the plane, their rows of the compiled step's
arrays, and what is read from those rows (:class:`PlaneRows`, the base of
:class:`rrbody.engine.plugin.plane.PlaneFriction`).

The rows (one per body, columns :mod:`rrbody.contact.columns`) are written only by the plugin: by
``add`` (:meth:`PlaneFriction.add_footprint`), ``remove``, the compiled step and, for a body rrbody's
builder drives, :meth:`PlaneRows.drive`. Everyone else reads them through the accessors here
(:attr:`PlaneRows.rows`, :meth:`PlaneRows.row_index`, :meth:`PlaneRows.row_of`,
:meth:`PlaneRows.rows_of_ids`): read-only views, made once per membership change, so that the hot
readers (the run loop, the recorder's capture) pay no copy and no view per step. The row order itself
(:attr:`PlaneRows.bodies_by_row`, :attr:`PlaneRows.row_ids`) is for the readers that rebuild their own
arrays once per membership change (the active bodies' rows, the struct reads' addresses).
``tests/test_private_fields.py`` checks that no other module reaches into the private fields.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.engine.memory.batchio import rows_of
from rrbody.engine.plugin.footprints import Footprints
from rrbody.engine.plugin.rows import Rows

__all__ = ["PlaneRows"]


class PlaneRows:
    """The bodies of a plane and their rows: membership, the id lookup of the compiled step, the
    read-only accessors and the readers of a body's friction and velocity. Amortised O(1) per body
    added or removed (arrays that double their capacity)."""

    def __init__(self) -> None:
        #: the plugin's steady step (StructIO.plan: its compiled call and its arguments), or None;
        #: dropped (_unplan) by every change of the arrays or the membership and every write of a row
        #: outside a step, made again by the next step
        self._plan: tuple[Any, tuple[Any, ...]] | None = None
        self._slots: dict[Any, int] = {}  # body -> row; its keys keep the order bodies were added in
        self._list: list[Any] = []  # row -> body
        self._rows = Rows(K.N_BODY)  # the kernel's ``bodies`` rows
        self._idrows = Rows(None, np.int64)  # row -> the body's id (int64 view of pymunk's uintptr)
        self._feet = Footprints()  # the footprints and wrench tables: the kernel's shapes, geo, tables
        self._geo = self._feet.rows  # row -> its footprint rows and geo block
        self._views()
        self._dirty = True  # membership changed: the id lookup is rebuilt at the next step
        self.members = 0  # counts membership changes (readers such as the recorder cache rows by it)
        self._k_lookup = np.zeros((2, 0), dtype=np.int64)
        self._cache = np.zeros((3, 16), dtype=np.int64)  # the kernel's row cache (kernel.plane_check)

    @property
    def bodies(self) -> tuple[Any, ...]:
        """The bodies that feel the plane's friction, in the order they were added."""
        return tuple(self._slots)

    def _views(self) -> None:
        """The kernel's arrays: views of the rows in use (no copy)."""
        self._unplan()  # the plugin's steady step holds the old arrays: made again at the next step
        self._bodies = self._rows.view
        self._k_shapes, self._k_geo, self._k_tables = self._feet.arrays
        # the readers' view (rows): made once per change here, so that a hot reader pays no view per call
        self._read_only = self._bodies.view()
        self._read_only.flags.writeable = False

    def _relink(self) -> None:
        """After adds or removals: the sorted id -> row table, and a reset of the kernel's row cache."""
        ids = self._idrows.view
        order = np.argsort(ids, kind="stable")
        self._k_lookup = np.ascontiguousarray(np.vstack([ids[order], order.astype(np.int64)]))
        self._cache[K.ROW_ID] = 0  # ids are pointers, never 0: every cached row is looked up again
        self._dirty = False
        self._unplan()

    def _unplan(self) -> None:
        """Drop the plugin's steady step (the plugin also drops its coupled step's arguments)."""
        self._plan = None

    # ---- read-only accessors -------------------------------------------------------------------
    @property
    def rows(self) -> np.ndarray:
        """Every body's row of the compiled step's ``bodies`` array, (bodies, N_BODY), columns
        :mod:`rrbody.contact.columns` (SI units; world frame unless a column says the body frame): a
        read-only view, live (the step updates it in place) until the next ``add`` or ``remove`` (they
        may move it: ``members`` counts them), then read it again. Row order is not the order of
        :attr:`~rrbody.engine.plugin.plane_rows.PlaneRows.bodies`: :meth:`row_index` gives a body's row."""
        return self._read_only

    @property
    def bodies_by_row(self) -> tuple[Any, ...]:
        """The bodies in row order: ``bodies_by_row[j]`` owns row ``j`` of :attr:`rows`. A new tuple (O(n)):
        for readers that rebuild something once per membership change (``members`` counts them), not per
        step; valid until the next ``add`` or ``remove``."""
        return tuple(self._list)

    @property
    def row_ids(self) -> np.ndarray:
        """Each row's body id (int64, :func:`rrbody.engine.memory.batchio.body_uid`), in row order: a read-only
        view (no copy), valid until the next ``add`` or ``remove``."""
        ids = self._idrows.view.view()
        ids.flags.writeable = False
        return ids

    def row_index(self, body: Any) -> int | None:
        """``body``'s row in :attr:`rows`, or None if it is not in the plugin (O(1)); valid until the
        next ``add`` or ``remove``."""
        return self._slots.get(body)

    def row_of(self, body: Any) -> np.ndarray:
        """``body``'s row of :attr:`rows` (a read-only view, N_BODY numbers, :mod:`rrbody.contact.columns`).
        Raises KeyError for a body not in the plugin."""
        return self._read_only[self._slots[body]]

    def rows_of_ids(self, ids: np.ndarray) -> np.ndarray:
        """The row in :attr:`rows` of each body id of ``ids`` (int64, :func:`rrbody.engine.memory.batchio.body_uid`),
        -1 for a body not in the plugin: one vectorised look-up in the step's own sorted id table
        (built again here if the membership changed since the last step)."""
        if self._dirty:
            self._relink()
        return rows_of(self._k_lookup[0], self._k_lookup[1], np.asarray(ids, dtype=np.int64))

    def drive(self, body: Any, *, omega: float, d: float, anchor: tuple[float, float], t0: float) -> None:
        """Mark plugin body ``body`` as held at its point P (``anchor``, body frame, m) by rrbody's circular
        driver (P on the circle of radius ``d``, m, about the origin at ``omega`` rad/s, from the plugin's
        time ``t0``, s): the compiled step then computes the driver's state with the friction (columns
        DRIVE_PX..DRIVE_VY, :meth:`drive_target`). For rrbody's builder; a user's joints need none."""
        self._bodies[self._slots[body], [K.DRIVEN, K.DRIVE_OMEGA, K.DRIVE_D, K.ANCHOR_X, K.ANCHOR_Y,
                                         K.DRIVE_T0]] = 1.0, omega, d, *anchor, t0
        self._unplan()  # a row written outside a step: the record of the last idle step no longer holds

    def drive_target(self, body: Any) -> list[float]:
        """Where the step just computed that the driver of a driven ``body`` (:meth:`drive`) must go: [x, y,
        vx, vy] of P at the step's end (m, m/s, world frame), a copy. Read before each ``space.step`` by
        rrbody's builder (one index into the rows, no view: it runs every step)."""
        return self._bodies[self._slots[body], K.DRIVE_PX:K.DRIVE_VY + 1].tolist()

    def step_arrays(self) -> tuple[np.ndarray, ...]:
        """Copies of the compiled step's own arrays (id lookup, row cache, rows, shapes, geo, tables), in
        :func:`rrbody.contact.kernel.plane_step`'s order, for timing the compiled call apart from the
        plugin (benchmarks/active.py): writing them changes nothing of the plugin."""
        if self._dirty:
            self._relink()
        return tuple(np.ascontiguousarray(a).copy() for a in (self._k_lookup, self._cache, self._bodies,
                                                               self._k_shapes, self._k_geo, self._k_tables))

    # ---- readers ---------------------------------------------------------------------------------
    def held_foot(self, body: Any) -> int | None:
        """For a body on point feet (``pressure=rrbody.pressure.points(...)``, two or more): the index of
        the foot static friction held at rest in the last step, the body turning about it (docs:
        Contacts, "Pivoting on a foot"); None while every foot slides, or at rest."""
        pin = int(self._bodies[self._slots[body], K.PINNED_FOOT])
        return pin - 1 if pin > 0 else None

    def velocity(self, body: Any) -> tuple[float, float, float]:
        """(vx, vy, spin) of ``body``'s centre of gravity at the plugin's time ``t`` (m/s, rad/s).

        pymunk's ``body.velocity`` after a step belongs to t + dt/2 (the staggered scheme); this is the
        mean of it and the velocity before the step, second-order accurate at t."""
        j = self._slots[body]
        v = body.velocity
        w = body.angular_velocity
        p = self._bodies[j]
        if p[K.PREV_GAP] <= 0.0 or p[K.STAGGERED] == 0.0:
            return float(v.x), float(v.y), float(w)
        if p[K.STOP] > 0.0 and v.x == 0.0 and v.y == 0.0 and w == 0.0:
            # the rest rule stopped it within the last step and nothing is left: at rest at t (the mean
            # below would still hold half the velocity read at that step's start)
            return 0.0, 0.0, 0.0
        return 0.5 * (p[K.PREV_VX] + v.x), 0.5 * (p[K.PREV_VY] + v.y), 0.5 * (p[K.PREV_SPIN] + w)

    def friction(self, body: Any) -> tuple[float, float, float]:
        """The friction the last ``step`` applied to ``body``: force (N, world frame) at its centre of
        gravity and torque about it (N m), static friction and the rest rule's stopping impulse
        included (zeros before the first step). Its product with the velocity is the friction power."""
        p = self._bodies[self._slots[body]]
        return float(p[K.FRICTION_FX]), float(p[K.FRICTION_FY]), float(p[K.FRICTION_TORQUE])

    def wrench(self, body: Any, velocity: tuple[float, float, float] | None = None,
               angle: float | None = None) -> tuple[float, float, float]:
        """The friction force (N, world frame) and torque about the centre of gravity (N m) on ``body``
        at its current angle and velocity, or at the given ones (no rest rule, no limiter)."""
        j = self._slots[body]
        v = body.velocity
        vx, vy, w = (float(v.x), float(v.y), float(body.angular_velocity)) if velocity is None else velocity
        a = float(body.angle) if angle is None else float(angle)
        ax, ay, aw = K.body_accel(j, a, vx, vy, w, self._bodies, self._k_shapes, self._k_geo, self._k_tables)
        m = self._bodies[j, K.MASS]
        return m * ax, m * ay, m * self._bodies[j, K.INERTIA_PER_MASS] * aw
