"""PlaneFriction: Coulomb friction from a horizontal plane on the bodies of any pymunk program.

::

    space = pymunk.Space()                        # a top-down space: no gravity
    pf = PlaneFriction(space, g=9.81)
    pf.add(body, mu=0.4)                          # a body you built, with its own shapes
    while running:
        pf.step(1 / 120)                          # instead of space.step(1 / 120)

The friction of each body is integrated over the area of its own shapes (circles, polygons,
segments with a radius, several per body) under a uniform normal pressure m g / A: exact for
circles (instantaneous-centre quadrature) and convex polygons (:mod:`rrbody.physics.polygon`).
One compiled call per step reads every body through ``pymunk.batch``, computes all wrenches and
writes the forces back; then ``space.step`` runs. The contract (what is read, when it acts, what is
guaranteed at rest) is in docs/engine.md.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.engine import kernel as K
from rrbody.engine.batchio import BatchIO
from rrbody.engine.shapes import Footprint, body_footprint
from rrbody.model.checks import check, check_choice

__all__ = ["PlaneFriction", "PRESSURES"]

#: normal-pressure profiles PlaneFriction.add accepts
PRESSURES: tuple[str, ...] = ("uniform",)


class PlaneFriction:
    """Dry friction of a horizontal plane under the bodies of one ``pymunk.Space``.

    Parameters
    ----------
    space : pymunk.Space
        The user's space. Its gravity and damping stay the user's business (a top-down space has
        neither); the plane's weight enters only through ``g``.
    g : float
        Gravitational acceleration pressing bodies on the plane, m/s^2, > 0.
    """

    def __init__(self, space: Any, g: float = 9.81) -> None:
        import pymunk

        if not isinstance(space, pymunk.Space):
            raise ValueError(f"space must be a pymunk.Space, got {space!r}")
        self.space = space
        self.g = float(check("g", g))
        self._io = BatchIO(space)
        self._slots: dict[Any, int] = {}  # body -> row
        self._list: list[Any] = []  # row -> body
        self._bodies = np.zeros((0, K.N_BODY))
        self._geo: list[tuple[np.ndarray, np.ndarray]] = []  # per body: footprint rows and geo block
        self.pre_step: list[Any] = []  # callables f(dt) run after friction is set, before space.step (builder)
        self._fresh: set[Any] = set()
        self._dirty = True
        self._kernel: Any = None  # the compiled step's entry point, found on the first step
        self.t = 0.0  # s: time advanced by step (compensated sum)
        self._tc = 0.0
        self.n_stopped = 0  # stops made by the rest rule so far
        self._t_stop: dict[Any, float] = {}

    # ---- membership --------------------------------------------------------------------------
    @property
    def bodies(self) -> tuple[Any, ...]:
        """The bodies that feel the plane's friction, in the order they were added."""
        return tuple(self._list)

    def add(self, body: Any, *, mu: float, pressure: str = "uniform") -> None:
        """Give ``body`` (dynamic, already in the space, with at least one shape of positive area)
        friction coefficient ``mu`` (>= 0) against the plane. Its mass is ``body.mass`` (from the
        shapes' density or mass, or set by you), its shapes' geometry is read now: call ``add``
        again after changing either. The body's current velocity is its velocity at the next step's
        start time (the first step gives it the half kick of the staggered scheme)."""
        self._check_body(body)
        mu = float(check("mu", mu))
        check_choice("pressure", pressure, PRESSURES)
        self._add(body, law=K.LAW_DRY, coeff=mu * self.g, footprint=body_footprint(body), snap=True, history=None)

    def _check_body(self, body: Any) -> None:
        import pymunk

        if not isinstance(body, pymunk.Body):
            raise ValueError(f"body must be a pymunk.Body, got {body!r}")
        if body.body_type != pymunk.Body.DYNAMIC:
            raise ValueError(f"body must be a dynamic pymunk.Body (kinematic and static bodies do not slide), "
                             f"got body_type {body.body_type!r}")
        if body.space is not self.space:
            raise ValueError("body must be added to the PlaneFriction's space first (space.add(body, *shapes))")
        m, moment = float(body.mass), float(body.moment)
        if not (0.0 < m < math.inf and 0.0 < moment < math.inf):
            raise ValueError(f"body mass and moment must be positive and finite (kg, kg m^2), got mass {m!r}, "
                             f"moment {moment!r}: give its shapes a density or mass, or set body.mass/moment")

    def _add(self, body: Any, *, law: float, coeff: float, footprint: Footprint, snap: bool,
             history: tuple[float, float, float, float] | None, v_eps: float = 0.0, staggered: bool = True) -> None:
        """``add`` for rrbody's builder too: any law (K.LAW_DRY with coeff mu g, K.LAW_VISCOUS with gamma)
        and footprint (point mass, sampled elements); ``snap`` False leaves the rest rule to the joint
        that holds a driven body; ``history`` = (vx, vy, w, gap) when the builder has made the half kick."""
        shapes, geo, reach, (gx, gy), jj = footprint
        m, moment = float(body.mass), float(body.moment)
        row = np.zeros(K.N_BODY)
        row[[K.MASS, K.IPM, K.LAW, K.COEFF, K.REACH, K.SNAP, K.VEPS, K.VGX, K.VGY, K.VJ, K.STAG]] = \
            m, moment / m, law, coeff, reach, 1.0 if snap else 0.0, v_eps, gx, gy, jj, 1.0 if staggered else 0.0
        if history is not None:
            row[[K.PVX, K.PVY, K.PW, K.GAP]] = history
        if body in self._slots:
            j = self._slots[body]
            self._bodies[j] = row
            self._geo[j] = (shapes, geo)
        else:
            self._slots[body] = len(self._list)
            self._list.append(body)
            self._bodies = np.vstack([self._bodies, row])
            self._geo.append((shapes, geo))
        if history is None:
            self._fresh.add(body)
        else:
            self._fresh.discard(body)
        self._dirty = True

    def remove(self, body: Any) -> None:
        """Stop applying friction to ``body`` (it stays in the space)."""
        if body not in self._slots:
            raise ValueError(f"body is not in this PlaneFriction, got {body!r}")
        j = self._slots.pop(body)
        self._list.pop(j)
        self._geo.pop(j)
        self._bodies = np.ascontiguousarray(np.delete(self._bodies, j, axis=0))
        self._slots = {b: i for i, b in enumerate(self._list)}
        self._fresh.discard(body)
        self._t_stop.pop(body, None)
        self._dirty = True

    def _pack(self) -> None:
        """Flatten every body's footprint rows and geo blocks into the kernel's arrays."""
        shapes, geos = [], []
        ng = ns = 0
        for j, (sh, geo) in enumerate(self._geo):
            sh = sh.copy()
            poly = sh[:, K.KIND] == K.POLYGON
            sh[poly, K.V0] += ng
            sh[poly, K.V1] += ng
            ranged = poly | (sh[:, K.KIND] == K.SAMPLED)
            sh[ranged, K.Q0] += ng
            sh[ranged, K.Q1] += ng
            self._bodies[j, K.S0], self._bodies[j, K.S1] = ns, ns + sh.shape[0]
            ns += sh.shape[0]
            ng += geo.shape[0]
            shapes.append(sh)
            geos.append(geo)
        self._k_shapes = np.ascontiguousarray(np.concatenate(shapes)) if shapes else np.zeros((0, K.N_SHAPE))
        self._k_geo = np.ascontiguousarray(np.concatenate(geos)) if geos else np.zeros((0, 3))
        ids = np.array([b.id for b in self._list], dtype=np.uint64).view(np.int64)
        order = np.argsort(ids)
        self._k_lookup = np.ascontiguousarray(np.vstack([ids[order], order.astype(np.int64)]))
        self._dirty = False

    # ---- stepping ----------------------------------------------------------------------------
    def _kick(self, dt: float) -> None:
        """Half kick of newly added bodies: their velocity becomes the one at t + dt/2."""
        for body in list(self._fresh):
            j = self._slots[body]
            v = body.velocity
            vx, vy, w = float(v.x), float(v.y), float(body.angular_velocity)
            if (vx, vy, w) != (0.0, 0.0, 0.0):
                ax, ay, aw, s = K.limited(j, float(body.angle), vx, vy, w, vx, vy, w, 0.5 * dt, self._bodies,
                                          self._k_shapes, self._k_geo)
                h = 0.5 * dt * s
                body.velocity = (vx + h * ax, vy + h * ay)
                body.angular_velocity = w + h * aw
            self._bodies[j, [K.PVX, K.PVY, K.PW, K.GAP]] = vx, vy, w, 0.5 * dt
        self._fresh.clear()

    def step(self, dt: float) -> None:
        """Apply one step of friction to every body of the plugin, then ``space.step(dt)`` (dt in s).

        Use it in place of ``space.step``: a plain ``space.step`` advances the space without friction.
        Forces you set on a body before the call (``body.force``, ``apply_force_at_...``) act as usual.
        """
        if not 0.0 < dt < math.inf:  # (also refuses NaN; no check helper: this is the hot path)
            raise ValueError(f"dt must be > 0 s and finite, got {dt!r}")
        dt = float(dt)
        if self._dirty:
            self._pack()
        if self._fresh:
            self._kick(dt)
        if self._list:
            got, ids, out = self._io.read()
            args = (got, ids, self._k_lookup, self._bodies, self._k_shapes, self._k_geo, self.t, dt, out)
            if self._kernel is None:
                self._kernel = K.fast_entry(K.plane_step, *args)  # runs this step's kernel once
                n_flag = int(np.count_nonzero(self._bodies[:, K.STOP]))
            else:
                n_flag = self._kernel(*args)
            self._io.write_forces()
            for f in self.pre_step:
                f(dt)
            if n_flag:
                self._rest(dt)
        self.space.step(dt)
        y = dt - self._tc
        t = self.t + y
        self._tc = (t - self.t) - y
        self.t = t

    def _rest(self, dt: float) -> None:
        """Bookkeeping of the rest rule: stop times, and exact zeros the step after a stop."""
        flags = self._bodies[:, K.STOP]
        for j in np.flatnonzero(flags):
            b = self._list[int(j)]
            if flags[j] == K.ZEROED:
                b.velocity = (0.0, 0.0)
                b.angular_velocity = 0.0
            else:
                self.n_stopped += 1
                self._t_stop[b] = self.t + dt

    def stop_time(self, body: Any) -> float | None:
        """When the rest rule last stopped ``body`` (s, the plugin's clock), if it is at rest now; else None."""
        j = self._slots[body]
        if self._bodies[j, K.STOP] > 0.0 or (body.velocity == (0.0, 0.0) and body.angular_velocity == 0.0):
            return self._t_stop.get(body)
        return None

    # ---- readers -----------------------------------------------------------------------------
    def velocity(self, body: Any) -> tuple[float, float, float]:
        """(vx, vy, spin) of ``body``'s centre of gravity at the plugin's time ``t`` (m/s, rad/s).

        pymunk's ``body.velocity`` after a step belongs to t + dt/2 (the staggered scheme); this is the
        mean of it and the velocity before the step, second-order accurate at t."""
        j = self._slots[body]
        v = body.velocity
        w = body.angular_velocity
        p = self._bodies[j]
        if p[K.GAP] <= 0.0 or p[K.STAG] == 0.0:
            return float(v.x), float(v.y), float(w)
        return 0.5 * (p[K.PVX] + v.x), 0.5 * (p[K.PVY] + v.y), 0.5 * (p[K.PW] + w)

    def wrench(self, body: Any, velocity: tuple[float, float, float] | None = None,
               angle: float | None = None) -> tuple[float, float, float]:
        """The friction force (N, world frame) and torque about the centre of gravity (N m) on ``body``
        at its current angle and velocity, or at the given ones (no rest rule, no limiter)."""
        if self._dirty:
            self._pack()
        j = self._slots[body]
        v = body.velocity
        vx, vy, w = (float(v.x), float(v.y), float(body.angular_velocity)) if velocity is None else velocity
        a = float(body.angle) if angle is None else float(angle)
        ax, ay, aw = K.body_accel(j, a, vx, vy, w, self._bodies, self._k_shapes, self._k_geo)
        m = self._bodies[j, K.MASS]
        return m * ax, m * ay, m * self._bodies[j, K.IPM] * aw
