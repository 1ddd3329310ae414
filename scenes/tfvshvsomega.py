"""tfvsHvsomega: contour of the flip time over (omega, H) at k = 1.5 s^-2, phi0 = pi (paper Fig. tfvsHvsomega).

(a) low omega: t_f grows with H (omega t_f -> C(H), increasing; paper Eq. SmallOmegaFlipTime);
(b) a wider omega range: at high omega the trend in H reverses. Blank cells: no flip (phi never
falls below phi0). Each cell is one run (no interpolation across jumps). The grids are 2-D sweeps (rrbody.sweep) saved
as NetCDF.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.sweep import run_fresh_or_resume
from rrbody.analysis.sweep_spec import Sweep
from rrbody.render.figures import save_figure

K = 1.5  # s^-2, paper caption
H_GRID = np.linspace(0.05, 0.75, 29)
W_LOW = np.linspace(0.05, 1.0, 39)  # rad/s, panel (a)
W_WIDE = np.geomspace(0.05, 30.0, 47)  # rad/s, panel (b)


def trend(ts: np.ndarray) -> str:
    """'increases' / 'decreases' / 'is not monotonic' for t_f along H (finite values only)."""
    t = ts[np.isfinite(ts)]
    dt = np.diff(t)
    if len(t) < 2:
        return "undefined"
    if np.all(dt > 0):
        return "increases"
    if np.all(dt < 0):
        return "decreases"
    return "increases overall" if t[-1] > t[0] else "decreases overall"


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. The two 2-D sweeps (omega x H); NetCDF with grid metadata is the data output.
    ds_a = run_fresh_or_resume(Sweep(base={"k": K}, axes={"omega": W_LOW, "H": H_GRID}), out_dir / "tf_low_omega.nc")
    ds_b = run_fresh_or_resume(Sweep(base={"k": K}, axes={"omega": W_WIDE, "H": H_GRID}), out_dir / "tf_wide_omega.nc")
    # 2. CSV copies of the grids (long format) for readers without NetCDF tools.
    for ds, name in ((ds_a, "tf_low_omega"), (ds_b, "tf_wide_omega")):
        df = ds[["t_f", "reverse_rotation"]].to_dataframe().reset_index()
        write_table(out_dir / f"{name}.csv", ["omega", "H", "t_f", "reverse_rotation"],
                    [[float(r.omega), float(r.H), None if not np.isfinite(r.t_f) else float(r.t_f),
                      int(r.reverse_rotation)] for r in df.itertuples()], force=force,
                    meta={"k": K, "phi0": "pi", "grid": "omega x H, row-major (omega slowest)"})
    # 3. Figure: one cell per grid point (log colour scale). Filled contours would interpolate across the
    #    jumps of t_f between neighbouring cells (up to 5x, where the flip moves to another minimum of phi),
    #    inventing values that no run produced; cells show exactly what each run gave.
    from matplotlib.patches import Patch

    fig, (a, b) = plt.subplots(1, 2, figsize=(11.5, 4.6), constrained_layout=True)
    for ax, ds, title in ((a, ds_a, r"(a) low $\omega$"), (b, ds_b, r"(b) wider $\omega$ range")):
        tf = np.asarray(ds["t_f"].values, float).T  # rows: H, columns: omega
        lo, hi = np.nanmin(tf), np.nanmax(tf)
        ax.set_facecolor("0.85")  # cells without a flip (masked) show the background
        pm = ax.pcolormesh(ds["omega"].values, ds["H"].values, np.ma.masked_invalid(tf), shading="nearest",
                           norm=LogNorm(lo, hi), cmap="viridis")
        ticks = [v for v in (0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100) if lo <= v <= hi]
        cb = fig.colorbar(pm, ax=ax, ticks=ticks, format="%g")
        cb.set_label(r"$t_f$ (s)")
        ax.set_xlabel(r"$\omega$ (rad/s)")
        ax.set_ylabel(r"H = (I$_{cm}$ + m l$^2$)/(m d l)")
        ax.set_title(title + r", $\mu g/d$ = 1.5 s$^{-2}$")
        if np.isnan(tf).any():
            ax.legend(handles=[Patch(color="0.85", label="no flip")], loc="upper right", fontsize=8)
    b.set_xscale("log")
    save_figure(fig, out_dir, "tfvshvsomega", force=force)
    # 4. Summary: the trend of t_f with H at the lowest and highest omega.
    low = np.asarray(ds_b["t_f"].values[0], float)
    high = np.asarray(ds_b["t_f"].values[-1], float)
    write_summary(out_dir, {"k": K, "low_omega": float(W_WIDE[0]), "high_omega": float(W_WIDE[-1]),
                            "low_trend": trend(low), "high_trend": trend(high),
                            "H_range": [float(H_GRID[0]), float(H_GRID[-1])],
                            "grids": f"(a) {len(W_LOW)} omega in [{W_LOW[0]:g}, {W_LOW[-1]:g}] x {len(H_GRID)} H; "
                                     f"(b) {len(W_WIDE)} log-spaced omega in [{W_WIDE[0]:g}, {W_WIDE[-1]:g}] x "
                                     f"{len(H_GRID)} H"}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "tfvshvsomega")
