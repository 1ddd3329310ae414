"""Pushing gym-pusht's T on a table: turn per unit push against speed, coupled and split steps (no paper figure).

The coupled step and the split step are set against the limits.

The question: does the T turn, per unit of push, as the exact motion says at gym-pusht's own 0.01 s step?
A kinematic disk of radius 15 units starts 0.5 units below the T's top bar at x = 60 (the bar's end) and
moves along +y at constant speed; the T (gym-pusht's: mass 1, moment 3000 units^2) rests on a table of mu
0.3 or 0.6 (g = 5886 units/s^2: 9.81 m/s^2 at 600 units per metre). Its rotation per unit travel of its
centre of gravity, dtheta/ds, read when that travel first reaches 3 and 30 units, from the plugin stepped
at 0.01 s with its coupled step (the default) and with the split step (friction before pymunk's contact
solve), beside the exact push (the dt -> 0 limit: rrbody.analysis.pushing.push_limit), the quasi-static
push (the limit surface: rrbody.analysis.pushing.quasi_static_push) and inertia alone (m b / I, the turn
of a push on no table). Outputs: results/coupled-push/ (pushes.csv, summary.json, coupled_push.png and
.svg: dtheta/ds against the push speed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

MUS = (0.3, 0.6)
SPEEDS = (1.0, 3.0, 10.0, 30.0, 100.0, 300.0)  # units/s
TRAVELS = (3.0, 30.0)  # units of the centre of gravity's travel at which dtheta/ds is read
G, DT, OFFSET, RADIUS, GAP = 5886.0, 0.01, 60.0, 15.0, 0.5  # units/s^2, s, units, units, units


def push(mu: float, speed: float, scheme: str, *, dt: float = DT, offset: float = OFFSET,
         travels: tuple[float, ...] = TRAVELS) -> tuple[dict[float, float], object]:
    """The push on the plugin at ``dt`` (s) with ``scheme``, the disk ``offset`` units from the T's axis:
    dtheta/ds (rad/unit) when the centre of gravity first travels each of ``travels`` (units), and the
    push's geometry (for the exact references)."""
    import pymunk

    from rrbody.analysis.pushing import PushGeometry
    from rrbody.envs.pusht import tee_body
    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    body, _ = tee_body(space)
    agent = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    agent.position = (256.0 + offset, 300.0 - RADIUS - GAP)  # the bar's face is the T's origin line, y = 300
    space.add(agent, pymunk.Circle(agent, RADIUS))
    agent.velocity = (0.0, speed)
    geometry = PushGeometry(body, RADIUS, tuple(agent.position), (0.0, speed))
    pf = PlaneFriction(space, g=G, scheme=scheme)
    pf.add(body, mu=mu)
    cg0 = np.array(body.local_to_world(body.center_of_gravity))
    out, todo = {}, list(travels)
    while todo:
        pf.step(dt)
        s = float(np.hypot(*(np.array(body.local_to_world(body.center_of_gravity)) - cg0)))
        if s >= todo[0]:
            out[todo.pop(0)] = body.angle / s
    return out, geometry


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib.pyplot as plt

    from rrbody.analysis.pushing import push_limit, quasi_static_push
    from rrbody.analysis.report import write_summary, write_table
    from rrbody.render.figures import save_figure

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    quasi = None
    for mu in MUS:
        for v in SPEEDS:
            coupled, geometry = push(mu, v, "coupled")
            split, _ = push(mu, v, "split")
            exact = push_limit(geometry, mu * G, TRAVELS)
            if quasi is None:
                quasi = quasi_static_push(geometry, TRAVELS)
            for s in TRAVELS:
                rows.append({"mu": mu, "speed": v, "travel": s, "coupled": coupled[s], "split": split[s],
                             "exact": exact[s], "quasi_static": quasi[s], "inertia": OFFSET * 1.0 / 3000.0})
    names = tuple(rows[0])
    write_table(out_dir / "pushes.csv", names, [[r[c] for c in names] for r in rows], force=force,
                meta={"units": "speed units/s, travel units, dtheta/ds rad per unit"})
    worst = {f"{s:g}": max(abs(r["coupled"] / r["exact"] - 1.0) for r in rows if r["travel"] == s
                           and (s == 30.0 or r["speed"] <= 30.0)) for s in TRAVELS}
    write_summary(out_dir, {"dt_s": DT, "g": G, "offset": OFFSET, "speeds": list(SPEEDS), "mus": list(MUS),
                            "rows": rows, "coupled_worst_relative_error": worst}, force=force)
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.0), sharey=True)
    for ax, s in zip(axes, TRAVELS):
        for mu, color in zip(MUS, ("tab:blue", "tab:red")):
            sel = [r for r in rows if r["mu"] == mu and r["travel"] == s]
            v = [r["speed"] for r in sel]
            ax.plot(v, [1e3 * r["exact"] for r in sel], "-", color=color, label=f"exact push, mu {mu:g}")
            ax.plot(v, [1e3 * r["coupled"] for r in sel], "o", color=color, label=f"coupled step, mu {mu:g}")
            ax.plot(v, [1e3 * r["split"] for r in sel], "x", color=color, ms=8, label=f"split step, mu {mu:g}")
        ax.axhline(1e3 * quasi[s], color="0.3", ls="--", label="quasi-static push (limit surface)")
        ax.axhline(1e3 * OFFSET / 3000.0, color="0.6", ls=":", label="inertia alone (m b / I)")
        ax.set(xscale="log", xlabel="push speed (units/s; x 1/600 for m/s)",
               title=f"read at {s:g} units of travel, dt {DT:g} s")
    axes[0].set_ylabel("dtheta/ds (mrad per unit of travel)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle("gym-pusht's T pushed at its bar's end: its turn per unit push at gym-pusht's step")
    fig.subplots_adjust(bottom=0.25, top=0.86, wspace=0.08)
    save_figure(fig, out_dir, "coupled_push", force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "coupled-push")
