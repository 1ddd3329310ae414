"""Which flip a picture shows: Trajectory.settled_flip (the run's own samples) and flip_mark (the whole run)."""

from __future__ import annotations

import math

import pytest

from rrbody.analysis.flip import flip_time
from rrbody.analysis.simulate import simulate
from rrbody.model.scene import rod_mass_scene
from rrbody.render.flip import FlipMark, flip_mark

SCENE = rod_mass_scene(0.2, 0.033, 0.6)  # t_f = 23.40 s; settled once phi rose 4 pi and 3 periods (31.4 s) passed


@pytest.mark.parametrize("t_max,settled", [(20.0, False), (30.0, False), (60.0, True)])
def test_settled_flip_follows_the_stopping_rule(t_max: float, settled: bool) -> None:
    traj = simulate(SCENE, t_max=t_max)
    t_f, ok = traj.settled_flip()
    assert ok is settled
    if settled:
        # same integrator, same rtol, same located minimum as flip_time (the run only adds output points)
        assert t_f == pytest.approx(flip_time(SCENE).t_f, abs=1e-9)
    else:
        assert t_f is None


def test_settled_flip_without_reverse_rotation_and_without_friction() -> None:
    normal = simulate(rod_mass_scene(0.6, 0.003, 0.6, math.pi / 2), t_max=80.0)  # Movie S2: phi never below phi0
    assert normal.settled_flip() == (None, True)
    frictionless = simulate(rod_mass_scene(0.2, 0.0, 0.6, friction="none"), t_max=30.0)
    assert frictionless.settled_flip() == (None, False)
    assert flip_mark(frictionless) == FlipMark("none", reason="no friction")


def test_flip_mark_captions_and_colours() -> None:
    m = FlipMark("flip", 23.4024)
    assert m.caption(0.0, 20.0) == "no flip within this span: t_f = 23.40 s comes later"
    assert m.caption(0.0, 60.0) == "flip at t_f = 23.40 s"
    assert m.caption(30.0, 60.0) == "after the flip (t_f = 23.40 s)"
    assert m.in_span(0.0, 60.0) and not m.in_span(0.0, 20.0)
    assert m.colour(10.0) == "#d62728" and m.colour(30.0) == "#1f77b4"
    assert FlipMark("unknown", reason="flip not settled").colour(1.0) == "#7f7f7f"
    with pytest.raises(ValueError, match="flip"):
        flip_mark(simulate(SCENE, t_max=1.0), math.nan)


def test_flip_mark_computes_beyond_the_scenes_horizon() -> None:
    """A scene built with t_max = 20 (as the CLI's --t-max does) must not cap the flip search."""
    traj = simulate(SCENE.with_(t_max=20.0), t_max=20.0)
    mark = flip_mark(traj)
    assert mark.status == "flip" and mark.t_f == pytest.approx(flip_time(SCENE).t_f, abs=1e-9)
