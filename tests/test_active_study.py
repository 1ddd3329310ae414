"""The active-bodies study's pieces: episode detection (exact on constructed signals), the run's
parameters, an ensemble that does not depend on the number of workers, marks in the Recorder, and the
docs page's example (docs/active.md) run as a reader copies it."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest

from rrbody.analysis.active_study import Box, ensemble
from rrbody.analysis.episodes import episode_marks, reverse_episodes

ROOT = Path(__file__).resolve().parents[1]


def _signal(sense: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Spin +2 rad/s (with the orbit) except -3 rad/s on [2, 4) s (1 turn back minus a little) and -1
    rad/s on [6, 7) s (1 rad back: no episode); sampled every 10 ms; the angle integrated exactly."""
    t = np.arange(0, 1001) * 0.01
    rate = np.where((t >= 2) & (t < 4), -3.0, np.where((t >= 6) & (t < 7), -1.0, 2.0))
    angle = np.concatenate([[0.0], np.cumsum(rate[:-1] * 0.01)])  # exact for a piecewise-constant spin
    return t, sense * angle, sense * rate


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_episodes_found_exactly(sense: float) -> None:
    t, a, w = _signal(sense)
    eps = reverse_episodes(t, a, w, sense=sense, hits=[1.7, 6.9], window=0.5)
    assert len(eps) == 1  # the second reversal turns back 1 rad < pi: not an episode
    e = eps[0]
    assert (e["t_start"], e["t_end"]) == (t[200], t[399])
    assert e["duration"] == t[399] - t[200]
    assert e["turns_back"] == pytest.approx(3.0 * (t[399] - t[200]) / (2 * math.pi), rel=1e-12)
    assert e["starts_at_collision"]  # a contact 0.3 s before its first sample
    assert not reverse_episodes(t, a, w, sense=sense, hits=[1.4], window=0.5)[0]["starts_at_collision"]
    assert len(reverse_episodes(t, a, w, sense=sense, min_turn=0.9)) == 2  # a lower threshold counts both
    # against the other orbit the stretches with spin +2 rad/s (4, 4 and 6 rad) are the episodes
    other = reverse_episodes(t, a, w, sense=-sense)
    assert [(e["t_start"], e["t_end"]) for e in other] == [(t[0], t[199]), (t[400], t[599]), (t[700], t[1000])]
    m = episode_marks(t, w, eps, sense=sense)
    assert set(np.unique(m[200:400])) == {-1.0} and m[100] == 1.0 and m[650] == 0.0


def test_bad_sense_and_box_parameters_name_themselves() -> None:
    t, a, w = _signal(1.0)
    with pytest.raises(ValueError, match="sense must be"):
        reverse_episodes(t, a, w, sense=0.5)
    for kw, name in (({"n": 1}, "n"), ({"packing": 0.9}, "packing"), ({"activity": 0.0}, "activity"),
                     ({"mix": 1.5}, "mix"), ({"seed": -1}, "seed"), ({"t_end": -1.0}, "t_end"), ({"every": 0},
                                                                                                 "every")):
        with pytest.raises(ValueError, match=f"^{name} must be"):
            Box(**kw)


def test_the_ensemble_does_not_depend_on_the_number_of_workers() -> None:
    points = [Box(n=24, packing=0.3, activity=3.0, seed=s, t_end=3.0) for s in (0, 1)]
    here = ensemble(points, workers=0)
    pooled = ensemble(points, workers=2)
    assert here == pooled  # every number equal: each point is deterministic from its seed
    assert [r["seed"] for r in here] == [0, 1] and here[0] != here[1]
    assert here[0]["packing"] == asdict(points[0])["packing"]


def test_the_ensemble_on_dask_gives_the_same_rows() -> None:
    from distributed import Client, LocalCluster

    points = [Box(n=12, packing=0.3, activity=3.0, seed=s, t_end=1.0) for s in (0, 1)]
    with LocalCluster(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        assert ensemble(points, scheduler=client) == ensemble(points, workers=0)


def test_an_interrupted_ensemble_resumes_from_its_checkpoint(tmp_path: Path) -> None:
    points = [Box(n=12, packing=0.3, activity=3.0, seed=s, t_end=1.0) for s in (0, 1, 2)]
    ck = tmp_path / "ens.jsonl"
    full = ensemble(points, workers=0, checkpoint=ck)
    lines = ck.read_text().splitlines()
    assert len(lines) == 4  # the header and one line per point
    ck.write_text("\n".join(lines[:2]) + "\n" + lines[2][:20])  # killed while writing the second point
    assert ensemble(points, workers=0, checkpoint=ck) == full  # the missing points recomputed, the same rows
    with pytest.raises(ValueError, match="written for a different sweep"):
        ensemble(points[:2], workers=0, checkpoint=ck)


def test_recorder_colours_by_marks_and_checks_them() -> None:
    import pymunk

    from rrbody.plugin import Active, PlaneFriction, Recorder

    space = pymunk.Space()
    pf = PlaneFriction(space)
    for k in range(2):
        b = pymunk.Body()
        s = pymunk.Circle(b, 0.05)
        s.density = 100.0
        b.position = (0.3 * k, 0.0)
        space.add(b, s)
        pf.add(b, mu=0.1)
        pf.activate(b, Active(force=1.0, point=(0.02, 0.0), drag=1.0, rot_drag=1.0))
    rec = Recorder(space, pf, motion=False)
    for _ in range(5):
        pf.step(0.01)
        rec.capture()
    marks = np.zeros((5, 2))
    marks[2:, 0] = -1.0
    assert rec.marks(marks) is marks and rec.colours(marks) is None
    img = rec.image(color=marks, size=(64, 64))
    assert img.shape[:2] == (64, 64)
    with pytest.raises(ValueError, match=r"color as marks must be an array \(frames, bodies\) = \(5, 2\)"):
        rec.image(color=np.zeros((4, 2)), size=(64, 64))
    with pytest.raises(ValueError, match="of -1, 0 and \\+1"):
        rec.image(color=np.full((5, 2), 0.5), size=(64, 64))


def test_the_docs_example_runs(tmp_path: Path) -> None:
    """docs/active.md's first program, as a reader copies it, in an empty folder."""
    text = (ROOT / "docs" / "active.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    assert re.match(r"after 10\.0 s: at \(-?\d+\.\d\d, -?\d+\.\d\d\) m, spin -?\d+\.\d\d rad/s", p.stdout), p.stdout
    assert list(tmp_path.iterdir()) == []  # it writes nothing
