"""PlaneFriction: Coulomb friction from a horizontal plane on the bodies of any pymunk program.

::

    space = pymunk.Space()                        # a top-down space: no gravity
    pf = PlaneFriction(space, g=9.81)
    pf.add(body, mu=0.4)                          # a body you built, with its own shapes
    while running:
        pf.step(1 / 120)                          # instead of space.step(1 / 120)

The friction of each body is integrated over the area of its own shapes (circles, polygons,
segments with a radius, several per body), each shape pressing with its own weight over its area
(centred on the centre of gravity: docs/plugin.md): exact for circles and convex polygons, or
under a pressure distribution you choose (``pf.add(body, mu=0.4, pressure=rrbody.pressure.ring(0.05))``:
a rim, an annulus, a Hertz patch, feet, any p(x, y); :mod:`rrbody.physics.contact`).
One compiled call per step reads every body (from their structs, :mod:`rrbody.engine.memory.structio`; else
through ``pymunk.batch``), computes all wrenches and writes the forces back; then ``space.step`` runs. The contract
(what is read, when it acts, what is guaranteed at rest) is in docs/plugin.md.

The plugin's table of bodies, and the read-only accessors through which the rest of rrbody reads
their rows, are its base class :class:`rrbody.engine.plugin.plane_rows.PlaneRows`; what ``add`` checks and
writes for a new body is :mod:`rrbody.engine.plugin.admit`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.contact.columns import NO_ACTIVE
from rrbody.engine.memory.batchio import BatchIO, body_uid
from rrbody.engine.memory.bodymem import layout
from rrbody.engine.memory.structio import IDLE, StructIO
from rrbody.engine.plugin.active import ActiveSet
from rrbody.engine.plugin.admit import FRICTION_METHODS, add_law, body_row, check_body, half_kick, not_finite
from rrbody.engine.plugin.coupling import MAX_ITER as COUPLED_MAX_ITER
from rrbody.engine.plugin.coupling import TOL as COUPLED_TOL
from rrbody.engine.plugin.coupling import Coupling
from rrbody.engine.plugin.plane_rows import PlaneRows
from rrbody.engine.plugin.shapes import body_footprint
from rrbody.model.active import Active
from rrbody.model.checks import check, check_choice
from rrbody.model.friction import check_mu_static
from rrbody.model.laws import bound_params, zero_speed_mu
from rrbody.model.pressure import PRESSURE_KINDS, Pressure, as_pressure
from rrbody.physics.footprint import Footprint

__all__ = ["PlaneFriction", "PRESSURES", "SCHEMES", "Active"]

_INF = math.inf  # (a module constant: the hot path's dt check reads no attribute of math)

#: normal-pressure profiles PlaneFriction.add accepts (rrbody.pressure; or their text form, "ring:0.05")
PRESSURES: tuple[str, ...] = PRESSURE_KINDS
#: how a step treats the plane's friction and pymunk's contacts: solved together (the default), or friction
#: first and pymunk's contact solve after (exact only for bodies that touch nothing: docs/plugin.md)
SCHEMES: tuple[str, ...] = ("coupled", "split")


class PlaneFriction(PlaneRows):
    """Dry friction of a horizontal plane under the bodies of one ``pymunk.Space``.

    Parameters
    ----------
    space : pymunk.Space
        The user's space. Its gravity and damping stay the user's business (a top-down space has
        neither); the plane's weight enters only through ``g``.
    g : float
        Gravitational acceleration, m/s^2, > 0.
    tilt : float
        The plane's angle from the horizontal, rad, in [0, pi/2) (default 0). On a tilted plane the
        bodies press with m g cos(tilt), and gravity's in-plane part m g sin(tilt) pulls each one at
        its centre of gravity toward ``downhill``. Bodies are taken as thin and flat: the in-plane pull
        tips nothing and leaves the pressure distribution as it is.
    downhill : float
        Direction of steepest descent in the space's coordinates, rad from the x axis (default 0).
    scheme : str
        ``"coupled"`` (the default): a body that touches something in a step gets its velocity from the
        plane's friction and its contacts solved together, implicitly (:mod:`rrbody.engine.plugin.coupling`);
        ``"split"``: friction is applied first and pymunk's contact solve runs after it, which is exact
        only where no step's friction could stop a body (bodies that touch nothing, or move fast).
        Bodies that touch nothing step the same way under both.
    tol : float
        The coupled solve's relative tolerance, in (0, 1e-3] (default 1e-10): each body's velocity change
        in a Newton iteration over its free velocity plus mu g dt.
    max_iter : int
        Newton iterations at most per island and step, in [1, 10000] (default 60); a solve that needs
        more warns (RuntimeWarning) naming the body and the change left, and keeps its last iterate.

    Notes
    -----
    ``add`` and ``remove`` cost O(1) amortised whatever the number of bodies (arrays that double their
    capacity; a removed body's row is replaced by the last one), so bodies can come and go one by one
    in scenes of 10^4 bodies. A body removed from the space must be removed from the plugin as well
    (``pf.remove(body)``): ``step`` raises ``ValueError`` naming a body that is no longer in the space,
    and one whose angle, velocity or spin is not finite, before it changes anything.
    """

    _act: ActiveSet | None = None  # the active bodies (activate), made on the first use

    def __init__(self, space: Any, g: float = 9.81, *, tilt: float = 0.0, downhill: float = 0.0,
                 scheme: str = "coupled", tol: float = COUPLED_TOL, max_iter: int = COUPLED_MAX_ITER) -> None:
        import pymunk

        if not isinstance(space, pymunk.Space):
            raise ValueError(f"space must be a pymunk.Space, got {space!r}")
        self.g = float(check("g", g))
        self.tilt = float(check("tilt", tilt))
        self.downhill = float(check("downhill", downhill))
        self.scheme = check_choice("scheme", scheme, SCHEMES)
        if not (isinstance(tol, (int, float)) and 0.0 < tol <= 1e-3):
            raise ValueError(f"tol must be in (0, 0.001], got {tol!r}")
        if not (isinstance(max_iter, int) and not isinstance(max_iter, bool) and 1 <= max_iter <= 10000):
            raise ValueError(f"max_iter must be an integer in [1, 10000], got {max_iter!r}")
        self.space = space
        # the normal load per unit mass, and gravity's pull along the plane (m/s^2, world frame)
        self._g_normal = self.g * math.cos(self.tilt)
        pull = self.g * math.sin(self.tilt)
        self._g_plane = (pull * math.cos(self.downhill), pull * math.sin(self.downhill))
        self._io = BatchIO(space)
        # reads and writes through the plugin bodies' own structs, where pymunk's layout is known
        self._sio = StructIO(self) if layout() is not None else None
        super().__init__()  # the table of bodies and their rows (rrbody.engine.plugin.plane_rows)
        self.pre_step: list[Any] = []  # callables f(dt) run after friction is set, before space.step (builder)
        self._fresh: set[Any] = set()
        self.t = 0.0  # s: time advanced by step (compensated sum)
        self._tc = 0.0
        self.n_stopped = 0  # stops made by the rest rule so far
        self._t_stop: dict[Any, float] = {}
        self._coupling = Coupling(space, tol=float(tol), max_iter=max_iter) if self.scheme == "coupled" else None
        self._dt = math.nan  # the last step's dt (s): a step of another size first moves the staggered velocities

    # ---- membership --------------------------------------------------------------------------
    def add(self, body: Any, *, mu: float, pressure: Pressure | str = "uniform", mu_static: float | None = None,
            friction_method: str = "auto", law: str = "dry", params: Mapping[str, float] | None = None) -> None:
        """Give ``body`` (dynamic, already in the space, with at least one shape of positive area)
        friction coefficient ``mu`` (>= 0) against the plane, its weight pressing on it as
        ``pressure`` says (:mod:`rrbody.pressure`: each shape's weight over its area, the default; a ring, an
        annulus, a Hertz patch, feet, or your own p(x, y); positions in the body frame from its centre
        of gravity, m; also the text form, e.g. ``"ring:0.05"``). ``mu_static`` (>= mu, default mu):
        a body at rest stays exactly at rest while the load on it (your forces and torques, gravity
        on a tilted plane) lies inside its contact's limit surface for mu_static, and breaks away in
        the step it leaves it, sliding as the maximum-dissipation rule says (docs: Contacts).
        ``friction_method``: "auto" (the exact wrench of the footprint each step; a body that is one
        disk, uniformly loaded, a ring or a Hertz patch, takes that profile's disk table, as exact) or
        "table" (the footprint's own wrench table, :mod:`rrbody.physics.footprint_table`: within 1e-10
        of the exact wrench, several times cheaper per step for polygons, built once per distinct
        footprint in about a second: for many bodies of few shapes). ``law``: the friction law, one of the law
        table's with a friction coefficient (:mod:`rrbody.model.laws`; "dry", the default), and ``params`` its
        further parameters by name (dry friction has none). Its mass is ``body.mass`` (from the
        shapes' density or mass, or set by you), its shapes' geometry is read now: call ``add``
        again after changing either. The body's current velocity is its velocity at the next step's
        start time (the first step gives it the half kick of the staggered scheme).

        Raises ValueError naming the body for a mass or moment that is not positive and finite, for a
        position, angle, velocity or spin that is not finite, and for a centre of gravity no non-negative
        pressure holds (it would tip); naming the law for one the table does not have, or has no form for
        a footprint or the friction_method (:func:`rrbody.engine.plugin.admit.add_law`). Amortised O(1): no copy of
        the other bodies' data."""
        check_body(body, self.space, self._name)
        mu = float(check("mu", mu))
        method = check_choice("friction_method", friction_method, FRICTION_METHODS)
        spec, lp = add_law(law, params, method, mu_static)
        mu0 = zero_speed_mu(spec.name, mu, lp)  # the law's coefficient at zero speed: static friction's floor
        mu_s = mu0 if mu_static is None else check_mu_static(mu_static, mu0, name=spec.rest or "mu")
        footprint = body_footprint(body, as_pressure(pressure), name=self._name, table=method == "table")
        g_n = self._g_normal
        self.add_footprint(body, law=K.LAW_CODE[spec.name], coeff=mu * g_n, footprint=footprint, snap=True,
                           history=None, static=mu_s * g_n if spec.sticks else 0.0, tabulate=method == "table",
                           params=bound_params(spec.name, lp, g_n)[:len(spec.params)])

    def _name(self, body: Any) -> str:
        """``pf.bodies[k] (repr)`` for messages (O(n): error paths only)."""
        if body in self._slots:
            return f"pf.bodies[{list(self._slots).index(body)}] ({body!r})"
        return repr(body)

    def add_footprint(self, body: Any, *, law: float, coeff: float, footprint: Footprint, snap: bool,
                      history: tuple[float, float, float, float] | None, v_eps: float = 0.0,
                      staggered: bool = True, static: float | None = None, tabulate: bool = False,
                      params: tuple[float, ...] = ()) -> None:
        """``add`` with the friction law and footprint already made (rrbody's builder, benchmarks), the body
        unchecked: any law of the law table with a plugin form (K.LAW_DRY with ``coeff`` mu g cos(tilt) in
        m/s^2, K.LAW_VISCOUS with gamma in 1/s; ``params`` its further parameters per unit mass, if it has
        any; another law is a ValueError naming it, :func:`rrbody.engine.plugin.admit.check_law`) and footprint
        (:mod:`rrbody.engine.plugin.shapes`, a point mass, sampled elements); ``snap`` False leaves
        the rest rule to the joint that holds a driven body; ``history`` = (vx, vy, spin, gap) (m/s,
        rad/s, s) when the caller has made the half kick; ``v_eps`` the speed under which the body
        counts as at rest (m/s); ``staggered`` False for a body stepped without the half-step
        velocity; ``static`` mu_static g cos(tilt) (m/s^2; default: coeff for dry friction, none for
        viscous, 0 switches static friction off); ``tabulate``: dry friction from the footprint's wrench
        table. A body already in the plugin is read again in place."""
        shapes, geo = footprint[0], footprint[1]
        row = body_row(body, law=law, coeff=coeff, footprint=footprint, snap=snap, history=history, v_eps=v_eps,
                       staggered=staggered, static=static, g_plane=self._g_plane, feet=self._feet, tabulate=tabulate,
                       params=params)
        j = self._slots.get(body)
        if j is None:
            j = self._rows.append_one(row)
            self._idrows.append_one(body_uid(body))
            self._slots[body] = j
            self._list.append(body)
            self._geo.append((shapes, geo))
            self._dirty = True
            self.members += 1
        else:  # re-read: the old footprint rows become garbage (compacted when they outnumber the live ones)
            self._feet.drop(j)
            self._rows.buf[j] = row
            self._geo[j] = (shapes, geo)
        self._feet.place(j, self._rows.buf)
        self._feet.compact_if_sparse(self._rows.buf)
        self._views()
        if history is None:
            self._fresh.add(body)
        else:
            self._fresh.discard(body)

    def remove(self, body: Any) -> None:
        """Stop applying friction to ``body`` (it stays in the space). Call it before or after
        ``space.remove(body, ...)``: the plugin refuses to step with a body that left the space.
        Amortised O(1) (the last row moves into the removed one's place)."""
        if body not in self._slots:
            raise ValueError(f"body is not in this PlaneFriction, got {body!r}")
        j = self._slots.pop(body)
        self._feet.drop(j)
        last = self._rows.n - 1
        if j != last:
            moved = self._list[last]
            self._rows.buf[j] = self._rows.buf[last]
            self._idrows.buf[j] = self._idrows.buf[last]
            self._list[j] = moved
            self._geo[j] = self._geo[last]
            self._slots[moved] = j  # an existing key: its place in the order of addition is kept
        self._list.pop()
        self._geo.pop()
        self._rows.n -= 1
        self._idrows.n -= 1
        self._feet.compact_if_sparse(self._rows.buf)
        self._views()
        self._fresh.discard(body)
        self._t_stop.pop(body, None)
        self._dirty = True
        self.members += 1

    # ---- stepping ----------------------------------------------------------------------------
    def _kick(self, dt: float) -> None:
        """Half kick of newly added bodies: their velocity becomes the one at t + dt/2."""
        for body in self._fresh:
            half_kick(body, self._slots[body], dt, self._g_plane, self._bodies, self._k_shapes, self._k_geo,
                      self._k_tables)
        self._fresh.clear()

    def step(self, dt: float) -> None:
        """Apply one step of friction to every body of the plugin, then ``space.step(dt)`` (dt in s).

        Use it in place of ``space.step``: a plain ``space.step`` advances the space without friction.
        Forces you set on a body before the call (``body.force``, ``apply_force_at_...``) act as usual.

        Raises ValueError, and changes nothing (no friction, no ``space.step``), naming the first body
        of the plugin that is no longer in the space (remove it from the plugin too: ``pf.remove(body)``)
        or whose angle, velocity or spin is not finite. The check is part of the compiled step; positions,
        which the step does not read, are checked by ``add``.
        """
        try:
            ok = 0.0 < dt < _INF  # (also refuses NaN; no check helper: this is the hot path)
        except TypeError:  # not a number
            ok = False
        if not ok:
            raise ValueError(f"dt must be a number > 0 s and finite, got {dt!r}")
        dt = float(dt)
        if dt != self._dt and self._list:
            self._resync(dt)
        self._dt = dt
        plan = self._plan
        if not self._list:
            if self._dirty:
                self._relink()
            n_flag = None  # no bodies: no friction, no pre_step callbacks
        elif plan is not None:
            # the steady step: the compiled call with the arguments the last step built (inside
            # gym-pusht's loop, building them in Python cost as much as the table's work at rest)
            n_flag = plan[0](*plan[1], self.t, dt)
            if n_flag == IDLE:  # nothing to do: every body at rest and held as it was
                n_flag = 0
            elif n_flag < 0:  # sleeping turned on, a body gone, the check failed (drops the plan)
                n_flag = self._step_apart(dt, NO_ACTIVE)
        else:
            n_flag = self._step_first(dt)
        stopping = None
        if n_flag is not None:
            if self.pre_step:
                for f in self.pre_step:
                    f(dt)
            if n_flag:
                stopping = self._rest()
        self.space.step(dt)
        if self._coupling is not None and self._list:
            self._couple(dt)
        if stopping:
            self._stops(stopping, dt)
        y = dt - self._tc
        t = self.t + y
        self._tc = (t - self.t) - y
        self.t = t

    def _step_first(self, dt: float) -> int:
        """A step with no plan: the one compiled call with arguments made now (then the plan for the next
        steps, where no body is active), or the separate calls. Returns the count of bodies the rest rule
        acts on."""
        if self._dirty:
            self._relink()
        # the common step (no half kick due; the bodies' structs, where sleeping is off): one compiled call
        acts = self._act
        if self._sio is None or self._fresh or (acts is not None and acts.pending):
            return self._step_apart(dt, None)
        act = NO_ACTIVE if acts is None else acts.arrays(self)
        arrays = (self._k_lookup, self._cache, self._bodies, self._k_shapes, self._k_geo, self._k_tables)
        n_flag = self._sio.step(arrays, self.t, dt, act)
        if n_flag < 0 and n_flag != IDLE:  # a step the compiled call does not take: the separate calls
            return self._step_apart(dt, act)
        if acts is None:  # the next steps: the same call, until something changes (_unplan)
            self._plan = self._sio.plan(arrays)
        return 0 if n_flag == IDLE else n_flag

    def _unplan(self) -> None:
        """Drop the steady step and the coupled step's arguments: every change of the plugin's arrays or
        membership, every write of a row outside a step, every step outside the one call."""
        super()._unplan()
        coupling = getattr(self, "_coupling", None)
        if coupling is not None:
            coupling.forget()

    # ---- active bodies (rrbody.engine.plugin.active) -------------------------------------------------
    def activate(self, body: Any, active: Active | None) -> None:
        """Make plugin body ``body`` self-propelled as ``active`` says (:class:`rrbody.plugin.Active`: a
        force fixed in the body frame at a body point, a medium's drag, Langevin noise; docs/active.md),
        or, with None, no longer. Its mass and moment are read at the next step (call ``activate`` again
        after changing them). The propulsion and drag act as loads, like your own forces: friction,
        its rest rule and static friction see them. Raises ValueError for a body not in the plugin."""
        if body not in self._slots:
            raise ValueError(f"body must be added to the PlaneFriction first (pf.add(body, mu=...)), got {body!r}")
        if self._act is None:
            self._act = ActiveSet()
        self._act.set(body, active)
        self._unplan()  # the active bodies' arrays and noise are drawn each step

    def seed(self, seed: int) -> None:
        """Restart the active bodies' noise from ``seed`` (integer in [0, 2^63 - 1]; the default is 0):
        the same seed and the same program give bit-identical runs."""
        if self._act is None:
            self._act = ActiveSet(seed)
        else:
            self._act.seed(seed)
        self._unplan()

    def _step_apart(self, dt: float, act: tuple[np.ndarray, np.ndarray] | None) -> int:
        """The step's read, half kicks, compiled step and write as separate calls (the bulk read, half kicks
        due, or a step :meth:`StructIO.step` handed back); ``act``: this step's active rows and noise if they
        were drawn already. Returns the kernel's count of bodies the rest rule acts on; raises the
        refusal's ValueError having changed nothing."""
        self._unplan()  # a step outside struct_step: its record of an idle step no longer holds
        io, read = self._route()
        got, ids, out = read
        if self._fresh:
            # the half kicks change velocities: check every body first, so a refused step changes nothing
            self._grow_caches(got.shape[0])
            if not K.plane_check(got, ids, self._k_lookup, self._cache, self._rows.n):
                self._refuse(got)
            self._kick(dt)
            got, ids, out = io.read()
        if self._act is not None and self._act.pending:  # newly active bodies: their half kick, checked first
            self._grow_caches(got.shape[0])
            if not K.plane_check(got, ids, self._k_lookup, self._cache, self._rows.n):
                self._refuse(got)
            self._act.kick(self, dt)
            got, ids, out = io.read()
        if act is None:
            act = NO_ACTIVE if self._act is None else self._act.arrays(self)
        args = (got, ids, self._k_lookup, self._cache, self._bodies, self._k_shapes, self._k_geo, self._k_tables,
                self.t, dt, out, *act)
        n_flag = K.plane_step(*args)
        if n_flag < 0:  # rare: the space grew past the caches, or the check failed
            if n_flag == -2:
                self._grow_caches(got.shape[0])
                n_flag = K.plane_step(got, ids, self._k_lookup, self._cache, *args[4:])
            if n_flag < 0:
                self._refuse(got)
        io.write_forces()
        return n_flag

    def _route(self) -> tuple[Any, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """This step's reader and writer and its first read: the plugin bodies' structs
        (:mod:`rrbody.engine.memory.structio`) where it is safe, else the space's bulk read (which also finds
        a body that left the space, for the refusal): a space with sleeping (a raw store would not
        wake a sleeping body, as pymunk's setter does), or a body not in the space."""
        if self._sio is not None and self.space.sleep_time_threshold == math.inf:
            read = self._sio.read()
            if read is not None:
                return self._sio, read
        return self._io, self._io.read()

    def _grow_caches(self, n: int) -> None:
        """Room in the kernel's row cache for ``n`` bodies of the space (doubling: amortised O(1))."""
        if n > self._cache.shape[1]:
            self._cache = np.zeros((3, max(n, 2 * self._cache.shape[1])), dtype=np.int64)  # ROW_ID 0: all stale
            self._unplan()

    def _refuse(self, got: np.ndarray) -> None:
        """Raise the ValueError for what :func:`rrbody.contact.kernel.plane_check` found (error path only)."""
        n_bad, i = int(self._cache[K.STATUS, K.BAD]), int(self._cache[K.STATUS, K.FIRST_BAD])
        if n_bad:
            a, vx, vy, w = got[i, :4].tolist()
            more = f" (and {n_bad - 1} more bodies)" if n_bad > 1 else ""
            raise ValueError(f"body {self._name(self._list[int(self._cache[K.ROWMAP, i])])}: "
                             f"{not_finite(None, a, (vx, vy), w)}{more}; the step was refused and nothing "
                             f"changed: give the body a finite state, or pf.remove(body)")
        gone = [b for b in self._slots if b.space is not self.space]
        more = f" (and {len(gone) - 1} more bodies)" if len(gone) > 1 else ""
        raise ValueError(f"body {self._name(gone[0])} is no longer in the space but still in this PlaneFriction"
                         f"{more}; the step was refused and nothing changed: call pf.remove(body) when you "
                         f"remove a body from the space")

    def _resync(self, dt: float) -> None:
        """A step of another size than the last: each body's velocity, which belongs to half the last step
        after it, moved to half this step after it with the acceleration it had (the friction and the loads
        the last step applied, and the space's gravity): (dt - gap) / 2 times it. pymunk moves the pose with
        the velocity first, so without this a step that changes size would move it with a velocity of
        another time (an error of order dt per change, which a step of alternating sizes piles up). A body
        the rest rule stopped, one with no history yet and a driven body (its driver keeps pace) are left."""
        rows = self._bodies
        gap = rows[:, K.PREV_GAP]
        shift = np.where((gap > 0.0) & (rows[:, K.STAGGERED] > 0.0) & (rows[:, K.STOP] == 0.0)
                         & (rows[:, K.DRIVEN] == 0.0), 0.5 * (dt - gap), 0.0)
        moved = np.flatnonzero(shift)
        if not moved.size:
            return
        gx, gy = self.space.gravity
        for j in moved.tolist():
            body, k, r = self._list[j], shift[j], rows[j]
            m = r[K.MASS]
            v = body.velocity
            body.velocity = (v.x + k * (gx + (r[K.FRICTION_FX] + r[K.LOAD_FX]) / m),
                             v.y + k * (gy + (r[K.FRICTION_FY] + r[K.LOAD_FY]) / m))
            body.angular_velocity += k * (r[K.FRICTION_TORQUE] + r[K.LOAD_TORQUE]) / (m * r[K.INERTIA_PER_MASS])

    def _couple(self, dt: float) -> None:
        """The coupled step after pymunk's (:mod:`rrbody.engine.plugin.coupling`), and its bookkeeping: the rest
        rule's flags of the bodies it solved are its own now (cleared), a body it brought to rest has stopped."""
        if self._dirty:
            self._relink()
        events = self._coupling.after_step(dt, self._list, self._slots, self._bodies,
                                           (self._k_shapes, self._k_geo, self._k_tables), self._k_lookup,
                                           self.members)
        if events is None:
            return
        for j in events.tolist():  # the bodies it brought to rest in this step
            self.n_stopped += 1
            self._t_stop[self._list[j]] = self.t + dt

    def _rest(self) -> list[int]:
        """The rest rule before pymunk's step: exact zeros the step after a stop; returns the rows it stops in
        this step (their stop times are counted after the step, :meth:`_stops`: the coupled step may keep
        them moving)."""
        flags = self._bodies[:, K.STOP]
        stopping = []
        for j in np.flatnonzero(flags).tolist():
            if flags[j] == K.ZEROED:
                b = self._list[j]
                b.velocity = (0.0, 0.0)
                b.angular_velocity = 0.0
            else:
                stopping.append(j)
        return stopping

    def _stops(self, rows: list[int], dt: float) -> None:
        """Count the rest rule's stops of this step (``rows``) that stand: those the coupled step did not take
        over (it clears the flag of every body it solves)."""
        flags = self._bodies[:, K.STOP]
        for j in rows:
            if flags[j] == K.STOPPING:
                self.n_stopped += 1
                self._t_stop[self._list[j]] = self.t + dt

    def stop_time(self, body: Any) -> float | None:
        """When the rest rule last stopped ``body`` (s, the plugin's clock), if it is at rest now; else None."""
        j = self._slots[body]
        if self._bodies[j, K.STOP] > 0.0 or (body.velocity == (0.0, 0.0) and body.angular_velocity == 0.0):
            return self._t_stop.get(body)
        return None
