"""Stribeck friction: the flip time against the Stribeck speed v_s, and a disk's spin-down on both paths.

mu(v) = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2). (a) The paper's rod-mass scene of Fig. SSs (H = 0.6,
omega = 0.6 rad/s, k = mu_k g / d = 0.003 s^-2) under Stribeck friction with mu_s = 1.5 and 2 mu_k: t_f
runs from Coulomb friction with mu_s (v_s -> infinity) to Coulomb friction with mu_k (v_s -> 0), both
limits drawn from dry-friction runs; t_f jumps where the global minimum of phi moves to another swing (an
independent integration agrees across the jumps, ``tests/test_stribeck.py``'s brute force). (b) A disk (R = 0.1 m,
mu_k 0.3, mu_s 0.5) spun at 20 rad/s about its centre: its spin on the ODE path (the contact method's footprint
quadrature) and as a pymunk body in the plugin, against the exact stop time (nested quadratures of I w' = -int mu(|w|
r) g r dm).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import flip_time
from rrbody.analysis.report import write_summary, write_table
from rrbody.integrate.free import simulate_free
from rrbody.model.scene import scene_from_params
from rrbody.render.figures import save_figure

G = 9.81
H, K, OMEGA = 0.6, 0.003, 0.6  # paper Fig. SSs's rod-mass scene (d = 1 m)
RATIOS = (1.5, 2.0)  # mu_s / mu_k
V_S = np.geomspace(1e-3, 30.0, 36)  # m/s: the mass moves at up to ~1 m/s
R, MU_K, MU_S, W0 = 0.1, 0.3, 0.5, 20.0  # the disk (m, -, -, rad/s)
V_SPIN = (0.005, 0.05, 0.5)  # m/s: the disk's rim moves at R W0 = 2 m/s
DT_PLUGIN = 1e-4  # s


def _stop_time(v_s: float) -> float:
    """The disk's exact stop time (docstring (b)): dw/dt = -(4 g / R^4) int_0^R mu(w r) r^2 dr."""
    from scipy.integrate import quad

    def J(w: float) -> float:
        return quad(lambda r: (MU_K + (MU_S - MU_K) * math.exp(-((w * r / v_s) ** 2))) * r * r, 0.0, R,
                    epsabs=0.0, epsrel=1e-13, limit=200)[0]

    return quad(lambda w: R**4 / (4.0 * G * J(w)), 0.0, W0, epsabs=0.0, epsrel=1e-12, limit=200)[0]


def _plugin_spin(v_s: float, t_end: float) -> tuple[np.ndarray, np.ndarray, float | None]:
    """The disk as a pymunk body under rrbody's plugin: (t, spin) every 50 steps of DT_PLUGIN, and the end of
    the step that stopped it (s; None if it still spins at ``t_end``)."""
    import pymunk

    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    body = pymunk.Body(1.0, 0.5 * R * R)
    space.add(body, pymunk.Circle(body, R))
    body.angular_velocity = W0
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=MU_K, law="stribeck", params={"mu_s": MU_S, "v_s": v_s})
    ts, ws, stop = [0.0], [W0], None
    for i in range(1, int(round(t_end / DT_PLUGIN)) + 1):
        pf.step(DT_PLUGIN)
        if stop is None and body.angular_velocity == 0.0:
            stop = i * DT_PLUGIN
        if i % 50 == 0:
            ts.append(i * DT_PLUGIN)
            ws.append(body.angular_velocity)
    return np.array(ts), np.array(ws), stop


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    mu_k = K / G
    # (a) t_f against v_s, and the two Coulomb limits
    rows, curves, limits = [], {}, {}
    for ratio in RATIOS:
        tf = []
        for v_s in V_S:
            s = scene_from_params(body="rod", H=H, k=K, omega=OMEGA, friction="stribeck", mu_s=ratio * mu_k,
                                  v_s=float(v_s))
            tf.append(float(flip_time(s).t_f))
            rows.append([ratio, float(v_s), tf[-1]])
        curves[ratio] = np.array(tf)
        limits[ratio] = float(flip_time(scene_from_params(body="rod", H=H, mu=ratio * mu_k, omega=OMEGA)).t_f)
    limits[1.0] = float(flip_time(scene_from_params(body="rod", H=H, mu=mu_k, omega=OMEGA)).t_f)
    write_table(out_dir / "tf_vs_vs.csv", ["mu_s_over_mu_k", "v_s", "t_f"], rows, force=force,
                meta={"H": H, "k": K, "omega": OMEGA, "coulomb_t_f": {str(r): t for r, t in limits.items()}})
    # (b) the spin-down, both paths
    spins = []
    for v_s in V_SPIN:
        T = _stop_time(v_s)
        s = scene_from_params(body="disk", R0=R, no_drive=True, spin0=W0, friction="stribeck", mu=MU_K, mu_s=MU_S,
                              v_s=v_s, friction_method="contact")
        tr = simulate_free(s, t_max=1.2 * T, dt_out=T / 200.0)
        tp, wp, stop = _plugin_spin(v_s, 1.2 * T)
        spins.append({"v_s": v_s, "T_exact": T, "T_ode": tr.events["t_stop"], "T_plugin": stop,
                      "ode": (tr.t, tr.spin), "plugin": (tp, wp)})
    write_table(out_dir / "spin_down.csv", ["v_s", "T_exact", "T_ode", "ode_rel_error", "T_plugin",
                                            "plugin_error_in_steps"],
                [[d["v_s"], d["T_exact"], d["T_ode"], (d["T_ode"] - d["T_exact"]) / d["T_exact"], d["T_plugin"],
                  None if d["T_plugin"] is None else (d["T_plugin"] - d["T_exact"]) / DT_PLUGIN] for d in spins],
                force=force, meta={"R": R, "mu_k": MU_K, "mu_s": MU_S, "spin0": W0, "dt_plugin": DT_PLUGIN})
    # the figure
    fig, (a, b) = plt.subplots(1, 2, figsize=(11.0, 4.3), constrained_layout=True)
    colors = {1.5: "#1f77b4", 2.0: "#d62728"}
    for ratio in RATIOS:
        # points, no line: t_f jumps between computed values (the global minimum moves to another swing)
        a.semilogx(V_S, curves[ratio], "o", ms=3.5, color=colors[ratio],
                   label=rf"Stribeck, $\mu_s$ = {ratio:g} $\mu_k$")
        a.axhline(limits[ratio], color=colors[ratio], ls="--", lw=0.9)
    a.axhline(limits[1.0], color="k", ls="--", lw=0.9, label=r"Coulomb limits ($\mu_k$; $\mu_s$, coloured)")
    a.set_xlabel(r"Stribeck speed $v_s$ (m/s)")
    a.set_ylabel(r"flip time $t_f$ (s)")
    a.set_title(rf"rod-mass, H = {H}, $\omega$ = {OMEGA} rad/s, $\mu_k g/d$ = {K} s$^{{-2}}$", fontsize=10)
    a.legend(fontsize=8)
    for d, c in zip(spins, ("#2ca02c", "#9467bd", "#ff7f0e")):
        t, w = d["ode"]
        b.plot(t, w, color=c, lw=1.3, label=rf"$v_s$ = {d['v_s']:g} m/s")
        tp, wp = d["plugin"]
        b.plot(tp[::4], wp[::4], "x", color=c, ms=4)
        b.axvline(d["T_exact"], color=c, ls=":", lw=0.9)
    b.plot([], [], "-", color="0.4", label="ODE path (contact method)")
    b.plot([], [], "x", color="0.4", label=f"plugin, pymunk, dt = {DT_PLUGIN:g} s")
    b.set_xlabel("t (s)")
    b.set_ylabel(r"spin $\omega$ (rad/s)")
    b.set_title(rf"disk R = {R} m, $\mu_k$ = {MU_K}, $\mu_s$ = {MU_S}; dotted: exact stop times", fontsize=10)
    b.legend(fontsize=8)
    save_figure(fig, out_dir, "stribeck", force=force)
    write_summary(out_dir, {
        "H": H, "k": K, "omega": OMEGA, "coulomb_t_f": {str(r): t for r, t in limits.items()},
        "t_f_range": {str(r): [float(curves[r].min()), float(curves[r].max())] for r in RATIOS},
        "spin_down": [{k: v for k, v in d.items() if k not in ("ode", "plugin")} for d in spins]}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "stribeck")
