"""Engine step settings for rrbody's scenes: validated parameters, the allowed and default dt, coarse labels.

Units: SI (s). pymunk silently accepts misspelled attributes, so rrbody sets pymunk parameters only
from :class:`EngineSettings`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from rrbody.model.checks import check, check_range
from rrbody.model.scene import Scene

__all__ = ["EngineSettings", "valid_dt_range", "check_dt", "default_dt", "coarse_meta", "make_settings",
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
        Whether the body's shapes take part in collisions (default False: a shape filter that matches
        nothing, as in the ODE model; cheaper than sensors, which still pair up every step).
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
        object.__setattr__(self, "dt", float(check("dt", self.dt)))
        object.__setattr__(self, "iterations", int(check("iterations", self.iterations)))
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
    if not fr.spec.load_scaled:  # a rate (the law table's): viscous friction's gamma
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


def make_settings(scene: Scene, dt: float | None, iterations: int | None, **kw: Any) -> EngineSettings:
    dt_v = default_dt(scene) if dt is None else float(check("dt", dt))
    return EngineSettings(dt=dt_v, iterations=10 if iterations is None else iterations, **kw)


def coarse_meta(scene: Scene, dt: float) -> dict[str, Any]:
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
