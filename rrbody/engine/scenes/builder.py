"""rrbody's own scenes in a pymunk space: a thin builder on :class:`~rrbody.engine.plugin.plane.PlaneFriction`.

What :func:`attach` adds to a ``pymunk.Space``
----------------------------------------------
- a **dynamic body** with the scene's mass and moment of inertia about its CM (``I_cm``); its pymunk
  angle is the body angle ``alpha`` (the R_A axis), its position the CM;
- shapes matching the geometry (a segment and a small circle for the rod-mass, a circle for a disk, a
  48-gon for an ellipse, plus a segment, the massless rod, when P lies outside the body). They carry
  no mass and, unless ``EngineSettings(collide=True)``, a shape filter that matches nothing;
- for a driven scene a **kinematic driver body** placed *exactly* on the circle
  ``P(t) = d (cos wt, sin wt)`` at the end of every step, and a ``PivotJoint`` at P;
- the body in the space's :class:`PlaneFriction` (one per space, shared by every attach), with the
  scene's friction law and footprint: the point law at the CM for a rod-mass, the exact
  instantaneous-centre quadrature for a disk or an ellipse, or the scene's sampled area elements when
  ``friction_method="sampled"``.

Step with ``h.plane.step(dt)`` (friction, then ``space.step``). The scheme is the plugin's staggered
one (second order, docs/engine.md); for a driven body the start is a half kick from phi''(0) of the
shared right-hand side, and the driver's velocity is P'(t_{n+1} + dt/2) plus the centripetal term
w^2 dt/2 (P - CM) that pymunk's linear drift of a rotating body omits, so P stays on the circle to
third order per step. A point mass has ``I_cm = 0``, which pymunk rejects: it gets
``I_cm = point_inertia * m l^2`` (default 1e-9; effect measured in docs/engine.md).

Units: SI (m, s, kg, rad), world frame.
"""

from __future__ import annotations

import math
import weakref
from typing import Any

import numpy as np

from rrbody._private import private_allowed
from rrbody.contact import kernel as K
from rrbody.engine.plugin.plane import PlaneFriction
from rrbody.engine.scenes.settings import EngineSettings, check_dt
from rrbody.model.laws import PLUGIN_AREA, bound_params, check_area, law_named
from rrbody.model.scene import Scene
from rrbody.physics import params as P
from rrbody.physics.bind import area_model, friction_per_mass, kernel_params
from rrbody.physics.footprint import apply_pressure, body_parts, combine, sampled_part

__all__ = ["EngineHandle", "attach", "plane_for"]

_PLANES: weakref.WeakKeyDictionary[Any, PlaneFriction] = weakref.WeakKeyDictionary()


def plane_for(space: Any, scene: Scene | None = None) -> PlaneFriction:
    """The PlaneFriction that :func:`attach` uses for ``space`` (created on first use, level or tilted
    as ``scene`` says; a scene's tilt must match the plane's: one space, one plane)."""
    pf = _PLANES.get(space)
    if pf is None:
        pf = _PLANES[space] = (PlaneFriction(space) if scene is None else
                               PlaneFriction(space, g=scene.g, tilt=scene.tilt, downhill=scene.downhill))
    elif scene is not None and _slope(scene.tilt, scene.downhill, scene.g) != _slope(pf.tilt, pf.downhill, pf.g):
        raise ValueError(f"scene tilt must match the space's plane (one space, one plane): the plane has tilt "
                         f"{pf.tilt!r} rad, downhill {pf.downhill!r} rad, g {pf.g!r} m/s^2; got tilt {scene.tilt!r}, "
                         f"downhill {scene.downhill!r}, g {scene.g!r}")
    return pf


def _slope(tilt: float, downhill: float, g: float) -> tuple[float, float, float]:
    """What a plane's tilt does to the bodies on it (a level plane's downhill and g do nothing here:
    the scenes' friction already carries mu g)."""
    return (tilt, downhill, g) if tilt != 0.0 else (0.0, 0.0, 0.0)


def _footprint(scene: Scene) -> tuple[float, float, float | None, tuple, tuple[float, ...]]:
    """(law, coeff, static, footprint, params) of the scene's body for the plugin kernel: the law's code
    from the law table, the friction coefficients and the law's parameters as the ODE path binds them
    (:func:`rrbody.physics.bind.friction_per_mass`, :func:`rrbody.model.laws.bound_params`). A law the
    plugin has no form for is a ValueError naming it and the plugin's area method (:func:`check_area`:
    here, before anything is added to the space)."""
    fr = scene.friction
    spec = law_named(fr.law)
    check_area(fr.law, PLUGIN_AREA, where="the engine path integrates the body's footprint")
    coeff, static = friction_per_mass(scene)
    static_or_none = static if fr.active and spec.sticks else None
    params = bound_params(fr.law, fr.params, scene.g * math.cos(scene.tilt))[:len(spec.params)]
    law = K.LAW_CODE[fr.law]
    if area_model(scene) == P.BODY_SAMPLED:
        return law, coeff, static_or_none, combine([sampled_part(kernel_params(scene)[1])]), params
    # the ODE path's contact method packs the same footprint (one description, both paths)
    return law, coeff, static_or_none, apply_pressure(body_parts(scene.body), scene.pressure), params


class EngineHandle:
    """What :func:`attach` added to a space, and the state readers.

    Attributes: ``space``, ``plane`` (its PlaneFriction: step with ``h.plane.step(dt)``), ``scene``,
    ``settings``, ``body`` (dynamic), ``driver`` (kinematic, or None for a free body), ``joint``
    (PivotJoint or None), ``shapes``.
    """

    def __init__(self, space: Any, scene: Scene, settings: EngineSettings) -> None:
        import pymunk

        self.space = space
        self.plane = plane_for(space, scene)
        self.scene = scene
        self.settings = settings
        body = scene.body
        self._beta = scene.phi0 - body.alpha0  # angle of CM->P in the body frame (rad)
        self.anchor = (body.l * math.cos(self._beta), body.l * math.sin(self._beta))  # P, body frame (m)
        i_cm = body.inertia_per_mass if not body.is_point else settings.point_inertia * body.l ** 2
        if not i_cm > 0.0:
            raise ValueError("a point mass needs l > 0 to be represented in the engine (I_cm = point_inertia m l^2)")
        self._staggered = settings.staggered
        self._t0 = self.plane.t
        dt = settings.dt
        m = body.mass
        self.body = pymunk.Body(m, m * i_cm, body_type=pymunk.Body.DYNAMIC)
        self.body.angle = body.alpha0
        history = None
        if scene.drive is None:
            pos0, vel = (0.0, 0.0), (*scene.v0, scene.spin0)
            if not self._staggered:
                history = (*vel, 0.0)
        else:
            self._omega, self._d = scene.drive.omega, scene.drive.d
            phi0, w0 = scene.phi0, scene.initial_phi_dot
            e = (math.cos(phi0), math.sin(phi0))
            # r = P - l e(phi); r' = P' - l phi' e_perp(phi): the impulsive start, the paper's Eq. 3
            pos0 = (self._d - body.l * e[0], -body.l * e[1])
            v0 = (body.l * w0 * e[1], self._d * self._omega - body.l * w0 * e[0], w0)
            vel = v0
            history = (*v0, 0.0)
            if self._staggered:
                # half kick: the state at t = dt/2 from phi''(0) of the shared right-hand side
                from rrbody.physics.dynamics import driven_rhs

                p, S = kernel_params(scene)
                f0 = np.empty(2)
                driven_rhs(0.0, np.array([phi0, w0]), p, S, f0)
                ph, wh, th = phi0 + 0.5 * dt * w0, w0 + 0.5 * dt * f0[1], 0.5 * dt * self._omega
                vel = (-self._d * self._omega * math.sin(th) + body.l * wh * math.sin(ph),
                       self._d * self._omega * math.cos(th) - body.l * wh * math.cos(ph), wh)
                history = (*v0, 0.5 * dt)
        self._v0 = (float(history[0]), float(history[1]), float(history[2])) if history else vel
        self.body.position = pos0
        self.body.velocity = vel[:2]
        self.body.angular_velocity = vel[2]
        self.shapes = self._make_shapes(pymunk)
        objs: list[Any] = [self.body, *self.shapes]
        self.driver = self.joint = None
        if scene.drive is not None:
            self.driver = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            self.driver.position = (self._d, 0.0)
            self.driver.velocity = (0.0, self._d * self._omega)
            self.joint = pymunk.PivotJoint(self.driver, self.body, (0.0, 0.0), self.anchor)
            objs += [self.driver, self.joint]
        law, coeff, static, fp, params = _footprint(scene)  # (checked before the space changes)
        space.add(*objs)
        # the rest rule is for free bodies: a driven body's joint decides its velocity
        self.plane.add_footprint(self.body, law=law, coeff=coeff, footprint=fp, snap=scene.drive is None,
                                 history=history, v_eps=1e-12 * scene.velocity_scale(), staggered=self._staggered,
                                 static=static, params=params)
        if scene.active is not None:  # a free body's propulsion and its medium (rrbody.engine.plugin.active)
            self.plane.activate(self.body, scene.active)
            self.plane.seed(scene.seed)  # its noise: the scene's seed, as on the ODE path
        if self.driver is not None:
            self.plane.drive(self.body, omega=self._omega, d=self._d, anchor=self.anchor, t0=self._t0)
            self._set_drive_writers()
            self.plane.pre_step.append(self._drive)
        # the solver must run at least the requested iterations (never lowered for other bodies)
        space.iterations = max(space.iterations, settings.iterations)

    def _set_drive_writers(self) -> None:
        """Chipmunk's setters for the driver (a pymunk property set costs ~1 us, these ~0.4 us); the
        public properties if this pymunk does not expose them."""
        try:
            if not private_allowed():  # RRBODY_NO_PRIVATE: the public properties (rrbody._private)
                raise ImportError
            from pymunk.batch import lib

            self._drv_ptr = self.driver._body
            self._set_v, self._set_p = lib.cpBodySetVelocity, lib.cpBodySetPosition
        except (ImportError, AttributeError):  # pragma: no cover - depends on the pymunk version
            drv = self.driver
            self._drv_ptr = None
            self._set_v = lambda _, v: setattr(drv, "velocity", v)
            self._set_p = lambda _, p: setattr(drv, "position", p)

    def _make_shapes(self, pymunk: Any) -> list[Any]:
        body = self.scene.body
        l = body.l
        shapes: list[Any] = []
        if body.is_point:
            r = 0.08 * l
            shapes.append(pymunk.Circle(self.body, r, (0.0, 0.0)))
            shapes.append(pymunk.Segment(self.body, (0.0, 0.0), self.anchor, 0.1 * r))
        else:
            ra, rb = body.semi_axes
            if ra == rb:
                shapes.append(pymunk.Circle(self.body, ra, (0.0, 0.0)))
            else:
                shapes.append(pymunk.Poly(self.body, [tuple(v) for v in body.outline(48)]))
            ax, ay = self.anchor
            if (ax / ra) ** 2 + (ay / rb) ** 2 > 1.0:  # P outside: the massless rod
                shapes.append(pymunk.Segment(self.body, (0.0, 0.0), self.anchor, 0.02 * min(ra, rb)))
        if not self.settings.collide:
            # matches nothing: no collision pairs at all (sensors would still be paired every step)
            for s in shapes:
                s.filter = pymunk.ShapeFilter(categories=0, mask=0)
        return shapes

    def _drive(self, dt: float) -> None:
        """Before each step: put the driver where the step's position update lands it exactly on
        P(t_{n+1}), with the velocity the joint solver should give P (computed in the plugin's compiled
        step, :func:`rrbody.contact.body.driver`)."""
        px, py, vx, vy = self.plane.drive_target(self.body)
        self._set_v(self._drv_ptr, (vx, vy))
        self._set_p(self._drv_ptr, (px, py))

    # ---- state readers -----------------------------------------------------------------------
    @property
    def beta(self) -> float:
        """Angle of CM -> P in the body frame (rad), fixed: ``phi`` is the body's angle plus it."""
        return self._beta

    @property
    def t0(self) -> float:
        """The plane's time (``plane.t``, s) when the body was attached: ``t`` counts from it."""
        return self._t0

    @property
    def t(self) -> float:
        """Time since attach (s)."""
        return self.plane.t - self._t0

    @property
    def t_rest(self) -> float | None:
        """When a free body came to rest (s since attach), if it is at rest now; else None."""
        ts = self.plane.stop_time(self.body)
        return None if ts is None else ts - self._t0

    @property
    def phi(self) -> float:
        """Angle of CM -> P (rad), continuous (pymunk's body angle is never wrapped)."""
        return self.body.angle + self._beta

    @property
    def phi_dot(self) -> float:
        """phi' = the body's spin (rad/s) at time ``t`` (the mean of the two half-step spins)."""
        return self.velocity()[2]

    def velocity(self) -> tuple[float, float, float]:
        """(vx, vy, spin) of the CM (m/s, rad/s) at the handle's time ``t``."""
        if self.plane.t == self._t0:
            return self._v0  # not stepped yet: the initial state
        return tuple(float(x) for x in self.plane.velocity(self.body))  # type: ignore[return-value]

    def pivot_world(self) -> tuple[float, float]:
        """The body's point P in world coordinates (m)."""
        p = self.body.local_to_world(self.anchor)
        return float(p.x), float(p.y)

    def pivot_error(self) -> float:
        """Distance (m) between the body's point P and the drive point P(t) on the circle."""
        if self.driver is None:
            return 0.0
        px, py = self.pivot_world()
        wt = self._omega * self.t
        return math.hypot(px - self._d * math.cos(wt), py - self._d * math.sin(wt))

    def detach(self) -> None:
        """Remove everything :func:`attach` added from the space and from its PlaneFriction."""
        self.plane.remove(self.body)
        objs = [*self.shapes, self.body]
        if self.driver is not None:
            self.plane.pre_step.remove(self._drive)
            objs = [self.joint, self.driver, *objs]
        self.space.remove(*objs)


def attach(space: Any, scene: Scene, *, settings: EngineSettings | None = None) -> EngineHandle:
    """Add ``scene``'s driven (or free) body to an existing ``pymunk.Space`` and return its handle.

    Step with ``h.plane.step(settings.dt)`` (the space's PlaneFriction: friction, then ``space.step``).
    The space's gravity and damping act on every body in it, the attached one too: rrbody's scenes lie
    on a horizontal plane, so give such a space none. ``space.iterations`` is raised to
    ``settings.iterations`` if lower. ``settings.dt`` is checked against the scene
    (:func:`~rrbody.engine.scenes.settings.valid_dt_range`): a coarser step raises ValueError.
    """
    import pymunk

    if not isinstance(space, pymunk.Space):
        raise ValueError(f"space must be a pymunk.Space, got {space!r}")
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be an rrbody Scene, got {scene!r} (for your own pymunk bodies use "
                         f"PlaneFriction(space).add(body, mu=...))")
    settings = EngineSettings() if settings is None else settings
    if not isinstance(settings, EngineSettings):
        raise ValueError(f"settings must be an EngineSettings, got {settings!r}")
    check_dt(scene, settings.dt)
    return EngineHandle(space, scene, settings)
