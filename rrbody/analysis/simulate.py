"""One entry point: ``simulate(scene, method=...) -> Trajectory``, with a registry of methods.

Methods: ``"ode"`` (the compiled direct ODE path, default) and ``"engine"`` (pymunk, registered by
:mod:`rrbody.engine` when it is imported). An unknown name lists the valid ones.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from rrbody.model.checks import check
from rrbody.model.scene import Scene
from rrbody.model.trajectory import Trajectory, driven_trajectory
from rrbody.physics.bind import ode_params

__all__ = ["simulate", "METHODS", "ACCURACY", "register_method", "default_dt_out", "resolve_rtol"]

#: accuracy presets -> ODE relative tolerance (chosen from benchmarks/results: see docs/accuracy.md)
ACCURACY: dict[str, float] = {"draft": 1e-9, "default": 1e-13, "paper": 1e-14}

#: the most output samples a trajectory may hold (memory: 7 columns of float64, about 1 GB)
MAX_SAMPLES = 20_000_000  # 2e7, as the message says

METHODS: dict[str, str] = {"ode": "rrbody.analysis.simulate:_simulate_ode", "engine": "rrbody.engine:simulate_engine"}
_LOADED: dict[str, Callable[..., Trajectory]] = {}


def register_method(name: str, func: Callable[..., Trajectory]) -> None:
    """Add an integrator path under ``name``."""
    _LOADED[name] = func
    METHODS.setdefault(name, f"{func.__module__}:{func.__name__}")


def _method(name: str) -> Callable[..., Trajectory]:
    if name not in METHODS:
        raise ValueError(f"method must be one of {', '.join(repr(m) for m in METHODS)}, got {name!r}")
    if name not in _LOADED:
        mod, attr = METHODS[name].split(":")
        _LOADED[name] = getattr(importlib.import_module(mod), attr)
    return _LOADED[name]


def resolve_rtol(rtol: float | None, accuracy: str = "default") -> float:
    """The ODE tolerance: an explicit ``rtol`` or the ``accuracy`` preset's."""
    if rtol is not None:
        return float(check("rtol", rtol))
    if accuracy not in ACCURACY:
        raise ValueError(f"accuracy must be one of {', '.join(repr(a) for a in ACCURACY)}, got {accuracy!r}")
    return ACCURACY[accuracy]


def default_dt_out(scene: Scene) -> float:
    """An output interval (s) that resolves the fastest motion: 1/64 of the shortest of the
    driving period and the initial spin period."""
    rates = [scene.omega, abs(scene.initial_phi_dot), abs(scene.spin0)]
    fastest = max(r for r in rates) if max(rates) > 0 else 1.0
    return (2.0 * math.pi / fastest) / 64.0


def simulate(scene: Scene, *, method: str = "ode", t_max: float | None = None, dt_out: float | None = None,
             progress: bool = False, **options: Any) -> Trajectory:
    """Run ``scene`` with ``method`` and return its :class:`Trajectory`.

    ``t_max`` (s) overrides ``scene.t_max``; one of them is required. ``dt_out`` is the sampling
    interval of the returned arrays (default :func:`default_dt_out`). Method options (e.g.
    ``rtol``/``accuracy`` for ``"ode"``, ``dt``/``iterations`` for ``"engine"``) pass through.
    """
    func = _method(method)
    horizon = t_max if t_max is not None else scene.t_max
    if horizon is None:
        raise ValueError("t_max must be given (in the scene or as an argument), got None (valid range: (0, inf))")
    horizon = float(check("t_max", horizon))
    dt = default_dt_out(scene) if dt_out is None else float(check("dt_out", dt_out))
    n = horizon / dt
    if n > MAX_SAMPLES:
        raise ValueError(f"dt_out must be >= t_max / 2e7 = {horizon / MAX_SAMPLES:.4g} s (at most 2e7 "
                         f"samples), got {dt:g} s (t_max = {horizon:g} s)")
    return func(scene, t_max=horizon, dt_out=dt, progress=progress, **options)


def _simulate_ode(scene: Scene, *, t_max: float, dt_out: float, progress: bool = False, rtol: float | None = None,
                  accuracy: str = "default", max_steps: int = 50_000_000, stepper: str = "auto") -> Trajectory:
    """The direct ODE path for driven bodies (compiled DOP853 switching to Radau IIA where stiff; ``stepper``
    forces one: "auto", "dop853", "radau", "rodas"); free bodies go to :mod:`rrbody.integrate.free`."""
    rtol_v = resolve_rtol(rtol, accuracy)
    max_steps = int(check("max_steps", max_steps))
    if not scene.driven:
        from rrbody.integrate.free import simulate_free

        return simulate_free(scene, t_max=t_max, dt_out=dt_out, rtol=rtol_v, max_steps=max_steps, progress=progress,
                             stepper=stepper)
    from rrbody.integrate.ode import integrate_driven

    p, S = ode_params(scene)
    res = integrate_driven(p, S, (scene.phi0, scene.initial_phi_dot), t_end=t_max, rtol=rtol_v, stop="t_end",
                           dt_out=dt_out, max_steps=max_steps, progress=progress, desc="ode", method=stepper)
    out = res.out
    if res.status == "reached t_end" and (len(out) == 0 or t_max - out[-1, 0] > 1e-9 * dt_out):
        # the output grid k * dt_out need not hit t_max: end on the horizon asked for, with the
        # integrator's own state there (the loop steps exactly onto t_end)
        out = np.vstack([out, [[res.t_end, res.y_end[0], res.y_end[1]]]])
    traj = driven_trajectory(scene, out[:, 0], out[:, 1], out[:, 2])
    minima = res.minima
    i = int(np.argmin(minima[:, 1])) if len(minima) else -1
    traj.events = {
        "minima": minima.tolist(),
        "n_minima": res.n_minima,
        "T1": res.T1 if math.isfinite(res.T1) else None,
        "phi_min": float(min(minima[i, 1], scene.phi0)) if i >= 0 else scene.phi0,
        "t_phi_min": float(minima[i, 0]) if i >= 0 and minima[i, 1] < scene.phi0 else 0.0,
    }
    traj.meta = {**traj.meta, "method": "ode", "rtol": rtol_v, "status": res.status, "n_steps": res.n_steps,
                 "n_rejected": res.n_rejected, "wall_s": res.wall}
    if res.status not in ("reached t_end",):
        where = "" if " at t=" in res.status else f" at t={res.t_end:.6g} s"
        traj.meta["warning"] = f"integration stopped early: {res.status}{where}"
    return traj
