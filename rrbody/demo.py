"""Fallback main job: the paper's phixtpm figure (phi(t) for three frictions)."""

from __future__ import annotations

import math
from pathlib import Path


def phixtpm_figure(out_dir: Path) -> Path:
    """phi(t) for k = 0.033, 0.05, 0.1 s^-2, H = 0.2, omega = 0.6 rad/s, phi0 = pi -> out_dir/phixtpm.png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .analysis import flip_time
    from .io import atomic_path
    from .scene import rod_mass_scene
    from .simulation import simulate

    out_dir.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    for k, color in ((0.033, "tab:blue"), (0.05, "tab:orange"), (0.1, "tab:green")):
        sc = rod_mass_scene(0.2, k, 0.6, math.pi)
        tr = simulate(sc, t_max=60.0, dt_out=0.02)
        tf = flip_time(sc).t_f
        ax.plot(tr.t, tr.phi, color=color, label=f"k = {k} s$^{{-2}}$, $t_f$ = {tf:.2f} s")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\phi$ (rad)")
    ax.set_title(r"phixtpm: H = 0.2, $\omega$ = 0.6 rad/s, $\phi_0 = \pi$")
    ax.legend()
    path = out_dir / "phixtpm.png"
    with atomic_path(path, force=True) as tmp:
        fig.savefig(tmp, format="png", dpi=120)
    plt.close(fig)
    return path
