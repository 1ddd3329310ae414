"""A tilted plane and static friction: mu = tan(alpha) invariant, stick, break-away (no paper figure; real contacts).

Plane tilted at alpha = atan(0.4), downhill along +x (plane coordinates, m). (a) A point mass
(ODE path) launched at 1 m/s at theta0 from downhill with mu = tan(alpha): exact, v (1 + cos theta)
stays v0 (1 + cos theta0) and v tends to v0 (1 + cos theta0)/2. (b) The plugin with static
friction: a 0.2 m box (density 2 kg/m^2, mu = 0.3, mu_s = 0.5) on a level plane pushed at its
centre of gravity by a force growing 1e-3 mu_s m g per step (dt = 1e-3 s) must not move until the
push reaches mu_s m g; the same box on the slope (mu < tan(alpha) < mu_s) released at rest must
stay bit for bit where it is; slid downhill with mu = 0.3 it accelerates at g (sin alpha - mu cos
alpha) on both paths. Output: results/incline/.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pymunk

from rrbody.analysis.report import write_summary
from rrbody.analysis.simulate import simulate
from rrbody.engine import PlaneFriction
from rrbody.model.scene import scene_from_params
from rrbody.render.figures import save_figure

G, ALPHA, DT = 9.81, math.atan(0.4), 1e-3  # m/s^2, rad, s
THETA0 = (60, 90, 120, 150)  # deg from downhill
MU, MU_S, STEP, HELD = 0.3, 0.5, 1e-3, 100_000  # kinetic, static, push step / limit, steps held


def _box(tilt: float, v: tuple[float, float] = (0.0, 0.0)) -> tuple[PlaneFriction, pymunk.Body]:
    """A 0.2 m x 0.2 m pymunk box (density 2 kg/m^2) in a PlaneFriction tilted at ``tilt`` (rad)."""
    space, body = pymunk.Space(), pymunk.Body()
    shape = pymunk.Poly.create_box(body, (0.2, 0.2))
    shape.density = 2.0
    space.add(body, shape)
    body.velocity = v
    pf = PlaneFriction(space, g=G, tilt=tilt, downhill=0.0)
    pf.add(body, mu=MU, mu_static=MU_S)
    return pf, body


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig, ((ax, av), (bx, bv)) = plt.subplots(2, 2, figsize=(11, 7.5), constrained_layout=True)
    inv = {"theta0_deg": list(THETA0), "max_drift": [], "v_final_over_v0": [], "v_limit_over_v0": [], "t_max": 3.0}
    for th in THETA0:  # (a) the invariant on the ODE path
        c = math.cos(math.radians(th))
        tr = simulate(scene_from_params(body="rod", H=0.2, no_drive=True, v0=(c, math.sin(math.radians(th))),
                                        mu=math.tan(ALPHA), g=G, tilt=ALPHA, downhill=0.0, t_max=inv["t_max"]),
                      dt_out=0.005)
        v = np.hypot(tr.vx_cm, tr.vy_cm)
        drift = float(np.max(np.abs((v + tr.vx_cm) / (1 + c) - 1)))  # v (1 + cos theta), relative
        inv["max_drift"].append(drift)
        inv["v_final_over_v0"].append(float(v[-1]))
        inv["v_limit_over_v0"].append((1 + c) / 2)
        line, = ax.plot(tr.x_cm, tr.y_cm, label=f"$\\theta_0$ = {th}°")
        av.plot(tr.t, v, color=line.get_color(), label=f"$\\theta_0$ = {th}°: drift {drift:.0e}")
        av.axhline((1 + c) / 2, color=line.get_color(), ls="--", lw=0.8)
    ax.set(xlabel="x, downhill (m)", ylabel="y, across the slope (m)",
           title="(a) point mass on the slope, $\\mu = \\tan\\alpha$ = 0.4 (ODE path),\n$v_0$ = 1 m/s at $\\theta_0$ "
                 f"from downhill, {inv['t_max']:g} s")
    ax.legend(fontsize=8)
    av.set(xlabel="t (s)", ylabel="v / v$_0$",
           title="speed; dashed: the limit (1 + cos $\\theta_0$)/2;\nlegend: max relative drift of v (1 + cos "
                 "$\\theta$)")
    av.legend(fontsize=8)
    pf, b = _box(0.0)  # (b) a growing push on a level plane
    limit, k, push, x, vx = MU_S * b.mass * G, 0, [], [], []
    while k * STEP < 1.2:
        k += 1
        b.force = (k * STEP * limit, 0.0)  # pymunk clears forces after each step: set it every step
        pf.step(DT)
        push.append(k * STEP)
        x.append(b.position.x)
        vx.append(b.velocity.x)
    x = np.array(x)
    # the break-away step: the first with a velocity (pymunk moves positions before it updates velocities,
    # so x follows one step later)
    moved = int(np.flatnonzero(np.array(vx) != 0.0)[0])
    still = bool(np.all(x[:moved + 1] == 0.0))  # not a nanometre of creep before the break
    bx.plot(push, 1e3 * x, "k-")
    bx.axvline(1.0, color="tab:red", ls=":", lw=0.8)
    bx.set(xlabel="push / ($\\mu_s m g$)", ylabel="displacement (mm)",
           title=f"(b) box on a level plane (plugin), push + {STEP:g} $\\mu_s m g$ per step:\n"
                 f"x {'= 0 exactly' if still else 'CREPT'} until it breaks away at push = {push[moved]:.3f}")
    pf, b = _box(ALPHA)  # held on the slope: tan(alpha) = 0.4 between mu and mu_s
    for _ in range(HELD):
        pf.step(DT)
    held = b.position == (0.0, 0.0) and b.angle == 0.0 and b.velocity == (0.0, 0.0)
    a_exact = G * (math.sin(ALPHA) - MU * math.cos(ALPHA))
    pf, b = _box(ALPHA, (1.0, 0.0))  # slid downhill from 1 m/s, both paths
    t, vp = [], []
    for _ in range(2000):
        pf.step(DT)
        t.append(pf.t)
        vp.append(pf.velocity(b)[0])
    tr = simulate(scene_from_params(body="box", R0=0.1, no_drive=True, v0=(1.0, 0.0), mu=MU, g=G, tilt=ALPHA,
                                    t_max=2.0), dt_out=0.01)
    a_plugin, a_ode = np.polyfit(t, vp, 1)[0], np.polyfit(tr.t, tr.vx_cm, 1)[0]
    bv.plot(t, vp, lw=3, alpha=0.5, label=f"plugin: a = {a_plugin:.12g} ({a_plugin / a_exact - 1:+.0e})")
    bv.plot(tr.t, tr.vx_cm, "k-", lw=1, label=f"ODE path: a = {a_ode:.12g} ({a_ode / a_exact - 1:+.0e})")
    bv.plot(tr.t, 1 + a_exact * tr.t, "r--", lw=1,
            label=f"exact g(sin$\\alpha$ - $\\mu$ cos$\\alpha$) = {a_exact:.12g}")
    bv.set(xlabel="t (s)", ylabel="downhill speed (m/s)",
           title=f"box slid downhill, $\\mu$ = {MU}; released at rest on the\n"
           f"slope ($\\mu_s$ = {MU_S}, plugin): {'bit-identical' if held else 'MOVED'} after {HELD:,} steps")
    bv.legend(fontsize=8)
    save_figure(fig, out_dir, "incline", force=force)
    write_summary(out_dir, {"alpha": ALPHA, "g": G, "invariant": inv,
                            "breakaway": {"push_at_break_over_limit": push[moved], "step_over_limit": STEP,
                                          "still_before": still,
                                          "mu": MU, "mu_static": MU_S},
                            "held": {"steps": HELD, "bit_identical": held},
                            "downhill_accel": {"exact": a_exact, "plugin": a_plugin, "ode": a_ode, "mu": MU}},
                  force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "incline")
