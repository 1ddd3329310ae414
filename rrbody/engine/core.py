"""The pymunk engine path: a scene's body as pymunk objects, driven by a kinematic body at P.

What :func:`attach` adds to a pymunk ``Space`` (the plugin API)
----------------------------------------------------------------
- a **kinematic driver body** whose position function places it *exactly* on the circle
  ``P(t) = d (cos wt, sin wt)`` at the end of every position update (no accumulated drift:
  positions are set from the clock, never integrated), its velocity set from the drive as below;
- a **dynamic body** with the scene's mass and moment of inertia about its CM (``I_cm``); its
  pymunk angle is the body angle ``alpha`` (the R_A axis), its position the CM;
- shapes matching the geometry: a segment and a small circle for the rod-mass, a circle for a
  disk, a convex polygon for an ellipse, plus a segment (the massless rod) when P lies outside
  the body. They carry no mass and are sensors unless ``EngineSettings(collide=True)``;
- a ``PivotJoint`` between the driver and the body at P;
- a **per-step friction hook** (the body's ``velocity_func``): the friction force and torque come
  from the same compiled kernel as the ODE path, :func:`rrbody.friction.body_wrench`, evaluated
  on the scene's *sampled* area elements. The body ignores the space's gravity and damping: it
  slides on a horizontal plane where friction is the only loss.

Time stepping (pymunk 7 / Chipmunk ``cpSpaceStep``): positions first move with the current
velocities, then each body's velocity function adds ``dt * force / m`` (here: friction), then the
joint's impulse solver makes the anchor velocities agree. Used plainly (``staggered=False``) this is
symplectic Euler with a velocity-level constraint, first order in ``dt``. rrbody's default
(``staggered=True``) reads the body's velocity as belonging to the half step, which makes the same
pymunk step second order (measured: ``docs/engine.md``, ``tests/test_engine.py``):

- the start is a half kick: velocities at t = dt/2 from phi''(0) of the shared right-hand side;
- friction at the position time t_{n+1} uses the velocity extrapolated from the last two half steps;
- the driver's velocity is P'(t_{n+1} + dt/2) plus the centripetal term omega_b^2 dt/2 (P - CM)
  that pymunk's linear drift of a rotating body omits, so P stays on the circle to third order per step;
- readers (:attr:`EngineHandle.phi_dot`, :meth:`EngineHandle.velocity`) average the two half steps.

Dry friction without chatter: the friction impulse of one step is scaled down (never up) so that it
cannot carry the body's kinetic energy past its minimum along the impulse direction. For a point
mass this stops the CM exactly when ``|v| <= mu g dt`` (a discrete static-friction rule); a free
body whose every point moves slower than ``mu g dt`` is set exactly at rest, and the kernel's zero
force at zero speed keeps it there. Friction therefore never does positive work on a free body.

A point mass has ``I_cm = 0``, which pymunk rejects; it is represented with
``I_cm = point_inertia * m l^2`` (default 1e-9), which changes H by that relative amount. Its effect
on phi(t) and t_f is linear in ``point_inertia`` and measured in ``docs/engine.md`` (at 1e-9 it is
far below the dt error).

Units: SI (m, s, kg, rad), world frame.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rrbody.physics.bind import kernel_params
from rrbody.model.checks import check_int, check_positive, check_range
from rrbody.model.scene import Scene

__all__ = ["EngineSettings", "EngineHandle", "attach", "simulate_engine", "engine_flip_time", "valid_dt_range",
           "COARSE_FRACTION", "MAX_FRACTION"]

#: the largest allowed dt as a fraction of the fastest time scale (see :func:`valid_dt_range`)
MAX_FRACTION = 1.0 / 20.0
#: above this fraction of the shortest motion period (or above the friction time) a result is labelled
#: coarse (meta["coarse"] = True); phixtpm at dt = 1/105 of its spin period: t_f error 8.9e-4 (docs/engine.md)
COARSE_FRACTION = 1.0 / 200.0


@dataclass(frozen=True)
class EngineSettings:
    """Validated engine parameters (pymunk silently accepts misspelled attributes; rrbody sets
    pymunk parameters only from here).

    Parameters
    ----------
    dt : float
        Time step in s, > 0 (the scene-dependent upper bound is checked by :func:`attach`).
    iterations : int
        Constraint-solver iterations per step, in [1, 100000]. A lone pivot joint against a
        kinematic body is solved exactly in one; more matter when bodies interact.
    point_inertia : float
        For a point mass (rod-mass body): I_cm used in pymunk as a fraction of m l^2, in [1e-12, 1e-2].
    collide : bool
        Whether the body's shapes take part in collisions (default False: sensors, as in the ODE model).
    staggered : bool
        True (default): rrbody's second-order use of pymunk's step (velocities live at half steps,
        see the module docstring). False: plain pymunk (first order), kept for comparison.
    """

    dt: float = 1e-3
    iterations: int = 10
    point_inertia: float = 1e-9
    collide: bool = False
    staggered: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "dt", check_range("dt", self.dt, 0.0, 10.0, lo_open=True))
        object.__setattr__(self, "iterations", check_int("iterations", self.iterations, 1, 100_000))
        object.__setattr__(self, "point_inertia", check_range("point_inertia", self.point_inertia, 1e-12, 1e-2))
        for name in ("collide", "staggered"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be True or False, got {getattr(self, name)!r}")


def _motion_scales(scene: Scene) -> dict[str, float]:
    """Periods (s) of the scene's motion that every step must resolve (refusal above MAX_FRACTION)."""
    out: dict[str, float] = {}
    if scene.drive is not None:
        out["driving period"] = scene.drive.period
        if scene.initial_phi_dot != 0.0:
            out["initial spin period"] = 2.0 * math.pi / abs(scene.initial_phi_dot)
    elif scene.spin0 != 0.0:
        out["initial spin period"] = 2.0 * math.pi / abs(scene.spin0)
    return out


def _friction_scale(scene: Scene) -> tuple[str, float] | None:
    """The friction time (s): 1/gamma (viscous) or v_scale/(mu g), the time dry friction alone needs
    to stop the fastest motion. Steps longer than it are stable (the impulse limit acts as a
    static-friction rule) but are labelled coarse."""
    fr = scene.friction
    if not fr.active:
        return None
    if fr.law == "viscous":
        return "viscous relaxation time 1/gamma", 1.0 / fr.coeff
    vs = scene.velocity_scale()
    return ("dry stopping time v/(mu g)", vs / fr.coeff) if vs > 0.0 else None


def valid_dt_range(scene: Scene) -> tuple[float, str]:
    """(dt_max, reason): the largest engine step (s) accepted for ``scene``, MAX_FRACTION of the
    shortest motion period (drive, initial spin), and which period that is. ``inf`` without motion."""
    scales = _motion_scales(scene)
    if not scales:
        return math.inf, "no periodic motion to resolve"
    name = min(scales, key=lambda k: scales[k])
    return MAX_FRACTION * scales[name], f"{name} = {scales[name]:.4g} s"


def check_dt(scene: Scene, dt: float) -> float:
    """Refuse a step too coarse for the scene (ValueError naming dt and the valid range)."""
    dt_max, why = valid_dt_range(scene)
    if not dt <= dt_max:
        raise ValueError(f"dt must lie in (0, {dt_max:.4g}] s for this scene (1/{round(1 / MAX_FRACTION)} of the "
                         f"{why}), got {dt!r}")
    return dt


def default_dt(scene: Scene) -> float:
    """The default engine step (s): the smallest of 1e-3 s, 1/2000 of the shortest motion period and
    1/10 of the friction time (phixtpm: 1e-3 s, t_f within 1.6e-6 relative, docs/engine.md)."""
    cands = [1e-3] + [T / 2000.0 for T in _motion_scales(scene).values()]
    fs = _friction_scale(scene)
    if fs is not None:
        cands.append(fs[1] / 10.0)
    return min(cands)


class EngineHandle:
    """What :func:`attach` added to a space, and the state readers.

    Attributes: ``space``, ``scene``, ``settings``, ``body`` (dynamic), ``driver`` (kinematic, or
    None for a free body), ``joint`` (PivotJoint or None), ``shapes``, ``t`` (s, time since attach,
    advanced by the driver's position function, or by the body's for a free body).
    """

    def __init__(self, space: Any, scene: Scene, settings: EngineSettings) -> None:
        import pymunk

        self.space = space
        self.scene = scene
        self.settings = settings
        body = scene.body
        self._beta = scene.phi0 - body.alpha0  # angle of CM->P in the body frame (rad)
        self._l = body.l
        self.anchor = (body.l * math.cos(self._beta), body.l * math.sin(self._beta))  # P, body frame (m)
        self._m = body.mass
        i_cm = body.inertia_per_mass if not body.is_point else settings.point_inertia * body.l ** 2
        if not i_cm > 0.0:
            raise ValueError("a point mass needs l > 0 to be represented in the engine (I_cm = point_inertia m l^2)")
        self._i = i_cm  # I_cm / m used by pymunk (m^2)
        # friction: the sampled area elements of the ODE path (BODY_POINT for a point mass)
        fscene = scene if body.is_point else scene.with_(friction_method="sampled")
        self._p, self._S = kernel_params(fscene)
        self._friction = scene.friction.active
        self._mu_g = scene.friction.coeff if scene.friction.law == "dry" else 0.0
        self._free = scene.drive is None
        # farthest friction-bearing point from the CM (m), for the stick test (a point mass: the CM only)
        self._reach = 0.0 if body.is_point else max(body.semi_axes)
        self.t_rest: float | None = None  # when a free body last came to rest (s)
        # clock: compensated sum so that t stays exact to rounding over 1e7 steps
        self.t = 0.0
        self._tc = 0.0
        self.n_steps = 0
        self.n_stuck = 0
        self.error: BaseException | None = None  # first exception raised inside a hook

        # ---- the dynamic body: CM at the body position, pymunk angle = body angle alpha ----
        self.body = pymunk.Body(self._m, self._m * i_cm, body_type=pymunk.Body.DYNAMIC)
        self.body.angle = body.alpha0
        self._staggered = settings.staggered
        dt = settings.dt
        if self._free:
            pos0 = (0.0, 0.0)
            vx0, vy0 = scene.v0
            w0 = scene.spin0
            vel_h = (vx0, vy0, w0)
            if self._staggered and self._friction:
                # half kick: velocities at t = dt/2 (the clamp keeps a slow body from reversing)
                fx, fy, tau, s = self._friction_step(vx0, vy0, w0, vx0, vy0, w0, 0.5 * dt)
                vel_h = (vx0 + 0.5 * dt * s * fx, vy0 + 0.5 * dt * s * fy, w0 + 0.5 * dt * s * tau / self._i)
        else:
            drive = scene.drive
            assert drive is not None
            self._omega = drive.omega
            self._d = drive.d
            phi0 = scene.phi0
            w0 = scene.initial_phi_dot
            e = (math.cos(phi0), math.sin(phi0))
            # r = P - l e(phi); r' = P' - l phi' e_perp(phi): the impulsive start, SPEC Eq. 3
            pos0 = (self._d - body.l * e[0], -body.l * e[1])
            vx0, vy0 = body.l * w0 * e[1], self._d * self._omega - body.l * w0 * e[0]
            vel_h = (vx0, vy0, w0)
            if self._staggered:
                # half kick: the state at t = dt/2 from phi''(0) of the shared right-hand side
                from rrbody.physics.dynamics import driven_rhs

                f0 = np.empty(2)
                driven_rhs(0.0, np.array([phi0, w0]), self._p, self._S, f0)
                ph = phi0 + 0.5 * dt * w0
                wh = w0 + 0.5 * dt * f0[1]
                th = 0.5 * dt * self._omega
                vel_h = (-self._d * self._omega * math.sin(th) + body.l * wh * math.sin(ph),
                         self._d * self._omega * math.cos(th) - body.l * wh * math.cos(ph), wh)
        # velocities one half step back (for the extrapolation to the position time) and the gap (s)
        self._prev = (vx0, vy0, w0)
        self._gap = 0.5 * dt
        self._before = (vx0, vy0, w0)  # velocity before the last step's update (for readers)
        self.body.position = pos0
        self.body.angle = body.alpha0
        self.body.velocity = vel_h[:2]
        self.body.angular_velocity = vel_h[2]
        self.body.velocity_func = self._velocity_update
        self.shapes = self._make_shapes(pymunk)
        objs: list[Any] = [self.body, *self.shapes]
        self.driver = None
        self.joint = None
        if not self._free:
            self.driver = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            self.driver.position = (self._d, 0.0)
            self.driver.velocity = (0.0, self._d * self._omega)
            self.driver.position_func = self._drive_position
            self.joint = pymunk.PivotJoint(self.driver, self.body, (0.0, 0.0), self.anchor)
            objs += [self.driver, self.joint]
        else:
            self.body.position_func = self._free_position
        space.add(*objs)
        # the solver must run at least the requested iterations (never lowered for other bodies)
        space.iterations = max(space.iterations, settings.iterations)

    # ---- construction helpers ----------------------------------------------------------------
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
        for s in shapes:
            s.sensor = not self.settings.collide
        return shapes

    # ---- per-step hooks (called by Chipmunk inside space.step; they must not raise) -------------
    def _tick(self, dt: float) -> None:
        y = dt - self._tc
        t = self.t + y
        self._tc = (t - self.t) - y
        self.t = t
        self.n_steps += 1

    def _guarded(self, func: Any, *args: Any) -> None:
        """Run a hook; keep the first exception. pymunk's C callbacks only print an exception and go
        on, which would silently drop the friction: :meth:`raise_if_failed` re-raises it."""
        if self.error is not None:
            return
        try:
            func(*args)
        except BaseException as e:  # noqa: BLE001 - re-raised by raise_if_failed
            self.error = e

    def raise_if_failed(self) -> None:
        """Re-raise an exception caught inside a per-step hook (call after ``space.step``)."""
        if self.error is not None:
            if not isinstance(self.error, Exception):  # KeyboardInterrupt, SystemExit: as they were
                raise self.error
            raise RuntimeError(f"rrbody engine hook failed at t={self.t:.6g} s: {self.error!r}") from self.error

    def _drive_position(self, driver: Any, dt: float) -> None:
        self._guarded(self._drive_position_impl, driver, dt)

    def _free_position(self, body: Any, dt: float) -> None:
        self._guarded(self._free_position_impl, body, dt)

    def _velocity_update(self, body: Any, gravity: Any, damping: float, dt: float) -> None:
        self._guarded(self._velocity_update_impl, body, gravity, damping, dt)

    def _drive_position_impl(self, driver: Any, dt: float) -> None:
        """Position function of the kinematic driver: P from the clock (no drift). Its velocity is
        set in the body's velocity function, after every position has moved."""
        self._tick(dt)
        wt = self._omega * self.t
        driver.position = (self._d * math.cos(wt), self._d * math.sin(wt))
        if not self._staggered:
            driver.velocity = (-self._d * self._omega * math.sin(wt), self._d * self._omega * math.cos(wt))

    def _free_position_impl(self, body: Any, dt: float) -> None:
        self._tick(dt)
        body.update_position(body, dt)

    def _friction_step(self, vx: float, vy: float, w: float, ex: float, ey: float, ew: float,
                       dt: float) -> tuple[float, float, float, float]:
        """Friction (fx, fy, tau) per unit mass at the velocity (ex, ey, ew) and the factor s in [0, 1]
        that keeps the impulse dt*s*(f, tau) from carrying the kinetic energy of the current velocity
        (vx, vy, w) past its minimum along the impulse (no chatter, never a gain for a free body)."""
        from rrbody.physics.wrench import body_wrench

        fx, fy, tau = body_wrench(self._p, self._S, self.body.angle, ex, ey, ew)
        num = -(vx * fx + vy * fy + w * tau)
        den = dt * (fx * fx + fy * fy + tau * tau / self._i)
        s = 1.0
        if den > 0.0 and num < den:
            if (ex, ey, ew) != (vx, vy, w):
                # near a stop the extrapolated velocity is unreliable: use the current one
                return self._friction_step(vx, vy, w, vx, vy, w, dt)
            s = max(num / den, 0.0)
        return fx, fy, tau, s

    def _velocity_update_impl(self, body: Any, gravity: Any, damping: float, dt: float) -> None:
        """Velocity function of the body (after all positions moved to t_{n+1}): set the driver's
        velocity, add the friction wrench, then pymunk's Euler update without the space's gravity
        and damping (the plane is horizontal).

        Staggered scheme: the body's velocity here is v_{n+1/2} (it carried the positions from t_n
        to t_{n+1}); friction is evaluated at v(t_{n+1}) extrapolated from the last two half-step
        velocities, and the driver's velocity is the one that carries P along the circle from
        t_{n+1} to t_{n+2} to third order: P'(t_{n+1} + dt/2) plus the centripetal term
        w^2 dt/2 (P - CM) that pymunk's linear drift of a rotating body leaves out.
        """
        v = body.velocity
        vx = v.x
        vy = v.y
        w = body.angular_velocity
        self._before = (vx, vy, w)
        if self._staggered:
            g = 0.5 * dt / self._gap
            px, py, pw = self._prev
            ex, ey, ew = vx + g * (vx - px), vy + g * (vy - py), w + g * (w - pw)
            self._prev = (vx, vy, w)
            self._gap = dt
            if self.driver is not None:
                th = self._omega * (self.t + 0.5 * dt)
                rot = body.rotation_vector
                ax, ay = self.anchor
                rx = rot.x * ax - rot.y * ay
                ry = rot.y * ax + rot.x * ay
                c = 0.5 * dt * ew * ew
                self.driver.velocity = (-self._d * self._omega * math.sin(th) + c * rx,
                                        self._d * self._omega * math.cos(th) + c * ry)
        else:
            ex, ey, ew = vx, vy, w
        if self._friction:
            fx, fy, tau, s = self._friction_step(vx, vy, w, ex, ey, ew, dt)
            if self._free and s < 1.0 and self._mu_g > 0.0:
                # every point slower than mu g dt: static friction holds the body this step
                if math.hypot(vx, vy) + abs(w) * self._reach <= self._mu_g * dt:
                    # (a point mass's spin is kinematic only: it stops with the CM, as in rrbody.free)
                    w_keep = 0.0
                    body.velocity = (0.0, 0.0)
                    body.angular_velocity = w_keep
                    body.force = (0.0, 0.0)
                    body.torque = 0.0
                    self._prev = (0.0, 0.0, w_keep)
                    self._before = (0.0, 0.0, w_keep)
                    if self.t_rest is None:
                        self.t_rest = self.t
                    self.n_stuck += 1
                    return
            if self._free and (vx, vy) != (0.0, 0.0):
                self.t_rest = None
            m = self._m * s
            f = body.force
            body.force = (f.x + m * fx, f.y + m * fy)
            body.torque = body.torque + m * tau
        body.update_velocity(body, (0.0, 0.0), 1.0, dt)

    # ---- state readers -----------------------------------------------------------------------
    @property
    def phi(self) -> float:
        """Angle of CM -> P (rad), continuous (pymunk's body angle is never wrapped)."""
        return self.body.angle + self._beta

    @property
    def phi_dot(self) -> float:
        """phi' = the body's spin (rad/s) at the handle's time ``t``. With the staggered scheme the
        body's velocity after a step belongs to t + dt/2; this is the mean of it and the previous one."""
        if self._staggered:
            if self.n_steps == 0:
                return self._before[2]
            return 0.5 * (self._before[2] + self.body.angular_velocity)
        return self.body.angular_velocity

    def velocity(self) -> tuple[float, float, float]:
        """(vx, vy, spin) of the CM (m/s, rad/s) at the handle's time ``t`` (see :attr:`phi_dot`)."""
        v = self.body.velocity
        w = self.body.angular_velocity
        if self._staggered:
            b = self._before
            if self.n_steps == 0:
                return b
            return 0.5 * (b[0] + v.x), 0.5 * (b[1] + v.y), 0.5 * (b[2] + w)
        return v.x, v.y, w

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
        """Remove everything :func:`attach` added from the space."""
        objs = [*self.shapes, self.body]
        if self.driver is not None:
            objs = [self.joint, self.driver, *objs]
        self.space.remove(*objs)


def attach(space: Any, scene: Scene, *, settings: EngineSettings | None = None) -> EngineHandle:
    """Add ``scene``'s driven (or free) body to an existing ``pymunk.Space`` and return its handle.

    The space keeps its own gravity and damping for other bodies; the attached body ignores both.
    ``space.iterations`` is raised to ``settings.iterations`` if lower. Step the space as usual with
    ``space.step(settings.dt)``; the handle's clock follows the steps. ``settings.dt`` is checked
    against the scene (:func:`valid_dt_range`): a coarser step raises ValueError.
    """
    import pymunk

    if not isinstance(space, pymunk.Space):
        raise ValueError(f"space must be a pymunk.Space, got {space!r}")
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be an rrbody Scene, got {scene!r}")
    settings = EngineSettings() if settings is None else settings
    if not isinstance(settings, EngineSettings):
        raise ValueError(f"settings must be an EngineSettings, got {settings!r}")
    check_dt(scene, settings.dt)
    return EngineHandle(space, scene, settings)


# ---- the run loop ------------------------------------------------------------------------------
@dataclass
class _RunResult:
    t_end: float
    status: str
    phi_min: float
    t_min: float
    has_min: bool
    T1: float
    minima: list[tuple[float, float]]
    n_minima: int
    out: np.ndarray
    n_steps: int
    wall: float
    max_pivot_error: float
    t_stop: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)


def _parabola_min(t0: float, f0: float, t1: float, f1: float, t2: float, f2: float) -> tuple[float, float]:
    """Vertex (t, f) of the parabola through three points; the middle point if it is degenerate."""
    a = (t1 - t0) * (f1 - f2)
    b = (t1 - t2) * (f1 - f0)
    den = a - b
    if den == 0.0:
        return t1, f1
    tv = t1 - 0.5 * ((t1 - t0) * a - (t1 - t2) * b) / den
    if not (t0 <= tv <= t2):
        return t1, f1
    # value: Lagrange interpolation at tv
    l0 = (tv - t1) * (tv - t2) / ((t0 - t1) * (t0 - t2))
    l1 = (tv - t0) * (tv - t2) / ((t1 - t0) * (t1 - t2))
    l2 = (tv - t0) * (tv - t1) / ((t2 - t0) * (t2 - t1))
    return tv, f0 * l0 + f1 * l1 + f2 * l2


def _run(scene: Scene, settings: EngineSettings, *, t_end: float, stop: str, dt_out: float = 0.0,
         settle_turns: float = 2.0, settle_periods: float = 3.0, max_steps: int = 50_000_000,
         progress: bool = False, max_minima: int = 200_000) -> _RunResult:
    """Step a fresh space holding ``scene`` until ``t_end`` or the ``stop`` rule ("t_end", "flip",
    "rr", "rest"); record phi on the ``dt_out`` grid (linear interpolation between steps)."""
    import pymunk

    space = pymunk.Space()
    h = attach(space, scene, settings=settings)
    dt = settings.dt
    omega = scene.omega
    period = 2.0 * math.pi / omega if omega > 0 else math.inf
    driven = not h._free
    n_grid = int(math.floor(t_end / dt_out + 1e-9)) + 1 if (dt_out > 0.0 and math.isfinite(t_end)) else 0
    # the trajectory ends on t_end itself when the grid k * dt_out misses it (issue 13, as the ODE path)
    n_out = n_grid + int(n_grid > 0 and t_end - (n_grid - 1) * dt_out > 1e-9 * dt_out)
    out = np.empty((n_out, 3 if driven else 7))
    k_out = 0

    def sample() -> tuple[float, ...]:
        b = h.body
        if driven:
            return (h.phi, h.phi_dot)
        x = b.position
        return (x.x, x.y, b.angle, *h.velocity())

    t_prev = 0.0
    s_prev = sample()
    if n_out:
        out[0, 0] = 0.0
        out[0, 1:] = s_prev
        k_out = 1
    phi0 = h.phi
    phi_min, t_min, has_min = math.nan, math.nan, False
    if driven and h.phi_dot >= 0.0:  # phi rises from the start: t = 0 is the first minimum candidate
        phi_min, t_min, has_min = phi0, 0.0, True
    theta0 = phi0 + math.pi
    T1 = math.nan
    minima: list[tuple[float, float]] = []
    n_minima = 0
    # the last three samples of (t, phi) for minimum detection
    ta, fa = math.nan, math.nan
    tb, fb = 0.0, phi0
    max_piv = 0.0
    status = "reached t_end"
    t_stop: float | None = None
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=t_end if math.isfinite(t_end) else None, desc="engine", unit="s(sim)", leave=False,
                   dynamic_ncols=True)
    wall0 = time.perf_counter()
    step = space.step
    n = 0
    try:
        while True:
            if h.t >= t_end - (0.5 * dt if k_out >= n_out else 1e-12 * dt):  # a pending t_end sample: one step on
                break
            if n >= max_steps:
                status = "max_steps reached"
                break
            step(dt)
            if h.error is not None:
                h.raise_if_failed()
            n += 1
            t = h.t
            s = sample()
            if n_out:
                while k_out < n_out and (k_out * dt_out if k_out < n_grid else t_end) <= t + 1e-12 * dt:
                    to = k_out * dt_out if k_out < n_grid else t_end
                    w = (to - t_prev) / (t - t_prev)
                    out[k_out, 0] = to
                    for j in range(len(s)):
                        out[k_out, j + 1] = s_prev[j] + w * (s[j] - s_prev[j])
                    k_out += 1
            if driven:
                f = s[0]
                if n % 64 == 0:
                    max_piv = max(max_piv, h.pivot_error())
                # discrete local minimum of phi at the middle sample: refine by a parabola
                if fb < fa and fb <= f:
                    tm, fm = _parabola_min(ta, fa, tb, fb, t, f)
                    if len(minima) < max_minima:
                        minima.append((tm, fm))
                    n_minima += 1
                    if not has_min or fm < phi_min:
                        phi_min, t_min, has_min = fm, tm, True
                # T_1: theta = phi - omega t + pi falls to theta0 - 2 pi (linear interpolation)
                if math.isnan(T1):
                    g0 = fb - omega * tb + math.pi - (theta0 - 2.0 * math.pi)
                    g1 = f - omega * t + math.pi - (theta0 - 2.0 * math.pi)
                    if g0 > 0.0 and g1 <= 0.0:
                        T1 = tb + (t - tb) * g0 / (g0 - g1)
                ta, fa, tb, fb = tb, fb, t, f
                if stop == "flip" and has_min and f >= phi_min + 2.0 * math.pi * settle_turns \
                        and t - t_min >= settle_periods * period:
                    status = "flip settled"
                    break
                if stop == "rr" and (not math.isnan(T1) or omega * t > 2.0 * math.pi):
                    status = "RR decided"
                    break
            else:
                if t_stop is None and h.t_rest is not None:
                    t_stop = h.t_rest
                    if stop == "rest":
                        status = "at rest"
                        break
            t_prev, s_prev = t, s
            if bar is not None and n % 4096 == 0:
                bar.update(t - bar.n)
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - wall0
    return _RunResult(t_end=h.t, status=status, phi_min=phi_min, t_min=t_min, has_min=has_min, T1=T1,
                      minima=minima, n_minima=n_minima, out=out[:k_out], n_steps=n, wall=wall,
                      max_pivot_error=max_piv, t_stop=t_stop)


def _settings(scene: Scene, dt: float | None, iterations: int | None, **kw: Any) -> EngineSettings:
    dt_v = default_dt(scene) if dt is None else check_positive("dt", dt, unit="s")
    return EngineSettings(dt=dt_v, iterations=10 if iterations is None else iterations, **kw)


def _coarse_meta(scene: Scene, dt: float) -> dict[str, Any]:
    """``coarse`` is True when dt exceeds COARSE_FRACTION of the shortest motion period or the
    friction time; a ``warning`` then says which and how to check."""
    scales = {k: v * COARSE_FRACTION for k, v in _motion_scales(scene).items()}  # allowed dt per scale
    fs = _friction_scale(scene)
    if fs is not None:
        scales[fs[0]] = fs[1]
    if not scales:
        return {"coarse": False}
    name = min(scales, key=lambda k: scales[k])
    frac = dt / scales[name]
    meta: dict[str, Any] = {"coarse": frac > 1.0, "dt_over_coarse_limit": frac, "limiting_time_scale": name}
    if meta["coarse"]:
        meta["warning"] = (f"coarse engine step: dt = {dt:g} s exceeds {scales[name]:.3g} s, the coarse limit set "
                           f"by the {name}; the answer is stable but less accurate (docs/engine.md): check it by "
                           "halving dt")
    return meta


def simulate_engine(scene: Scene, *, t_max: float, dt_out: float, progress: bool = False, dt: float | None = None,
                    iterations: int | None = None, max_steps: int = 50_000_000,
                    point_inertia: float = 1e-9, staggered: bool = True) -> Any:
    """Run ``scene`` in pymunk for ``t_max`` s; return the same :class:`~rrbody.trajectory.Trajectory`
    as the ODE path, sampled every ``dt_out`` s (linear interpolation between engine steps).

    ``dt`` (s; default :func:`default_dt`) and ``iterations`` are the engine settings; a dt above
    :func:`valid_dt_range` raises ValueError, one above COARSE_FRACTION of the shortest motion period
    or above the friction time is labelled ``meta["coarse"] = True`` with a warning. Driven events:
    ``minima`` (parabola through the three engine samples around each discrete minimum of phi),
    ``phi_min``, ``t_phi_min``, ``T1``; free: ``t_stop``, ``stop_position``, ``distance``, ``turn``.
    """
    from rrbody.model.trajectory import Trajectory, driven_trajectory

    max_steps = check_int("max_steps", max_steps, 1)
    settings = _settings(scene, dt, iterations, point_inertia=point_inertia, staggered=staggered)
    check_dt(scene, settings.dt)
    if t_max / settings.dt > max_steps:
        raise ValueError(f"max_steps must be >= t_max/dt = {t_max / settings.dt:.4g} for this run (dt = "
                         f"{settings.dt:g} s), got {max_steps}; raise it or shorten t_max")
    res = _run(scene, settings, t_end=t_max, stop="t_end", dt_out=dt_out, max_steps=max_steps, progress=progress)
    meta_engine = {"method": "engine", "dt": settings.dt, "iterations": settings.iterations,
                   "point_inertia": settings.point_inertia if scene.body.is_point else None,
                   "status": res.status, "n_steps": res.n_steps, "wall_s": res.wall,
                   **_coarse_meta(scene, settings.dt)}
    if scene.driven:
        traj = driven_trajectory(scene, res.out[:, 0], res.out[:, 1], res.out[:, 2])
        minima = [m for m in res.minima]
        below = [m for m in minima if m[1] < scene.phi0]
        best = min(below, key=lambda m: m[1]) if below else None
        traj.events = {
            "minima": [list(m) for m in minima],
            "n_minima": res.n_minima,
            "T1": res.T1 if math.isfinite(res.T1) else None,
            "phi_min": float(best[1]) if best else scene.phi0,
            "t_phi_min": float(best[0]) if best else 0.0,
        }
        meta_engine["max_pivot_error_m"] = res.max_pivot_error
    else:
        o = res.out
        body = scene.body
        beta = scene.phi0 - body.alpha0
        ang = o[:, 3]
        xp = o[:, 1] + body.l * np.cos(ang + beta)
        yp = o[:, 2] + body.l * np.sin(ang + beta)
        from rrbody._version import __version__

        traj = Trajectory(t=o[:, 0], phi=ang + beta, phi_dot=o[:, 6].copy(), x_cm=o[:, 1], y_cm=o[:, 2],
                          vx_cm=o[:, 4], vy_cm=o[:, 5], x_p=xp, y_p=yp, body_angle=ang, spin=o[:, 6].copy(),
                          meta={"scene": scene.describe(), "rrbody_version": __version__})
        stopped = res.t_stop is not None
        x_end, y_end = (float(o[-1, 1]), float(o[-1, 2])) if stopped and len(o) else (math.nan, math.nan)
        traj.events = {"t_stop": res.t_stop,
                       "stop_position": [x_end, y_end] if stopped else None,
                       "distance": math.hypot(x_end, y_end) if stopped else None,
                       "turn": float(o[-1, 3] - body.alpha0) if stopped and len(o) else None}
    traj.meta = {**traj.meta, **meta_engine}
    if res.status != "reached t_end":
        traj.meta["warning"] = f"integration stopped early: {res.status} at t={res.t_end:.6g} s"
    return traj


def engine_flip_time(scene: Scene, *, t_max: float | None = None, dt: float | None = None,
                     iterations: int | None = None, settle_turns: float = 2.0, settle_periods: float = 3.0,
                     max_steps: int = 50_000_000, point_inertia: float = 1e-9, staggered: bool = True,
                     progress: bool = False) -> Any:
    """Flip time of a driven scene by the engine path, with the ODE path's definitions and stopping
    rule (:func:`rrbody.analysis.flip_time`): t_f is the time of the lowest minimum of phi, located
    by a parabola through the three engine samples around it. ``t_max`` None: run until settled.
    ``FlipResult.rtol`` is NaN (the engine has a step, not a tolerance)."""
    from rrbody.integrate.events import FlipResult, classify_flip

    if not scene.driven:
        raise ValueError("engine_flip_time needs a driven scene (drive is None: a free body has no flip)")
    settle_turns = check_range("settle_turns", settle_turns, 0.5, 100.0)
    settle_periods = check_range("settle_periods", settle_periods, 0.0, 1e6)
    max_steps = check_int("max_steps", max_steps, 1)
    settings = _settings(scene, dt, iterations, point_inertia=point_inertia, staggered=staggered)
    check_dt(scene, settings.dt)
    horizon = t_max if t_max is not None else scene.t_max
    horizon = math.inf if horizon is None else check_positive("t_max", horizon, unit="s")
    assert scene.drive is not None
    minima_arr = lambda r: np.array(r.minima, dtype=float).reshape(-1, 2)  # noqa: E731
    if not scene.friction.active:
        res = _run(scene, settings, t_end=min(horizon, 2.0 * scene.drive.period), stop="rr", max_steps=max_steps)
        _, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                        phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                        t_end=res.t_end)
        return FlipResult(None, phi_min, res.t_min, rr, res.T1 if math.isfinite(res.T1) else None, settled,
                          regime, res.t_end, res.n_steps, res.n_minima, math.nan, res.wall, minima_arr(res))
    res = _run(scene, settings, t_end=horizon, stop="flip", settle_turns=settle_turns, settle_periods=settle_periods,
               max_steps=max_steps, progress=progress)
    t_f, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                      phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                      t_end=res.t_end)
    cm = _coarse_meta(scene, settings.dt)
    if cm.get("coarse"):
        regime += f" [{cm['warning']}]"
    return FlipResult(t_f, phi_min, res.t_min, rr, res.T1 if math.isfinite(res.T1) else None, settled, regime,
                      res.t_end, res.n_steps, res.n_minima, math.nan, res.wall, minima_arr(res))
