"""seco1: flip time vs phi0, k = 7.5, 12.5, 17.5 s^-2 (H = 0.25, omega = 100 rad/s); inset: CM path (paper Fig. seco1).

The phi0 interval with reverse rotation is centred on pi and does not depend on friction: its
edges are located by bisection on the RR test (docs/physics.md, "Definitions rrbody fixes") for each k and without
friction. Inset: k = 0.0015 s^-2, H = 0.2, omega = 0.6 rad/s, phi0 = pi, CM position over 250 s.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import reverse_rotation_exists
from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.simulate import simulate
from rrbody.analysis.sweep import run_fresh_or_resume
from rrbody.analysis.sweep_spec import Sweep
from rrbody.model.scene import rod_mass_scene
from rrbody.render.figures import save_figure

H, OMEGA = 0.25, 100.0  # paper caption (main panel)
KS = (7.5, 12.5, 17.5)  # s^-2
N_PHI0 = 97  # phi0 samples over [pi/2, 3pi/2]
INSET = {"k": 0.0015, "H": 0.2, "omega": 0.6, "t": 250.0}
EDGE_TOL = 1e-9  # rad: bisection tolerance on the interval edges


def rr_edge(H: float, k: float, omega: float, inside: float, outside: float, friction: str) -> float:
    """Bisect the RR test in phi0 between a point with RR (``inside``) and one without (``outside``)."""
    a, b = inside, outside
    while abs(b - a) > EDGE_TOL:
        m = 0.5 * (a + b)
        if reverse_rotation_exists(rod_mass_scene(H, k, omega, m, friction=friction)):
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def rr_interval(k: float, friction: str = "dry") -> tuple[float, float]:
    """[lo, hi] of phi0 with RR, bracketed on a coarse grid around pi then bisected."""
    grid = np.linspace(math.pi / 2, math.pi, 65)
    ok = [reverse_rotation_exists(rod_mass_scene(H, k, OMEGA, float(p), friction=friction)) for p in grid]
    j = int(np.argmax(ok))  # first phi0 with RR below pi
    if not ok[j] or j == 0:
        raise ValueError(f"no RR edge found in [pi/2, pi] for k={k}")
    lo = rr_edge(H, k, OMEGA, float(grid[j]), float(grid[j - 1]), friction)
    grid2 = np.linspace(math.pi, 1.5 * math.pi, 65)
    ok2 = [reverse_rotation_exists(rod_mass_scene(H, k, OMEGA, float(p), friction=friction)) for p in grid2]
    j2 = len(ok2) - 1 - int(np.argmax(ok2[::-1]))  # last phi0 with RR above pi
    hi = rr_edge(H, k, OMEGA, float(grid2[j2]), float(grid2[min(j2 + 1, len(grid2) - 1)]), friction)
    return lo, hi


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. t_f over a phi0 grid for the three k (a 2-D sweep on local processes, checkpointed).
    phi0s = np.linspace(math.pi / 2, 1.5 * math.pi, N_PHI0)
    sw = Sweep(base={"H": H, "omega": OMEGA}, axes={"k": KS, "phi0": phi0s})
    ds = run_fresh_or_resume(sw, out_dir / "seco1_sweep.nc")
    # 2. The RR interval: with and without friction.
    interval0 = rr_interval(0.0, "none")
    per_k = []
    for k in KS:
        lo, hi = rr_interval(k)
        t_pi = float(ds["t_f"].sel(k=k).interp(phi0=math.pi)) if N_PHI0 % 2 == 1 else None
        per_k.append({"k": k, "rr_interval": [lo, hi], "t_f_pi": t_pi})
    shift = max(max(abs(r["rr_interval"][0] - interval0[0]), abs(r["rr_interval"][1] - interval0[1])) for r in per_k)
    # 3. Inset data: the long CM history.
    tr = simulate(rod_mass_scene(INSET["H"], INSET["k"], INSET["omega"], math.pi), t_max=INSET["t"], dt_out=0.05)
    # 4. Data tables.
    rows = []
    for k in KS:
        for p in phi0s:
            rr = bool(ds["reverse_rotation"].sel(k=k, phi0=p))
            tf = float(ds["t_f"].sel(k=k, phi0=p))
            rows.append([k, float(p), tf if math.isfinite(tf) else None, int(rr)])
    write_table(out_dir / "seco1.csv", ["k", "phi0", "t_f", "reverse_rotation"], rows, force=force,
                meta={"H": H, "omega": OMEGA, "rr_interval_frictionless": interval0})
    write_table(out_dir / "seco1_inset.csv", ["t", "x_cm", "y_cm"],
                np.column_stack([tr.t, tr.x_cm, tr.y_cm]).tolist(), force=force, meta=INSET)
    # 5. Figure: t_f vs phi0 (RR points only), the frictionless RR interval shaded; inset CM history.
    fig, ax = plt.subplots(figsize=(6.6, 4.8), constrained_layout=True)
    ax.axvspan(*interval0, color="0.92", zorder=0, label="RR interval (no friction)")
    for k, c, mk in zip(KS, ("tab:blue", "tab:orange", "tab:green"), ("o", "s", "^")):
        rr = ds["reverse_rotation"].sel(k=k).values.astype(bool)
        tf = ds["t_f"].sel(k=k).values
        ax.plot(phi0s[rr], tf[rr], mk + "-", ms=3, lw=0.8, color=c, label=rf"$\mu g/d$ = {k:g} s$^{{-2}}$")
    ax.axvline(math.pi, color="0.5", ls=":", lw=0.8)
    ax.set_xlabel(r"$\phi_0$ (rad)")
    ax.set_ylabel(r"$t_f$ (s)")
    ax.set_xlim(phi0s[0], phi0s[-1])
    ax.set_ylim(bottom=0)
    ax.set_title(r"H = 0.25, $\omega$ = 100 rad/s (RR starts only)")
    ax.legend(loc="upper left", fontsize=8)
    ins = ax.inset_axes((0.745, 0.47, 0.25, 0.4))
    circ = np.linspace(0, 2 * math.pi, 200)
    ins.plot(tr.x_cm, tr.y_cm, color="tab:green", lw=0.3)
    ins.plot(np.cos(circ), np.sin(circ), "k-", lw=0.8)
    ins.set_aspect("equal")
    ins.set_xticks([])
    ins.set_yticks([])
    ins.set_title("inset: CM history, 0 < t < 250 s\n"
                  r"$\mu g/d$ = 0.0015 s$^{-2}$, H = 0.2, $\omega$ = 0.6 rad/s", fontsize=6)
    save_figure(fig, out_dir, "seco1", force=force)
    # 6. Summary for the report.
    write_summary(out_dir, {"H": H, "omega": OMEGA, "rr_interval_frictionless": list(interval0), "per_k": per_k,
                            "max_interval_shift": shift, "edge_tol": EDGE_TOL, "inset": INSET}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "seco1")
