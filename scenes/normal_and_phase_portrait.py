"""NormalAndPhasePortrait: (a) normal rotations, from t = 0 and transient; (b) theta's phase portrait (paper Fig.
NormalAndPhasePortrait).

(a) phi(t) for k = 0.003 s^-2, H = 0.6, omega = 0.6 rad/s, phi0 = pi/2 (normal rotation from the
start; inset: its CM history for 0 < t < 80 s) and for k = 0.003 s^-2, H = 0.8, omega = 2 rad/s,
phi0 = pi (near the RR transition). (b) (theta, theta') for k = 0.27 s^-2, H = 0.4,
omega = 1.7 rad/s from phi0 = pi (RR) and phi0 = pi/2 (normal), with the line of valid initial
conditions theta' = -(omega/H) cos(theta) - omega (rrbody.portraits).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import flip_time
from rrbody.analysis.portraits import initial_point, theta_series, valid_initial_line
from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.simulate import simulate
from rrbody.model.scene import rod_mass_scene
from rrbody.render.figures import save_figure

A_NORMAL = {"k": 0.003, "H": 0.6, "omega": 0.6, "phi0": math.pi / 2}
A_TRANSIENT = {"k": 0.003, "H": 0.8, "omega": 2.0, "phi0": math.pi}
B = {"k": 0.27, "H": 0.4, "omega": 1.7}
T_A = 80.0  # s: the paper's inset horizon
T_B = 14.0  # s: past the flip (t_f = 4.9 s) and into the settled normal rotation
DT_OUT = 0.01  # s


def run(p: dict, t_max: float) -> tuple:
    sc = rod_mass_scene(p["H"], p["k"], p["omega"], p["phi0"])
    return simulate(sc, t_max=t_max, dt_out=DT_OUT), flip_time(sc)


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. Panel (a) runs.
    tr_n, f_n = run(A_NORMAL, T_A)
    tr_t, f_t = run(A_TRANSIENT, T_A)
    # 2. Panel (b) runs and their rotating-frame angle theta.
    runs_b = {}
    for phi0 in (math.pi, math.pi / 2):
        tr, f = run({**B, "phi0": phi0}, T_B)
        th, thd = theta_series(tr.t, tr.phi, tr.phi_dot, B["omega"])
        runs_b[phi0] = (tr, f, th, thd)
    # 3. Data tables.
    write_table(out_dir / "panel_a.csv", ["t", "phi_normal", "phi_transient", "x_cm_normal", "y_cm_normal"],
                np.column_stack([tr_n.t, tr_n.phi, tr_t.phi, tr_n.x_cm, tr_n.y_cm]).tolist(), force=force,
                meta={"normal": A_NORMAL, "transient": A_TRANSIENT})
    tb = runs_b[math.pi][0].t
    write_table(out_dir / "panel_b.csv", ["t", "theta_pi", "theta_dot_pi", "theta_halfpi", "theta_dot_halfpi"],
                np.column_stack([tb, runs_b[math.pi][2], runs_b[math.pi][3], runs_b[math.pi / 2][2],
                                 runs_b[math.pi / 2][3]]).tolist(), force=force, meta=B)
    # 4. Figure.
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    ax.plot(tr_n.t, tr_n.phi, "-", color="tab:blue", lw=1.3,
            label=r"H = 0.6, $\omega$ = 0.6, $\phi_0=\pi/2$")
    ax.plot(tr_t.t, tr_t.phi, "--", color="tab:pink", lw=1.5, label=r"H = 0.8, $\omega$ = 2, $\phi_0=\pi$")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\phi$ (rad)")
    ax.set_xlim(0, T_A)
    ax.set_title(r"(a) $\mu g/d$ = 0.003 s$^{-2}$")
    ax.legend(loc="lower right", fontsize=8)
    ins = ax.inset_axes((0.05, 0.47, 0.36, 0.43))
    circ = np.linspace(0, 2 * math.pi, 200)
    ins.plot(np.cos(circ), np.sin(circ), ":", color="k", lw=0.8)
    ins.plot(tr_n.x_cm, tr_n.y_cm, color="tab:green", lw=0.6)
    ins.plot([tr_n.x_cm[-1]], [tr_n.y_cm[-1]], "o", color="tab:green", ms=4)
    ins.set_aspect("equal")
    ins.set_xticks([])
    ins.set_yticks([])
    ins.set_title(r"CM, 0 < t < 80 s, $\phi_0=\pi/2$", fontsize=7)
    th_line, thd_line = valid_initial_line(B["H"], B["omega"], np.linspace(-4 * math.pi, 4 * math.pi, 1200))
    bx.plot(th_line, thd_line, "k--", lw=0.9, label="valid initial conditions")
    for phi0, c, mk, lab in ((math.pi, "tab:orange", "^", r"$\phi_0=\pi$ (RR)"),
                             (math.pi / 2, "tab:green", "s", r"$\phi_0=\pi/2$ (normal)")):
        _, _, th, thd = runs_b[phi0]
        bx.plot(th, thd, "-", color=c, lw=1.0, label=lab)
        th0, thd0 = initial_point(B["H"], B["omega"], phi0)
        bx.plot([th0], [thd0], mk, color=c, ms=9, mec="k")
    allth = np.concatenate([runs_b[p][2] for p in runs_b])
    bx.set_xlim(allth.min() - 0.5, allth.max() + 0.5)
    allthd = np.concatenate([runs_b[p][3] for p in runs_b])
    bx.set_ylim(min(allthd.min(), thd_line.min()) - 0.5, max(allthd.max(), thd_line.max()) + 0.5)
    bx.axhline(0, color="0.7", lw=0.6)
    bx.set_xlabel(r"$\theta = \phi - \omega t + \pi$ (rad)")
    bx.set_ylabel(r"$\dot\theta$ (rad/s)")
    bx.set_title(r"(b) $\mu g/d$ = 0.27 s$^{-2}$, H = 0.4, $\omega$ = 1.7 rad/s")
    bx.legend(loc="upper center", fontsize=8)
    save_figure(fig, out_dir, "normal_and_phase_portrait", force=force)
    # 5. Summary for the report.
    def s(f: object, p: dict) -> dict:
        return {**p, "t_f": f.t_f, "phi_min": f.phi_min, "reverse_rotation": f.reverse_rotation,  # type: ignore[attr-defined]
                "regime": f.regime}  # type: ignore[attr-defined]

    def mean_rate(t0: float, t1: float) -> float:
        """Mean phi' (rad/s) of the transient run over [t0, t1]."""
        i0, i1 = np.searchsorted(tr_t.t, [t0, t1])
        return float((tr_t.phi[i1] - tr_t.phi[i0]) / (tr_t.t[i1] - tr_t.t[i0]))

    write_summary(out_dir, {"a_normal": s(f_n, A_NORMAL), "a_transient": s(f_t, A_TRANSIENT),
                            "a_transient_rate": [mean_rate(5.0, 40.0), mean_rate(60.0, 79.0)],
                            "b_pi": s(runs_b[math.pi][1], {**B, "phi0": math.pi}),
                            "b_half_pi": s(runs_b[math.pi / 2][1], {**B, "phi0": math.pi / 2})}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "normal-and-phase-portrait")
