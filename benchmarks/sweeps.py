"""Sweeps: time of H_c sweeps (the ``Hc`` scene's workload) and flip-time sweeps vs worker processes.

1. H_c(k) at omega = 0.3 rad/s, phi0 = pi, tol = 1e-6 on H (the issue's accuracy), H_lo = 1e-4,
   dry and viscous, with :func:`rrbody.sweep.run_sweep` on 1 and 2 local worker processes, over N
   values of k in [0.005, 2] per law. The issue's target ("the Hc scene, dry and viscous, >= 50 k
   values each, H_c to 1e-6, under 2 min on 2 cores") is that workload itself: 50 values of the
   friction parameter k per law, timed directly (not extrapolated).
2. Where the time of one H_c goes: the number of RR tests one :func:`rrbody.analysis.critical_h`
   call makes and the cost of one RR test (:func:`rrbody.analysis.reverse_rotation_exists`).
3. Flip-time sweep throughput (trajectories per second): a 2-D grid of the phixtpm family
   (omega = 0.6, H in [0.1, 0.4], k in [0.02, 0.2]) on 1 and 2 workers.

Output of the sweeps goes to a temporary folder; only timings are kept.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from .common import StudyResult, Target, best_time, fmt, machine_text, md_table, module_available, write_csv

NAME = "sweeps"
TITLE = "Sweeps: H_c and flip-time sweeps vs worker processes"

TARGET_VALUES = 50   # values of the friction parameter k per law (">= 50 k values each")
TARGET_SECONDS = 120.0


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("rrbody.analysis.sweep")
    if not ok:
        print(f"[sweeps] skipped: rrbody.analysis.sweep not importable ({why})", flush=True)
        return StudyResult(NAME, TITLE, skipped=f"rrbody.analysis.sweep not importable ({why})")
    from rrbody.analysis import flip as analysis
    from rrbody.analysis.sweep import run_sweep
    from rrbody.analysis.sweep_spec import Sweep

    t0 = time.perf_counter()
    # the target workload itself (worker start-up, ~1 s of imports and numba cache, included)
    n_k = 12 if quick else TARGET_VALUES
    n_h, n_kf = (4, 5) if quick else (30, 40)
    ks = tuple(float(x) for x in np.geomspace(0.005, 2.0, n_k))
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory(prefix="rrbody-bench-") as tmp:
        for law in ("dry", "viscous"):
            sw = Sweep(base={"omega": 0.3, "friction": law}, axes={"k": ks}, quantity="critical_h",
                       options={"tol": 1e-6, "H_lo": 1e-4})
            for workers in (1, 2):
                w0 = time.perf_counter()
                run_sweep(sw, Path(tmp) / f"hc_{law}_{workers}.csv", workers=workers, progress=False, force=True)
                wall = time.perf_counter() - w0
                rows.append({"sweep": f"H_c {law}", "points": n_k, "workers": workers, "wall_s": wall,
                             "points_per_s": n_k / wall})
                print(f"[sweeps] H_c {law}, {n_k} k values, {workers} workers: {wall:.1f} s", flush=True)
        fsw = Sweep(base={"omega": 0.6}, axes={"H": tuple(np.linspace(0.1, 0.4, n_h)),
                                               "k": tuple(np.linspace(0.02, 0.2, n_kf))}, quantity="flip_time")
        for workers in (1, 2):
            w0 = time.perf_counter()
            run_sweep(fsw, Path(tmp) / f"tf_{workers}.csv", workers=workers, progress=False, force=True)
            wall = time.perf_counter() - w0
            rows.append({"sweep": "flip_time (phixtpm family)", "points": n_h * n_kf, "workers": workers,
                         "wall_s": wall, "points_per_s": n_h * n_kf / wall})
            print(f"[sweeps] flip_time {n_h * n_kf} points, {workers} workers: {wall:.1f} s", flush=True)

    # ---- the Hc scene itself, as `rrbody scene hc` runs it (its own grid and tolerance) ----
    scene_wall = math.nan
    scene_file = Path(__file__).resolve().parent.parent / "scenes" / "hc.py"
    if not quick and scene_file.exists():
        import importlib.util

        spec = importlib.util.spec_from_file_location("rrbody_bench_scene_hc", scene_file)
        if spec is not None and spec.loader is not None:
            mod = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(mod)
            with tempfile.TemporaryDirectory(prefix="rrbody-bench-") as tmp:
                w0 = time.perf_counter()
                mod.main(Path(tmp), force=True)
                scene_wall = time.perf_counter() - w0
            n_scene = len(mod.np.arange(0.0, mod.K_MAX + mod.DK / 2, mod.DK))
            rows.append({"sweep": f"Hc scene as shipped ({n_scene} k values x 2 laws, tol {mod.TOL:g})",
                         "points": 2 * n_scene, "workers": 1, "wall_s": scene_wall,
                         "points_per_s": 2 * n_scene / scene_wall})
            print(f"[sweeps] Hc scene: {scene_wall:.1f} s", flush=True)

    # ---- where one H_c's time goes ----
    calls = [0]
    orig = analysis.reverse_rotation_exists

    def counting(*a: Any, **kw: Any) -> bool:
        calls[0] += 1
        return orig(*a, **kw)

    per_hc = []
    analysis.reverse_rotation_exists = counting  # type: ignore[assignment]
    try:
        for k in (0.01, 0.1, 1.0):
            calls[0] = 0
            analysis.critical_h(k, 0.3, tol=1e-6, H_lo=1e-4)
            n_tests = calls[0]
            w, _ = best_time(lambda: analysis.critical_h(k, 0.3, tol=1e-6, H_lo=1e-4), max_repeats=3, min_total=1.0)
            per_hc.append({"k": k, "rr_tests": n_tests, "wall_s": w})
    finally:
        analysis.reverse_rotation_exists = orig  # type: ignore[assignment]
    from rrbody.analysis.simulate import ACCURACY
    from rrbody.model.scene import rod_mass_scene

    # how loose may the RR test's rtol be for H_c to 1e-6? (reference: rtol 1e-13, tol 1e-9)
    tol_rows = []
    for law in ("dry", "viscous"):
        for k in ((0.1, 1.0) if not quick else (0.1,)):
            ref = analysis.critical_h(k, 0.3, friction=law, tol=1e-9, H_lo=1e-4, rtol=1e-13)
            for r in (1e-6, 1e-8, 1e-10, 1e-13):
                w, hc = best_time(lambda: analysis.critical_h(k, 0.3, friction=law, tol=1e-6, H_lo=1e-4, rtol=r),
                                  max_repeats=3)
                tol_rows.append({"law": law, "k": k, "rtol": r, "H_c": hc, "abs_err": abs(hc - ref), "wall_s": w})
    sc = rod_mass_scene(0.1, 0.1, 0.3)
    rr_default, _ = best_time(lambda: analysis.reverse_rotation_exists(sc), min_total=0.1, max_repeats=20)
    rr_loose, _ = best_time(lambda: analysis.reverse_rotation_exists(sc, rtol=1e-8), min_total=0.1, max_repeats=20)
    files = [str(write_csv(out / "sweeps.csv", rows)), str(write_csv(out / "sweeps_hc_cost.csv", per_hc)),
             str(write_csv(out / "sweeps_hc_rtol.csv", tol_rows))]

    hc2 = [r for r in rows if r["sweep"].startswith("H_c") and r["workers"] == 2]
    pps2 = sum(r["points"] for r in hc2) / sum(r["wall_s"] for r in hc2)
    measured = sum(r["wall_s"] for r in hc2) * (TARGET_VALUES / n_k)  # = the measured wall time unless quick
    hc1 = [r for r in rows if r["sweep"].startswith("H_c") and r["workers"] == 1]
    speedup = (sum(r["wall_s"] for r in hc1) / sum(r["wall_s"] for r in hc2)) if hc1 else math.nan
    mean_tests = float(np.mean([r["rr_tests"] for r in per_hc]))
    single = float(np.mean([r["wall_s"] for r in per_hc]))
    ideal = 2 * TARGET_VALUES * single / 2
    targets = [Target("Hc scene: 2 laws x 50 values of k, H_c to 1e-6, on 2 cores", f"< {TARGET_SECONDS:.0f} s",
                      f"{fmt(measured)} s ({fmt(pps2)} H_c/s on 2 workers, {2 * n_k} values"
                      f"{', scaled from the quick run' if quick else ''})",
                      measured < TARGET_SECONDS,
                      f"ideal 2-core time {fmt(ideal)} s; one H_c = ~{mean_tests:.0f} RR tests x "
                      f"{fmt(rr_default * 1e3)} ms; the target needs "
                      f"<= {fmt(2 * TARGET_SECONDS / (2 * TARGET_VALUES) * 1e3)} ms per H_c per core")]
    md = [f"## {TITLE}", "", machine_text(), "",
          "H_c sweeps: omega = 0.3, phi0 = pi, tol = 1e-6, H_lo = 1e-4, k log-spaced in [0.005, 2], default "
          f"rtol ({fmt(ACCURACY['default'])}); `rrbody.sweep.run_sweep` with local worker processes.", "",
          md_table(["sweep", "points", "workers", "wall (s)", "points per s"],
                   [(r["sweep"], r["points"], r["workers"], r["wall_s"], r["points_per_s"]) for r in rows]), "",
          f"Parallel speed-up of the H_c sweeps on 2 workers: {fmt(speedup)}x (shared machine). Projected time of "
          f"the target workload (2 laws x {TARGET_VALUES} values of k) on 2 workers: {fmt(measured)} s "
          f"(target {TARGET_SECONDS:.0f} s).", "",
          "Where one H_c goes (single process, default rtol):", "",
          md_table(["k", "RR tests", "wall (s)"], [(r["k"], r["rr_tests"], r["wall_s"]) for r in per_hc]), "",
          f"Ideal 2-core time of the target workload from the single-process cost per H_c ({fmt(single * 1e3)} ms): "
          f"{fmt(ideal)} s.", "",
          "H_c to tol 1e-6 at looser RR-test tolerances (error against tol 1e-9, rtol 1e-13):", "",
          md_table(["law", "k", "rtol", "H_c", "abs err", "wall (s)"],
                   [(r["law"], r["k"], r["rtol"], fmt(r["H_c"], 10), r["abs_err"], r["wall_s"]) for r in tol_rows]),
          "",
          f"One RR test (H=0.1, k=0.1, w=0.3): {fmt(rr_default * 1e3)} ms at the default rtol, "
          f"{fmt(rr_loose * 1e3)} ms at rtol 1e-8.", "",
          "Data: `sweeps.csv`, `sweeps_hc_cost.csv`, `sweeps_hc_rtol.csv`."]
    diff = max(abs(a["H_c"] - b["H_c"]) for a in tol_rows for b in tol_rows
               if (a["law"], a["k"]) == (b["law"], b["k"]) and b["rtol"] == 1e-13)
    t6 = sum(r["wall_s"] for r in tol_rows if r["rtol"] == 1e-6)
    t13 = sum(r["wall_s"] for r in tol_rows if r["rtol"] == 1e-13)
    hl = [f"H_c to tol 1e-6 differs by at most {fmt(diff)} between RR-test rtol 1e-6 and 1e-13 "
          f"({fmt(t13 / t6)}x cheaper at 1e-6); one H_c = ~{mean_tests:.0f} RR tests (64-point scan + bisection)."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.extra = {"highlights": hl}
    res.wall_s = time.perf_counter() - t0
    return res
