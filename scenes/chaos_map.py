"""Chaos map: the maximal Lyapunov exponent and the fraction of time in reverse rotation over (tilt, omega).

The rod-mass body of ``rrbody scene chaos`` (H = 0.5, frictionless, on a plane tilted downhill
along +x) on a 100 x 100 grid: tilt in [0, 1] rad, omega in [0.5, 4] rad/s. Per point the sweep
quantity ``chaos`` (:mod:`rrbody.analysis.chaos_map`): 20 driving periods of transient, then the
tangent-method exponent averaged over 200 periods and the spin sampled 32 times a period (reverse
rotation: phi' omega < 0). The same sweep as ``rrbody sweep --quantity chaos`` and the benchmark
``chaos_map`` (benchmarks/chaos_map.py) time. Output: results/chaos-map/ (chaos_map.nc with its
sidecar, chaos_map.png/.svg, summary.json).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

H = 0.5
TILTS = tuple(float(x) for x in np.linspace(0.0, 1.0, 100))   # rad
OMEGAS = tuple(float(x) for x in np.linspace(0.5, 4.0, 100))  # rad/s
OPTIONS: dict[str, Any] = {"periods": 200, "transient": 20, "rr_samples": 32}


def sweep(tilts: tuple[float, ...] = TILTS, omegas: tuple[float, ...] = OMEGAS) -> Any:
    """The map's :class:`rrbody.analysis.sweep_spec.Sweep` (smaller grids for tests and quick benchmarks)."""
    from rrbody.analysis.sweep_spec import Sweep

    return Sweep(base={"H": H, "k": None, "friction": "none"}, axes={"tilt": tilts, "omega": omegas},
                 quantity="chaos", options=dict(OPTIONS))


def main(out_dir: Path, *, force: bool = True) -> None:
    from rrbody.analysis.report import write_summary
    from rrbody.analysis.sweep import run_fresh_or_resume
    from rrbody.render.chaos_map import chaos_map_arrays, plot_chaos_map

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    table = out_dir / "chaos_map.nc"
    run_fresh_or_resume(sweep(), table)
    a = chaos_map_arrays(table)
    lam, floor, rr = a["lambda_max"], a["lambda_floor"], a["rr_fraction"]
    chaotic = lam > 10.0 * floor  # well above what a regular orbit's estimate decays to over the span
    write_summary(out_dir, {
        "H": H, "friction": "none", "tilt_rad": [TILTS[0], TILTS[-1], len(TILTS)],
        "omega_rad_per_s": [OMEGAS[0], OMEGAS[-1], len(OMEGAS)], "options": OPTIONS,
        "points": int(lam.size), "errors": int(np.count_nonzero(~np.isfinite(lam))),
        "chaotic_points (lambda_max > 10 log(T)/T)": int(np.count_nonzero(chaotic)),
        "lambda_max_largest": float(np.nanmax(lam)),
        "relative_spread_median_chaotic": float(np.nanmedian(a["lambda_spread"][chaotic] / lam[chaotic]))
        if chaotic.any() else None,
        "rr_fraction_range": [float(np.nanmin(rr)), float(np.nanmax(rr))]}, force=force)
    for ext in ("png", "svg"):
        plot_chaos_map(table, out_dir / f"chaos_map.{ext}", force=True,
                       title=f"Tilted driven rod-mass, H = {H:g}, no friction: {len(TILTS)} x {len(OMEGAS)} points, "
                             f"{OPTIONS['transient']} + {OPTIONS['periods']} driving periods each")


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "chaos-map")
