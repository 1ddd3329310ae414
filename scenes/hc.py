"""Hc: critical geometry H_c vs k = mu g/d, dry and viscous, with q-exponential fits (paper Fig. Hc).

H_c(k) is the largest H for which reverse rotation exists (docs/physics.md, "Definitions rrbody fixes")
at omega = 0.3 rad/s, phi0 = pi, found by scan + bisection (rrbody.analysis.critical_h) on a uniform grid of k. The fit
protocol that reproduces the paper's q and lambda: H_c(0) fixed at the exact frictionless value,
unweighted least squares over k in [0, 1] s^-2 (101 points per law); other ranges are reported too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rrbody.analysis.fits import fit_q_exponential, q_exponential
from rrbody.analysis.flip import critical_h, frictionless_critical_h
from rrbody.analysis.report import write_summary, write_table
from rrbody.render.figures import save_figure

OMEGA = 0.3  # rad/s (paper caption)
K_MAX_FIT = 1.0  # s^-2: the fitted range [0, K_MAX_FIT]
K_MAX = 2.0  # s^-2: computed range (the extra part feeds the range study)
DK = 0.01  # s^-2: grid step
TOL = 1e-8  # bisection tolerance on H (absolute); far below the fit residuals (~1e-3)
PAPER = {"dry": {"q": 1.936, "q_err": 0.004, "lam": 41.32, "lam_err": 0.09},
         "viscous": {"q": 1.724, "q_err": 0.003, "lam": 11.64, "lam_err": 0.01}}


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. H_c(k) on a uniform k grid for both friction laws (k = 0: the exact frictionless value).
    H0 = frictionless_critical_h()
    ks = np.round(np.arange(0.0, K_MAX + DK / 2, DK), 10)
    hc = {}
    for law in ("dry", "viscous"):
        hc[law] = np.array([H0 if k == 0 else critical_h(float(k), OMEGA, friction=law, tol=TOL, H_lo=1e-4)
                            for k in ks])
    Hc0_numeric = critical_h(0.0, OMEGA, friction="none", tol=TOL, H_lo=1e-4)  # the ODE path, no friction
    # 2. q-exponential fits, H_c(0) fixed at the exact value, over [0, K_MAX_FIT].
    fits = {law: fit_q_exponential(ks, hc[law], H0=H0, x_range=(0.0, K_MAX_FIT), relative=False,
                                   p0=(PAPER[law]["lam"], PAPER[law]["q"])) for law in hc}
    # 3. Range study: the same protocol over other k ranges.
    study = []
    for kmax in (0.1, 0.2, 0.3, 0.5, 1.0, 1.5, 2.0):
        row: dict = {"k_max": kmax}
        for law in hc:
            f = fit_q_exponential(ks, hc[law], H0=H0, x_range=(0.0, kmax), relative=False,
                                  p0=(PAPER[law]["lam"], PAPER[law]["q"]))
            row[law] = {"q": f.params["q"], "q_err": f.stderr["q"], "lam": f.params["lam"], "lam_err": f.stderr["lam"]}
        study.append(row)
    # 4. Data: H_c per k and law, with fitted values and residuals inside the fit range.
    rows = []
    for i, k in enumerate(ks):
        r = [float(k)]
        for law in ("dry", "viscous"):
            model = float(fits[law](np.array([k]))[0])
            r += [float(hc[law][i]), model, float(hc[law][i]) - model if k <= K_MAX_FIT + 1e-12 else None]
        rows.append(r)
    write_table(out_dir / "hc.csv", ["k", "Hc_dry", "fit_dry", "resid_dry", "Hc_viscous", "fit_viscous",
                                     "resid_viscous"],
                rows, force=force, meta={"omega": OMEGA, "phi0": "pi", "tol": TOL, "fit_range": [0.0, K_MAX_FIT]})
    # 5. Figure: both curves with their fits (linear axes as in the paper; log inset for the tail).
    fig, ax = plt.subplots(figsize=(6.4, 4.6), constrained_layout=True)
    kk = np.linspace(0, K_MAX_FIT, 400)
    colors = {"viscous": "tab:blue", "dry": "tab:red"}
    for law in ("viscous", "dry"):
        m = ks <= K_MAX_FIT + 1e-12
        f = fits[law]
        ax.plot(ks[m], hc[law][m], "o", ms=3, color=colors[law], clip_on=False,
                label=f"{law}: q = {f.params['q']:.3f}, $\\lambda$ = {f.params['lam']:.2f}")
        ax.plot(kk, q_exponential(kk, H0, f.params["lam"], f.params["q"]), "-", color="k", lw=1)
    ax.set_xlabel(r"$\mu g/d$ (s$^{-2}$)")
    ax.set_ylabel(r"$H_c$")
    ax.set_title(r"Critical geometry: $\omega$ = 0.3 rad/s, $\phi_0=\pi$; lines: q-exponential fits")
    ax.set_xlim(-0.02, K_MAX_FIT + 0.02)  # room for the markers at k = 0 and k = 1
    ax.set_ylim(0, 0.82)
    ax.legend(loc="upper right")
    ins = ax.inset_axes((0.45, 0.4, 0.33, 0.3))
    inside, beyond = ks[1:] <= K_MAX_FIT + 1e-12, ks[1:] >= K_MAX_FIT - 1e-12
    for law in ("viscous", "dry"):
        ins.loglog(ks[1:], hc[law][1:], ".", ms=2, color=colors[law])
        f = fits[law]
        model = q_exponential(ks[1:], H0, f.params["lam"], f.params["q"])
        # the fit is solid over its range and dashed where it is only extrapolated
        ins.loglog(ks[1:][inside], model[inside], "k-", lw=0.7)
        ins.loglog(ks[1:][beyond], model[beyond], "k--", lw=0.7)
    ins.axvline(K_MAX_FIT, color="0.5", ls=":", lw=0.8)
    ins.text(0.97 * K_MAX_FIT, 0.05, "fit range", fontsize=6, ha="right", va="bottom", color="0.35",
             transform=ins.get_xaxis_transform())
    ins.set_xlabel(r"$\mu g/d$ (s$^{-2}$); dashed: extrapolated fit", fontsize=7)
    ins.set_ylabel(r"$H_c$", fontsize=7)
    ins.tick_params(labelsize=6)
    save_figure(fig, out_dir, "hc", force=force)
    # 6. Summary for the report.
    write_summary(out_dir, {
        "omega": OMEGA, "tol": TOL, "Hc0_exact": H0, "Hc0_numeric": Hc0_numeric, "paper": PAPER,
        "fits": {law: {"q": f.params["q"], "q_err": f.stderr["q"], "lam": f.params["lam"], "lam_err": f.stderr["lam"],
                       "k_range": list(f.x_range), "n": f.n, "rms": f.rms} for law, f in fits.items()},
        "range_study": study,
    }, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "hc")
