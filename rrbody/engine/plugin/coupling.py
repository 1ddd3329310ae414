"""The coupled step in pymunk: the plane's friction solved together with the contacts of the plugin's bodies.

After ``space.step`` the plugin reads the contacts pymunk found and solved in that step for each of its
bodies (:mod:`rrbody.engine.memory.arbiters`: through pymunk's public API, or through Chipmunk's own C functions
where a probe proves they give the same bits), groups its bodies into islands joined by contacts
(:mod:`rrbody.contact.islands`), and solves each island's velocities again with the plane's friction
inside the solve (:mod:`rrbody.contact.coupled`), from the velocity each body had before any impulse of the
step: its velocity at the step's start and the loads the plugin applied, with pymunk's own velocity update
(``space.gravity`` and ``space.damping``). The answer replaces the velocity pymunk's solver gave those
bodies; pymunk keeps everything else: positions (which it moves at the start of its next step, with its own
penetration correction, kept apart from the velocity), collision detection, its contacts' impulses as its
collision handlers saw them, joints and bodies off the plane. Why after the step and not inside pymunk's
contact solve: docs/plugin.md, "The coupled step".

An island with a dynamic body that is not on the plane, or a body held by a joint, is left as pymunk solved
it (the split step: the plane's friction applied before pymunk's solve).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from rrbody.contact import coupled as CP
from rrbody.contact import islands as I
from rrbody.engine.memory import arbiters
from rrbody.engine.memory.bodymem import addresses

__all__ = ["Coupling", "TOL", "MAX_ITER", "MAX_SWEEPS"]

#: relative tolerance of the coupled solve: each body's velocity change in a Newton iteration, over its
#: free velocity plus mu g dt (the Newton iteration converges quadratically, so the answer is far closer)
TOL = 1e-10
#: Newton iterations at most per island (a step that needs more warns, naming the body)
MAX_ITER = 60
#: projected Gauss-Seidel sweeps over an island's contact points at most per Newton iteration
MAX_SWEEPS = 500


class Coupling:
    """The plugin's coupled step for ``space`` (made by :class:`rrbody.engine.plugin.plane.PlaneFriction`):
    :meth:`after_step` runs after each ``space.step``. ``tol``, ``max_iter`` and ``max_sweeps``: see the module
    constants; ``route``: one of :data:`rrbody.engine.memory.arbiters.ROUTES`, or None for the fastest proven here."""

    def __init__(self, space: Any, *, tol: float = TOL, max_iter: int = MAX_ITER, max_sweeps: int = MAX_SWEEPS,
                 route: str | None = None) -> None:
        self.space = space
        self.tol = tol
        self.max_iter = max_iter
        self.max_sweeps = max_sweeps
        compiled = arbiters.compiled_route() if route in (None, "compiled") else None
        if route == "compiled" and compiled is None:
            raise ValueError("route 'compiled' is not available here (RRBODY_NO_PRIVATE=1, or this pymunk or "
                             "platform reads other numbers through it: rrbody.engine.memory.arbiters)")
        self._api = None if compiled is None else compiled.api
        self.route = "public" if self._api is None else "compiled"
        self._space_address = 0 if self._api is None else arbiters.space_address(space)
        self._raw = np.zeros((16, I.N_RP))
        self._body = np.zeros((0, I.N_RB))
        self._rec = np.zeros(4 + 6 * 16, dtype=np.int64)
        self._addrs = np.zeros(0, dtype=np.int64)
        self._members = -1  # the plugin's membership count the per-row arrays were made at
        self._args: tuple[Any, ...] | None = None  # the compiled route's arguments after dt (forget() drops them)
        self._count = np.zeros(1, dtype=np.int64)
        self._report = np.zeros((0, CP.N_OUT))
        self._n_isl = 0
        self._touched = False  # whether the last step solved an island
        self._told_large = False  # whether the warning for an island left for its size was given

    @property
    def last_report(self) -> np.ndarray:
        """The last step's report, a row per island (:data:`rrbody.contact.coupled.N_OUT` columns)."""
        return self._report[:self._n_isl]

    def forget(self) -> None:
        """Drop the arguments made for the plugin's arrays (they changed, or a row was written outside a step):
        made again at the next step. The per-row arrays, the Jacobian memo among them, are made again when the
        membership changes."""
        self._args = None

    def _prepare(self, bodies: list[Any], rows: np.ndarray, arrays: tuple[np.ndarray, np.ndarray, np.ndarray],
                 lookup: np.ndarray, members: int) -> None:
        """The per-row arrays for the plugin's ``bodies`` and the compiled route's arguments."""
        n = len(bodies)
        if members != self._members or self._body.shape[0] != n:
            self._body = np.zeros((n, I.N_RB))
            self._order = np.zeros(n, dtype=np.int64)
            self._vel = np.zeros((n, 3))
            self._events = np.zeros(n, dtype=np.int64)
            self._report = np.zeros((n, CP.N_OUT))
            self._n_isl = 0
            self._memo = np.zeros((n, CP.N_MEMO))
            if self._api is not None:
                self._addrs = addresses(bodies)
            self._members = members
        if self._api is not None:
            self._args = (self._api, self._space_address, self._addrs, lookup, self._rec, self._raw,
                          self._body, rows, *arrays, self.tol, self.max_iter, self.max_sweeps, self._order, self._vel,
                          self._events, self._report, self._memo)
            self._touch_args = (self._api, self._addrs, self._count)

    def after_step(self, dt: float, bodies: list[Any], slots: dict[Any, int], rows: np.ndarray,
                   arrays: tuple[np.ndarray, np.ndarray, np.ndarray], lookup: np.ndarray,
                   members: int) -> np.ndarray | None:
        """Solve again, coupled, the velocities of the plugin's bodies that touched something in the step
        just taken (``dt``, s). The plugin hands over its bodies by row (``bodies``; ``slots``: body -> row),
        their rows (:mod:`rrbody.contact.columns`), its footprint arrays (shapes, geo, tables), its sorted id
        table and its membership count (the arrays are taken as they were at the last :meth:`forget`).
        Returns None where no body was solved, else the rows of the bodies it brought to rest in this step
        (held now, moving at the step's start)."""
        if self._args is None or members != self._members:
            self._prepare(bodies, rows, arrays, lookup, members)
        if self._api is not None:
            # the cheap first look, unless something touched in the last step (it most likely touches again: the
            # whole step finds out as cheaply)
            if not self._touched and not arbiters.touching(*self._touch_args):
                return None
            while True:
                counts = arbiters.step_compiled(dt, *self._args)
                nb = counts[0]
                if nb >= 0:
                    break
                if -nb > (self._rec.shape[0] - 4) // 6:
                    self._rec = np.zeros(4 + 6 * 2 * -nb, dtype=np.int64)
                else:
                    self._raw = np.zeros((2 * -nb, I.N_RP))
                self._prepare(bodies, rows, arrays, lookup, members)
        else:
            space = self.space
            gx, gy = space.gravity
            damp = space.damping ** dt
            while True:
                n_raw = arbiters.read_public(space, bodies, slots, self._raw, self._body)
                if n_raw < 0:
                    self._raw = np.zeros((2 * -n_raw, I.N_RP))
                    continue
                if n_raw == 0:
                    self._n_isl = 0
                    return None
                counts = I.couple_islands(
                    self._raw, n_raw, self._body, rows, *arrays, dt, damp, gx, gy, self.tol, self.max_iter,
                    self.max_sweeps, self._order, self._vel, self._events, self._report, self._memo)
                arbiters.write_public(bodies, self._order[:counts[0]], self._vel)
                break
        nb, n_ev, n_isl, n_bad, n_large = counts
        self._n_isl = n_isl
        self._touched = n_isl > 0
        if n_large and not self._told_large:
            self._told_large = True  # (once per plugin: a jammed space has such islands at every step)
            warnings.warn(f"an island of more than {CP.MAX_ISLAND} touching bodies on the plane is left to the split "
                          "step (friction before pymunk's contact solve): the coupled solve of a jammed cluster costs "
                          "seconds a step (docs/plugin.md, 'The coupled step'); this is said once",
                          RuntimeWarning, stacklevel=4)
        if not nb:
            return None
        if n_bad:
            for r in self._report[:n_isl]:
                if r[CP.OUT_RESIDUAL] > self.tol:
                    k = int(r[CP.OUT_WORST])
                    name = f"pf.bodies[{list(slots).index(bodies[k])}] ({bodies[k]!r})" if k >= 0 else "(an island)"
                    warnings.warn(f"the coupled step did not converge for body {name}: its velocity still moved by "
                                  f"{r[CP.OUT_RESIDUAL]:.3g} of its scale after {int(r[CP.OUT_ITER])} Newton "
                                  f"iterations (tolerance {self.tol:g}); its velocity is the last iterate",
                                  RuntimeWarning, stacklevel=4)
        return self._events[:n_ev]
