"""phixtpm: phi(t) for three dry frictions, H = 0.2, omega = 0.6 rad/s, phi0 = pi (paper Fig. phixtpm).

Transient reverse rotation (phi decreasing on average), then perennial normal rotation; the flip
time t_f (global minimum of phi) shortens as k = mu g/d grows.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import flip_time
from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.simulate import simulate
from rrbody.model.scene import rod_mass_scene
from rrbody.render.figures import save_figure

H, OMEGA, PHI0 = 0.2, 0.6, math.pi  # paper caption
KS = (0.033, 0.05, 0.1)  # s^-2, "from bottom to top"
DT_OUT = 0.02  # s: output sampling, ~500 samples per driving period


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. Flip time of each run (direct ODE path, stops once the flip is certain).
    flips = {k: flip_time(rod_mass_scene(H, k, OMEGA, PHI0)) for k in KS}
    # 2. One common horizon: well past the slowest flip, so every curve shows the normal-rotation regime.
    t_max = 2.5 * max(float(r.t_f) for r in flips.values())
    trajs = {k: simulate(rod_mass_scene(H, k, OMEGA, PHI0), t_max=t_max, dt_out=DT_OUT) for k in KS}
    # 3. Data: phi(t) for the three k on a common time grid.
    t = trajs[KS[0]].t
    write_table(out_dir / "phixtpm.csv", ["t", *[f"phi_k{k:g}" for k in KS]],
                np.column_stack([t, *[trajs[k].phi for k in KS]]).tolist(), force=force,
                meta={"H": H, "omega": OMEGA, "phi0": PHI0, "k": list(KS),
                      "t_f": {str(k): flips[k].t_f for k in KS}})
    # 4. Figure: phi(t), flip times marked.
    fig, ax = plt.subplots(figsize=(6.4, 4.4), constrained_layout=True)
    for k, c in zip(KS, ("tab:blue", "tab:orange", "tab:green")):
        r = flips[k]
        ax.plot(trajs[k].t, trajs[k].phi, color=c, lw=1.2,
                label=rf"$\mu g/d$ = {k:g} s$^{{-2}}$, $t_f$ = {r.t_f:.2f} s")
        ax.plot([r.t_f], [r.phi_min], "o", color=c, ms=5)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\phi$ (rad)")
    ax.set_title(r"H = 0.2, $\omega$ = 0.6 rad/s, $\phi_0=\pi$ (dots: flip time)")
    ax.legend(loc="upper left", fontsize=9)
    ax.set_xlim(0, t_max)
    save_figure(fig, out_dir, "phixtpm", force=force)
    # 5. Summary for the report.
    write_summary(out_dir, {"H": H, "omega": OMEGA, "phi0": PHI0,
                            "runs": [{"k": k, "t_f": flips[k].t_f, "phi_min": flips[k].phi_min,
                                      "regime": flips[k].regime} for k in KS]}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "phixtpm")
