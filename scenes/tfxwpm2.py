"""tfxwpm2: flip time vs omega (k = 7.5 s^-2, H = 0.25) and vs mu (g/d = 25 s^-2), power-law fits (paper Fig. tfxwpm2).

Low omega: t_f ~ 1/omega, independent of mu (gamma = 0 in t_f ~ omega^(gamma-1) k^(-gamma/2)); the
exact limit omega t_f -> C(H) (rrbody.report.small_omega_C) is drawn beside the paper's
2 sqrt(2)/(2 + 1/H). High omega: t_f ~ omega (gamma = 2). An optimal omega in between. t_f vs mu
~ 1/mu at low mu for omega = 0.6 (H = 0.25) and omega = 200 (H = 0.73, mu 0.001 to 0.03).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.fits import fit_power_law
from rrbody.analysis.report import paper_small_omega_C, small_omega_C, write_summary, write_table
from rrbody.analysis.sweep import run_fresh_or_resume
from rrbody.analysis.sweep_spec import Sweep
from rrbody.render.figures import save_figure

K, H = 7.5, 0.25  # s^-2, paper caption
G_OVER_D = 25.0  # s^-2: k = 25 mu in the mu panels
W_GRID = np.geomspace(0.01, 300.0, 121)  # rad/s
W_OPT = np.linspace(1.0, 10.0, 181)  # rad/s: dense grid around the optimum
LOW_FIT = (0.01, 0.3)  # rad/s: omega^2 <= 0.09 << k = 7.5
HIGH_FIT = (30.0, 300.0)  # rad/s: omega^2 >= 900 >> k
MU_W06 = np.geomspace(1e-5, 0.3, 43)  # omega = 0.6, H = 0.25 (panel e)
MU_W06_FIT = (1e-5, 3e-4)  # k = 25 mu <= 0.0075 << omega^2 = 0.36
MU_W1 = np.geomspace(0.01, 1.0, 25)  # omega = 1, H = 0.25 (inset of panel a)
MU_W200 = np.geomspace(0.001, 0.03, 9)  # omega = 200, H = 0.73 (paper: data not shown)
LOW_W_MU = (0.05, np.geomspace(1.0, 20.0, 7))  # omega = 0.05: t_f vs k at low omega (inset of panel b)


def tf_of(ds, name: str = "t_f") -> np.ndarray:
    return np.asarray(ds[name].values, dtype=float)


def broken_at_jumps(y: np.ndarray, ratio: float = 1.3) -> np.ndarray:
    """A copy of y where the segment after a jump (neighbours differing by
    more than ``ratio``) is cut, so a line plot does not join values across a jump of t_f."""
    out = np.array(y, float)
    jump = np.zeros(len(out), bool)
    jump[1:] = np.maximum(out[1:], out[:-1]) > ratio * np.minimum(out[1:], out[:-1])
    out[jump] = np.nan
    return out


def draw_fit(ax, fit, lo: float, hi: float, colour: str, label: str) -> None:
    """The fitted power law: solid over its fit range (shaded), dashed where extrapolated (x3 either side)."""
    a, b = fit.x_range
    inside = np.geomspace(max(lo, a), min(hi, b), 50)
    if inside[0] < inside[-1]:
        ax.loglog(inside, fit(inside), "-", color=colour, lw=1.2, label=label)
        ax.axvspan(max(lo, a), min(hi, b), color=colour, alpha=0.07, lw=0)
    for x0, x1 in ((a / 3, a), (b, b * 3)):
        x0, x1 = max(lo, x0), min(hi, x1)  # only inside the panel's own range
        if x0 < x1:
            xx = np.geomspace(x0, x1, 20)
            ax.loglog(xx, fit(xx), "--", color=colour, lw=0.9)


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. Sweeps (local processes, checkpointed): t_f vs omega, the dense optimum grid, the mu scans.
    d_w = run_fresh_or_resume(Sweep(base={"H": H, "k": K}, axes={"omega": W_GRID}), out_dir / "tf_vs_omega.nc")
    d_opt = run_fresh_or_resume(Sweep(base={"H": H, "k": K}, axes={"omega": W_OPT}), out_dir / "tf_optimum.nc")
    d_m06 = run_fresh_or_resume(Sweep(base={"H": H, "omega": 0.6}, axes={"k": G_OVER_D * MU_W06}),
                                out_dir / "tf_vs_mu_w0.6.nc")
    d_m1 = run_fresh_or_resume(Sweep(base={"H": H, "omega": 1.0}, axes={"k": G_OVER_D * MU_W1}),
                               out_dir / "tf_vs_mu_w1.nc")
    d_m200 = run_fresh_or_resume(Sweep(base={"H": 0.73, "omega": 200.0}, axes={"k": G_OVER_D * MU_W200}),
                                 out_dir / "tf_vs_mu_w200.nc")
    d_low = run_fresh_or_resume(Sweep(base={"H": H, "omega": LOW_W_MU[0]}, axes={"k": LOW_W_MU[1]}),
                                out_dir / "tf_vs_k_low_omega.nc")
    tf_w, tf_opt = tf_of(d_w), tf_of(d_opt)
    # 2. Power-law fits.
    f_lo = fit_power_law(W_GRID, tf_w, x_range=LOW_FIT)
    f_hi = fit_power_law(W_GRID, tf_w, x_range=HIGH_FIT)
    f_m06 = fit_power_law(MU_W06, tf_of(d_m06), x_range=MU_W06_FIT)
    f_m200 = fit_power_law(MU_W200, tf_of(d_m200))
    f_m1 = fit_power_law(MU_W1, tf_of(d_m1))
    # 3. Optimum: the smallest t_f over both omega grids.
    w_all = np.concatenate([W_GRID, W_OPT])
    t_all = np.concatenate([tf_w, tf_opt])
    j = int(np.nanargmin(t_all))
    #    t_f is smooth near the grid minimum (checked: no jump within +-0.1 rad/s), so refine it by
    #    bounded scalar minimisation; the omega tolerance 1e-4 rad/s is far below the grid step.
    from scipy.optimize import minimize_scalar

    from rrbody.analysis.flip import flip_time
    from rrbody.model.scene import rod_mass_scene

    opt = minimize_scalar(lambda w: float(flip_time(rod_mass_scene(H, K, float(w))).t_f),
                          bounds=(w_all[j] - 0.1, w_all[j] + 0.1), method="bounded", options={"xatol": 1e-4})
    w_star, t_star = float(opt.x), float(opt.fun)
    # 4. The small-omega limit: exact C(H) vs the paper's estimate vs the ODE at the smallest omega.
    w_min = float(W_GRID[0])
    phi_min_low = float(d_w["phi_min"].values[0])
    small = {"omega": w_min, "k": K, "H": H, "exact_C": small_omega_C(H), "paper_C": paper_small_omega_C(H),
             "numeric_C": w_min * float(tf_w[0]), "exact_phi_min": math.pi / 2 + small_omega_C(H),
             "numeric_phi_min": phi_min_low}
    low_k_tf = tf_of(d_low)
    spread = float((np.nanmax(low_k_tf) - np.nanmin(low_k_tf)) / np.nanmean(low_k_tf))
    # 5. Data tables.
    write_table(out_dir / "tf_vs_omega.csv", ["omega", "t_f", "phi_min", "reverse_rotation"],
                [[float(w), float(t), float(p), int(r)] for w, t, p, r in
                 zip(W_GRID, tf_w, d_w["phi_min"].values, d_w["reverse_rotation"].values)], force=force,
                meta={"k": K, "H": H, "phi0": "pi"})
    write_table(out_dir / "tf_vs_mu.csv", ["omega", "H", "mu", "k", "t_f"],
                [[0.6, H, float(m), G_OVER_D * float(m), float(t)] for m, t in zip(MU_W06, tf_of(d_m06))]
                + [[1.0, H, float(m), G_OVER_D * float(m), float(t)] for m, t in zip(MU_W1, tf_of(d_m1))]
                + [[200.0, 0.73, float(m), G_OVER_D * float(m), float(t)] for m, t in zip(MU_W200, tf_of(d_m200))],
                force=force, meta={"g_over_d": G_OVER_D, "phi0": "pi"})
    # 6. Figure: (a) linear, (b) log-log with fits, (c) high omega, (d) low omega, (e) t_f vs mu, (f) omega = 200.
    fig, axs = plt.subplots(2, 3, figsize=(13, 7.6), constrained_layout=True)
    a, b, c, d, e, f = axs.ravel()
    m = W_GRID <= 12
    # lines are cut where t_f jumps between neighbouring omega (the flip moves to another minimum of phi)
    a.plot(W_GRID[m], tf_w[m], "o", ms=2.5, color="tab:blue", label=r"$t_f$, log-spaced $\omega$ grid")
    a.plot(W_GRID[m], broken_at_jumps(tf_w[m]), "-", lw=0.6, color="tab:blue")
    mo = W_OPT <= 12
    a.plot(W_OPT[mo], tf_opt[mo], ".", ms=1.5, color="tab:cyan", label=r"dense grid, 1 $\leq \omega \leq$ 10")
    a.plot([w_star], [t_star], "r*", ms=10, label=rf"optimum $\omega$ = {w_star:.3f}, $t_f$ = {t_star:.4f} s")
    a.set_ylim(0, 6)
    a.set_xlabel(r"$\omega$ (rad/s)")
    a.set_ylabel(r"$t_f$ (s)")
    a.set_title(r"(a) $\mu g/d$ = 7.5 s$^{-2}$, H = 0.25")
    a.legend(loc="upper right", fontsize=7)
    ia = a.inset_axes((0.36, 0.42, 0.36, 0.3))
    ia.semilogx(MU_W1, tf_of(d_m1), "o-", ms=2, lw=0.7, color="tab:purple")
    ia.set_xlabel(r"$\mu$ (g/d = 25 s$^{-2}$)", fontsize=7, labelpad=1)
    ia.set_ylabel(r"$t_f$ (s)", fontsize=7, labelpad=1)
    ia.tick_params(labelsize=6)
    ia.set_title(r"$\omega$ = 1 rad/s: $t_f$ vs $\mu$", fontsize=7)
    for ax, lo, hi, title in ((b, 0.01, 300, "(b) log-log"), (c, 3.0, 300, r"(c) high $\omega$"),
                              (d, 0.01, 1.0, r"(d) low $\omega$")):
        mm = (W_GRID >= lo) & (W_GRID <= hi)
        ax.loglog(W_GRID[mm], tf_w[mm], "o", ms=2.5, color="tab:blue")
        for fit, col in ((f_lo, "tab:red"), (f_hi, "tab:green")):
            draw_fit(ax, fit, lo, hi, col, rf"$t_f \propto \omega^{{{fit.params['b']:.3f}}}$, fit over "
                     rf"{fit.x_range[0]:.3g}-{fit.x_range[1]:.3g} rad/s")
        ax.set_xlabel(r"$\omega$ (rad/s)")
        ax.set_ylabel(r"$t_f$ (s)")
        ax.set_title(title + " (shaded: fit range; dashed: extrapolated)", fontsize=9)
        ax.legend(loc="lower left" if ax is b else "upper center", fontsize=7)
    ww = np.geomspace(0.01, 1.0, 20)
    d.loglog(ww, small_omega_C(H) / ww, "k:", lw=1, label=r"exact limit $C(H)/\omega$")
    d.loglog(ww, paper_small_omega_C(H) / ww, "m--", lw=1, label=r"paper $2\sqrt{2}/(\omega(2+1/H))$")
    d.legend(loc="upper right", fontsize=7)
    ib = b.inset_axes((0.45, 0.55, 0.27, 0.25))
    ib.semilogx(LOW_W_MU[1], low_k_tf, "s-", ms=2.5, lw=0.7, color="tab:brown")
    ib.set_ylim(0, 1.5 * np.nanmax(low_k_tf))
    ib.set_title(rf"$\omega$ = {LOW_W_MU[0]} rad/s: $t_f$ vs $\mu g/d$", fontsize=7)
    ib.set_xlabel(r"$\mu g/d$ (s$^{-2}$)", fontsize=6, labelpad=1)
    ib.set_ylabel(r"$t_f$ (s)", fontsize=6, labelpad=1)
    ib.tick_params(labelsize=6)
    e.loglog(MU_W06, tf_of(d_m06), "o", ms=2.5, color="tab:orange")
    draw_fit(e, f_m06, MU_W06[0], MU_W06[-1], "k", rf"$t_f \propto \mu^{{{f_m06.params['b']:.3f}}}$, fit over "
             rf"$\mu \leq$ {MU_W06_FIT[1]:g}")
    e.set_xlabel(r"$\mu$")
    e.set_ylabel(r"$t_f$ (s)")
    e.set_title(r"(e) $\omega$ = 0.6 rad/s, H = 0.25, g/d = 25 s$^{-2}$", fontsize=9)
    e.legend(fontsize=8)
    f.loglog(MU_W200, tf_of(d_m200), "o", ms=3, color="tab:olive")
    draw_fit(f, f_m200, MU_W200[0], MU_W200[-1], "k", rf"$t_f \propto \mu^{{{f_m200.params['b']:.3f}}}$, "
             "fit over all points")
    f.set_xlabel(r"$\mu$")
    f.set_ylabel(r"$t_f$ (s)")
    f.set_title(r"(f) $\omega$ = 200 rad/s, H = 0.73, g/d = 25 s$^{-2}$", fontsize=9)
    f.legend(fontsize=8)
    fig.suptitle(r"Flip time vs $\omega$ and $\mu$ ($\phi_0=\pi$)")
    save_figure(fig, out_dir, "tfxwpm2", force=force)

    # 7. Summary for the report.
    def fs(fit) -> dict:
        return {"A": fit.params["A"], "b": fit.params["b"], "b_err": fit.stderr["b"], "range": list(fit.x_range),
                "n": fit.n, "rms_log": fit.rms}

    write_summary(out_dir, {"k": K, "H": H, "fit_low": fs(f_lo), "fit_high": fs(f_hi), "fit_mu_w06": fs(f_m06),
                            "fit_mu_w1": fs(f_m1), "fit_mu_w200": fs(f_m200),
                            "optimum": {"omega": w_star, "t_f": t_star,
                                        "grid_omega": float(w_all[j]), "grid_t_f": float(t_all[j])},
                            "small_omega": small,
                            "low_omega_mu_omega": LOW_W_MU[0], "low_omega_mu_k": [float(LOW_W_MU[1][0]),
                                                                                  float(LOW_W_MU[1][-1])],
                            "low_omega_mu_spread": spread}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "tfxwpm2")
