"""SSs: phi(t) and the CM history, red before t_f and blue after (paper Fig. SSs; the still of Movie S1).

k = 0.003 s^-2, H = 0.6, omega = 0.6 rad/s, phi0 = pi. During reverse rotation the CM traces
petal-shaped loops with cusps; after the flip its path rounds off as phi locks to the drive.
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

K, H, OMEGA, PHI0 = 0.003, 0.6, 0.6, math.pi  # paper caption
DT_OUT = 0.02  # s: smooth CM paths (~500 samples per driving period)
RED, BLUE, GREEN = "#d62728", "#1f77b4", "#2ca02c"


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    scene = rod_mass_scene(H, K, OMEGA, PHI0)
    # 1. Flip time, then one trajectory reaching well into the normal-rotation regime.
    r = flip_time(scene)
    t_f = float(r.t_f)
    t_max = 1.6 * t_f
    tr = simulate(scene, t_max=t_max, dt_out=DT_OUT)
    before = tr.t <= t_f
    # 2. Data: t, phi and the CM position, with a flag for "before t_f".
    write_table(out_dir / "sss.csv", ["t", "phi", "x_cm", "y_cm", "before_flip"],
                [[float(a), float(b), float(c), float(d), int(e)] for a, b, c, d, e in
                 zip(tr.t, tr.phi, tr.x_cm, tr.y_cm, before)], force=force,
                meta={"k": K, "H": H, "omega": OMEGA, "phi0": PHI0, "t_f": t_f})
    # 3. Figure: phi(t) on top; below, the CM history up to three times (red before t_f, blue after).
    fig = plt.figure(figsize=(9.5, 6.4), constrained_layout=True)
    gs = fig.add_gridspec(2, 3, height_ratios=(1.0, 1.1))
    ax = fig.add_subplot(gs[0, :])
    # the two parts share the sample at t_f's side so the curve has no gap
    k = int(np.count_nonzero(before))
    ax.plot(tr.t[:k + 1], tr.phi[:k + 1], color=RED, lw=1.3, label=r"$t < t_f$: reverse rotation")
    ax.plot(tr.t[k:], tr.phi[k:], color=BLUE, lw=1.3, label=r"$t > t_f$: normal rotation")
    ax.axvline(t_f, color="0.5", ls=":", lw=1, label=r"flip time $t_f$")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\phi$ (rad)")
    ax.set_title(rf"$\mu g/d$ = {K} s$^{{-2}}$, H = {H}, $\omega$ = {OMEGA} rad/s, $\phi_0=\pi$;"
                 rf" $t_f$ = {t_f:.2f} s")
    circle = np.linspace(0, 2 * math.pi, 200)
    for j, t_end in enumerate((0.5 * t_f, t_f, t_max)):
        a = fig.add_subplot(gs[1, j])
        m = tr.t <= t_end
        a.plot(np.cos(circle), np.sin(circle), ":", color="k", lw=0.8)  # the path of P (radius d = 1 m)
        n = int(np.count_nonzero(m))
        a.plot(tr.x_cm[:min(k + 1, n)], tr.y_cm[:min(k + 1, n)], color=RED, lw=0.8)
        if n > k:
            a.plot(tr.x_cm[k:n], tr.y_cm[k:n], color=BLUE, lw=0.8)
        i = n - 1
        a.plot([tr.x_cm[i]], [tr.y_cm[i]], "o", color=GREEN, ms=6, label="CM now" if j == 0 else None)
        a.set_aspect("equal")
        lim = 1.0 + H + 0.1
        a.set_xlim(-lim, lim)
        a.set_ylim(-lim, lim)
        a.set_title(f"CM history, 0 < t < {tr.t[i]:.1f} s", fontsize=9)
        a.set_xlabel("x (m)")
        if j == 0:
            a.set_ylabel("y (m)")
    ax.plot([], [], ":", color="k", lw=0.8, label="path of P (radius d = 1 m), below")
    ax.plot([], [], "o", color=GREEN, ms=6, label="CM at the panel's last time, below")
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    save_figure(fig, out_dir, "sss", force=force)
    # 4. Summary for the report.
    write_summary(out_dir, {"k": K, "H": H, "omega": OMEGA, "phi0": PHI0, "t_f": t_f, "phi_min": r.phi_min,
                            "regime": r.regime}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "sss")
