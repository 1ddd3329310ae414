"""Where :class:`rrbody.engine.plugin.plane.PlaneFriction` keeps its bodies' footprints and wrench tables:
the kernel's ``shapes``, ``geo`` and ``tables`` arrays (:mod:`rrbody.contact.columns`), growable, with
a body's rows placed, dropped and compacted in amortised O(1), and each wrench table stored once.

A footprint is a body's parts (rows of :mod:`rrbody.physics.contact`, geometry in the body frame from
its centre of gravity, m) and their geometry block; placed, its polygon and sample ranges are shifted
to where its block lands. A wrench table (rows of 3) is named: "disk" (the disk's table,
:mod:`rrbody.physics.icr_table`, scale-free) or "footprint:" and a hash of a footprint's rows (its own
table, :mod:`rrbody.physics.footprint_table`); the process keeps every table it built or loaded
(:data:`BUILT`), and the cache folder keeps them across processes (:func:`stored`), so a shape's table
is built once per machine (and per version of the sources) and copied into each plugin that uses it.
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np

from rrbody.contact import columns
from rrbody.engine.plugin.rows import Rows
from rrbody.physics import contact as C
from rrbody.physics.footprint_table import build_footprint_table
from rrbody.physics.icr_table import build_radial_table, build_table

__all__ = ["Footprints", "BUILT", "stored"]

#: the wrench tables built in this process, by name: a few MB each, kept for the process's life
BUILT: dict[str, np.ndarray] = {}


def stored(name: str, build: Any) -> np.ndarray:
    """The wrench table ``name`` from the cache folder, or ``build()`` and stored there
    (:func:`rrbody._cache.stored_arrays`: atomic, an unreadable file built again).

    Tables live beside the compiled kernels (``rrbody._cache.kernels_dir()/tables``): a table is a
    pure function of the footprint and of the kernel sources that build and read it, which that
    folder's name hashes, so an edit to them never loads a stale table, and old tables go with old
    kernels. A file that holds no table (rows of 3 floats) is built again."""
    from rrbody._cache import kernels_dir, stored_arrays

    path = kernels_dir() / "tables" / (name.replace(":", "-") + ".npz")
    (table,) = stored_arrays(path, lambda: (np.ascontiguousarray(build(), dtype=np.float64),),
                             valid=lambda arrays: len(arrays) == 1 and arrays[0].ndim == 2
                             and arrays[0].shape[1] == 3 and arrays[0].dtype == np.float64)
    return table


class Footprints:
    """The footprints of a plugin's body rows (``rows[j]``: body row j's parts and geometry block) and
    the kernel's arrays they are placed in."""

    def __init__(self) -> None:
        self.rows: list[tuple[np.ndarray, np.ndarray]] = []  # body row -> its footprint rows and geo block
        self._shapes = Rows(C.N_SHAPE)  # every body's footprint rows, ranges shifted into ``_geo``
        self._geo = Rows(3)
        self._tables = Rows(3)  # the wrench tables the bodies use, one copy of each
        self._table_at: dict[str, int] = {}  # a table's name -> its first row in ``_tables``
        self._dead = [0, 0]  # rows of _shapes, _geo no body points to any more (compacted when many)

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The kernel's ``shapes``, ``geo`` and ``tables``: views of the rows in use (no copy)."""
        return self._shapes.view, self._geo.view, self._tables.view

    @property
    def tables(self) -> int:
        """How many distinct wrench tables this plugin holds."""
        return len(self._table_at)

    def friction_table(self, shapes: np.ndarray, geo: np.ndarray, tabulate: bool) -> tuple[float, float]:
        """(TABLE_KIND, TABLE_START) of a dry body with this footprint: one uniformly loaded disk takes the disk's
        table (as exact as its quadrature, within 1e-10, and ~6x cheaper), one ring or Hertz patch its
        profile's disk table (within 1e-10 of its closed forms); with ``tabulate`` any other
        its own table (one per distinct footprint: its rows and geometry, ranges local to it); else
        the exact wrench every step."""
        if shapes.shape[0] == 1 and shapes[0, C.KIND] == C.ELLIPSE and shapes[0, C.RADIUS_A] == shapes[0, C.RADIUS_B]:
            return columns.TABLE_CIRCLE, self._table("disk", lambda: build_table(1.0, 1.0))
        if shapes.shape[0] == 1 and shapes[0, C.KIND] in (C.RING, C.HERTZ):  # radial profiles: their own disk tables
            profile = "ring" if shapes[0, C.KIND] == C.RING else "hertz"
            return columns.TABLE_CIRCLE, self._table(profile, lambda: build_radial_table(profile))
        if tabulate:
            key = "footprint:" + hashlib.sha256(shapes.tobytes() + geo.tobytes()).hexdigest()
            return columns.TABLE_FOOTPRINT, self._table(key, lambda: build_footprint_table(shapes, geo, 0,
                                                                                           shapes.shape[0]))
        return columns.TABLE_NONE, 0.0

    def _table(self, name: str, build: Any) -> int:
        """The first row of the wrench table ``name`` in ``tables``, appended the first time it is
        asked for: from the process's tables (:data:`BUILT`), else from the cache folder
        (:func:`stored`), else built by ``build()`` and kept in both."""
        at = self._table_at.get(name)
        if at is None:
            table = BUILT.get(name)
            if table is None:
                table = BUILT[name] = stored(name, build)
            at = self._table_at[name] = self._tables.append(table)
        return at

    def place(self, j: int, bodies: np.ndarray) -> None:
        """Append body row j's footprint to ``shapes`` and ``geo``, its polygon and sample ranges shifted
        to where its geo block lands, and point the row's SHAPE_FIRST, SHAPE_END (in ``bodies``) at it."""
        sh, geo = self.rows[j]
        s0 = self._shapes.append(sh)
        if geo.shape[0]:  # polygons and samples: their vertex and rule ranges move with the block
            ng = self._geo.append(geo)
            if ng:
                rows = self._shapes.buf[s0:s0 + sh.shape[0]]
                kind = rows[:, C.KIND]
                # VERTEX_FIRST, VERTEX_END, QUAD_FIRST, QUAD_END: consecutive columns
                rows[kind == C.POLYGON, C.VERTEX_FIRST:C.QUAD_END + 1] += ng
                rows[kind == C.SAMPLED, C.QUAD_FIRST:C.QUAD_END + 1] += ng
        bodies[j, columns.SHAPE_FIRST] = s0
        bodies[j, columns.SHAPE_END] = s0 + sh.shape[0]

    def drop(self, j: int) -> None:
        """Body row j's placed rows are garbage now (the caller compacts once the rows are consistent)."""
        sh, geo = self.rows[j]
        self._dead[0] += sh.shape[0]
        self._dead[1] += geo.shape[0]

    def compact_if_sparse(self, bodies: np.ndarray) -> None:
        """Rewrite ``shapes`` and ``geo`` from the live footprints once garbage outnumbers them (plus some
        slack): O(live) work after at least as many dead rows, so O(1) amortised per add or remove."""
        live_s = self._shapes.n - self._dead[0]
        live_g = self._geo.n - self._dead[1]
        if self._dead[0] <= live_s + 64 and self._dead[1] <= live_g + 1024:
            return
        self._shapes.n = self._geo.n = 0
        self._dead = [0, 0]
        for j in range(len(self.rows)):
            self.place(j, bodies)
