"""Flip time, the reverse-rotation (RR) test and the critical geometry H_c (docs/physics.md, "Definitions
rrbody fixes").

Definitions
-----------
- **Flip time** t_f: time of the global minimum of phi(t), reported whenever phi falls below
  phi0 at all (including the paper's low-omega "incomplete RR"); None when phi never does. The run stops once the flip
  is settled (see :mod:`rrbody.ode`, rule ``"flip"``): phi has risen ``settle_turns`` full turns above its lowest
  minimum and ``settle_periods`` driving periods have passed since it.
- **RR exists** iff T_1 (first time theta = phi - omega t + pi has fallen by 2 pi) exists and
  omega T_1 < 2 pi. Exact in the frictionless limit (see :func:`frictionless_T1`).
- **H_c(k)**: the RR/no-RR boundary met first when H grows from small values (RR exists for all
  H below it), found by a grid scan and bisection. Without friction it is the only boundary: for
  every H above H_c(0) the mean spin over the first revolution is positive (tending to zero as
  H -> infinity).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from rrbody.analysis.simulate import resolve_rtol
from rrbody.integrate.events import FlipResult, classify_flip, rr_from_T1
from rrbody.integrate.ode import STEP_METHODS, integrate_driven
from rrbody.model.checks import check, check_positive
from rrbody.model.scene import Scene, rod_mass_scene
from rrbody.physics.bind import ode_params

__all__ = ["flip_time", "reverse_rotation_exists", "critical_h", "critical_h_of", "frictionless_T1",
           "frictionless_critical_h", "without_phantom_minimum"]


def without_phantom_minimum(res: FlipResult) -> FlipResult:
    """``res`` with ``phi_min`` NaN when phi had no minimum in the run (``t_phi_min`` NaN: phi fell all
    along, or the run stopped before phi turned): the event rules give phi0 there, a value phi was not at
    its lowest, which must not be read beside a missing time. JSON shows both as null."""
    if math.isnan(res.t_phi_min) and not math.isnan(res.phi_min):
        return replace(res, phi_min=math.nan)
    return res


def flip_time(scene: Scene, *, rtol: float | None = None, accuracy: str = "default", t_max: float | None = None,
              settle_turns: float = 2.0, settle_periods: float = 3.0, max_steps: int = 50_000_000,
              progress: bool = False, stepper: str = "auto") -> FlipResult:
    """Flip time of a driven scene by the direct ODE path.

    ``t_max`` (s; default ``scene.t_max``, else unbounded) caps the horizon; without friction there
    is no flip and only the RR question is answered. The minimum's time and value are located to
    the integrator's accuracy (Newton on the step size; see :mod:`rrbody.integrate.ode`).
    ``stepper``: ``"auto"`` (DOP853 with automatic switching to the stiff Radau IIA), ``"dop853"``,
    ``"radau"`` or ``"rodas"`` (:data:`rrbody.integrate.ode.STEP_METHODS`). A body with l = 0 (P at the CM) is
    answered at once: the drive exerts no torque about P, so there is no reverse rotation to end.
    """
    if not scene.driven:
        raise ValueError("flip_time needs a driven scene (drive is None: a free body has no flip)")
    if stepper not in STEP_METHODS:
        raise ValueError(f"stepper must be one of {', '.join(repr(m) for m in STEP_METHODS)}, got {stepper!r}")
    rtol_v = resolve_rtol(rtol, accuracy)
    max_steps = int(check("max_steps", max_steps))  # NaN, negative or fractional would disable the cap
    if scene.body.l == 0.0:
        regime = ("l = 0: P is at the CM, so the drive exerts no torque about P and phi (the body angle) only "
                  "spins down under friction: no reverse rotation, no flip")
        return FlipResult(None, scene.phi0, 0.0, False, None, True, regime, 0.0, 0, 0, rtol_v, 0.0, np.empty((0, 2)))
    settle_turns = float(check("settle_turns", settle_turns))
    settle_periods = float(check("settle_periods", settle_periods))
    horizon = t_max if t_max is not None else scene.t_max
    horizon = math.inf if horizon is None else check_positive("t_max", horizon, unit="s")
    p, S = ode_params(scene)
    y0 = (scene.phi0, scene.initial_phi_dot)
    if not scene.friction.active:
        res = integrate_driven(p, S, y0, t_end=min(horizon, 2.0 * scene.drive.period), rtol=rtol_v,  # type: ignore[union-attr]
                               stop="rr", max_steps=max_steps, method=stepper)
        _, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                        phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                        t_end=res.t_end)
        return without_phantom_minimum(FlipResult(None, phi_min, res.t_min, rr, res.T1 if math.isfinite(res.T1)
                                                  else None, settled, regime, res.t_end, res.n_steps,
                                                  res.n_minima, rtol_v, res.wall, res.minima))
    res = integrate_driven(p, S, y0, t_end=horizon, rtol=rtol_v, stop="flip", settle_turns=settle_turns,
                           settle_periods=settle_periods, max_steps=max_steps, progress=progress, desc="flip time",
                           method=stepper)
    t_f, regime, rr, settled, phi_min = classify_flip(scene, status=res.status, has_min=res.has_min,
                                                      phi_min=res.phi_min, t_min=res.t_min, T1=res.T1,
                                                      t_end=res.t_end)
    T1 = res.T1 if math.isfinite(res.T1) else None
    return without_phantom_minimum(FlipResult(t_f, phi_min, res.t_min, rr, T1, settled, regime, res.t_end,
                                              res.n_steps, res.n_minima, rtol_v, res.wall, res.minima))


def reverse_rotation_exists(scene: Scene, *, rtol: float | None = None, accuracy: str = "default") -> bool:
    """T_1 exists and omega T_1 < 2 pi. Integrates at most one driving period."""
    p, S = ode_params(scene)
    res = integrate_driven(p, S, (scene.phi0, scene.initial_phi_dot), t_end=1.01 * scene.drive.period,  # type: ignore[union-attr]
                           rtol=resolve_rtol(rtol, accuracy), stop="rr")
    return rr_from_T1(res.T1, scene.omega)


def critical_h(k: float, omega: float, *, phi0: float = math.pi, friction: str = "dry", tol: float = 1e-9,
               rtol: float | None = None, accuracy: str = "default", H_lo: float = 1e-3, H_hi: float = 1.0,
               n_scan: int = 64) -> float:
    """H_c(k) for the rod-mass body: first RR -> no-RR boundary as H grows from ``H_lo``.

    The scan over ``n_scan`` log-spaced H in [H_lo, H_hi] brackets the boundary; bisection then
    narrows it to ``tol`` (absolute, in H). Raises ValueError if no boundary lies in the range.
    """
    return critical_h_of(lambda H: rod_mass_scene(H, k, omega, phi0, friction=friction), tol=tol, rtol=rtol,
                         accuracy=accuracy, H_lo=H_lo, H_hi=H_hi, n_scan=n_scan, what=f"k={k:g}, omega={omega:g}")


def critical_h_of(scene_at: Callable[[float], Scene], *, tol: float = 1e-9, rtol: float | None = None,
                  accuracy: str = "default", H_lo: float = 1e-3, H_hi: float = 1.0, n_scan: int = 64,
                  what: str = "") -> float:
    """H_c of any family of scenes ``scene_at(H)`` (a body whose H = I_P / (m d l) is set by H, e.g.
    a polygon with fixed l whose drive radius d = I_P / (m H l) varies at fixed k): the first RR ->
    no-RR boundary as H grows from ``H_lo`` (the scan and bisection of :func:`critical_h`)."""
    tol = float(check("tol", tol))
    H_lo = check_positive("H_lo", H_lo)
    H_hi = check_positive("H_hi", H_hi)
    if not H_hi > H_lo:
        raise ValueError(f"H_hi must be > H_lo={H_lo:g}, got {H_hi!r}")

    def rr(H: float) -> bool:
        return reverse_rotation_exists(scene_at(H), rtol=rtol, accuracy=accuracy)

    grid = np.geomspace(H_lo, H_hi, n_scan)
    if not rr(float(grid[0])):
        raise ValueError(f"no reverse rotation even at H_lo={H_lo:g}{' (' + what + ')' if what else ''}; lower H_lo")
    a = float(grid[0])
    b = None
    for H in grid[1:]:
        if rr(float(H)):
            a = float(H)
        else:
            b = float(H)
            break
    if b is None:
        raise ValueError(f"reverse rotation persists up to H_hi={H_hi:g}; raise H_hi")
    while b - a > tol:
        m = 0.5 * (a + b)
        if rr(m):
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def frictionless_T1(H: float, omega: float) -> float:
    """Exact T_1 without friction from phi0 = pi (s): 4 H K(m) / (omega (H + 1)), m = 4H/(H+1)^2.

    The rotating-frame pendulum H theta'' = -omega^2 sin(theta) starts at the bottom with
    theta' = -omega (1 + 1/H); one revolution takes a complete elliptic integral K(m).
    """
    from scipy.special import ellipk

    return 4.0 * H * float(ellipk(4.0 * H / (H + 1.0) ** 2)) / (omega * (H + 1.0))


def frictionless_critical_h() -> float:
    """H_c(0) = 0.79272623...: root of 2 H K(4H/(H+1)^2) = pi (H + 1) (phi0 = pi)."""
    from scipy.optimize import brentq
    from scipy.special import ellipk

    return float(brentq(lambda H: 2 * H * ellipk(4 * H / (H + 1) ** 2) - math.pi * (H + 1), 0.3, 0.99, xtol=1e-15))
