"""The Push-T table study (scenes/pusht_table.py, docs/envs-study.md): its measurement on a few episodes
keeps the invariants the page relies on, and the page's tables are the recorded run's.

A released T cannot move without a table (gym-pusht wipes every velocity each step): its travel after
the agent's last contact is exactly 0. On a table a pushed T slides on. The off-centre push turns the T
as the inertia predicts without a table and, on a table, as the exact push does: at the env's own 10 ms
step with its coupled step, not with the split step.
"""
from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("pymunk")

from rrbody.cli.scenes import scenes_dir  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def scene() -> ModuleType:
    spec = importlib.util.spec_from_file_location("rrbody_scene_pusht_table_test", scenes_dir() / "pusht_table.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_scene_follows_the_convention(scene: ModuleType) -> None:
    """``rrbody scene pusht-table`` runs it: main(out_dir, *, force), a one-line listing under 130 characters."""
    import inspect

    params = inspect.signature(scene.main).parameters
    assert list(params) == ["out_dir", "force"] and params["force"].kind is inspect.Parameter.KEYWORD_ONLY
    first = scene.__doc__.splitlines()[0]
    assert "no paper figure" in first and len(first) < 130


@pytest.mark.parametrize("seed", [6, 7])
def test_after_contact_travel_is_zero_without_a_table_and_not_on_one(scene: ModuleType, seed: int) -> None:
    """The same random walk in every world: coverage in [0, 1]; the T touched in each; without a table
    (and from the nudged start) not a hair of travel or turn after the release; on the mu 0.3 table it
    slides on (walks whose last contact sends the T off, no wall after; walk 0's glancing last contact
    leaves it at rest on the coupled step)."""
    rows, _ = scene.episode("walks", seed)
    by = {r["world"]: r for r in rows}
    assert set(by) == set(scene.WORLDS)
    for r in rows:
        assert 0.0 <= r["coverage"] <= 1.0 and r["contact_steps"] > 0 and r["at_rest"]
    for world in ("no table", "no table, nudged"):
        assert by[world]["travel_after"] == 0.0 and by[world]["turn_after"] == 0.0 and not by[world]["wall_after"]
    assert by["no table"]["apart_from_no_table"] == 0.0
    assert by["mu 0.3"]["travel_after"] > 0.0
    assert scene.check_no_table(rows)["moved"] == 0


def test_a_pinch_squirts_the_t_out_on_a_table(scene: ModuleType) -> None:
    """Walk 8 pinches the T against a wall and squirts it out far faster than the agent, and it slides
    far (walk 1 did so until the table stepped a fast T near a wall in sub-steps: its pinch now plays out
    otherwise)."""
    r = scene.rollout("mu 0.3", 8, scene.walk(8))
    assert r["pinch"] and r["release_speed"] > 5 * r["agent_speed"] and r["travel_after"] > 100.0 and r["at_rest"]


def test_a_fast_hit_on_a_table_slides_about_v2_over_2_mu_g(scene: ModuleType) -> None:
    """A T struck and left alone on a table slides v^2 / (2 mu g) (to within one step's travel, and a
    little turning); without a table it stops at once: the probe's release step and travel."""
    hit = np.array([[256.0, 200.0], [256.0, 470.0]] + [[256.0, 470.0]] * 8)  # up into the stem, then back off
    for world, mu in (("no table", None), ("mu 0.3", 0.3), ("mu 0.6", 0.6)):
        env = scene.make(world, state=[256.0, 430.0, 256.0, 250.0, 0.0])
        probe = scene.Probe(env)
        for a in hit:
            env.step(a)
        pose = np.array(probe.pose)
        k = int(np.flatnonzero(probe.touch)[-1])
        v = float(np.hypot(*(scene.cog(*pose[k + 1, :3]) - scene.cog(*pose[k, :3])))) / env.dt
        travel = math.hypot(*(pose[-1, :2] - pose[k + 1, :2]))
        if mu is None:
            assert travel == 0.0
        else:
            stop = v ** 2 / (2 * mu * 9.81 * 600.0)  # units: g / scale, scale 1/600 m per unit
            assert stop > 5.0 and abs(travel - stop) < 0.02 * stop + v * env.dt, (world, travel, stop)


def test_the_off_centre_push_turns_by_inertia_without_a_table_and_by_friction_on_one(scene: ModuleType) -> None:
    """Push at b = 40 units: without a table dtheta/ds is the impulse's m b / I (the 3-unit chord reads
    3 % low). On the table at 10 units/s, slower than mu g dt (17.7 units/s at mu 0.3): stepped at 0.1 ms
    (the study's dt -> 0 row) it is within 10 % of the quasi-static limit-surface answer, far from the
    inertia's, and within 1 % of the exact push of a disk at constant speed (an ODE, not the plugin); the
    env's coupled step at its own 10 ms gives that within 1 %; the split step there turns it as if there
    were no table (friction stops it within each step, then the contact sets it moving from rest)."""
    pred = scene.predictions([40.0])
    inertia, quasi = pred["m b / I (inertia)"][0], pred["quasi-static (limit surface)"][0]
    assert quasi > 1.5 * inertia
    free = scene.push("no table", 40.0, 50.0)["rate"]
    assert free == pytest.approx(inertia, rel=0.05)
    limit = scene.push("mu 0.3", 40.0, 10.0, dt=1e-4)["rate"]
    assert limit == pytest.approx(quasi, rel=0.1) and limit > 1.4 * free
    assert scene.exact_push(40.0, [10.0], ["mu 0.3"])["mu 0.3"]["10"] == pytest.approx(limit, rel=0.01)
    assert scene.push("mu 0.3", 40.0, 10.0)["rate"] == pytest.approx(limit, rel=0.01)
    split = scene.push("mu 0.3", 40.0, 10.0, scheme="split")["rate"]
    assert split == pytest.approx(free, rel=0.01)


def test_the_split_table_is_the_envs_table_but_its_scheme(scene: ModuleType) -> None:
    """The scene's split step replaces the env's coupled table by the same table (mu, mu_static, g,
    pressure) stepped split, keeps the sub-steps near a wall, and is refused without a table."""
    env, split = scene.make("mu 0.6", seed=3), scene.make("mu 0.6", seed=3, scheme="split")
    assert env.plane.scheme == "coupled" and split.plane.scheme == "split"
    assert split.plane.g == env.plane.g and split.plane.space is split.space
    assert env.table.mu == split.table.mu == 0.6
    assert split._advance is not split.plane.step  # guarded: sub-steps where the T would cross a wall
    with pytest.raises(ValueError, match="table"):
        scene.make("no table", seed=3, scheme="split")
    with pytest.raises(ValueError, match="scheme"):
        scene.make("mu 0.3", seed=3, scheme="fast")


def test_the_page_quotes_the_recorded_run(scene: ModuleType) -> None:
    """docs/envs-study.md holds the tables the scene writes from results/pusht-table/summary.json, as
    they are there (the figures in its prose are checked by hand against the same file)."""
    summary = json.loads((ROOT / "results" / "pusht-table" / "summary.json").read_text())
    table = scene.markdown(summary)
    assert (ROOT / "results" / "pusht-table" / "table.md").read_text() == table
    page = (ROOT / "docs" / "envs-study.md").read_text()
    for block in table.strip().split("\n\n"):
        assert block in page
