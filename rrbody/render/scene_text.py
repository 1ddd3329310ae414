"""The scene as the pictures label it: body and drive geometry from a trajectory's metadata, the
friction parameter as the paper writes it (mu g/d), and a one-line title (matplotlib mathtext).
Shared by the movie (:mod:`rrbody.render.movie_figure`) and the rerun recording
(:mod:`rrbody.render.rerun`). Lengths in m, omega in rad/s, mu g/d in s^-2, gamma in s^-1.
"""

from __future__ import annotations

import math
from typing import Any

from rrbody.model.trajectory import Trajectory

__all__ = ["scene_info", "friction_text", "title_text"]


def scene_info(traj: Trajectory) -> dict[str, Any]:
    """Body and drive geometry from ``traj.meta['scene']``; without it, a point mass on a rod."""
    sc = dict(traj.meta.get("scene") or {})
    if "body" not in sc:
        sc["body"] = "rod"
        sc["l"] = float(math.hypot(traj.x_p[0] - traj.x_cm[0], traj.y_p[0] - traj.y_cm[0]))
        sc["R_A"] = sc["R_B"] = 0.0
    return sc


def friction_text(sc: dict[str, Any]) -> str:
    """The friction parameter as the paper writes it: mu g/d = ... s^-2 (dry), gamma = ... s^-1 (viscous)."""
    law = (sc.get("friction") or {}).get("law", "dry")
    if law == "none" or sc.get("k") is None:
        return "no friction"
    if law == "viscous":
        return rf"viscous $\gamma$ = {sc['k']:.4g} s$^{{-1}}$"
    return rf"$\mu g/d$ = {sc['k']:.4g} s$^{{-2}}$"


def title_text(sc: dict[str, Any]) -> str:
    """Body, H, friction, omega and phi0 in one line (mathtext)."""
    kind = sc.get("body", "rod")
    parts = [f"H = {sc['H']:.4g}"] if sc.get("H") is not None else []
    if sc.get("drive"):
        parts.append(friction_text(sc))
        parts.append(rf"$\omega$ = {sc['drive']['omega']:.4g} rad/s")
    else:
        law = (sc.get("friction") or {}).get("law", "dry")
        parts.append(f"free body, {law} friction")
    if sc.get("phi0") is not None:
        frac = float(sc["phi0"]) / math.pi
        txt = (r"$\pi$" if abs(frac - 1) < 1e-12 else r"$\pi/2$" if abs(frac - 0.5) < 1e-12 else f"{sc['phi0']:.4g}")
        parts.append(rf"$\phi_0$ = {txt}")
    name = {"rod": "rod-mass body", "disk": "disk", "ellipse": "ellipse"}.get(kind, kind)
    if kind != "rod" and sc.get("R_A"):
        name += f" (R$_A$ = {sc['R_A']:.3g} m, R$_B$ = {sc['R_B']:.3g} m, l = {sc.get('l', 0):.3g} m)"
    return name + ": " + ", ".join(parts)
