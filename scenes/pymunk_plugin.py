"""pymunk plugin: three driven dry-friction bodies and a moving ball in one ordinary pymunk Space (no paper figure).

Shows rrbody's scenes in a user's own top-down ``pymunk.Space``: ``rrbody.engine.attach`` adds a
kinematic driver on the circle, a PivotJoint and the body's area friction (the space's
``PlaneFriction``); the user's loop calls ``plane.step(dt)`` in place of ``space.step(dt)``. The
ball is the user's own body and keeps its own motion. Outputs: phi(t) of each body (CSV), a figure (PNG/SVG) of phi(t)
from the engine beside the ODE path, the CM paths on their drive circles (d = 1, 2, 3 m), the
engine-minus-ODE difference of phi, and the ball's coasting against its exact straight line; and summary.json with
each body's flip time next to the ODE path's (both with the exact area integral: the difference is the engine's dt
error; the ODE with 256 sampled elements is listed too, for the sampling error an element-based engine would add).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pymunk

from rrbody.analysis.flip import flip_time
from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.simulate import simulate
from rrbody.engine import EngineSettings, attach
from rrbody.integrate.events import E_TMIN, STOP_T_END, new_event_state, on_step
from rrbody.model.bodies import Disk, Ellipse
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene, rod_mass_scene
from rrbody.render.figures import save_figure

DT = 2e-3  # s: engine step (second order: t_f good to ~1e-5 relative here, docs/engine.md)
T_MAX = 30.0  # s: past every body's flip


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. Three scenes on concentric drive circles (d = 1, 2, 3 m), k = mu g / d = 0.05 s^-2, omega = 0.6 rad/s.
    scenes = {
        "rod-mass": rod_mass_scene(0.2, 0.05, 0.6, math.pi),
        "disk": Scene(body=Disk(R=0.2, l=0.4), drive=CircularDrive(0.6, d=2.0),
                      friction=Friction.from_k("dry", 0.05, 2.0), samples=256),
        "ellipse": Scene(body=Ellipse(R0=0.3, delta=0.5, l=0.6), drive=CircularDrive(0.6, d=3.0),
                         friction=Friction.from_k("dry", 0.05, 3.0), samples=256),
    }
    # 2. An ordinary top-down pymunk program: a space (no gravity: the plane is horizontal) and a ball ...
    space = pymunk.Space()
    ball = pymunk.Body(1.0, pymunk.moment_for_circle(1.0, 0.0, 0.1))
    ball.position = (0.0, -5.0)
    ball.velocity = (0.0, -0.1)
    space.add(ball, pymunk.Circle(ball, 0.1))
    # 3. ... to which the plugin attaches the driven bodies (validated settings, one handle each).
    settings = EngineSettings(dt=DT)
    handles = {name: attach(space, sc, settings=settings) for name, sc in scenes.items()}
    # 4. The user's loop: step (friction, then space.step), read phi and the CM from the handles.
    plane = handles["rod-mass"].plane  # one PlaneFriction per space, shared by every attach
    n = round(T_MAX / DT)
    t = DT * np.arange(n + 1)
    phi = {k: np.empty(n + 1) for k in handles}
    phid = {k: np.empty(n + 1) for k in handles}
    cm = {k: np.empty((n + 1, 2)) for k in handles}
    ball_y = np.empty(n + 1)
    for i in range(n + 1):
        if i:
            plane.step(DT)
        for k, h in handles.items():
            phi[k][i] = h.phi
            phid[k][i] = h.phi_dot  # second order: the mean of the two half-step spins
            cm[k][i] = tuple(h.body.position)
        ball_y[i] = ball.position.y
    # 5. Flip times: the lowest minimum of phi, found by rrbody's one event detector (fed each step's
    #    two ends; minima located on the cubic Hermite interpolant of (phi, phi')), against the ODE path.
    summary = {"dt": DT, "t_max": T_MAX, "ball_y_after_t_max_m": ball.position.y, "bodies": {}}
    for k, sc in scenes.items():
        ev = new_event_state(sc.phi0, sc.initial_phi_dot)
        minima = np.empty((256, 2))
        for i in range(n):
            on_step(ev, minima, t[i], phi[k][i], phid[k][i], t[i + 1], phi[k][i + 1], phid[k][i + 1], sc.omega,
                    STOP_T_END, 2.0, 3.0)
        t_f = float(ev[E_TMIN])
        ode = flip_time(sc)  # ODE path, exact area integral (instantaneous-centre quadrature)
        same = flip_time(sc.with_(friction_method="sampled")) if not sc.body.is_point else ode  # same elements
        summary["bodies"][k] = {"H": sc.H, "t_f_engine": t_f, "t_f_ode": ode.t_f, "t_f_ode_same_elements": same.t_f,
                                "rel_diff_vs_ode": (t_f - ode.t_f) / ode.t_f,
                                "rel_diff_vs_ode_same_elements": (t_f - same.t_f) / same.t_f,
                                "pivot_error_at_t_max_m": handles[k].pivot_error()}
    every = 25  # CSV and comparison: every 25th step (0.05 s)
    write_table(out_dir / "phi.csv", ["t", *[f"phi_{k}" for k in scenes]],
                [[float(t[i]), *[float(phi[k][i]) for k in scenes]] for i in range(0, n + 1, every)], force=force,
                meta={"dt": DT, "scenes": {k: sc.describe() for k, sc in scenes.items()}})
    # 6. The ODE path with the same (exact) area integral, sampled every 25th engine step, for the comparison.
    every_t = t[::every]
    ode_phi = {k: simulate(sc, t_max=T_MAX, dt_out=every * DT).phi[: len(every_t)] for k, sc in scenes.items()}
    # 7. Figure: (a) phi(t), engine vs ODE; (b) CM paths on the drive circles; (c) their difference;
    #    (d) the user's own ball, coasting on the frictionless top-down space, against its exact line.
    fig, axs = plt.subplots(2, 2, figsize=(11, 8.4), constrained_layout=True)
    a, b, c, e = axs.ravel()
    circle = np.linspace(0.0, 2.0 * math.pi, 361)
    for k, sc in scenes.items():
        line, = a.plot(t, phi[k], lw=1.2, label=f"{k} (d = {sc.d:g} m), engine")
        col = line.get_color()
        a.plot(every_t, ode_phi[k], "--", color="k", lw=0.7)
        a.axvline(summary["bodies"][k]["t_f_ode"], ls=":", lw=0.8, color=col)
        b.plot(sc.d * np.cos(circle), sc.d * np.sin(circle), ":", color=col, lw=0.9)
        b.plot(cm[k][:, 0], cm[k][:, 1], lw=0.7, color=col, label=f"{k}: CM path, drive circle d = {sc.d:g} m")
        rel = summary["bodies"][k]["rel_diff_vs_ode"]
        c.semilogy(every_t, np.abs(phi[k][::every] - ode_phi[k]) + 1e-16, lw=0.9, color=col,
                   label=f"{k}: t$_f$ engine vs ODE {rel:+.1e} (relative)")
    a.plot([], [], "--", color="k", lw=0.7, label="ODE path (same exact area integral)")
    a.set(xlabel="t (s)", ylabel=r"$\phi$ (rad)",
          title=r"$\phi(t)$: engine (solid) and ODE (dashed); dotted: ODE $t_f$")
    a.legend(fontsize=8)
    b.plot([0], [0], "k+", ms=8)
    b.set(xlabel="x (m)", ylabel="y (m)", title="CM paths around their drive circles (dotted)", aspect="equal")
    b.legend(fontsize=7, loc="upper right")
    c.set_ylim(bottom=1e-9)
    c.set(xlabel="t (s)", ylabel=r"|$\phi_{engine} - \phi_{ODE}$| (rad)",
          title=f"engine (dt = {DT:g} s) minus ODE, same area integral")
    c.legend(fontsize=7)
    e.plot(t, ball_y, lw=1.2, label="pymunk ball (same space, not added to the plugin)")
    e.plot(t, -5.0 - 0.1 * t, "k--", lw=0.8, label=r"exact straight line $y_0 + v_y t$")
    e.set(xlabel="t (s)", ylabel="ball y (m)", title="the user's own ball: unaffected by the plugin")
    e.legend(fontsize=8)
    summary["ball_y_exact_m"] = -5.0 - 0.1 * T_MAX
    save_figure(fig, out_dir, "pymunk_plugin", force=force)
    write_summary(out_dir, summary, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "pymunk-plugin")
