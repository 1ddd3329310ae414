"""What a run's events mean: the flip report shared by every integrator path.

The ODE loop and the engine path both record the lowest minimum of phi, the RR time T_1 and how the
run ended; :func:`classify_flip` turns those into the reported flip by one set of rules, so both
paths report the same events with the same meaning. Times in s, angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from rrbody.model.scene import Scene

__all__ = ["FlipResult", "classify_flip", "rr_from_T1"]


def rr_from_T1(T1: float, omega: float) -> bool:
    """Reverse rotation exists iff T_1 exists and omega T_1 < 2 pi (the mean phi' over the first
    backward revolution of theta is negative)."""
    return math.isfinite(T1) and omega * T1 < 2.0 * math.pi


@dataclass
class FlipResult:
    """Outcome of :func:`flip_time` (s, rad). ``t_f`` is None when there is no flip to report."""

    t_f: float | None
    phi_min: float
    t_phi_min: float
    reverse_rotation: bool
    T1: float | None
    settled: bool
    regime: str
    t_stop: float
    n_steps: int
    n_minima: int
    rtol: float
    wall_s: float
    minima: np.ndarray

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("minima")
        return d


def _rr_from_T1(T1: float, omega: float) -> bool:
    return math.isfinite(T1) and omega * T1 < 2.0 * math.pi


def classify_flip(scene: Scene, *, status: str, has_min: bool, phi_min: float, t_min: float, T1: float,
                  t_end: float) -> tuple[float | None, str, bool, bool, float]:
    """Turn a run's lowest minimum into the reported flip: (t_f, regime, RR exists, settled, phi_min).

    Shared by both integrator paths, so the ODE and the engine report flips by the same rules:
    ``t_f`` is the time of the lowest minimum when the run settled and phi fell below phi0;
    otherwise None, with the regime saying why. Without friction there is never a flip (the run
    only answers the RR question) and ``phi_min`` is passed through as the run found it.
    """
    rr = rr_from_T1(T1, scene.omega)
    if not scene.friction.active:
        regime = ("no friction: reverse rotation is perennial, there is no flip" if rr
                  else "no friction: no reverse rotation")
        return None, regime, rr, False, phi_min
    settled = status == "flip settled"
    turned_back = has_min and phi_min < scene.phi0
    t_f: float | None = None
    if not settled:
        where = "" if " at t=" in status else f" at t={t_end:.6g} s"
        regime = (f"not settled: {status}{where}; " +
                  (f"the lowest minimum so far is at t={t_min:.6g} s, so t_f >= that" if has_min
                   else "phi has had no minimum yet"))
    elif not turned_back:
        regime = "no reverse rotation: phi never falls below phi0 (normal rotation from the start)"
    elif rr:
        regime = "reverse rotation (theta made a full backward turn in the first period), then normal rotation"
        t_f = t_min
    else:
        regime = (f"incomplete reverse rotation: phi fell by {scene.phi0 - phi_min:.4g} rad before turning "
                  "forward (no full backward turn of theta in the first period)")
        t_f = t_min
    return t_f, regime, rr, settled, (phi_min if has_min else scene.phi0)
