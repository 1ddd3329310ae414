"""The definitions figure: O, P, CM, d, l, phi, omega t (and where theta comes from), drawn to scale.

P is driven counter-clockwise on the circle of radius d about O, at angle omega t; the body turns
freely about P; the CM lies at distance l from P, and phi is the angle of the vector CM -> P with
the x axis. Units: m and rad.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["schematic_figure"]


def schematic_figure(*, d: float = 1.0, l: float = 0.5, wt: float = math.radians(40.0),
                     phi: float = math.radians(100.0)) -> Any:
    """A matplotlib Figure defining the geometry (defaults chosen so every label is legible)."""
    from rrbody.model.extras import require

    require("matplotlib", purpose="the schematic figure")
    from matplotlib.figure import Figure
    from matplotlib.patches import FancyArrowPatch

    P = np.array([d * math.cos(wt), d * math.sin(wt)])
    e = np.array([math.cos(phi), math.sin(phi)])
    CM = P - l * e
    fig = Figure(figsize=(6.4, 5.2))
    ax = fig.add_axes((0.02, 0.02, 0.96, 0.9))
    ax.set_aspect("equal")
    ax.axis("off")
    s = np.linspace(0, 2 * math.pi, 361)
    ax.plot(d * np.cos(s), d * np.sin(s), ":", color="k", lw=1.2)
    ax.annotate("", xy=(1.45 * d, 0), xytext=(-1.2 * d, 0), arrowprops={"arrowstyle": "->", "color": "0.55"})
    ax.text(1.46 * d, -0.02, "x", va="top", color="0.4")
    ax.annotate("", xy=(0, 1.3 * d), xytext=(0, -1.15 * d), arrowprops={"arrowstyle": "->", "color": "0.55"})
    ax.text(0.03, 1.3 * d, "y", ha="left", color="0.4")
    # O, the crank O -> P (length d) and its angle omega t
    ax.plot([0, P[0]], [0, P[1]], color="0.45", lw=1.2)
    ax.plot([0], [0], "+", color="k", ms=12, mew=1.6)
    ax.text(-0.05, -0.07, "O", ha="right", va="top", fontsize=14)
    ax.text(0.55 * P[0] - 0.03, 0.55 * P[1] + 0.06, "d", fontsize=14, ha="right", color="0.3")
    a = np.linspace(0, wt, 40)
    ax.plot(0.3 * np.cos(a), 0.3 * np.sin(a), color="0.3", lw=1)
    ax.text(0.36 * math.cos(wt / 2), 0.36 * math.sin(wt / 2), r"$\omega t$", fontsize=12, va="center")
    # the drive's sense (counter-clockwise, rate omega)
    arc = FancyArrowPatch((d * math.cos(1.7), d * math.sin(1.7)), (d * math.cos(2.3), d * math.sin(2.3)),
                          connectionstyle="arc3,rad=0.15", arrowstyle="-|>", mutation_scale=16, color="k", lw=1.4)
    ax.add_patch(arc)
    ax.text(1.08 * d * math.cos(2.0), 1.08 * d * math.sin(2.0), r"$\omega$", fontsize=14, ha="right")
    # the body: CM on a massless rod of length l, turning freely about P
    ax.plot([CM[0], P[0]], [CM[1], P[1]], color="0.15", lw=3, solid_capstyle="round")
    ax.plot([P[0]], [P[1]], "o", color="k", ms=8)
    ax.text(P[0] + 0.06, P[1] + 0.02, "P", fontsize=14)
    ax.plot([CM[0]], [CM[1]], "o", color="#2ca02c", ms=16, mec="k")
    ax.text(CM[0] + 0.06, CM[1] - 0.08, "CM", fontsize=13, ha="left", va="top", color="#1a6e1a")
    mid = 0.5 * (CM + P)
    nrm = np.array([-e[1], e[0]])
    ax.text(*(mid + 0.08 * nrm), "l", fontsize=14, ha="center", va="center", style="italic")
    # phi: angle of CM -> P with the x axis, measured at the CM
    ax.plot([CM[0], CM[0] + 0.42], [CM[1], CM[1]], "--", color="0.5", lw=1)
    b = np.linspace(0.0, phi, 60)
    ax.plot(CM[0] + 0.22 * np.cos(b), CM[1] + 0.22 * np.sin(b), color="#d62728", lw=1.4)
    ax.annotate("", xy=(CM[0] + 0.22 * np.cos(b[-1]), CM[1] + 0.22 * np.sin(b[-1])),
                xytext=(CM[0] + 0.22 * np.cos(b[-4]), CM[1] + 0.22 * np.sin(b[-4])),
                arrowprops={"arrowstyle": "-|>", "color": "#d62728"})
    ax.text(CM[0] + 0.3 * np.cos(b[len(b) // 2]), CM[1] + 0.3 * np.sin(b[len(b) // 2]), r"$\phi$", fontsize=15,
            color="#d62728", ha="center", va="center")
    ax.set_xlim(-1.3 * d, 1.55 * d)
    ax.set_ylim(-1.2 * d, 1.35 * d)
    fig.suptitle(r"P moves on the circle of radius $d$ about O at rate $\omega$; the body turns freely about P;"
                 "\n" r"$l$ = |CM P|; $\phi$ = angle of CM $\to$ P with the x axis; "
                 r"$\theta = \phi - \omega t + \pi$", fontsize=10)
    return fig
