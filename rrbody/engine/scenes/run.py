"""The run loop for rrbody's scenes in pymunk: trajectories (:func:`simulate_engine`) and flip times
(:func:`engine_flip_time`) with the ODE path's definitions: events come from the one event detector
(:func:`rrbody.integrate.events.on_step`, called once per engine step, for a driven body from the
compiled per-step tracker :func:`rrbody.engine.scenes.track.track_step`), a free body's rest from the
plugin's rest rule. Units: SI (s, rad, m)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rrbody.engine.memory.bodymem import address, layout
from rrbody.engine.scenes.builder import EngineHandle, attach
from rrbody.engine.scenes.settings import EngineSettings, check_dt, coarse_meta, make_settings
from rrbody.engine.scenes.track import (
    ANG_IN,
    K_OUT,
    MAX_PIV,
    PHI_PREV,
    PHID_PREV,
    REACHED_END,
    REST_IN,
    T_END,
    new_track,
    track_step,
)
from rrbody.integrate.events import (
    E_HAVEMIN,
    E_NMIN,
    E_PHIMIN,
    E_T1,
    E_TMIN,
    E_TSTOP,
    FLIP_SETTLED,
    GO_ON,
    RR_DECIDED,
    STOP_FLIP,
    STOP_REST,
    STOP_RR,
    STOP_T_END,
    new_event_state,
)
from rrbody.model.checks import check, check_positive
from rrbody.model.scene import Scene

__all__ = ["simulate_engine", "engine_flip_time"]


# ---- the run loop ------------------------------------------------------------------------------
@dataclass
class _RunResult:
    t_end: float
    status: str
    phi_min: float
    t_min: float
    has_min: bool
    T1: float
    minima: np.ndarray  # rows (t s, phi rad), the first max_minima local minima of phi
    n_minima: int
    out: np.ndarray
    n_steps: int
    wall: float
    max_pivot_error: float
    t_stop: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)


#: the engine's stop names -> the shared detector's stop rules (rrbody.integrate.events)
_STOPS = {"t_end": STOP_T_END, "flip": STOP_FLIP, "rr": STOP_RR, "rest": STOP_REST}
_STATUS = {FLIP_SETTLED: "flip settled", RR_DECIDED: "RR decided"}


def _run(scene: Scene, settings: EngineSettings, *, t_end: float, stop: str, dt_out: float = 0.0,
         settle_turns: float = 2.0, settle_periods: float = 3.0, max_steps: int = 50_000_000,
         progress: bool = False, max_minima: int = 200_000) -> _RunResult:
    """Step a fresh space holding ``scene`` until ``t_end`` or the ``stop`` rule ("t_end", "flip",
    "rr", "rest"); record the state on the ``dt_out`` grid (linear interpolation between steps).

    Driven events come from the shared detector (:func:`rrbody.integrate.events.on_step`), called once
    per step with (t, phi, phi') at both ends of the step, phi' being the handle's second-order
    velocity (the mean of the two half-step spins): local minima of phi and T_1 are located on the cubic
    Hermite interpolant of (phi, phi') over the step, and the settle and RR stop rules are the ODE
    path's. A free body's rest is the plugin's rest rule (:mod:`rrbody.contact.kernel`); its time goes
    into the same event slot (E_TSTOP) the ODE path's free bodies use.
    """
    import pymunk

    if stop not in _STOPS:
        raise ValueError(f"stop must be one of {', '.join(repr(k) for k in _STOPS)}, got {stop!r}")
    space = pymunk.Space()
    h = attach(space, scene, settings=settings)
    driven = h.driver is not None
    n_grid = int(math.floor(t_end / dt_out + 1e-9)) + 1 if (dt_out > 0.0 and math.isfinite(t_end)) else 0
    # the trajectory ends on t_end itself when the grid k * dt_out misses it (as the ODE path does)
    n_out = n_grid + int(n_grid > 0 and t_end - (n_grid - 1) * dt_out > 1e-9 * dt_out)
    out = np.empty((n_out, 3 if driven else 7))
    # the one event detector: t = 0 is a minimum candidate if phi rises from the start
    ev = new_event_state(scene.phi0, scene.initial_phi_dot) if driven else new_event_state(scene.phi0, 0.0)
    minima = np.empty((max_minima, 2))
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=t_end if math.isfinite(t_end) else None, desc="engine", unit="s(sim)", leave=False,
                   dynamic_ncols=True)
    wall0 = time.perf_counter()
    try:
        if driven:
            fs = new_track(beta=h.beta, anchor=h.anchor, d=scene.drive.d, omega=scene.omega,
                           dt=settings.dt, dt_out=dt_out, n_grid=n_grid, n_out=n_out, t_end=t_end, rule=_STOPS[stop],
                           settle_turns=settle_turns, settle_periods=settle_periods, phi0=h.phi, phid0=h.phi_dot)
            if n_out:
                out[0] = 0.0, fs[PHI_PREV], fs[PHID_PREV]
                fs[K_OUT] = 1
            n, status = _driven_loop(h, fs, ev, minima, out, max_steps, bar)
            k_out, max_piv = int(fs[K_OUT]), float(fs[MAX_PIV])
        else:
            n, status, k_out = _free_loop(h, ev, out, t_end, dt_out, n_grid, stop, max_steps, bar)
            max_piv = 0.0
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - wall0
    n_min = int(ev[E_NMIN])
    return _RunResult(t_end=h.t, status=status, phi_min=float(ev[E_PHIMIN]), t_min=float(ev[E_TMIN]),
                      has_min=bool(ev[E_HAVEMIN]), T1=float(ev[E_T1]), minima=minima[:min(n_min, max_minima)].copy(),
                      n_minima=n_min, out=out[:k_out], n_steps=n, wall=wall, max_pivot_error=max_piv,
                      t_stop=None if math.isnan(ev[E_TSTOP]) else float(ev[E_TSTOP]))


def _driven_loop(h: EngineHandle, fs: np.ndarray, ev: np.ndarray, minima: np.ndarray, out: np.ndarray,
                 max_steps: int, bar: Any) -> tuple[int, str]:
    """Step a driven body until the tracker (:func:`rrbody.engine.scenes.track.track_step`: samples, events,
    pivot error, horizon) or ``max_steps`` stops it; returns (steps, status). Per step: the plugin's
    step and one compiled call."""
    dt = h.settings.dt
    plane = h.plane
    step = plane.step  # friction for the body, then space.step
    t0 = h.t0
    offs = layout()
    addr = address(h.body._body) if offs is not None else 0
    offs = np.zeros(10, dtype=np.int64) if offs is None else offs
    j = plane.row_index(h.body)
    bodies = plane.rows  # the plugin's rows (read-only): fixed while nothing is added to this run's own space
    body = h.body
    if 0.0 >= fs[T_END] - (0.5 * dt if fs[K_OUT] >= out.shape[0] else 1e-12 * dt):  # as track_step's test
        return 0, "reached t_end"
    n = 0
    while n < max_steps:
        step(dt)
        n += 1
        if not addr:  # a pymunk whose body layout is unknown: its getters
            p, v = body.position, body.velocity
            w = body.angular_velocity
            fs[ANG_IN:REST_IN + 1] = body.angle, w, p.x, p.y, float(v.x == 0.0 and v.y == 0.0 and w == 0.0)
        code = track_step(plane.t - t0, addr, offs, j, bodies, fs, ev, minima, out)
        if code != GO_ON:
            return n, ("reached t_end" if code == REACHED_END else _STATUS[code])
        if bar is not None and n % 4096 == 0:
            bar.update(plane.t - t0 - bar.n)
    return n, "max_steps reached"


def _free_loop(h: EngineHandle, ev: np.ndarray, out: np.ndarray, t_end: float, dt_out: float, n_grid: int,
               stop: str, max_steps: int, bar: Any) -> tuple[int, str, int]:
    """Step a free body to ``t_end``, its rest (``stop`` "rest") or ``max_steps``, sampling (x, y, angle,
    vx, vy, spin) onto the output grid; returns (steps, status, output rows written)."""
    dt = h.settings.dt
    n_out = out.shape[0]

    def sample() -> tuple[float, ...]:
        x = h.body.position
        return (x.x, x.y, h.body.angle, *h.velocity())

    t_prev = 0.0
    s_prev = sample()
    k_out = 0
    if n_out:
        out[0, 0] = 0.0
        out[0, 1:] = s_prev
        k_out = 1
    step = h.plane.step  # friction for the body, then space.step
    n = 0
    status = "reached t_end"
    while True:
        if h.t >= t_end - (0.5 * dt if k_out >= n_out else 1e-12 * dt):  # a pending t_end sample: one step on
            break
        if n >= max_steps:
            status = "max_steps reached"
            break
        step(dt)
        n += 1
        t = h.t
        s = sample()
        while k_out < n_out and (k_out * dt_out if k_out < n_grid else t_end) <= t + 1e-12 * dt:
            to = k_out * dt_out if k_out < n_grid else t_end
            w = (to - t_prev) / (t - t_prev)
            out[k_out, 0] = to
            for i in range(len(s)):
                out[k_out, i + 1] = s_prev[i] + w * (s[i] - s_prev[i])
            k_out += 1
        if math.isnan(ev[E_TSTOP]):
            t_rest = h.t_rest
            if t_rest is not None:
                ev[E_TSTOP] = t_rest
                if stop == "rest":
                    status = "at rest"
                    break
        t_prev, s_prev = t, s
        if bar is not None and n % 4096 == 0:
            bar.update(t - bar.n)
    return n, status, k_out


def simulate_engine(scene: Scene, *, t_max: float, dt_out: float, progress: bool = False, dt: float | None = None,
                    iterations: int | None = None, max_steps: int = 50_000_000,
                    point_inertia: float = 1e-9, staggered: bool = True) -> Any:
    """Run ``scene`` in pymunk for ``t_max`` s; return the same :class:`~rrbody.trajectory.Trajectory`
    as the ODE path, sampled every ``dt_out`` s (linear interpolation between engine steps).

    ``dt`` (s; default :func:`default_dt`) and ``iterations`` are the engine settings; a dt above
    :func:`valid_dt_range` raises ValueError, one above COARSE_FRACTION of the shortest motion period
    or above the friction time is labelled ``meta["coarse"] = True`` with a warning. Driven events:
    ``minima`` (every local minimum of phi, located by the shared detector on the cubic Hermite
    interpolant of (phi, phi') over the engine step, :func:`rrbody.integrate.events.on_step`),
    ``phi_min``, ``t_phi_min``, ``T1``, with the ODE path's meanings; free: ``t_stop`` (the plugin's
    rest rule), ``stop_position``, ``distance``, ``turn``, as on the ODE path.
    """
    from rrbody.model.trajectory import Trajectory, driven_trajectory

    max_steps = int(check("max_steps", max_steps))
    settings = make_settings(scene, dt, iterations, point_inertia=point_inertia, staggered=staggered)
    check_dt(scene, settings.dt)
    if t_max / settings.dt > max_steps:
        raise ValueError(f"max_steps must be >= t_max/dt = {t_max / settings.dt:.4g} for this run (dt = "
                         f"{settings.dt:g} s), got {max_steps}; raise it or shorten t_max")
    res = _run(scene, settings, t_end=t_max, stop="t_end", dt_out=dt_out, max_steps=max_steps, progress=progress)
    meta_engine = {"method": "engine", "dt": settings.dt, "iterations": settings.iterations,
                   "point_inertia": settings.point_inertia if scene.body.is_point else None,
                   "status": res.status, "n_steps": res.n_steps, "wall_s": res.wall,
                   **coarse_meta(scene, settings.dt)}
    if scene.driven:
        traj = driven_trajectory(scene, res.out[:, 0], res.out[:, 1], res.out[:, 2])
        minima = res.minima
        i = int(np.argmin(minima[:, 1])) if len(minima) else -1
        best = minima[i] if i >= 0 and minima[i, 1] < scene.phi0 else None
        traj.events = {
            "minima": minima.tolist(),
            "n_minima": res.n_minima,
            "T1": res.T1 if math.isfinite(res.T1) else None,
            "phi_min": float(best[1]) if best is not None else scene.phi0,
            "t_phi_min": float(best[0]) if best is not None else 0.0,
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
    rule (:func:`rrbody.analysis.flip_time`), from the same event detector
    (:func:`rrbody.integrate.events.on_step`): t_f is the time of the lowest minimum of phi, located on
    the cubic Hermite interpolant of (phi, phi') over the engine step. ``t_max`` None: run until settled.
    ``FlipResult.rtol`` is NaN (the engine has a step, not a tolerance)."""
    from rrbody.integrate.events import FlipResult, classify_flip

    if not scene.driven:
        raise ValueError("engine_flip_time needs a driven scene (drive is None: a free body has no flip)")
    settle_turns = float(check("settle_turns", settle_turns))
    settle_periods = float(check("settle_periods", settle_periods))
    max_steps = int(check("max_steps", max_steps))
    settings = make_settings(scene, dt, iterations, point_inertia=point_inertia, staggered=staggered)
    check_dt(scene, settings.dt)
    horizon = t_max if t_max is not None else scene.t_max
    horizon = math.inf if horizon is None else check_positive("t_max", horizon, unit="s")
    assert scene.drive is not None
    if not scene.friction.active:
        res = _run(scene, settings, t_end=min(horizon, 2.0 * scene.drive.period), stop="rr", max_steps=max_steps)
        _, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                        phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                        t_end=res.t_end)
        return FlipResult(None, phi_min, res.t_min, rr, res.T1 if math.isfinite(res.T1) else None, settled,
                          regime, res.t_end, res.n_steps, res.n_minima, math.nan, res.wall, res.minima)
    res = _run(scene, settings, t_end=horizon, stop="flip", settle_turns=settle_turns, settle_periods=settle_periods,
               max_steps=max_steps, progress=progress)
    t_f, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                      phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                      t_end=res.t_end)
    cm = coarse_meta(scene, settings.dt)
    if cm.get("coarse"):
        regime += f" [{cm['warning']}]"
    return FlipResult(t_f, phi_min, res.t_min, rr, res.T1 if math.isfinite(res.T1) else None, settled, regime,
                      res.t_end, res.n_steps, res.n_minima, math.nan, res.wall, res.minima)
