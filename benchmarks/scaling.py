"""Scaling: how the cost of one flip time grows with the number of driving periods omega t_f / (2 pi).

Two series of rod-mass scenes (dry friction, phi0 = pi, d = 1 m), each run with the default
settings of ``rrbody flip-time`` (rtol = ACCURACY['default']):

- fast driving: H = 0.25, k = 7.5, omega from 3 to 1000 rad/s (t_f grows with omega);
- weak friction: H = 0.2, omega = 0.6, k from 0.1 down to 0.0005 (t_f grows like 1/k).

The cost counted is the wall time of ``flip_time`` (best of up to 3 after compilation), which
includes the settling run after the minimum; the observed exponent is the least-squares slope of
log(cost) against log(periods), over the points costing more than 5 ms (below that the fixed cost
of a call dominates). The scaling with the number of area elements is in the ``area`` and
``engine`` studies.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

from .common import StudyResult, best_time, fmt, loglog_slope, machine_text, md_table, save_figure, write_csv

NAME = "scaling"
TITLE = "Scaling: cost of one flip time vs number of driving periods"

SERIES: dict[str, dict[str, Any]] = {
    "fast driving (H=0.25, k=7.5)": {"H": 0.25, "k": [7.5], "omega": [3.0, 10.0, 30.0, 100.0, 300.0, 1000.0]},
    "weak friction (H=0.2, w=0.6)": {"H": 0.2, "k": [0.1, 0.03, 0.01, 0.003, 0.001, 0.0005], "omega": [0.6]},
}


def run(out: Path, *, quick: bool = False) -> StudyResult:
    from rrbody.analysis.flip import flip_time
    from rrbody.analysis.simulate import ACCURACY
    from rrbody.model.scene import rod_mass_scene

    t0 = time.perf_counter()
    flip_time(rod_mass_scene(0.2, 0.05, 0.6), rtol=1e-6)   # compile
    rows: list[dict[str, Any]] = []
    slopes: list[tuple[str, float, int]] = []
    for label, spec in SERIES.items():
        pts = [(k, w) for k in spec["k"] for w in spec["omega"]]
        if quick:
            pts = pts[:3]
        series = []
        for k, w in pts:
            sc = rod_mass_scene(spec["H"], k, w)
            wall, res = best_time(lambda: flip_time(sc), max_repeats=3, min_total=0.05)
            periods = w * (res.t_f or math.nan) / (2 * math.pi)
            row = {"series": label, "H": spec["H"], "k": k, "omega": w, "t_f": res.t_f, "periods_to_flip": periods,
                   "periods_integrated": w * res.t_stop / (2 * math.pi),
                   "t_stop": res.t_stop, "n_steps": res.n_steps, "wall_s": wall,
                   "us_per_step": wall / max(res.n_steps, 1) * 1e6, "rtol": res.rtol}
            print(f"[scaling] {label}: k={k:g} w={w:g}: t_f={res.t_f} periods={periods:.3g} wall={wall:.4f} s",
                  flush=True)
            rows.append(row)
            series.append(row)
        big = [r for r in series if r["wall_s"] > 5e-3 and math.isfinite(r["periods_to_flip"])]
        slopes.append((label, loglog_slope([r["periods_to_flip"] for r in big], [r["wall_s"] for r in big]),
                       loglog_slope([r["periods_integrated"] for r in big], [r["wall_s"] for r in big]), len(big)))
    files = [str(write_csv(out / "scaling.csv", rows))]
    files.append(str(_plot(out / "scaling.png", rows)))
    md = [f"## {TITLE}", "", machine_text(), "",
          f"Default settings of `rrbody flip-time` (rtol = {fmt(ACCURACY['default'])}); cost = wall time of one "
          "`flip_time` call including the settling run after the minimum (best of up to 3).", "",
          md_table(["series", "k", "omega", "t_f (s)", "periods to flip", "periods integrated", "steps", "wall (s)",
                    "us/step"],
                   [(r["series"], r["k"], r["omega"], r["t_f"], r["periods_to_flip"], r["periods_integrated"],
                     r["n_steps"], r["wall_s"], r["us_per_step"]) for r in rows]), "",
          "Observed exponent (cost ~ periods^p, fit over calls costing > 5 ms; 'integrated' counts the settling "
          "run too): " + "; ".join(
              f"{lab}: p = {fmt(s1)} vs periods to flip, {fmt(s2)} vs periods integrated ({n} points)"
              for lab, s1, s2, n in slopes) + ".", "",
          "Plot: `scaling.png`; data: `scaling.csv`."]
    res = StudyResult(NAME, TITLE, [], "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    res.extra = {"slopes": slopes, "highlights": [
        "cost of one flip time ~ (driving periods integrated)^p: " + "; ".join(
            f"{lab}: p = {fmt(s2)}" for lab, _s1, s2, _n in slopes)
        + f"; ~{fmt(float(sum(r['us_per_step'] for r in rows) / len(rows)))} us per step."]}
    return res


def _plot(path: Path, rows: list[dict[str, Any]]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for label, mk in zip(SERIES, "os"):
        rs = [r for r in rows if r["series"] == label and math.isfinite(r["periods_to_flip"])]
        if rs:
            ax.loglog([r["periods_to_flip"] for r in rs], [r["wall_s"] for r in rs], marker=mk, label=label)
    ax.set_xlabel("driving periods to the flip, omega t_f / 2 pi")
    ax.set_ylabel("wall time of one flip_time call (s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Cost of one flip time (default rtol)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path
