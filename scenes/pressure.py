"""Pressure distributions: spin-down per profile and the stop ratio of washers (no paper figure; real contacts).

(a) A disk (pymunk Circle, R = 0.1 m, density 2 kg/m^2, I/m = R^2/2) spins in place at 20 rad/s in
the plugin (mu = 0.3, dt = 1e-3 s) under uniform, ring(R), annulus(R/2, R) and hertz(R) pressure;
exact: omega = w0 - alpha t, alpha = mu g lever / (I/m), the lever the profile's mean distance from
the centre. (b) Washers of inner radius f R (uniform pressure on their area, I/m = (f^2 R^2 + R^2)/2)
slide and spin; exact: the ratio eps* = v/(R Omega) at which both stop together, the root of
F(eps) = eps T(eps)/kappa from the footprint kernel (f = 1: the hoop on its rim, eps* = 1). Markers:
the plugin's ratio just before the stop, launched at eps0 = 0.4 and 2.0. Output: results/pressure/.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pymunk
from scipy.optimize import brentq

from rrbody import pressure as rp
from rrbody.analysis.report import write_summary
from rrbody.engine import PlaneFriction
from rrbody.physics import contact as C
from rrbody.physics.footprint import apply_pressure, ellipse_part
from rrbody.render.figures import save_figure

G, R, MU, W0 = 9.81, 0.1, 0.3, 20.0  # m/s^2, m, -, rad/s
LEVERS = {"uniform": (rp.uniform(), 2 * R / 3), "ring": (rp.ring(R), R),  # profile: mean lever arm (m)
          "annulus": (rp.annulus(R / 2, R), (2 / 3) * (R ** 3 - (R / 2) ** 3) / (R ** 2 - (R / 2) ** 2)),
          "hertz": (rp.hertz(R), 3 * math.pi * R / 16)}
F_GRID = [i / 40 for i in range(41)]  # inner radius / R (i/40: exact decimals for the markers' lookup)
F_SIM, EPS0 = (0.0, 0.5, 0.75, 1.0), (0.4, 2.0)


def _washer(f: float) -> tuple[rp.Pressure, float]:
    """Pressure and kappa = I/(m R^2) of a washer of inner radius f R (f = 1: a hoop on its rim)."""
    return (rp.ring(R), 1.0) if f == 1.0 else (rp.annulus(f * R, R), 0.5 * (1 + f * f))


def _eps_star(f: float) -> float:
    """Root of |F(eps)| = eps |T(eps)| / (R kappa) (per unit load and mu g), as tests/test_contacts.py."""
    pr, kappa = _washer(f)
    shapes, geo, *_ = apply_pressure([ellipse_part(0.0, 0.0, R, R)], pr)

    def gap(eps: float) -> float:
        fx, fy, tq = C.footprint_wrench(shapes, geo, 0, shapes.shape[0], eps * R, 0.0, 1.0, 0.0)
        return math.hypot(fx, fy) - eps * abs(tq) / R / kappa

    return brentq(gap, 0.05, 5.0, xtol=1e-14)


def _run(pr: rp.Pressure, kappa: float, v: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Plugin run of a disk body (moment kappa m R^2) until it rests: times (s) and (vx, vy, spin) at them."""
    space, body = pymunk.Space(), pymunk.Body()
    shape = pymunk.Circle(body, R)
    shape.density = 2.0
    space.add(body, shape)
    body.moment = kappa * R * R * body.mass
    body.velocity, body.angular_velocity = (v, 0.0), W0
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=MU, pressure=pr)
    t, s = [0.0], [(v, 0.0, W0)]
    while not (body.angular_velocity == 0.0 and body.velocity == (0.0, 0.0)):
        pf.step(dt)
        t.append(pf.t)
        s.append(pf.velocity(body))
    return np.array(t), np.array(s)


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.3), constrained_layout=True)
    spin = {}
    for name, (pr, lever) in LEVERS.items():
        alpha = MU * G * lever / (R * R / 2)
        t, s = _run(pr, 0.5, 0.0, 1e-3)
        keep = t < W0 / alpha - 2e-3  # before the stop step (the limiter and the rest rule act there)
        fit = -np.polyfit(t[keep], s[keep, 2], 1)[0]
        spin[name] = {"alpha_exact": alpha, "alpha_measured": fit, "rel_err": fit / alpha - 1}
        ax.plot(t, s[:, 2], lw=2.5, alpha=0.7,
                label=f"{name}: $\\alpha$ = {alpha:.2f} rad/s$^2$, fit {fit / alpha - 1:+.0e}")
        ax.plot(t, np.maximum(W0 - alpha * t, 0.0), "k--", lw=0.8)
    ax.set(xlabel="t (s)", ylabel=r"$\omega$ (rad/s)",
           title="(a) disk spinning in place (plugin); dashed: exact $\\omega_0 - \\alpha t$")
    ax.legend(fontsize=8)
    eps = [_eps_star(f) for f in F_GRID]
    bx.plot(F_GRID, eps, "k-", label=r"exact $\varepsilon^*(f)$ (kernel fixed point)")
    sim = []
    for f in F_SIM:
        pr, kappa = _washer(f)
        for e0, mk in zip(EPS0, ("^", "v")):
            t, s = _run(pr, kappa, e0 * R * W0, 2.5e-4)
            ok = (s[:, 2] > 0) & (np.hypot(s[:, 0], s[:, 1]) > 0)
            last = float((np.hypot(s[ok, 0], s[ok, 1]) / (R * s[ok, 2]))[-4])  # the last 3: limiter and rest rule
            sim.append({"f": f, "eps0": e0, "eps_last": last})
            bx.plot([f, f], [e0, last], color="0.75", lw=0.8)
            bx.plot(f, last, mk, color="tab:red", ms=6,
                    label=f"plugin, from $\\varepsilon_0$ = {e0:g}" if f == 0 else None)
    bx.set(xlabel=r"$f = R_i/R$", ylabel=r"$\varepsilon = v/(R\Omega)$", ylim=(0.6, 1.06),
           title="(b) washers: the ratio where slide and spin stop together")
    bx.text(0.98, 0.03, "grey: from the launch ratio (0.4 or 2, off scale) to the plugin's ratio just before\n"
            "the stop; the approach is slow, so markers sit between $\\varepsilon_0$ and $\\varepsilon^*$ (inset: the "
            "gap)",
            transform=bx.transAxes, ha="right", va="bottom", fontsize=7)
    bx.legend(fontsize=8, loc="upper left")
    ins = bx.inset_axes((0.14, 0.45, 0.4, 0.3))
    ins.axhline(0.0, color="k", lw=0.6)
    for e0, mk in zip(EPS0, ("^", "v")):
        pts = [(r["f"], r["eps_last"] - eps[F_GRID.index(r["f"])]) for r in sim if r["eps0"] == e0]
        ins.plot(*zip(*pts), mk, color="tab:red", ms=4)
    ins.set_ylabel(r"$\varepsilon_{last} - \varepsilon^*$", fontsize=7)
    ins.set_yscale("symlog", linthresh=1e-5)
    ins.tick_params(labelsize=6)
    save_figure(fig, out_dir, "pressure", force=force)
    write_summary(out_dir, {"R": R, "mu": MU, "g": G, "w0": W0, "spin_down": spin,
                            "stop_ratio": {"f": F_GRID, "eps_exact": eps, "sim": sim},
                            "disk_ratio": eps[0], "hoop_ratio": eps[-1]}, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "pressure")
