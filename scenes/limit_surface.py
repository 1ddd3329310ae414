"""Limit surfaces: the loads static friction holds under four pressures and four feet (no paper figure; real contacts).

The limit set of a contact is every (force, torque) its friction can give at rest; its boundary is
the kinetic friction of each motion (rrbody.physics.limit). For a disk of radius R = 0.1 m the slice
F_y = 0 is drawn from twists (v_x, 0, omega), which keep F_y = 0 for these symmetric contacts:
force per mu N against torque per mu N R. The axis crossings are exact: a push of mu N, a torque
of mu N times the mean lever (2R/3 uniform, R ring, 3 pi R/16 Hertz). Dots: random loads tested by
the stick rule itself (filled: held), which must fall inside the curves and the open ones outside.
Output: results/limit-surface/.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody import pressure as rp
from rrbody.analysis.report import write_summary
from rrbody.model.bodies import Disk
from rrbody.physics import contact as C
from rrbody.physics.footprint import apply_pressure, body_parts
from rrbody.physics.limit import at_rest
from rrbody.render.figures import save_figure

R = 0.1  # m
PROFILES = {"uniform": rp.uniform(), "ring": rp.ring(R), "annulus R/2..R": rp.annulus(R / 2, R),
            "hertz": rp.hertz(R), "4 feet at 0.07 m": rp.points([(0.05, 0.05, 1), (-0.05, 0.05, 1),
                                                                  (-0.05, -0.05, 1), (0.05, -0.05, 1)])}


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.path import Path as Path2

    fig, axes = plt.subplots(1, len(PROFILES), figsize=(15, 3.4), constrained_layout=True, sharey=True)
    rng = np.random.default_rng(7)
    summary = {}
    for ax, (name, pr) in zip(axes, PROFILES.items()):
        shapes, geo, *_ = apply_pressure(body_parts(Disk(R=R)), pr)
        n = shapes.shape[0]
        th = np.linspace(0.0, 2 * math.pi, 721)  # twist (cos th, 0, sin th / R): the slice's boundary
        edge = np.array([C.footprint_wrench(shapes, geo, 0, n, math.cos(a), 0.0, math.sin(a) / R, 0.0) for a in th])
        ax.plot(-edge[:, 0], -edge[:, 2] / R, "k-", lw=1.5)
        loads = rng.uniform(-1.2, 1.2, size=(300, 2)) * [1.0, max(abs(edge[:, 2])) / R]
        held = np.array([at_rest(shapes, geo, 0, n, fx, 0.0, tq * R, 0.5 * R * R, 1.0, 1.0)[3] for fx, tq in loads])
        ax.plot(*loads[held].T, "o", color="tab:blue", ms=2.5)
        ax.plot(*loads[~held].T, "o", mfc="none", color="tab:red", ms=2.5)
        push, twist = float(-edge[0, 0]), float(-edge[180, 2] / R)
        # the stick rule's answers against the drawn boundary (loads within 1e-3 of it not counted)
        curve = Path2(np.column_stack([-edge[:, 0], -edge[:, 2] / R]))
        inside = curve.contains_points(loads)
        near = ~(curve.contains_points(loads, radius=2e-3) == curve.contains_points(loads, radius=-2e-3))
        summary[name] = {"push_limit": push, "torque_limit_over_R": twist, "held": int(held.sum()), "tested": len(held),
                         "disagree": int(np.sum((held != inside) & ~near))}
        ax.set_title(f"{name}\npush {push:.3f} $\\mu N$, torque {twist:.3f} $\\mu N R$", fontsize=9)
        ax.set_xlabel("force / (mu N)")
        ax.axhline(0, color="0.8", lw=0.5)
        ax.axvline(0, color="0.8", lw=0.5)
    axes[0].set_ylabel("torque / (mu N R)")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    save_figure(fig, out_dir, "limit_surface", force=force)
    write_summary(out_dir, {"R": R, "exact": {"uniform": 2 / 3, "ring": 1.0, "hertz": 3 * math.pi / 16},
                            "profiles": summary}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "limit-surface")
