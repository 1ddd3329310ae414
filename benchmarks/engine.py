"""Engine path (pymunk): error vs dt, cost per step vs area elements, and the PlaneFriction plugin.

1. Error vs dt on the phixtpm scene (rod-mass, H = 0.2, k = 0.05, w = 0.6, phi0 = pi): phi at
   t = 10 s and the flip time, against the ODE path at rtol = 1e-13 (the ODE study shows that is
   converged to ~1e-12). The observed order is the least-squares slope of log(error) vs log(dt).
2. Cost per step vs the number of sampled area elements N (disk R = 0.1 m driven at l = 0.2 m,
   w = 0.6, dry friction k = 0.05), against the same driven disk without friction (a bare
   pymunk step with the drive, the pivot joint and rrbody's position/velocity hooks).
3. The plugin against pymunk's own steps (:mod:`benchmarks.plugin`): 100 bodies (half circles, half
   boxes) with PlaneFriction vs the same space with pymunk's tank-example constraints; growth to
   1,000 bodies.
4. What a user calls, per step (:func:`user_step`): ``simulate(scene, method="engine")`` on phixtpm
   (rod-mass H = 0.2, k = 0.05, w = 0.6, dt = 1e-3 s; the whole call: set-up, the trajectory on its
   default grid, the events) against the same driven body in plain pymunk (a kinematic driver, a
   ``PivotJoint``, the driver's velocity set every step, ``space.step``), with the breakdown between
   them: pymunk's bare ``space.step`` and rrbody's ``h.plane.step`` alone. Interleaved, best of the
   repeats, each a fresh space.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

from rrbody.physics.bind import kernel_params

from . import plugin as plugin_study
from .common import (
    StudyResult,
    Target,
    fmt,
    loglog_slope,
    machine_text,
    md_table,
    module_available,
    save_figure,
    write_csv,
)

NAME = "engine"
TITLE = "Engine path (pymunk): error vs dt, cost per step vs area elements"

DTS = [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4]
ELEMENTS = [16, 64, 256, 1024, 4096]
T_FIX = 10.0


def user_step(repeats: int, steps: int) -> dict[str, float]:
    """Seconds per step of study 4's variants ("bare", "plain", "plane_step", "simulate"), interleaved over
    ``repeats`` fresh spaces, best of them (noise on a shared machine only adds time)."""
    import pymunk

    from rrbody.analysis.simulate import simulate
    from rrbody.engine import EngineSettings, attach
    from rrbody.model.scene import rod_mass_scene

    sc = rod_mass_scene(0.2, 0.05, 0.6, math.pi)
    dt, d, w, l = 1e-3, 1.0, 0.6, 0.2

    def plain(drive: bool) -> None:
        space = pymunk.Space()
        drv = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        drv.position, drv.velocity = (d, 0.0), (0.0, d * w)
        b = pymunk.Body(1.0, 1e-9 * l * l)  # rrbody's point mass: I_cm = 1e-9 m l^2
        b.position, b.velocity = (d + l, 0.0), (0.0, d * w)
        space.add(drv, b, pymunk.PivotJoint(drv, b, (0.0, 0.0), (-l, 0.0)))
        space.iterations = 10
        if not drive:
            for _ in range(steps):
                space.step(dt)
            return
        for i in range(steps):  # the driver's velocity on the circle, P'(t) at the step's middle
            th = w * (i + 0.5) * dt
            drv.velocity = (-d * w * math.sin(th), d * w * math.cos(th))
            space.step(dt)

    def plane_step() -> None:
        h = attach(pymunk.Space(), sc, settings=EngineSettings(dt=dt))
        st = h.plane.step
        for _ in range(steps):
            st(dt)

    def user() -> None:
        tr = simulate(sc, method="engine", t_max=steps * dt, dt=dt)
        assert tr.meta["n_steps"] == steps, tr.meta["n_steps"]

    fns = {"bare": lambda: plain(False), "plain": lambda: plain(True), "plane_step": plane_step, "simulate": user}
    user()  # loads the compiled kernels, not timed
    best = {k: math.inf for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            best[k] = min(best[k], (time.perf_counter() - t0) / steps)
    print("[engine] per step: " + ", ".join(f"{k} {v * 1e6:.2f} us" for k, v in best.items()) +
          f" (simulate / plain {best['simulate'] / best['plain']:.2f}x)", flush=True)
    return best


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("rrbody.engine")
    if not ok:
        print(f"[engine] skipped: rrbody.engine not importable ({why})", flush=True)
        return StudyResult(NAME, TITLE, skipped=f"rrbody.engine not importable ({why})")
    from rrbody.analysis.flip import flip_time
    from rrbody.engine import default_dt, engine_flip_time, simulate_engine
    from rrbody.integrate.ode import integrate_driven
    from rrbody.model.bodies import Disk
    from rrbody.model.drive import CircularDrive
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene, rod_mass_scene

    t0 = time.perf_counter()
    dts = DTS[:3] if quick else DTS
    elements = ELEMENTS[:3] if quick else ELEMENTS
    # ---- 1. error vs dt ----
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    p, S = kernel_params(sc)
    phi_ref = float(integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=T_FIX, rtol=1e-13).y_end[0])
    tf_ref = flip_time(sc, rtol=1e-13).t_f
    assert tf_ref is not None
    dt_default = default_dt(sc)
    rows: list[dict[str, Any]] = []
    for dt in sorted(set(dts + [dt_default]), reverse=True):
        w0 = time.perf_counter()
        tr = simulate_engine(sc, t_max=T_FIX, dt_out=T_FIX, dt=dt)
        wall = time.perf_counter() - w0
        phi = float(tr.phi[-1])
        do_tf = dt >= (1e-3 if quick else 2.5e-4)
        tf_err, tf_wall = math.nan, math.nan
        if do_tf:
            w0 = time.perf_counter()
            fr = engine_flip_time(sc, dt=dt)
            tf_wall = time.perf_counter() - w0
            tf_err = abs(fr.t_f - tf_ref) / tf_ref if fr.t_f is not None else math.inf
        rows.append({"dt": dt, "default": dt == dt_default, "phi_err": abs(phi - phi_ref), "wall_s": wall,
                     "cost_per_sim_s": wall / T_FIX, "us_per_step": wall / (T_FIX / dt) * 1e6,
                     "tf_rel_err": tf_err, "tf_wall_s": tf_wall})
        print(f"[engine] dt={dt:g}: phi err {abs(phi - phi_ref):.3g}, {wall:.2f} s, t_f err {tf_err:.3g}", flush=True)
    order_phi = loglog_slope([r["dt"] for r in rows], [r["phi_err"] for r in rows])
    tfr = [r for r in rows if math.isfinite(r["tf_rel_err"]) and r["tf_rel_err"] > 0]
    order_tf = loglog_slope([r["dt"] for r in tfr], [r["tf_rel_err"] for r in tfr])

    # ---- 2. cost per step vs area elements ----
    drive = CircularDrive(omega=0.6, d=1.0)
    t_sim = 2.0 if quick else 4.0
    dt_e = 1e-3

    def per_step(scene: Scene) -> float:
        best = math.inf
        for _ in range(3 if quick else 5):
            tr = simulate_engine(scene, t_max=t_sim, dt_out=t_sim, dt=dt_e)
            best = min(best, float(tr.meta["wall_s"]) / int(tr.meta["n_steps"]))
        return best

    # warm-up (first use of the sampled-friction hook loads its compiled kernels), not counted
    simulate_engine(Scene(body=Disk(R=0.1, l=0.2), drive=drive, friction=Friction("dry", 0.05),
                          friction_method="sampled", samples=16), t_max=0.5, dt_out=0.5, dt=dt_e)
    bare = per_step(Scene(body=Disk(R=0.1, l=0.2), drive=drive, friction=Friction("none")))
    erows = [{"elements": 0, "label": "bare (no friction)", "us_per_step": bare * 1e6, "ratio_to_bare": 1.0}]
    for n in elements:
        scn = Scene(body=Disk(R=0.1, l=0.2), drive=drive, friction=Friction("dry", 0.05), friction_method="sampled",
                    samples=n)
        n_actual = kernel_params(scn)[1].shape[0]
        c = per_step(scn)
        erows.append({"elements": n_actual, "label": f"{n_actual} elements", "us_per_step": c * 1e6,
                      "ratio_to_bare": c / bare})
        print(f"[engine] {n_actual} elements: {c * 1e6:.1f} us/step ({c / bare:.2f}x bare)", flush=True)
    point = per_step(sc.with_())
    erows.append({"elements": 1, "label": "rod-mass (point friction)", "us_per_step": point * 1e6,
                  "ratio_to_bare": point / bare})
    # ---- 3. the plugin against pymunk's own steps ----
    reps = 3 if quick else 7
    prows = plugin_study.many_bodies([100, 300] if quick else [100, 300, 1000], reps)
    slope = plugin_study.growth_slope(prows)
    us = user_step(reps, 2000 if quick else 5000)
    u_ratio = us["simulate"] / us["plain"]
    arows, adds_target = plugin_study.add_scaling((1000, 3000) if quick else (1000, 10_000), 2 if quick else 5)
    push_us, push_target = plugin_study.pushed_body(3 if quick else 7)
    # file names relative to the results folder (a machine's paths have no place in the recorded results)
    files = [write_csv(out / "engine_dt.csv", rows).name, write_csv(out / "engine_elements.csv", erows).name,
             write_csv(out / "engine_plugin.csv", prows).name, write_csv(out / "engine_plugin_adds.csv", arows).name,
             write_csv(out / "engine_plugin_push.csv",
                       [{"variant": k, "us_per_step": v} for k, v in push_us.items()]).name,
             _plot(out / "engine.png", rows, erows).name]
    near256 = min((r for r in erows if r["elements"] > 1), key=lambda r: abs(math.log(r["elements"] / 256)))
    p100 = prows[0]
    targets = [Target("engine step with 256 area elements vs bare driven step", "<= 3x",
                      f"{near256['ratio_to_bare']:.2f}x ({fmt(near256['us_per_step'])} us vs {fmt(bare * 1e6)} us "
                      f"per step, {near256['elements']} elements)", near256["ratio_to_bare"] <= 3.0),
               Target("PlaneFriction, 100 bodies (half circles, half boxes) vs pymunk's tank-example constraints",
                      "<= 2x", f"{p100['plugin_over_tank']:.2f}x ({fmt(p100['plugin_us'])} us vs "
                      f"{fmt(p100['tank_us'])} us per step; bare step {fmt(p100['bare_us'])} us)",
                      p100["plugin_over_tank"] <= 2.0),
               Target("PlaneFriction cost growth 100 -> " + str(prows[-1]["bodies"]) + " bodies", "linear",
                      f"log-log slope {slope:.2f}; {fmt(prows[0]['plugin_us_per_body'])} -> "
                      f"{fmt(prows[-1]['plugin_us_per_body'])} us per body", slope <= 1.1),
               Target("simulate(method='engine') per step (phixtpm, dt 1e-3 s: what a user calls) vs the same "
                      "driven body in plain pymunk (driver velocity set every step)", "<= 6x",
                      f"{u_ratio:.2f}x ({fmt(us['simulate'] * 1e6)} us vs {fmt(us['plain'] * 1e6)} us; "
                      f"h.plane.step alone {fmt(us['plane_step'] * 1e6)} us, bare space.step "
                      f"{fmt(us['bare'] * 1e6)} us)", u_ratio <= 6.0,
                      f"interleaved, best of {reps} fresh spaces x {2000 if quick else 5000} steps"),
               adds_target, push_target]  # the docs quote targets by position: new ones go last
    md = [f"## {TITLE}", "", machine_text(), "",
          f"Error vs dt: phixtpm scene (rod-mass H=0.2, k=0.05, w=0.6), phi({T_FIX:g} s) and t_f against the ODE "
          f"path at rtol = 1e-13 (t_f = {tf_ref:.12g} s, phi({T_FIX:g} s) = {phi_ref:.12g} rad). "
          f"Default engine dt for this scene: {fmt(dt_default)} s.", "",
          md_table(["dt (s)", "default", "phi(10 s) abs err (rad)", "t_f rel err", "wall per simulated s (s)",
                    "us per step", "flip-time wall (s)"],
                   [(r["dt"], r["default"], r["phi_err"], r["tf_rel_err"], r["cost_per_sim_s"], r["us_per_step"],
                     r["tf_wall_s"]) for r in rows]), "",
          f"Observed order in dt: phi(10 s): {fmt(order_phi)}; t_f: {fmt(order_tf)}.", "",
          f"Cost per step vs sampled area elements (driven disk R=0.1 m, l=0.2 m, w=0.6, dt={dt_e:g} s, "
          f"{t_sim:g} simulated s, best of 5):", "",
          md_table(["body / friction", "us per step", "x bare"],
                   [(r["label"], r["us_per_step"], r["ratio_to_bare"]) for r in erows]), "",
          "Plot: `engine.png`; data: `engine_dt.csv`, `engine_elements.csv`.", "",
          f"PlaneFriction against pymunk's own steps (benchmarks/plugin.py: N bodies, half circles, half "
          f"boxes, sliding and spinning, no contacts; interleaved, best of {reps} fresh builds x "
          f"{plugin_study.STEPS} steps, dt = 1/120 s, mu = {plugin_study.MU}):", "",
          md_table(["bodies", "bare step (us)", "tank constraints (us)", "PlaneFriction (us)", "tank / bare",
                    "PlaneFriction / tank", "PlaneFriction us per body"],
                   [(r["bodies"], r["bare_us"], r["tank_us"], r["plugin_us"], r["tank_over_bare"],
                     r["plugin_over_tank"], r["plugin_us_per_body"]) for r in prows]), "",
          f"Growth: log-log slope of the plugin's step cost vs bodies {fmt(slope)}.", "",
          f"What a user calls, per step (phixtpm, rod-mass H=0.2, k=0.05, w=0.6, dt = 1e-3 s; interleaved, best of "
          f"{reps} fresh spaces x {2000 if quick else 5000} steps): the whole `simulate(scene, method=\"engine\")` "
          "call (set-up, the trajectory on its default grid, the events) against the same driven body in plain "
          "pymunk, and the breakdown between them:", "",
          md_table(["what", "us per step", "x plain pymunk"],
                   [("pymunk: bare `space.step` (kinematic driver + PivotJoint)", us["bare"] * 1e6,
                     us["bare"] / us["plain"]),
                    ("pymunk: the driver's velocity set, then `space.step` (the baseline)", us["plain"] * 1e6, 1.0),
                    ("rrbody: `h.plane.step` alone (friction, driver, `space.step`)", us["plane_step"] * 1e6,
                     us["plane_step"] / us["plain"]),
                    ("rrbody: `simulate(scene, method=\"engine\")`", us["simulate"] * 1e6, u_ratio)]), "",
          "Adding and removing bodies one by one (benchmarks/plugin.py study 3: the bodies above already in the "
          "space, N adds, the first step after them, N removes in random order; interleaved, best of the repeats):",
          "",
          md_table(["bodies", "adds (s)", "us per add", "first step (ms)", "removes (s)", "us per remove",
                    "adds / smallest N", "removes / smallest N"],
                   [(r["bodies"], r["adds_s"], r["us_per_add"], r["first_step_s"] * 1e3, r["removes_s"],
                     r["us_per_remove"], r["adds_ratio"], r["removes_ratio"]) for r in arows]), "",
          "The machine is shared by several engineers: re-run on a quiet machine before quoting absolute "
          "times (the ratios are measured interleaved in one run)."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    d0 = [r for r in rows if r["default"]][0]
    res.extra = {"order_phi": order_phi, "order_tf": order_tf, "highlights": [
        f"engine path converges at order {fmt(order_phi)} in dt (phi(10 s)), {fmt(order_tf)} (t_f); default dt "
        f"{fmt(d0['dt'])} s on phixtpm: t_f rel err {fmt(d0['tf_rel_err'])}, {fmt(d0['us_per_step'])} us per step."]}
    return res


def _plot(path: Path, rows: list[dict[str, Any]], erows: list[dict[str, Any]]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(14, 4.3))
    a1.loglog([r["dt"] for r in rows], [r["phi_err"] for r in rows], "o-", label="phi(10 s) abs err (rad)")
    tf = [r for r in rows if math.isfinite(r["tf_rel_err"]) and r["tf_rel_err"] > 0]
    if tf:
        a1.loglog([r["dt"] for r in tf], [r["tf_rel_err"] for r in tf], "s-", label="t_f rel err")
    a1.set_xlabel("dt (s)")
    a1.set_ylabel("error")
    a1.legend(fontsize=8)
    a1.set_title("engine error vs dt (phixtpm)", fontsize=10)
    a2.loglog([r["cost_per_sim_s"] for r in rows], [r["phi_err"] for r in rows], "o-")
    a2.set_xlabel("wall time per simulated second (s)")
    a2.set_ylabel("phi(10 s) abs err (rad)")
    a2.set_title("engine work-precision", fontsize=10)
    er = [r for r in erows if r["elements"] > 1]
    a3.loglog([r["elements"] for r in er], [r["us_per_step"] for r in er], "o-", label="dry, sampled elements")
    a3.axhline(erows[0]["us_per_step"], color="k", ls=":", label="bare driven step")
    a3.axhline(3 * erows[0]["us_per_step"], color="r", ls="--", lw=1, label="3x bare (target)")
    a3.set_xlabel("area elements")
    a3.set_ylabel("us per step")
    a3.legend(fontsize=8)
    a3.set_title("engine cost per step", fontsize=10)
    from matplotlib.ticker import NullFormatter

    for a in (a1, a2, a3):
        a.grid(True, which="both", alpha=0.3)
        a.xaxis.set_minor_formatter(NullFormatter())
        a.yaxis.set_minor_formatter(NullFormatter())
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path
