"""Top-down pymunk example: a puck and a box slide and spin to rest on a rough table (no paper figure).

Copy this into your own program: an ordinary pymunk space without gravity (we look down on the
table), your own bodies and shapes, and rrbody's PlaneFriction in place of hand-tuned damping or
pymunk's tank-example joints. Each body gets Coulomb friction integrated over the area of its own
shapes; ``pf.step(dt)`` replaces ``space.step(dt)``; a Recorder films them. Output:
results/topdown/summary.json (where and when each body stopped) and topdown.png (a poster of four
instants with their velocities and friction forces, and their trails; the README's picture).
"""

from __future__ import annotations

from pathlib import Path

import pymunk

from rrbody.plugin import PlaneFriction
from rrbody.render.recorder import Recorder  # rrbody.plugin.Recorder: its pictures need the movie extra

#: the poster's instants (s)
POSTER_TIMES = (0.0, 0.2, 0.5, 1.0)


def main(out_dir: Path, *, force: bool = True) -> None:
    space = pymunk.Space()  # top-down: no gravity in the plane
    pf = PlaneFriction(space, g=9.81)  # the table presses with g; mu per body below

    puck = pymunk.Body()
    puck_shape = pymunk.Circle(puck, 0.05)
    box = pymunk.Body()
    box_shape = pymunk.Poly.create_box(box, (0.2, 0.1))
    for shape in (puck_shape, box_shape):
        shape.density = 800.0  # kg/m^2: pymunk computes mass and moment
        shape.elasticity = 0.9
    box.position = (0.0, 0.3)
    space.add(puck, puck_shape, box, box_shape)

    puck.velocity, puck.angular_velocity = (2.0, 0.5), 30.0  # launched sliding and spinning
    box.velocity, box.angular_velocity = (1.5, -0.4), -12.0
    pf.add(puck, mu=0.3)
    pf.add(box, mu=0.5)

    rec = Recorder(space, pf)  # films them: poses, velocities and the friction applied, per step
    dt = 1.0 / 240.0
    while pf.t < 5.0:
        pf.step(dt)  # friction for every body of the plugin, then space.step(dt)
        rec.capture()

    from rrbody.analysis.report import write_summary

    Path(out_dir).mkdir(parents=True, exist_ok=True)
    write_summary(Path(out_dir), {name: {"stopped_at_s": pf.stop_time(b), "position_m": list(b.position),
                                         "angle_rad": b.angle}
                                  for name, b in (("puck", puck), ("box", box))}, force=force)
    # the poster: launch, while both slide, the box at rest, both at rest (the stops: summary.json)
    rec.poster(Path(out_dir) / "topdown.png", times=POSTER_TIMES, arrows=("velocity", "friction"), trails=True,
               force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "topdown")
