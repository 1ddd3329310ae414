"""Free bodies: no drive; a body launched with a CM velocity and a spin slides to rest under friction.

State y = (x, y, alpha, vx, vy, Omega): CM position (m, world frame, starting at the origin), body
angle (rad), CM velocity (m/s) and spin (rad/s); equations in :func:`rrbody.physics.dynamics.free_rhs`
(friction wrench from :func:`rrbody.physics.wrench.body_wrench`: point, sampled area or ICR quadrature).

Stopping (dry friction)
-----------------------
Coulomb friction stops a body in finite time, with a discontinuous right-hand side at rest. The
one stepping loop (:func:`rrbody.integrate.loop.advance`, rest rule of :mod:`rrbody.integrate.events`)
stops it exactly and cleanly:

- kinetic energy per unit mass K = (v^2 + (I_cm/m) Omega^2)/2 and dissipated power P = -(F.v + tau Omega)
  give the time left before rest if the decelerations stay as they are: tau_left = 2 K / P
  (exact for a point mass, and asymptotically for any body, whose approach to rest is self-similar:
  v and Omega both decay linearly with a fixed ratio). Steps are capped at ``STEP_FRACTION`` of
  tau_left, so the integration approaches the stop geometrically and never steps across it;
- a step that would raise K is rejected and halved (the velocity or the spin may turn through zero
  while the body slides on: an off-centre load, a tilt);
- once sqrt(2 K) falls below ``STOP_SPEED_FRACTION`` of its initial value, the last 2K/P seconds
  are completed analytically (linear decay: distance v tau/2, turn Omega tau/2), velocities are
  set to exactly zero and stay there. The stop time is reported in ``events['t_stop']``.

A point mass has no rotational inertia: its spin is kinematic only (kept as given while it slides)
and set to zero when it stops. Viscous friction decays exponentially and never stops: t_stop is None.

On a tilted plane gravity pulls along it and the stop rule weighs the mechanical energy (kinetic
less gravity's work). A body at rest (launched from rest, or come to rest) stays at rest if static
friction holds the pull (:func:`rrbody.physics.limit.at_rest`, the contact's limit surface);
one it cannot hold (released at rest, or come to rest on a slope steeper than mu_static allows)
starts to slide in the maximum-dissipation direction: the run goes on from tau = 1e-6 t_max after
the stop along the break-away acceleration (constant at first: exact to O(tau^2)), and
``events['break_aways']`` counts those stops.

Point feet (pressure ``points``) under dry friction: a foot can come to rest while the body still
turns about it (a pivot), and break away again; :class:`rrbody.integrate.pivot.FeetRun` steps the
same loop one accepted step at a time and reports ``events['pivots']`` (foot, start and end times,
what ended each).

An active body with Langevin noise (or with the scene's ``noise_dt``) runs with fixed steps of the
stochastic Runge-Kutta scheme SRA1 instead (:mod:`rrbody.integrate.sde`: strong order 1.5, weak order
2 for its additive noise), seeded by the scene's ``seed``; the same right-hand side, no rest rule.
"""

from __future__ import annotations

import math
import time

import numpy as np

from rrbody._version import __version__
from rrbody.integrate.chunks import run_in_chunks
from rrbody.integrate.events import E_TSTOP, STEP_FRACTION, STOP_REST, STOP_SPEED_FRACTION, STOP_T_END, new_event_state
from rrbody.integrate.loop import L_NEXTOUT, L_NOUT, L_NREJ, L_NSTEP, L_T, STEP_METHODS, advance_for, new_loop_state
from rrbody.integrate.pivot import FeetRun
from rrbody.integrate.sde import run_sde, uses_sde
from rrbody.model.scene import Scene
from rrbody.model.trajectory import Trajectory
from rrbody.physics import params as P
from rrbody.physics.bind import ode_params
from rrbody.physics.contact import H_PARTS, HEADER
from rrbody.physics.dynamics import SYSTEM_FREE, free_rhs, system_from_params
from rrbody.physics.footprint import packed
from rrbody.physics.limit import at_rest
from rrbody.physics.pivot_foot import feet_of

__all__ = ["simulate_free", "FREE_STEPPERS", "STEP_FRACTION", "STOP_SPEED_FRACTION"]

#: the stepping methods for free bodies: the loop's Radau IIA serves the 2-state driven body only (its
#: stiff method for free bodies, also under "auto", is RODAS4)
FREE_STEPPERS: tuple[str, ...] = tuple(m for m in STEP_METHODS if m != "radau")


def simulate_free(scene: Scene, *, t_max: float, dt_out: float, rtol: float = 1e-10, max_steps: int = 50_000_000,
                  progress: bool = False, stepper: str = "auto") -> Trajectory:
    """Integrate a free (undriven) scene from t = 0 to ``t_max`` (s), sampled every ``dt_out`` (s).

    The CM starts at the origin with velocity ``scene.v0`` (m/s, world frame), the body angle at
    ``scene.body.alpha0`` with spin ``scene.spin0`` (rad/s); P (for the phi / x_p, y_p columns) is
    the body point at distance l along the direction ``phi0`` at t = 0. ``events['t_stop']`` is
    the time of rest (s; None if the body still moves at ``t_max``), ``events['stop_position']``
    the CM there (m). ``rtol`` scales the error control: positions by the sliding distance scale,
    velocities by the initial speed, angles by pi, spin by the initial rotation rate. ``stepper``
    (:data:`FREE_STEPPERS`): "auto" (DOP853, switching to RODAS4 where stiff), "dop853" or "rodas".
    A body on point feet also reports ``events['pivots']`` (:mod:`rrbody.integrate.pivot`; its run
    shows no progress bar: it goes one accepted step at a time). An active body with noise (or with
    ``scene.noise_dt``) takes fixed steps of :mod:`rrbody.integrate.sde` (``rtol`` unused; ``meta``
    records the step ``dt``, the ``seed`` and the ``scheme``).
    """
    if scene.driven:
        raise ValueError("simulate_free needs a free scene (drive=None); use rrbody.simulate for driven ones")
    if stepper not in FREE_STEPPERS:
        raise ValueError(f"stepper must be one of {', '.join(repr(m) for m in FREE_STEPPERS)} for a free body "
                         f"(Radau IIA is the driven body's stiff method), got {stepper!r}")
    sde = uses_sde(scene)
    if sde and stepper != "auto":
        raise ValueError(f"stepper must be 'auto' for an active body with noise (it runs with the fixed steps "
                         f"of rrbody.integrate.sde, set by the scene's noise_dt), got {stepper!r}")
    a = scene.active
    if a is not None and scene.friction.active and scene.friction.law == "dry" and a.force <= scene.friction.coeff * \
            math.cos(scene.tilt) * scene.body.mass:
        # an active body the plane's dry friction can stop has no rest rule here: the plugin path has one
        raise ValueError(f"active force must exceed the dry friction mu g m = "
                         f"{scene.friction.coeff * math.cos(scene.tilt) * scene.body.mass!r} N on the ODE path (which "
                         f"has no rest rule for an active body; run it with method='engine'), got {a.force!r} N")
    p, S = ode_params(scene)
    body = scene.body
    icm = body.inertia_per_mass
    rmax = max(body.semi_axes)
    v0 = np.array(scene.v0, dtype=np.float64)
    w0 = scene.spin0
    y = np.array([0.0, 0.0, body.alpha0, v0[0], v0[1], w0])
    f = np.empty(6)
    free_rhs(0.0, y, p, S, f)
    # the rest rule (a stop in finite time) is dry friction's, a law that sticks (the law table's); an active
    # body is driven on by its propulsion
    dry = scene.friction.active and scene.friction.spec.sticks and scene.active is None
    pull = math.hypot(p[P.GTX], p[P.GTY])  # gravity along a tilted plane (m/s^2)
    t_start = 0.0
    rests = False  # an active body static friction holds at rest: it stays there (its load is constant)
    if a is not None and scene.friction.active and scene.friction.spec.sticks and v0[0] == v0[1] == w0 == 0.0:
        # launched at rest: the propulsion is a load like a tilt's pull; static friction holds the sum or
        # the body breaks away along the maximum-dissipation acceleration (as on the plugin path)
        held = _held_at_rest(scene, p, active=True)
        if held[3] and sde:
            raise ValueError(f"v0 and spin0 must not both be zero for an active body with noise whose load static "
                             f"friction holds at rest (propulsion {a.force!r} N, static friction up to "
                             f"{p[P.MUS] * scene.body.mass!r} N): the ODE path's noise has no rest rule; run it "
                             f"with method='engine'")
        if held[3]:
            rests = True
        elif not sde:  # (the fixed-step noise scheme starts at t = 0: there friction is regularised at rest)
            t_start = _break_away(y, held, 1e-6 * t_max, icm)
            v0 = y[3:5].copy()
            w0 = y[5]
            free_rhs(t_start, y, p, S, f)
    if dry and pull > 0.0 and v0[0] == v0[1] == w0 == 0.0:
        held = _held_at_rest(scene, p)
        if not held[3]:
            # released at rest and not held: it starts along the break-away acceleration
            t_start = _break_away(y, held, 1e-6 * t_max, icm)
            v0 = y[3:5].copy()
            w0 = y[5]
            free_rhs(t_start, y, p, S, f)
    # speed scale: translation plus rotation (gyration radius for bodies with inertia), and what the
    # tilt's pull adds over the run
    u0 = math.hypot(v0[0], v0[1]) + math.sqrt(icm) * abs(w0)
    if scene.active is not None:  # what the propulsion adds over the run (or up to its drag's terminal speed)
        gam = max(scene.active.drag, 1.0 / t_max)
        u0 = max(u0, scene.active.force / (body.mass * gam))
        if icm > 0.0:
            w0 = max(abs(w0), abs(scene.active.torque) / (body.mass * icm * max(scene.active.rot_drag, 1.0 / t_max)))
    if pull > (p[P.COEFF] if dry else 0.0):  # kinetic friction cannot stop it: it speeds up downhill
        u0 = max(u0, (pull - (p[P.COEFF] if dry else 0.0)) * t_max)
    decel = scene.friction.coeff if dry else (scene.friction.coeff * max(u0, 1e-300) if scene.friction.active else 0.0)
    t_scale = min(t_max, u0 / decel) if decel > 0.0 and u0 > 0.0 else t_max
    length = max(rmax, u0 * t_scale, 1e-300)
    wscale = max(abs(w0), u0 / max(rmax, 1e-300) if rmax > 0.0 else abs(w0), 1e-300)
    uscale = max(u0, wscale * rmax, 1e-300)
    scale = rtol * np.array([length, length, math.pi, uscale, uscale, wscale])
    rates = [r for r in (abs(w0), decel / max(u0, 1e-300) if decel > 0 else 0.0) if r > 0.0]
    st = new_loop_state(1e-3 / max(rates) if rates else t_max, STEP_METHODS[stepper])
    st[L_T] = t_start
    ev = new_event_state(scene.phi0, 0.0)
    n_out = int(math.floor(t_max / dt_out + 1e-9)) + 1
    out = np.empty((n_out, 7))
    # above the kernels' zero-speed threshold v_eps, below which dry friction is switched off
    u_stop = max(STOP_SPEED_FRACTION * max(u0, 1e-300), 10.0 * p[P.VEPS])
    t0 = time.perf_counter()
    n_breaks = 0  # stops static friction could not hold, each followed by a break-away
    pivots: list[dict[str, object]] | None = None  # a body on feet: its pivots (rrbody.integrate.pivot)
    h_sde = 0.0
    if sde:  # Langevin noise: fixed steps of the stochastic scheme, the same right-hand side
        status, h_sde = run_sde(scene, p, S, y, st, out, t_max=t_max, dt_out=dt_out, max_steps=max_steps,
                                progress=progress)
    elif (u0 == 0.0 and dry) or rests:
        ev[E_TSTOP] = 0.0
        status = 1
        out[:, 0] = np.arange(n_out) * dt_out
        out[:, 1:] = y
        out[:, 4:7] = 0.0
        st[L_NOUT] = n_out
    elif (feet := feet_of(S) if dry and int(p[P.BODY]) == P.BODY_CONTACT else None) is not None:
        # on point feet: sliding, pivoting on a foot and breaking away, one accepted step at a time
        # (rrbody.integrate.pivot); the stop and a break-away from it as below
        def held(alpha: float) -> tuple[float, float, float, bool]:
            return (0.0, 0.0, 0.0, True) if pull == 0.0 else _held_at_rest(scene, p, alpha)

        run_feet = FeetRun(p, S, feet, y, f, st, ev, out, dt_out=dt_out, t_max=t_max, rtol=rtol, scale=scale,
                           mode=STEP_METHODS[stepper], u_stop=u_stop, t_scale=t_scale, max_steps=max_steps, held=held,
                           break_from_rest=lambda yy, h: _break_away(yy, h, 1e-6 * t_max, icm, rotate=yy[2]))
        status = run_feet.go()
        n_breaks = run_feet.n_breaks
        pivots = run_feet.pivots
    else:
        minima = np.empty((0, 2))
        run = advance_for(system_from_params(p, SYSTEM_FREE))

        def go() -> int:
            return run_in_chunks(
                lambda n: run(y, f, st, ev, p, S, t_max, STOP_REST if dry else STOP_T_END, 0.0, 0.0, rtol, scale, -1,
                              math.inf, n, minima, out, dt_out, STEP_METHODS[stepper], u_stop),
                st, max_steps, progress=progress, total=t_max, desc="free body")

        status = go()
        while status == 1 and dry and pull > 0.0 and ev[E_TSTOP] < t_max:
            held = _held_at_rest(scene, p, y[2])
            if held[3]:
                break
            # came to rest where static friction cannot hold it (thrown up a steep slope): it breaks
            # away from the stop. The loop wrote the samples after the stop as rest: drop them, and
            # go on from the stop along the break-away acceleration
            t_stop = float(ev[E_TSTOP])
            n_keep = int(np.count_nonzero(out[:int(st[L_NOUT]), 0] <= t_stop))
            st[L_NOUT] = n_keep
            st[L_NEXTOUT] = n_keep * dt_out
            st[L_T] = t_stop + _break_away(y, held, 1e-6 * t_max, icm, rotate=y[2])
            ev[E_TSTOP] = math.nan
            free_rhs(st[L_T], y, p, S, f)
            n_breaks += 1
            status = go()
    wall = time.perf_counter() - t0
    n_done = int(st[L_NOUT])
    if status == 1 and n_done < n_out:
        # at rest: the remaining samples repeat the final state exactly (no drift)
        rest = np.empty((n_out - n_done, 7))
        rest[:, 0] = np.arange(n_done, n_out) * dt_out
        rest[:, 1:] = y
        out[n_done:] = rest
        n_done = n_out
    o = out[:n_done]
    if status in (0, 1) and (n_done == 0 or t_max - o[-1, 0] > 1e-9 * dt_out):
        o = np.vstack([o, np.concatenate([[t_max], y])])  # end on the horizon asked for
    t = o[:, 0]
    alpha = o[:, 3]
    beta = scene.phi0 - body.alpha0
    phi = alpha + beta
    l = body.l
    traj = Trajectory(t=t, phi=phi, phi_dot=o[:, 6].copy(), x_cm=o[:, 1], y_cm=o[:, 2], vx_cm=o[:, 4], vy_cm=o[:, 5],
                      x_p=o[:, 1] + l * np.cos(phi), y_p=o[:, 2] + l * np.sin(phi), body_angle=alpha,
                      spin=o[:, 6].copy(), meta={"scene": scene.describe(), "rrbody_version": __version__})
    stopped = status == 1 and math.isfinite(ev[E_TSTOP])
    statuses = {0: "reached t_end", 1: "came to rest", 3: f"max_steps reached (cap max_steps={max_steps})",
                4: "step size underflow"}
    traj.events = {
        "t_stop": float(ev[E_TSTOP]) if stopped and ev[E_TSTOP] <= t_max else None,
        "stop_position": [float(y[0]), float(y[1])] if stopped else None,
        "distance": float(math.hypot(y[0], y[1])) if stopped else None,
        "turn": float(y[2] - body.alpha0) if stopped else None,
    }
    traj.meta = {**traj.meta, "method": "ode", "rtol": rtol, "status": statuses.get(status, str(status)),
                 "n_steps": int(st[L_NSTEP]), "n_rejected": int(st[L_NREJ]), "wall_s": wall}
    if sde:
        traj.meta.update(scheme="SRA1 (fixed steps, rrbody.integrate.sde)", dt=h_sde, seed=scene.seed)
        del traj.meta["rtol"]
    if status in (3, 4):
        traj.meta["warning"] = (f"integration stopped early: {statuses[status]} at t={st[L_T]:.6g} s "
                                f"after {wall:.3g} s of computing")
    traj.events["break_aways"] = n_breaks
    if pivots is not None:
        traj.events["pivots"] = pivots
    return traj


def _break_away(y: np.ndarray, held: tuple[float, float, float, bool], tau: float, icm: float,
                rotate: float | None = None) -> float:
    """Set the state ``y`` (at rest) to the motion tau seconds after a break-away with the
    acceleration ``held[:3]`` (m/s^2 body frame, rad/s^2; rotated into the world frame by the body
    angle ``rotate``, default the state's own): constant at first, so exact to O(tau^2 da/dt), and
    moving, so dry friction has a direction again. Returns tau (s)."""
    a = y[2] if rotate is None else rotate
    c, s = math.cos(a), math.sin(a)
    ax, ay = c * held[0] - s * held[1], s * held[0] + c * held[1]
    aw = held[2] if icm > 0.0 else 0.0
    y[0] += 0.5 * ax * tau * tau
    y[1] += 0.5 * ay * tau * tau
    y[2] += 0.5 * aw * tau * tau
    y[3], y[4], y[5] = ax * tau, ay * tau, aw * tau
    return tau


def _held_at_rest(scene: Scene, p: np.ndarray, alpha: float | None = None, *,
                  active: bool = False) -> tuple[float, float, float, bool]:
    """(ax, ay, spin', held) of the scene's body at rest at angle ``alpha`` (default its start) under
    gravity's pull along the tilted plane (and, with ``active``, its propulsion and the propulsion's
    torque): held by static friction (then zeros), or the break-away acceleration (m/s^2, body frame;
    rad/s^2)."""
    F = packed(scene.body, scene.pressure)
    a = scene.body.alpha0 if alpha is None else float(alpha)
    c, s = math.cos(a), math.sin(a)
    gx, gy = p[P.GTX], p[P.GTY]
    icm = scene.body.inertia_per_mass
    lx, ly, lt = c * gx + s * gy, -s * gx + c * gy, 0.0
    if active:  # the propulsion per unit mass (body frame) and its torque per unit mass (m^2/s^2)
        lx += p[P.AFX]
        ly += p[P.AFY]
        lt = p[P.AALPHA] * icm
    # a point mass's spin is kinematic: any positive j serves its (torque-free) metric
    return at_rest(F, F, HEADER, HEADER + int(F[0, H_PARTS]), lx, ly, lt, icm if icm > 0.0 else 1.0, p[P.MUS],
                   p[P.COEFF])
