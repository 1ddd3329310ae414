"""The figure of a ``chaos`` sweep over two parameters: the maximal Lyapunov exponent and the fraction
of time in reverse rotation as two colour maps (pcolormesh) over the grid.

Input: the sweep's table (a ``.nc`` or ``.csv`` written by :func:`rrbody.analysis.sweep.run_sweep`
with ``quantity="chaos"`` on a 2-D grid). Left: lambda_max (1/s), with the points whose estimate
is below its floor log(T)/T (not told apart from 0, :mod:`rrbody.analysis.chaos_map`) drawn at the
bottom of the scale; right: rr_fraction (0..1). Cells whose point failed (an ``error`` row) are
left blank. Output: PNG or SVG, written atomically and byte-reproducibly.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["chaos_map_arrays", "plot_chaos_map"]

#: axis labels with units for the usual axes (others: the parameter's name)
_LABELS = {"tilt": "tilt (rad)", "omega": "omega (rad/s)", "H": "H", "k": "k = mu g / d (1/s^2)", "d": "d (m)",
           "phi0": "phi0 (rad)", "mu": "mu", "l": "l (m)"}


def chaos_map_arrays(table: str | os.PathLike[str]) -> dict[str, Any]:
    """The grid of a 2-D ``chaos`` sweep: ``x``, ``y`` (the first and second axis values),
    ``names`` (the two axis names), ``spec`` and 2-D arrays ``lambda_max``, ``lambda_floor``,
    ``rr_fraction``, ``lambda_spread`` indexed [first axis, second axis] (NaN where a point failed)."""
    from rrbody.analysis.sweep_store import load_sweep, read_meta

    meta = read_meta(table)
    spec = meta["spec"]
    if spec.get("quantity") != "chaos" or spec.get("mode") != "grid" or len(spec["axes"]) != 2:
        raise ValueError(f"table must be a chaos sweep over a 2-D grid, got quantity {spec.get('quantity')!r}, mode "
                         f"{spec.get('mode')!r}, {len(spec['axes'])} axes ({str(table)!r})")
    names = list(spec["axes"])
    x, y = (np.asarray(spec["axes"][n], dtype=float) for n in names)
    data = load_sweep(table)
    out: dict[str, Any] = {"x": x, "y": y, "names": names, "spec": spec}
    cols = ("lambda_max", "lambda_floor", "rr_fraction", "lambda_spread")
    if Path(table).suffix == ".nc":
        for c in cols:
            out[c] = np.asarray(data[c].values, dtype=float)
    else:
        for c in cols:
            out[c] = np.array([float(r[c]) if r[c] not in ("", None) else math.nan for r in data]).reshape(len(x),
                                                                                                          len(y))
    return out


def _edges(v: np.ndarray) -> np.ndarray:
    """Cell edges around the grid values (midpoints; the end cells as wide as their neighbours)."""
    if len(v) == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def plot_chaos_map(table: str | os.PathLike[str], path: str | os.PathLike[str], *, force: bool = False,
                   title: str | None = None) -> Path:
    """Draw the two maps of the 2-D ``chaos`` sweep ``table`` to ``path`` (.png at 150 dpi, or .svg)."""
    from rrbody.model.extras import require

    require("matplotlib", purpose="a figure")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.model.io import atomic_path
    from rrbody.render.figures import savefig_reproducible

    fmt = Path(path).suffix.lower().lstrip(".")
    if fmt not in ("png", "svg"):
        raise ValueError(f"path must end in .png or .svg, got {str(path)!r}")
    a = chaos_map_arrays(table)
    xe, ye = _edges(a["x"]), _edges(a["y"])
    # the exponent where it is above its floor; below it the estimate is not told apart from 0
    lam = np.where(a["lambda_max"] > a["lambda_floor"], a["lambda_max"], 0.0)
    lam[~np.isfinite(a["lambda_max"])] = math.nan
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
    spec = a["spec"]
    opts = spec.get("options", {})
    base = ", ".join(f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}" for k, v in spec["base"].items()
                     if v is not None and k != "scene")
    for ax, z, lab, cmap, lim in ((axes[0], lam, "maximal Lyapunov exponent lambda_max (1/s)", "magma",
                                   (0.0, max(float(np.nanmax(lam)) if np.isfinite(lam).any() else 1.0, 1e-12))),
                                  (axes[1], a["rr_fraction"], "fraction of time in reverse rotation (phi' omega < 0)",
                                   "coolwarm", (0.0, 1.0))):
        # rows of z follow the first axis: draw it on the vertical axis, the second along x
        m = ax.pcolormesh(ye, xe, np.ma.masked_invalid(z), cmap=cmap, vmin=lim[0], vmax=lim[1], shading="flat",
                          rasterized=True)
        fig.colorbar(m, ax=ax, label=lab)
        ax.set(xlabel=_LABELS.get(a["names"][1], a["names"][1]), ylabel=_LABELS.get(a["names"][0], a["names"][0]))
    from rrbody.analysis.chaos_map import CHAOS_DEFAULTS

    span = (f"{opts['t_max']:g} s" if opts.get("t_max") is not None else
            f"{opts.get('periods', CHAOS_DEFAULTS['periods'])} driving periods")
    axes[0].set_title(f"lambda_max over {span} (0 where below log(T)/T)", fontsize=9)
    axes[1].set_title(f"reverse rotation: share of the same {span}", fontsize=9)
    fig.suptitle(title if title is not None else f"Chaos map: {base}; {len(a['x'])} x {len(a['y'])} points",
                 fontsize=10)
    with atomic_path(path, force=force, name="plot") as tmp:
        savefig_reproducible(fig, tmp, fmt=fmt, **({"dpi": 150} if fmt == "png" else {}))
    plt.close(fig)
    return Path(path)

