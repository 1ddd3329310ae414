"""A T pushed in MuJoCo on the split adapter (scenes/mujoco_push.py, docs/mujoco.md "Pushing: friction and
contacts"): the scene's model turns as inertia says without a table, the adapter's dt -> 0 limit lies
between inertia and the limit surface, and at Push-T's 10 ms step the split adapter turns a slowly pushed T
less than no table at all would. Every reference is exact and outside the adapter: m b / I, and
quasi-static pushing from the footprint's limit surface (also computed, independently, by the Push-T study).
"""

from __future__ import annotations

import importlib
import inspect
import json
from pathlib import Path
from types import ModuleType

import pytest

pytest.importorskip("mujoco")

RESULTS = Path(__file__).resolve().parents[1] / "results" / "mujoco-push"


@pytest.fixture(scope="module")
def scene() -> ModuleType:
    return importlib.import_module("scenes.mujoco_push")  # the checkout's scene script (a package: scenes/)


@pytest.fixture(scope="module")
def exact(scene: ModuleType) -> dict[str, float]:
    return scene.predictions()


def test_the_scene_follows_the_convention(scene: ModuleType) -> None:
    """``rrbody scene mujoco-push`` runs it: main(out_dir, *, force), a one-line listing under 130 characters."""
    params = inspect.signature(scene.main).parameters
    assert list(params) == ["out_dir", "force"] and params["force"].kind is inspect.Parameter.KEYWORD_ONLY
    first = scene.__doc__.splitlines()[0]
    assert "no paper figure" in first and len(first) < 130


def test_the_references_are_the_push_t_studys(exact: dict[str, float]) -> None:
    """m b / I with gym-pusht's I, and the limit surface's quasi-static turn, as scenes/pusht_table.py computes
    them through the plugin's footprint (results/pusht-table/summary.json, offset 60): another path to the
    same kernel, so equal to rounding."""
    study = json.loads((RESULTS.parent / "pusht-table" / "summary.json").read_text())["push"]["predictions"]
    for name, value in exact.items():
        assert value == pytest.approx(1e3 * study[name][-1], rel=1e-9)


def test_without_a_table_the_model_turns_as_inertia_says(scene: ModuleType, exact: dict[str, float]) -> None:
    """MuJoCo alone on a frictionless plane, Push-T's 10 ms step: the impulse turns the T by m b / I per unit
    travel. The rate drifts by 1.6 % over 30 units of travel as the contact moves on the bar (measured), so
    by 0.2 % over the first 3: the tolerance 0.5 %. This checks the scene's geometry, inertia and units."""
    rate = scene.push(None, 10.0, 0.01, reads=(3.0,))[3.0]
    assert rate == pytest.approx(exact["m b / I (inertia)"], rel=5e-3)


def test_the_adapters_limit_lies_between_inertia_and_the_limit_surface(scene: ModuleType,
                                                                        exact: dict[str, float]) -> None:
    """At 0.1 ms a push turns the T more than inertia alone (the table resists the far end) and less than
    quasi-static pushing (the T's mass lags the limit surface), for either mu."""
    for mu in (0.3, 0.6):
        rate = scene.push(mu, 10.0, 1e-4, reads=(3.0,))[3.0]
        assert exact["m b / I (inertia)"] < rate < exact["quasi-static (limit surface)"], (mu, rate)


def test_at_push_ts_step_the_split_adapter_turns_a_slow_push_less_than_no_table(scene: ModuleType,
                                                                                 exact: dict[str, float]) -> None:
    """The documented limit: at 10 ms, mu 0.6 and 10 units/s, friction applied before MuJoCo's contact solve
    (xfrc_applied, held fixed in it) and the pusher's soft contact set the T rattling, and it turns less
    per unit travel than with no table at all (measured 14.4 against m b / I = 20), where any table's dt -> 0
    limit turns it more (the test above). A coupled adapter would fail this test: then docs/mujoco.md's
    section changes with it."""
    rate = scene.push(0.6, 10.0, 0.01, reads=(3.0,))[3.0]
    assert rate < exact["m b / I (inertia)"]


def test_the_page_shows_the_recorded_run(scene: ModuleType) -> None:
    """results/mujoco-push/table.md is the scene's table of its summary.json, and docs/mujoco.md holds it."""
    summary = json.loads((RESULTS / "summary.json").read_text())
    table = scene.markdown(summary)
    assert (RESULTS / "table.md").read_text() == table
    assert table in (RESULTS.parents[1] / "docs" / "mujoco.md").read_text()
