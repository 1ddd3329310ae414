"""ODE path: rrbody's compiled DOP853 vs scipy ``solve_ivp`` (RK45, DOP853, LSODA, Radau).

Four rod-mass cases (d = 1 m, phi0 = pi, dry friction, impulsive start phi'(0) = (w/H) cos phi0):

- ``phixtpm``: H = 0.2, k = 0.05, w = 0.6 (the paper's phixtpm figure, middle curve);
- ``slow``: w = 0.01, H = 0.25, k = 7.5 (slow driving, strong friction: stiff for explicit methods);
- ``fast``: w = 300, H = 0.25, k = 7.5 (fast driving: ~1800 driving periods before the flip);
- ``weak``: w = 0.6, H = 0.2, k = 0.0015 (weak friction: t_f ~ 450 s).

Measured: the relative error of the flip time t_f and the absolute error of phi at a fixed time
``t_fix`` against a tight reference, and the wall time of each run (best of a few repeats after
compilation). scipy integrates the paper's Eq. 2 written in plain Python (the dry term's 0/0 at rest is
taken as 0, as rrbody does), with rtol = atol, a non-terminal event on phi' = 0 (direction +1) for
the minima of phi and a terminal one for rrbody's settle rule, up to twice the reference run's stop
time. t_f is the time of the lowest minimum.

A scipy run that exceeds its time cap is stopped (the right-hand side raises); its error is then
unknown, and the time it spent before the cap is a lower bound on its cost, hence on the speed
ratio. (The CSV also lists a linear extrapolation from the fraction of the horizon covered, for
information only: the stiff impulsive start makes the first instants much dearer than the rest.)
"""

from __future__ import annotations

import inspect
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.physics.bind import kernel_params

from .common import StudyResult, Target, best_time, best_wall_cpu, fmt, machine_text, md_table, save_figure, write_csv

NAME = "ode"
TITLE = "ODE path: work-precision vs scipy solve_ivp"

REF_RTOL = 1e-14          # reference tolerance; 1e-13 and 1e-15 bound its uncertainty
RTOLS = [10.0 ** -e for e in range(3, 14)]            # rrbody: 1e-3 ... 1e-13
SCIPY_RTOLS = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
SCIPY_METHODS = ["RK45", "DOP853", "LSODA", "Radau"]
LEVELS = {"draft": 1e-4, "default": 1e-6, "paper": 1e-9}   # t_f relative-error level of each preset
TARGET_RATIO = {"phixtpm": 100.0, "slow": 100.0, "fast": 100.0,
                "weak": 100.0}  # each hard case >= 100x at matched t_f error


@dataclass(frozen=True)
class Case:
    name: str
    H: float
    k: float
    omega: float
    t_fix: float      # s: time at which phi is compared
    label: str


CASES = [
    Case("phixtpm", 0.2, 0.05, 0.6, 10.0, "phixtpm: H=0.2, k=0.05, w=0.6"),
    Case("slow", 0.25, 7.5, 0.01, 50.0, "slow/strong: H=0.25, k=7.5, w=0.01"),
    Case("fast", 0.25, 7.5, 300.0, 10.0, "fast/long: H=0.25, k=7.5, w=300"),
    Case("weak", 0.2, 0.0015, 0.6, 400.0, "weak/long: H=0.2, k=0.0015, w=0.6"),
]


# ---------------------------------------------------------------------------------------------
# scipy side: the paper's Eq. 2 in plain Python
# ---------------------------------------------------------------------------------------------
class _Capped(Exception):
    def __init__(self, t: float) -> None:
        super().__init__(t)
        self.t = t


def _python_rhs(H: float, k: float, w: float, deadline: float | None = None) -> Any:
    """the paper's Eq. 2 (rod-mass, d = 1): phi'' = (w^2/H) sin s + (k/H)(w cos s - H phi')/|v|, s = phi - w t.

    |v| = sqrt(w^2 + H^2 phi'^2 - 2 w H phi' cos s) is the CM speed over d; where it vanishes (the
    impulsive start from phi0 = pi) the dry term is 0/0 and is taken as 0, like rrbody's kernels.
    ``deadline`` (perf_counter seconds): raise _Capped once it has passed (checked every 512 calls).
    """
    eps = 1e-12 * w
    calls = [0]

    def f(t: float, y: np.ndarray) -> list[float]:
        phi, pd = y
        s = phi - w * t
        c = math.cos(s)
        den = math.sqrt(max(w * w + H * H * pd * pd - 2.0 * w * H * pd * c, 0.0))
        fr = k * (w * c - H * pd) / den if den > eps else 0.0
        if deadline is not None:
            calls[0] += 1
            if calls[0] & 511 == 0 and time.perf_counter() > deadline:
                raise _Capped(float(t))
        return [pd, (w * w * math.sin(s) + fr) / H]

    return f


def _min_event(t: float, y: np.ndarray) -> float:
    return float(y[1])


_min_event.direction = 1  # type: ignore[attr-defined]


def _settle_rule() -> tuple[float, float]:
    """rrbody's flip-settled rule: flip_time's defaults (turns risen, driving periods passed)."""
    from rrbody.analysis.flip import flip_time

    par = inspect.signature(flip_time).parameters
    return float(par["settle_turns"].default), float(par["settle_periods"].default)


def _settle_event(omega: float) -> Any:
    """rrbody's flip-settled rule as a terminal solve_ivp event: it crosses zero upwards once phi has
    risen by 2 pi settle_turns above its running minimum and settle_periods driving periods have
    passed since that minimum. The running minimum is kept from the points scipy evaluates the
    event at (every accepted step, and the dense output inside a step while locating a root)."""
    turns, periods = _settle_rule()
    low = [math.inf, 0.0]

    def settle(t: float, y: np.ndarray) -> float:
        if y[0] < low[0]:
            low[0], low[1] = float(y[0]), t
        return min(y[0] - low[0] - 2.0 * math.pi * turns, t - low[1] - periods * 2.0 * math.pi / omega)

    settle.terminal = True  # type: ignore[attr-defined]
    settle.direction = 1  # type: ignore[attr-defined]
    return settle


def scipy_run(case: Case, method: str, rtol: float, t_end: float, *, events: bool, cap: float) -> dict[str, Any]:
    """One solve_ivp run; returns wall time, t_f (events) or phi(t_end), and capping information.

    With ``events`` the run establishes its flip the way rrbody's does: it stops once its lowest
    minimum is settled (:func:`_settle_event`, a terminal event), at most at twice ``t_end`` (the
    reference's stop time; rrbody's runs get the same limit), and without a settled flip by then it
    has no t_f. Its cost is thus that of reaching its own settle point, as rrbody's is. (Taking the
    lowest minimum inside a fixed horizon instead credits a run whose body is still turning
    backwards at the horizon's end with the last minimum before it.)
    """
    from scipy.integrate import solve_ivp

    y0 = [math.pi, case.omega / case.H * math.cos(math.pi)]
    t0 = time.perf_counter()
    f = _python_rhs(case.H, case.k, case.omega, deadline=t0 + cap)
    horizon = 2.0 * t_end if events else t_end
    try:
        sol = solve_ivp(f, (0.0, horizon), y0, method=method, rtol=rtol, atol=rtol,
                        events=[_min_event, _settle_event(case.omega)] if events else None)
    except _Capped as c:
        wall = time.perf_counter() - t0
        frac = max(c.t, 1e-300) / t_end
        return {"wall_s": wall, "capped": True, "t_reached": c.t, "wall_extrapolated_s": wall / frac,
                "t_f": math.nan, "phi": math.nan, "nfev": math.nan, "status": "capped"}
    wall = time.perf_counter() - t0
    out: dict[str, Any] = {"wall_s": wall, "capped": False, "t_reached": float(sol.t[-1]),
                           "wall_extrapolated_s": wall, "nfev": sol.nfev, "status": sol.message}
    if not sol.success:
        out.update(t_f=math.nan, phi=math.nan)
        return out
    if events:
        te, ye = sol.t_events[0], sol.y_events[0].reshape(-1, 2)
        if sol.status == 1 and len(te) and ye[:, 0].min() < math.pi:  # the settle event ended the run
            out["t_f"] = float(te[int(np.argmin(ye[:, 0]))])
        else:
            out["t_f"] = math.nan
            out["status"] = "no settled flip within twice the reference's stop time"
        out["phi"] = math.nan
    else:
        out["t_f"] = math.nan
        out["phi"] = float(sol.y[0, -1])
    return out


# ---------------------------------------------------------------------------------------------
# rrbody side
# ---------------------------------------------------------------------------------------------
def _scene(case: Case) -> Any:
    from rrbody.model.scene import rod_mass_scene

    return rod_mass_scene(case.H, case.k, case.omega)


def rr_flip(case: Case, rtol: float | None, *, repeats: int = 3, t_max: float | None = None) -> tuple[float, Any]:
    """Best wall time and result of ``flip_time`` (rtol None: the default settings).

    ``t_max`` bounds runs that never settle: at loose tolerances the fast case's computed body
    never flips at all (rtol 1e-4: still unsettled after 3700 s and 2e6 steps).
    """
    from rrbody.analysis.flip import flip_time

    sc = _scene(case)
    if rtol is None:
        return best_time(lambda: flip_time(sc, t_max=t_max), max_repeats=repeats)
    return best_time(lambda: flip_time(sc, rtol=rtol, t_max=t_max), max_repeats=repeats)


def rr_phi(case: Case, rtol: float, *, repeats: int = 3) -> tuple[float, float]:
    from rrbody.integrate.ode import integrate_driven

    sc = _scene(case)
    p, S = kernel_params(sc)
    y0 = (sc.phi0, sc.initial_phi_dot)
    wall, res = best_time(lambda: integrate_driven(p, S, y0, t_end=case.t_fix, rtol=rtol, stop="t_end"),
                          max_repeats=repeats)
    return wall, float(res.y_end[0])


def _ratio(x: float) -> str:
    return f"{x:.0f}x" if x >= 10 else f"{x:.2g}x"


def _rel(a: float | None, ref: float) -> float:
    if a is None or not math.isfinite(a):
        return math.inf
    return abs(a - ref) / abs(ref)


# ---------------------------------------------------------------------------------------------
def run(out: Path, *, quick: bool = False) -> StudyResult:
    from rrbody.analysis.simulate import ACCURACY

    t_study = time.perf_counter()
    cases = [c for c in CASES if c.name == "phixtpm"] if quick else CASES
    rtols = [1e-6, 1e-9, 1e-12] if quick else RTOLS
    sp_rtols = [1e-6, 1e-9] if quick else SCIPY_RTOLS
    # time caps (s) per scipy run and per series of tolerances; DOP853 (the target's peer) gets the most
    if quick:
        caps = {("DOP853", "tf"): (1.0, 2.0)}
        other_cap = (1.0, 2.0)
    else:
        caps = {("DOP853", "tf"): (40.0, 80.0), ("DOP853", "phi"): (10.0, 20.0)}
        other_cap = (4.0, 8.0)
    ref_rtols = [REF_RTOL] if quick else [1e-13, REF_RTOL, 1e-15]
    default_rtol = ACCURACY["default"]
    machine = machine_text()

    # compile once (numba cache) and keep compilation out of every timing
    rr_flip(cases[0], 1e-6, repeats=1)
    rr_phi(cases[0], 1e-6, repeats=1)

    refs: dict[str, dict[str, Any]] = {}
    rr_rows: list[dict[str, Any]] = []
    sp_rows: list[dict[str, Any]] = []
    for case in cases:
        print(f"[ode] {case.name}: reference", flush=True)
        # ---- reference: rrbody at REF_RTOL; 1e-13 and 1e-15 bound its uncertainty ----
        rf: dict[float, Any] = {}
        ph: dict[float, float] = {}
        for r in ref_rtols:
            rf[r] = rr_flip(case, r, repeats=1)[1]
            ph[r] = rr_phi(case, r, repeats=1)[1]
        ref = rf[REF_RTOL]
        if ref.t_f is None:
            raise RuntimeError(f"reference run of case {case.name} found no flip: {ref.regime}")
        tf_ref = ref.t_f
        phi_ref = ph[REF_RTOL]
        unc_tf = max([_rel(rf[r].t_f, tf_ref) for r in ref_rtols if r != REF_RTOL] + [0.0])
        unc_phi = max([abs(ph[r] - phi_ref) for r in ref_rtols if r != REF_RTOL] + [0.0])
        refs[case.name] = {"t_f": tf_ref, "t_stop": ref.t_stop, "phi_fix": phi_ref, "unc_tf": unc_tf,
                           "unc_phi": unc_phi, "regime": ref.regime}
        # ---- rrbody at each tolerance (horizon capped at twice the reference's stop time) ----
        for r in rtols:
            w_tf, res = rr_flip(case, r, t_max=2.0 * ref.t_stop)
            w_phi, phi = rr_phi(case, r)
            rr_rows.append({"case": case.name, "method": "rrbody", "rtol": r, "t_f": res.t_f,
                            "err_tf": _rel(res.t_f, tf_ref), "wall_tf_s": w_tf, "n_steps": res.n_steps,
                            "settled": res.settled,
                            "phi_fix": phi, "err_phi": abs(phi - phi_ref), "wall_phi_s": w_phi})
        # ---- the default settings of `rrbody flip-time` (wall and CPU time: the machine is shared) ----
        from rrbody.analysis.flip import flip_time

        sc_def = _scene(case)
        w_def, c_def, res_def = best_wall_cpu(lambda: flip_time(sc_def, t_max=2.0 * ref.t_stop), repeats=3)
        refs[case.name].update(default_wall=w_def, default_cpu=c_def, default_err=_rel(res_def.t_f, tf_ref),
                               default_rtol=default_rtol)
        # ---- scipy ----
        for m in SCIPY_METHODS:
            for measure in ("tf", "phi"):
                spent = 0.0
                stop_reason = ""
                for r in sp_rtols:
                    row: dict[str, Any] = {"case": case.name, "method": m, "rtol": r, "measure": measure}
                    if stop_reason:
                        row.update(status=stop_reason)
                        sp_rows.append(row)
                        continue
                    run_cap, series_cap = caps.get((m, measure), other_cap)
                    cap = max(0.2, min(run_cap, series_cap - spent))
                    horizon = ref.t_stop if measure == "tf" else case.t_fix
                    print(f"[ode] {case.name}: scipy {m} rtol={r:g} ({measure}, cap {cap:.1f} s)", flush=True)
                    res_sp = scipy_run(case, m, r, horizon, events=(measure == "tf"), cap=cap)
                    spent += res_sp["wall_s"]
                    # short runs: best of 3, like rrbody's (noise on a shared machine only adds time)
                    for _ in range(2):
                        if res_sp["capped"] or res_sp["wall_s"] > 1.0:
                            break
                        again = scipy_run(case, m, r, horizon, events=(measure == "tf"), cap=cap)
                        spent += again["wall_s"]
                        if again["wall_s"] < res_sp["wall_s"]:
                            res_sp = again
                    row.update(res_sp)
                    row["err"] = _rel(res_sp["t_f"], tf_ref) if measure == "tf" else (
                        abs(res_sp["phi"] - phi_ref) if math.isfinite(res_sp["phi"]) else math.inf)
                    if res_sp["capped"]:
                        row["err"] = math.nan
                        stop_reason = "skipped: a looser run of this series was capped"
                    elif spent >= caps.get((m, measure), other_cap)[1]:
                        stop_reason = "skipped: series time budget used"
                    sp_rows.append(row)
    # ---- cross-check of the reference with scipy DOP853 at rtol = atol = 1e-13 ----
    cross = []
    for case in cases if not quick else cases[:1]:
        if case.name not in ("phixtpm", "weak"):
            continue
        res_sp = scipy_run(case, "DOP853", 1e-13, refs[case.name]["t_stop"], events=True, cap=60.0)
        cross.append((case.name, res_sp["t_f"], _rel(res_sp["t_f"], refs[case.name]["t_f"]), res_sp["wall_s"]))

    files = []
    rr_cols = ["case", "method", "rtol", "t_f", "err_tf", "wall_tf_s", "n_steps", "settled", "phi_fix", "err_phi",
               "wall_phi_s"]
    files.append(str(write_csv(out / "ode_rrbody.csv", rr_rows, rr_cols)))
    sp_cols = ["case", "method", "rtol", "measure", "t_f", "phi", "err", "wall_s", "capped", "t_reached",
               "wall_extrapolated_s", "nfev", "status"]
    files.append(str(write_csv(out / "ode_scipy.csv", sp_rows, sp_cols)))
    ref_rows = [{"case": c, **v} for c, v in refs.items()]
    files.append(str(write_csv(out / "ode_reference.csv", ref_rows)))
    files.append(str(_plot(out / "ode_work_precision.png", cases, rr_rows, sp_rows)))

    # ---- analysis: speed ratios at matched t_f error vs scipy DOP853 ----
    targets: list[Target] = []
    ratio_lines = []
    for case in cases:
        mine = [r for r in rr_rows if r["case"] == case.name and math.isfinite(r["err_tf"])]
        theirs = [r for r in sp_rows if r["case"] == case.name and r["method"] == "DOP853" and r["measure"] == "tf"
                  and "wall_s" in r]
        ratios = []
        for s in theirs:
            if s["capped"]:
                continue
            e = s["err"]
            floor = refs[case.name]["unc_tf"]
            ok = [r for r in mine if r["err_tf"] <= max(e, floor)]
            if not math.isfinite(e) or not ok:
                continue
            best = min(ok, key=lambda r: r["wall_tf_s"])
            ratios.append((s["rtol"], e, s["wall_s"], best["rtol"], best["wall_tf_s"], s["wall_s"] / best["wall_tf_s"]))
        capped = [s for s in theirs if s["capped"]]
        lower = None
        if capped and mine:
            # compared with rrbody's most accurate run: a capped scipy run (rtol >= 1e-12, atol = rtol) is
            # assumed no more accurate than that (on phixtpm and weak scipy's t_f error is always larger)
            most_accurate = min(mine, key=lambda r: r["err_tf"])
            lower = min(s["wall_s"] for s in capped) / most_accurate["wall_tf_s"]
        for rt, e, ws, rr_rt, rr_w, ratio in ratios:
            ratio_lines.append((case.name, fmt(rt), fmt(e), fmt(ws), fmt(rr_rt), fmt(rr_w), f"{ratio:.0f}x"))
        if lower is not None:
            cheapest_capped = min(capped, key=lambda s: s["wall_s"])
            ratio_lines.append((case.name, f"{fmt(cheapest_capped['rtol'])} (capped)", "unknown",
                                f"≥ {fmt(cheapest_capped['wall_s'])} (capped at t = "
                                f"{fmt(cheapest_capped['t_reached'])} s)",
                                fmt(most_accurate["rtol"]) + " (most accurate)", fmt(most_accurate["wall_tf_s"]),
                                f"≥ {lower:.0f}x"))
        if case.name in TARGET_RATIO:
            want = TARGET_RATIO[case.name]
            if ratios:
                lo = min(x[-1] for x in ratios)
                hi = max(x[-1] for x in ratios)
                targets.append(Target(f"ODE vs scipy DOP853, {case.name}", f">= {want:.0f}x at matched t_f error",
                                      f"{lo:.0f}x-{hi:.0f}x over {len(ratios)} matched points"
                                      + (f"; capped runs: >= {lower:.0f}x" if lower else ""),
                                      lo >= want, "worst matched point counts"))
            elif lower is not None:
                targets.append(Target(f"ODE vs scipy DOP853, {case.name}", f">= {want:.0f}x at matched t_f error",
                                      f">= {lower:.0f}x (every scipy run capped; time spent before the cap)",
                                      lower >= want))
            else:
                targets.append(Target(f"ODE vs scipy DOP853, {case.name}", f">= {want:.0f}x", "no matched point",
                                      None))
    # ---- against every scipy method: the worst ratio (which method beats rrbody where) ----
    any_lines = []
    for case in cases:
        mine = [r for r in rr_rows if r["case"] == case.name and math.isfinite(r["err_tf"])]
        floor = refs[case.name]["unc_tf"]
        for m in SCIPY_METHODS:
            pts = []
            for s_ in sp_rows:
                if (s_["case"], s_["method"], s_["measure"]) != (case.name, m, "tf") or "wall_s" not in s_:
                    continue
                if s_["capped"] or not math.isfinite(s_["err"]):
                    continue
                ok = [r for r in mine if r["err_tf"] <= max(s_["err"], floor)]
                if ok:
                    best = min(ok, key=lambda r: r["wall_tf_s"])
                    pts.append((s_["wall_s"] / best["wall_tf_s"], s_["rtol"], s_["err"]))
            if pts:
                lo = min(pts)
                any_lines.append((case.name, m, _ratio(lo[0]), fmt(lo[1]), fmt(lo[2]),
                                  _ratio(max(p_[0] for p_ in pts)), len(pts)))
            else:
                any_lines.append((case.name, m, "-", "-", "-", "-", 0))
    for case in cases:
        rf = refs[case.name]
        ok = rf["default_err"] <= 1e-6 and rf["default_cpu"] < 1.0
        targets.append(Target(f"default `flip-time` converged, {case.name}", "t_f rel err <= 1e-6 in < 1 s",
                              f"err {fmt(rf['default_err'])} in {fmt(rf['default_cpu'])} s CPU, "
                              f"{fmt(rf['default_wall'])} s wall (rtol {fmt(default_rtol)})",
                              ok, "judged on CPU time (shared machine)"))

    # ---- presets: cheapest rtol whose t_f error, and that of every tighter rtol, meets the level on all cases ----
    preset_rows = []
    recommend: dict[str, float | None] = {}
    for pname, level in LEVELS.items():
        chosen = None
        for r in sorted(rtols, reverse=True):   # loosest first
            good = True
            for case in cases:
                floor = refs[case.name]["unc_tf"]
                tighter = [x for x in rr_rows if x["case"] == case.name and x["rtol"] <= r]
                if not all(x["err_tf"] <= max(level, floor) for x in tighter):
                    good = False
                    break
            if good:
                chosen = r
                break
        recommend[pname] = chosen
        costs = []
        for case in cases:
            row = [x for x in rr_rows if x["case"] == case.name and chosen is not None and x["rtol"] == chosen]
            costs.append(f"{fmt(row[0]['wall_tf_s'])} s" if row else "-")
        preset_rows.append((pname, fmt(level), fmt(chosen) if chosen else "none in range",
                            f"{fmt(ACCURACY.get(pname))}", *costs))

    # per-step / per-evaluation costs: where the speed ratio comes from
    sp_eval = [r["wall_s"] / r["nfev"] for r in sp_rows if r.get("method") == "DOP853" and r.get("measure") == "tf"
               and "wall_s" in r and not r["capped"] and isinstance(r.get("nfev"), int) and r["nfev"] > 0]
    rr_step = [r["wall_tf_s"] / r["n_steps"] for r in rr_rows if r["n_steps"] > 0 and r["wall_tf_s"] > 0.01]
    cost_line = ""
    if sp_eval and rr_step:
        cost_line = (f"scipy DOP853 (Python right-hand side): median {fmt(float(np.median(sp_eval)) * 1e6)} us per "
                     f"right-hand-side evaluation (wall / nfev), i.e. ~{fmt(12 * float(np.median(sp_eval)) * 1e6)} us "
                     f"per 12-stage step; rrbody: median {fmt(float(np.median(rr_step)) * 1e6)} us per accepted step "
                     "(flip_time wall / steps, runs over 10 ms; rejected steps and event location included).")
    # ---- Markdown ----
    md = [f"## {TITLE}", "", machine, "",
          "Reference: rrbody's flip_time / integrate_driven at rtol = 1e-14; its uncertainty is the largest "
          "difference to the runs at 1e-13 and 1e-15 (round-off limits long runs: |phi| reaches 2e4 rad in "
          "the fast case). scipy integrates the paper's Eq. 2 in pure Python (rtol = atol); its t_f is the time of "
          "the lowest phi' = 0 (+) event, and its run stops, as rrbody's does, once that minimum is settled by "
          f"rrbody's rule (phi risen {_settle_rule()[0]:g} turns above it and {_settle_rule()[1]:g} driving periods "
          "passed; a terminal event), or has no t_f by twice the reference run's stop time. Times are best of up to 3 "
          "runs "
          "(after compilation for rrbody; runs over 1 s are timed once). phi is compared at t_fix = "
          f"{', '.join(f'{c.t_fix:g} s ({c.name})' for c in cases)}.",
          "", md_table(["case", "t_f ref (s)", "rel. unc.", "phi(t_fix) ref (rad)", "abs. unc.", "stop time (s)"],
                       [(c, fmt(v["t_f"], 14), v["unc_tf"], fmt(v["phi_fix"], 12), v["unc_phi"], v["t_stop"])
                        for c, v in refs.items()])]
    if cross:
        md += ["", "Cross-check of the reference with scipy DOP853 at rtol = atol = 1e-13: " + "; ".join(
            f"{c}: t_f = {fmt(tf, 14)} (rel. diff {fmt(e)}, {fmt(w)} s)" for c, tf, e, w in cross) + "."]
    md += ["", "### rrbody: error and cost per tolerance", "",
           md_table(["case", "rtol", "t_f rel err", "t_f wall (s)", "steps", "settled", "phi(t_fix) abs err",
                     "phi wall (s)"],
                    [(r["case"], r["rtol"], r["err_tf"], r["wall_tf_s"], r["n_steps"], r["settled"], r["err_phi"],
                      r["wall_phi_s"]) for r in rr_rows]),
           "", "A run that has not settled by twice the reference's stop time counts as failed (error inf).",
           "", "### Speed ratio at matched t_f error (scipy DOP853 wall / cheapest rrbody run at least as accurate)",
           "", md_table(["case", "scipy rtol", "scipy t_f err", "scipy wall (s)", "rrbody rtol", "rrbody wall (s)",
                          "ratio"], ratio_lines),
           "", cost_line,
           "", "### Every scipy method: speed ratio at matched t_f error (scipy wall / rrbody wall; < 1: scipy faster)",
           "", md_table(["case", "scipy method", "lowest ratio", "at scipy rtol", "scipy t_f err", "highest ratio",
                          "matched points"], any_lines),
           "", "### Default settings of `rrbody flip-time`", "",
           md_table(["case", "rtol", "t_f rel err", "CPU (s)", "wall (s)"],
                    [(c, v["default_rtol"], v["default_err"], v["default_cpu"], v["default_wall"])
                     for c, v in refs.items()]),
           "", "### Accuracy presets from the data", "",
           "Cheapest rtol such that it, and every tighter rtol tried, gives t_f within the level on every case "
           "(or within the reference's own uncertainty where that is larger).", "",
           md_table(["preset", "t_f rel err level", "recommended rtol", "current rtol",
                     *[f"cost {c.name}" for c in cases]], preset_rows),
           "", "Plot: `ode_work_precision.png`. Data: `ode_rrbody.csv`, `ode_scipy.csv`, `ode_reference.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t_study
    hl = [f"recommended presets (cheapest rtol whose t_f rel. error, and that of every tighter rtol, is within "
          f"1e-4 / 1e-6 / 1e-9 on all cases): draft {fmt(recommend['draft'])}, default {fmt(recommend['default'])}, "
          f"paper {fmt(recommend['paper'])} (current: {', '.join(f'{k} {fmt(v)}' for k, v in ACCURACY.items())})."]
    for case in cases:
        lows = [(x[2], x[1]) for x in any_lines if x[0] == case.name and x[2] != "-"]
        slower = [f"{m} ({r})" for r, m in lows if r.endswith("x") and float(r[:-1]) < 1.0]
        if slower:
            hl.append(f"{case.name}: scipy {', '.join(slower)} beat rrbody at matched t_f error (lowest ratio "
                      "scipy/rrbody wall); this case is stiff for an explicit method.")
    failed = [r for r in rr_rows if not math.isfinite(r["err_tf"])]
    for r in failed:
        hl.append(f"{r['case']} at rtol {fmt(r['rtol'])}: no settled flip within twice the reference's stop time "
                  "(the computed body never flips).")
    if cost_line:
        hl.append(cost_line)
    worst_unc = max(refs.values(), key=lambda v: v["unc_tf"])
    hl.append(f"reference t_f uncertainty (rtol 1e-13 / 1e-15 vs 1e-14): up to {fmt(worst_unc['unc_tf'])} relative "
              "(round-off floor of the long runs).")
    res.extra = {"recommend": recommend, "refs": refs, "highlights": hl}
    return res


def _plot(path: Path, cases: list[Case], rr_rows: list[dict[str, Any]], sp_rows: list[dict[str, Any]]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(cases), figsize=(4.2 * len(cases), 7.5), squeeze=False)
    styles = {"rrbody": ("k", "o"), "RK45": ("tab:blue", "s"), "DOP853": ("tab:red", "^"),
              "LSODA": ("tab:green", "D"), "Radau": ("tab:purple", "v")}
    for j, case in enumerate(cases):
        for i, measure in enumerate(("tf", "phi")):
            ax = axes[i, j]
            mine = [r for r in rr_rows if r["case"] == case.name]
            e = [r["err_tf" if measure == "tf" else "err_phi"] for r in mine]
            w = [r["wall_tf_s" if measure == "tf" else "wall_phi_s"] for r in mine]
            pts = [(a, b) for a, b in zip(w, e) if math.isfinite(b) and b > 0]
            if pts:
                ax.loglog(*zip(*pts), color="k", marker="o", label="rrbody (default: DOP853, Radau IIA where stiff)")
            for m in SCIPY_METHODS:
                rows = [r for r in sp_rows if r["case"] == case.name and r["method"] == m and r["measure"] == measure
                        and "wall_s" in r]
                pts = [(r["wall_s"], r["err"]) for r in rows if not r["capped"] and math.isfinite(r["err"])
                       and r["err"] > 0]
                c, mk = styles[m]
                if pts:
                    ax.loglog(*zip(*pts), color=c, marker=mk, label=f"scipy {m}")
                cap = [r["wall_s"] for r in rows if r["capped"]]
                if cap:
                    ax.axvline(min(cap), color=c, ls=":", lw=1)
            ax.set_xlabel("wall time (s)")
            ax.set_ylabel("t_f relative error" if measure == "tf" else f"|phi({case.t_fix:g} s) error| (rad)")
            ax.set_title(case.label, fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            if i == 0 and j == 0:
                ax.legend(fontsize=7)
    fig.suptitle("Work-precision: error vs wall time (dotted: time a capped scipy run spent, a lower bound on its "
                 "cost)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path
