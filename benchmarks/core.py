"""Core: per-step cost against a lean DOP853, the stiff case against scipy LSODA, RHS costs.

Three measurements, each interleaved (the contenders alternate within every repeat, so a burst of
load on the shared machine hits both) and reduced to the best of several repeats:

1. **DOP853 step vs a lean compiled DOP853** (``benchmarks/_lean.py``: two states, the point-mass
   right-hand side inline, scipy's tableau, error norm and controller, no events): phixtpm
   (H 0.2, k 0.05, w 0.6) to t = 60 s at rtol 1e-13 with rrbody's loop forced to DOP853
   (``stepper="dop853"``, no output grid); cost per accepted step.
2. **Stiff case vs scipy LSODA given the analytic Jacobian** (w 0.01, H 0.25, k 7.5), over the same
   horizon (rrbody's default flip-time stop time): scipy's RHS and Jacobian in plain Python (the
   competitor's normal use), a non-terminal event on phi' = 0 for the minima. Reference t_f:
   rrbody at rtol 1e-13, cross-checked against scipy Radau at 1e-12. Every run of every contender is
   timed in the same repeats, interleaved (best of 7). Speed ratio at matched error:
   for each LSODA run, the cheapest rrbody run (rtol 1e-6 .. 1e-13) at least as accurate. The
   work-precision diagram (``core_stiff.png``) adds the old method, rrbody's DOP853 alone (the only
   method of version 0.1.0: ~290k explicit steps at any tolerance), and scipy's Radau with the
   analytic Jacobian. Where rrbody's time goes: its accepted and rejected steps per tolerance (a
   rejected Radau step is mostly a Newton iteration that did not converge: the step is then halved).
3. **Right-hand side cost**: point mass vs disk and ellipse (delta 0.5) by the instantaneous-centre
   quadrature at their default node counts and by its precomputed table (friction_method "table";
   both <= 1e-10 relative wrench error, docs/extended.md), each called in a compiled loop with its
   system code compiled in (as the stepping loop does). The 5x target is judged on the ellipse's
   table, the specialised instantaneous-centre panels it asks for; the ellipse's default ("auto",
   the quadrature, because a table takes seconds to build per aspect ratio) is reported beside it.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

from .common import StudyResult, Target, fmt, machine_text, md_table, save_figure, write_csv


def _load_note() -> str:
    """A warning for the targets table when the machine was busy: a 1-minute load average of at
    least the number of cores means another job shared every core during the timings."""
    import os

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else 0.0
    return f"loaded machine (load {load:.1f}): re-run on a quiet one" if load >= (os.cpu_count() or 1) else ""


NAME = "core"
TITLE = "Core: DOP853 step vs a lean baseline, stiff case vs LSODA, RHS cost by body"

STIFF = (0.25, 7.5, 0.01)
AUTO = "rrbody (auto: DOP853, Radau IIA where stiff)"
OLD = "rrbody, DOP853 only (the old method)"
LSODA = "scipy LSODA + analytic Jacobian"
RADAU = "scipy Radau + analytic Jacobian"


def _interleaved(fns: dict[Any, Any], repeats: int) -> dict[Any, float]:
    """Best wall time of each callable, the callables alternating within every repeat."""
    best = {k: math.inf for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best


def _step_study(repeats: int) -> tuple[list[dict[str, Any]], Target]:
    from rrbody.integrate.dop853 import TABLEAU
    from rrbody.integrate.ode import integrate_driven
    from rrbody.model.scene import rod_mass_scene
    from rrbody.physics.bind import kernel_params

    from ._lean import lean_dop853

    H, k, w, t_end, rtol = 0.2, 0.05, 0.6, 60.0, 1e-13
    sc = rod_mass_scene(H, k, w)
    p, S = kernel_params(sc)
    y0 = (sc.phi0, sc.initial_phi_dot)
    lean = lambda: lean_dop853(H, k, w, t_end, rtol, *TABLEAU)  # noqa: E731
    ours = lambda: integrate_driven(p, S, y0, t_end=t_end, rtol=rtol, method="dop853")  # noqa: E731
    lean()
    ours()  # compile outside the timing
    phi_lean, n_lean = lean()
    res = ours()
    best = _interleaved({"lean": lean, "rrbody": ours}, repeats)
    per_lean = best["lean"] / n_lean
    per_ours = best["rrbody"] / res.n_steps
    ratio = per_ours / per_lean
    rows = [{"what": "lean DOP853 (benchmarks/_lean.py)", "steps": n_lean, "wall_s": best["lean"],
             "ns_per_step": per_lean * 1e9, "phi_end": phi_lean},
            {"what": "rrbody loop, stepper=dop853", "steps": res.n_steps, "wall_s": best["rrbody"],
             "ns_per_step": per_ours * 1e9, "phi_end": float(res.y_end[0])}]
    tgt = Target("DOP853 step vs lean compiled DOP853", "<= 1.3x",
                 f"{ratio:.2f}x ({per_ours * 1e9:.0f} vs {per_lean * 1e9:.0f} ns per step; {res.n_steps} vs {n_lean} "
                 f"steps, phi(60 s) differs by {abs(phi_lean - res.y_end[0]):.1e} rad)", ratio <= 1.3,
                 _load_note())
    return rows, tgt


def _scipy_implicit(H: float, k: float, w: float, t_end: float, rtol: float, method: str) -> tuple[float, float]:
    """(t_f, wall) by scipy's ``method`` with the analytic Jacobian, in plain Python (d = 1 m): the
    tests' independent reference (tests/reference.py), timed as a whole."""
    from tests.reference import scipy_stiff_flip_time

    t0 = time.perf_counter()
    try:
        tf, _ = scipy_stiff_flip_time(H, k, w, t_end, method=method, rtol=rtol)
    except RuntimeError:
        tf = math.nan
    return tf, time.perf_counter() - t0


def _stiff_study(repeats: int, quick: bool) -> tuple[list[dict[str, Any]], Target, dict[str, Any]]:
    from rrbody.analysis.flip import flip_time
    from rrbody.integrate.ode import integrate_driven
    from rrbody.model.scene import rod_mass_scene
    from rrbody.physics.bind import kernel_params

    H, k, w = STIFF
    sc = rod_mass_scene(H, k, w)
    ref = flip_time(sc, rtol=1e-13)
    horizon = ref.t_stop
    rr_rtols = [1e-6, 1e-8, 1e-10, 1e-12] if quick else [10.0 ** -e for e in range(6, 14)]
    old_rtols = [1e-6, 1e-10] if quick else [1e-6, 1e-8, 1e-10, 1e-12]
    ls_rtols = [1e-6, 1e-9] if quick else [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
    # Radau at 1e-12 is also the reference's cross-check
    radau_rtols = [1e-6, 1e-12] if quick else [1e-6, 1e-8, 1e-10, 1e-12]
    # the new default (automatic switching), the old method alone (DOP853 throughout, the only method
    # of version 0.1.0), both by rrbody's flip_time, and scipy's LSODA and Radau, all over the same
    # horizon; one run each for the error, then every contender timed in the same repeats,
    # interleaved, best of ``repeats``
    runs: dict[tuple[str, float], Any] = {}
    for label, stepper, rtols in ((AUTO, "auto", rr_rtols), (OLD, "dop853", old_rtols)):
        for r in rtols:
            runs[label, r] = lambda r=r, stepper=stepper: flip_time(sc, rtol=r, t_max=horizon, stepper=stepper)
    for method, label, rtols in (("LSODA", LSODA, ls_rtols), ("Radau", RADAU, radau_rtols)):
        for r in rtols:
            runs[label, r] = lambda r=r, method=method: _scipy_implicit(H, k, w, horizon, r, method)
    results = {key: fn() for key, fn in runs.items()}
    best = _interleaved(runs, repeats)
    rows: list[dict[str, Any]] = []
    p, S = kernel_params(sc)
    for (label, r), res in results.items():
        ours = label in (AUTO, OLD)
        tf = (res.t_f if res.t_f is not None else math.nan) if ours else res[0]
        err = abs(tf - ref.t_f) / ref.t_f if math.isfinite(tf) else math.inf
        # the same run again for its rejected steps (flip_time reports the accepted ones)
        rej = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=horizon, rtol=r, stop="flip",
                               method="auto" if label == AUTO else "dop853").n_rejected if ours else None
        rows.append({"method": label, "rtol": r, "t_f": tf, "err": err, "wall_s": best[label, r],
                     "steps": res.n_steps if ours else None, "rejected": rej})
    mine = [(x["rtol"], x["err"], x["wall_s"]) for x in rows if x["method"] == AUTO]
    ratios = []
    for x in rows:
        if x["method"] != LSODA or not math.isfinite(x["err"]):
            continue
        ok = [m for m in mine if m[1] <= x["err"]]
        if ok:
            cheapest = min(ok, key=lambda m: m[2])
            ratios.append((x["rtol"], x["err"], x["wall_s"], cheapest[0], cheapest[2], x["wall_s"] / cheapest[2]))
    worst = min((x[5] for x in ratios), default=math.nan)
    tgt = Target("stiff case (w 0.01, H 0.25, k 7.5) vs scipy LSODA with analytic Jacobian, same horizon",
                 ">= 10x at matched t_f error", f"{worst:.1f}x (lowest over {len(ratios)} LSODA tolerances)",
                 bool(worst >= 10.0) if math.isfinite(worst) else None, _load_note())
    radau_tf = results[RADAU, 1e-12][0]
    extra = {"ref_tf": ref.t_f, "radau_tf": radau_tf, "radau_rel": abs(radau_tf - ref.t_f) / ref.t_f,
             "horizon": horizon, "ratios": ratios}
    return rows, tgt, extra


def _plot_stiff(path: Path, rows: list[dict[str, Any]], ref_tf: float) -> Path:
    """Work-precision diagram of the stiff case: t_f error against wall time, old and new methods."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    styles = {AUTO: ("k", "o", "-"), OLD: ("0.5", "o", "--"), LSODA: ("tab:green", "D", "-"),
              RADAU: ("tab:purple", "v", "-")}
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for label, (c, mk, ls) in styles.items():
        # in tolerance order; rrbody's rtol 1e-13 run is the reference itself (error 0) and is left out
        pts = [(r["wall_s"],
                r["err"]) for r in rows if r["method"] == label and math.isfinite(r["err"]) and r["err"] > 0]
        if pts:
            ax.loglog(*zip(*pts), color=c, marker=mk, ls=ls, label=label)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("t_f relative error")
    ax.set_title(f"Stiff case w 0.01, H 0.25, k 7.5 (t_f = {ref_tf:.6f} s, rrbody at rtol 1e-13);\n"
                 "each curve in tolerance order (1e-6 first), same horizon", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path


def _rhs_study(repeats: int, quick: bool = False) -> tuple[list[dict[str, Any]], Target]:
    from rrbody.model.bodies import Disk, Ellipse
    from rrbody.model.drive import CircularDrive
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene, rod_mass_scene
    from rrbody.physics import params as P
    from rrbody.physics.bind import kernel_params
    from rrbody.physics.dynamics import SYSTEM_DRIVEN, system_from_params

    from ._kernels import loop_rhs_for

    drive = CircularDrive(omega=0.6, d=1.0)
    disk, ell = Disk(R=0.1, l=0.2), Ellipse(R0=0.1, delta=0.5, l=0.2)
    scenes = {"point mass": rod_mass_scene(0.2, 0.05, 0.6),
              "disk R 0.1 (icr)": Scene(body=disk, drive=drive, friction=Friction("dry", 0.05), friction_method="icr"),
              "ellipse R0 0.1 delta 0.5 (icr)": Scene(body=ell, drive=drive, friction=Friction("dry", 0.05)),
              "disk R 0.1 (table)": Scene(body=disk, drive=drive, friction=Friction("dry", 0.05),
                                          friction_method="table"),
              "ellipse R0 0.1 delta 0.5 (table)": Scene(body=ell, drive=drive, friction=Friction("dry", 0.05),
                                                        friction_method="table")}
    calls = {}
    for name, sc in scenes.items():
        p, S = kernel_params(sc)
        run = loop_rhs_for(system_from_params(p, SYSTEM_DRIVEN))
        m = (1_000_000 if name == "point mass" else 100_000) // (10 if quick else 1)  # (--quick: a smoke run)
        run(p, S, 10)
        calls[name] = (lambda run=run, p=p, S=S, m=m: run(p, S, m), m, int(p[P.NQ]))
    best = _interleaved({k: v[0] for k, v in calls.items()}, repeats)
    rows = [{"body": k, "nodes_per_panel": calls[k][2], "ns_per_eval": best[k] / calls[k][1] * 1e9} for k in calls]
    pt = rows[0]["ns_per_eval"]
    ell = rows[2]["ns_per_eval"]
    tab = rows[4]["ns_per_eval"]
    # judged on the table (the specialised ICR panels); the ellipse's default ("auto") stays the
    # quadrature, since a table takes seconds to build per aspect ratio: reported beside it
    tgt = Target("ellipse RHS vs point-mass RHS (its wrench table, friction_method 'table'; <= 1e-10 wrench error)",
                 "<= 5x",
                 f"{tab / pt:.2f}x ({tab:.0f} vs {pt:.0f} ns); the ellipse's default ('auto', the quadrature) "
                 f"{ell / pt:.0f}x; disk: table (its default) {rows[3]['ns_per_eval'] / pt:.1f}x, icr "
                 f"{rows[1]['ns_per_eval'] / pt:.1f}x",
                 tab / pt <= 5.0, _load_note())
    return rows, tgt


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    repeats = 3 if quick else 7
    step_rows, step_t = _step_study(repeats)
    print(f"[core] step: {step_t.measured}", flush=True)
    rhs_rows, rhs_t = _rhs_study(repeats, quick)
    print(f"[core] rhs: {rhs_t.measured}", flush=True)
    stiff_rows, stiff_t, extra = _stiff_study(repeats, quick)
    print(f"[core] stiff: {stiff_t.measured}", flush=True)
    # file names relative to the results folder (a machine's paths have no place in the recorded results)
    files = [write_csv(out / "core_step.csv", step_rows).name, write_csv(out / "core_rhs.csv", rhs_rows).name,
             write_csv(out / "core_stiff.csv", stiff_rows).name,
             _plot_stiff(out / "core_stiff.png", stiff_rows, extra["ref_tf"]).name]
    md = [f"## {TITLE}", "", machine_text(), "",
          "### DOP853 step vs a lean compiled DOP853 (phixtpm to 60 s, rtol 1e-13)",
          "", md_table(["what", "steps", "wall (s)", "ns per step", "phi(60 s)"],
                       [(r["what"], r["steps"], r["wall_s"], r["ns_per_step"],
                         f"{r['phi_end']:.15g}") for r in step_rows]),
          "", "### Right-hand side cost by body (compiled loop, system code compiled in)", "",
          md_table(["body (friction method)", "ICR nodes per panel", "ns per evaluation"],
                   [(r["body"], r["nodes_per_panel"], r["ns_per_eval"]) for r in rhs_rows]),
          "", f"### Stiff case w 0.01, H 0.25, k 7.5 over {fmt(extra['horizon'])} s (rrbody's default stop time)", "",
          f"Reference t_f = {extra['ref_tf']!r} s (rrbody rtol 1e-13); scipy Radau at 1e-12 differs by "
          f"{fmt(extra['radau_rel'])} relative.", "",
          md_table(["method", "rtol", "t_f", "t_f rel err", "wall (s)", "steps", "rejected"],
                   [(r["method"], r["rtol"], r["t_f"], r["err"], r["wall_s"], r["steps"], r["rejected"])
                    for r in stiff_rows]), "",
          "Where rrbody's time goes (auto): every step of this case is a Radau IIA step (the run starts stiff and "
          "stays so); a step costs 2-6 Newton iterations of 3 right-hand sides each. The Newton iteration starts "
          "from the previous step's collocation polynomial and a step whose iteration fails is halved (RADAU5, "
          "scipy), and the step cost is dominated by the right-hand sides: per attempted step",
          "",
          md_table(["rtol", "accepted", "rejected", "us per attempted step"],
                   [(r["rtol"], r["steps"], r["rejected"], r["wall_s"] / (r["steps"] + r["rejected"]) * 1e6)
                    for r in stiff_rows if r["method"] == AUTO]), "",
          md_table(["LSODA rtol", "LSODA t_f err", "LSODA wall (s)", "rrbody rtol", "rrbody wall (s)", "ratio"],
                   [(a, b, c, d, e, f"{g:.1f}x") for a, b, c, d, e, g in extra["ratios"]]), "",
          "![stiff case work precision](core_stiff.png)", "",
          "Data: `core_step.csv`, `core_rhs.csv`, `core_stiff.csv`; diagram `core_stiff.png`."]
    res = StudyResult(NAME, TITLE, [step_t, stiff_t, rhs_t], "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    res.extra = {"highlights": [f"{t.name}: {t.measured} ({t.verdict})" for t in (step_t, stiff_t, rhs_t)]}
    return res
