"""Chaos on a tilted plane: a chaotic and a regular orbit of the circularly forced double pendulum (the first outlook).

The rod-mass body on a plane tilted by 0.5 rad (downhill along +x), without friction: a pendulum
hanging downhill from P while P is driven round its circle, the paper's "circularly forced double
pendulum". Two drives: omega = 2 rad/s with H = 0.5 (chaotic: the tangent method's maximal
Lyapunov exponent converges to a positive value) and omega = 0.6 rad/s with H = 0.3 (regular: it
falls towards 0 like log(t)/t). Per orbit: phi' against theta = phi - omega t + pi over the first
T_ORBIT s, the stroboscopic Poincare section (N_SECTION periods), and the running Lyapunov estimates
by both methods (tangent over T_LYAP s, two trajectories over T_TWO s). Output: results/chaos/
(summary.json, chaos.png/.svg).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

TILT = 0.5  # rad
ORBITS = {"chaotic": {"H": 0.5, "omega": 2.0}, "regular": {"H": 0.3, "omega": 0.6}}
T_ORBIT, N_SECTION, T_LYAP, T_TWO = 200.0, 3000, 20000.0, 5000.0  # s, periods, s, s


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.analysis.chaos import lyapunov, poincare
    from rrbody.analysis.report import write_summary
    from rrbody.analysis.simulate import simulate
    from rrbody.model.scene import scene_from_params
    from rrbody.render.figures import save_figure

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    summary: dict = {"tilt_rad": TILT, "friction": "none", "orbits": {}}
    fig, axes = plt.subplots(3, 2, figsize=(11, 11), constrained_layout=True)
    for col, (name, par) in enumerate(ORBITS.items()):
        sc = scene_from_params(H=par["H"], k=None, omega=par["omega"], friction="none", tilt=TILT)
        traj = simulate(sc, t_max=T_ORBIT, dt_out=0.01)
        sec = poincare(sc, points=N_SECTION, kind="strobe", rtol=1e-12)
        tan = lyapunov(sc, t_max=T_LYAP)
        two = lyapunov(sc, t_max=T_TWO, method="two", d0=1e-7)
        half = tan.running[len(tan.times) // 2:, 0]
        spread = float((half.max() - half.min()) / abs(tan.exponents[0]))
        summary["orbits"][name] = {
            "H": sc.H, "omega": sc.omega, "lambda_tangent": [float(x) for x in tan.exponents],
            "lambda_two": float(two.exponents[0]), "t_tangent": T_LYAP, "t_two": T_TWO,
            "spread_last_half": spread, "log_t_over_t": math.log(T_LYAP) / T_LYAP,
            "sum_tangent": float(tan.exponents.sum()), "section_points": int(len(sec.t))}
        theta = np.mod(np.asarray(traj.theta), 2 * math.pi)
        a = axes[0, col]
        a.plot(theta, traj.phi_dot, ",", color="0.2")
        a.set(xlabel="theta = phi - omega t + pi (rad, mod 2 pi)", ylabel="phi' (rad/s)", xlim=(0, 2 * math.pi),
              title=f"{name}: H = {sc.H:g}, omega = {sc.omega:g} rad/s, tilt {TILT:g} rad; first {T_ORBIT:g} s")
        b = axes[1, col]
        b.plot(sec.theta, sec.phi_dot, ".", ms=1.5, color="k")
        b.set(xlabel="theta (rad, mod 2 pi)", ylabel="phi' (rad/s)", xlim=(0, 2 * math.pi),
              title=f"stroboscopic Poincare section, {len(sec.t)} periods")
        c = axes[2, col]
        c.plot(tan.times, tan.running[:, 0], lw=1.2, label=f"tangent: lambda_1 = {tan.exponents[0]:.4g} 1/s")
        c.plot(two.times, two.running[:, 0], lw=1.0, ls="--", label=f"two trajectories: {two.exponents[0]:.4g} 1/s")
        c.plot(tan.times, np.log(tan.times) / tan.times, color="0.5", ls=":", lw=1, label="log(t)/t")
        c.set(xscale="log", yscale="symlog" if name == "regular" else "linear", xlabel="t (s)",
              ylabel="running estimate of lambda_1 (1/s)",
              title=(f"maximal Lyapunov exponent (last half of the run within {100 * spread:.2g} %)"
                     if name == "chaotic" else "maximal Lyapunov exponent: falling towards 0 (dotted: log(t)/t)"))
        if name == "regular":
            c.set_yscale("symlog", linthresh=1e-5)
        c.legend(fontsize=8)
        for ax in (a, b, c):
            ax.title.set_fontsize(9)
    write_summary(out_dir, summary, force=force)
    save_figure(fig, out_dir, "chaos", force=force)
    plt.close(fig)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "chaos")
