"""``rrbody lyapunov``: the command line gives the Python API's exponents, writes the running
estimates as CSV and a figure, and refuses bad input in one line (exit 2, nothing written). In-process
(:func:`tests.clirun.run_here`), the first bad input also through the real command, which must answer the same."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from rrbody.analysis.chaos import lyapunov
from rrbody.model.scene import scene_from_params
from tests.clirun import assert_bad_input, run_here

SCENE = ["--H", "0.2", "--k", "0.05", "--omega", "0.6"]


def test_lyapunov_command_gives_the_apis_exponents_and_writes_its_outputs(tmp_path: Path) -> None:
    viscous, dry = run_here([["lyapunov", *SCENE, "--friction", "viscous", "--t-max", "300", "--json",
                              "--out", "r.csv", "--plot", "r.png"],
                             ["lyapunov", *SCENE, "--t-max", "200", "--json"]], cwd=tmp_path, real=0)
    assert viscous.code == 0, viscous.err
    d = json.loads(viscous.out)
    api = lyapunov(scene_from_params(H=0.2, k=0.05, omega=0.6, friction="viscous"), t_max=300.0)
    assert d["exponents"] == [float(x) for x in api.exponents] and d["method"] == "tangent"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.png"]
    rows = list(csv.reader(line for line in (tmp_path / "r.csv").read_text().splitlines() if not line.startswith("#")))
    assert rows[0] == ["t_s", "lambda_1_per_s", "lambda_2_per_s"] and len(rows) - 1 == d["n_renorm"]
    assert [float(x) for x in rows[-1][1:]] == d["exponents"]
    assert dry.code == 0, dry.err
    assert json.loads(dry.out)["method"] == "two"  # auto: dry friction has a kink, so two trajectories


def test_lyapunov_refuses_bad_input_in_one_line(tmp_path: Path) -> None:
    cases = [(["--t-max", "100", "--renorm", "-1"], "--renorm"), (["--t-max", "100", "--no-drive"], "--no-drive"),
             (["--t-max", "100", "--out", "x.txt"], "--out"), (["--t-max", "100", "--estimate", "tangent"],
                                                               "--estimate"),
             (["--t-max", "100", "--d0", "1"], "--d0"), ([], "--t-max")]
    runs = run_here([["lyapunov", *SCENE, *extra, "--out", "o.csv"] if "--out" not in extra else
                     ["lyapunov", *SCENE, *extra] for extra, _ in cases], cwd=tmp_path)
    for r, (_, option) in zip(runs, cases):
        assert_bad_input(r, option, tmp_path)


def test_poincare_command_writes_the_apis_points(tmp_path: Path) -> None:
    from rrbody.analysis.chaos import poincare

    ok, bad_points, bad_dir, free = run_here(
        [["poincare", "--H", "0.2", "--omega", "0.6", "--friction", "none", "--points", "40", "--direction", "down",
          "--out", "s.csv", "--plot", "s.png", "--json"],
         ["poincare", "--H", "0.2", "--omega", "0.6", "--friction", "none", "--points", "0", "--out", "x.csv"],
         ["poincare", "--H", "0.2", "--omega", "0.6", "--friction", "none", "--direction", "left", "--out", "x.csv"],
         ["poincare", "--R0", "0.2", "--body", "disk", "--no-drive", "--v0", "1,0", "--k", "1", "--out", "x.csv"]],
        cwd=tmp_path, real=0)  # the first writes; the bad inputs of the test above run the real command
    assert ok.code == 0, ok.err
    assert json.loads(ok.out)["n"] == 40
    api = poincare(scene_from_params(H=0.2, k=None, omega=0.6, friction="none"), points=40, direction=-1)
    rows = [line.split(",") for line in (tmp_path / "s.csv").read_text().splitlines()[2:]]
    assert [float(r[0]) for r in rows] == list(api.t) and [float(r[2]) for r in rows] == list(api.phi_dot)
    before = {"s.csv", "s.png"}
    for r, option in ((bad_points, "--points"), (bad_dir, "--direction"), (free, "--no-drive")):
        assert_bad_input(r, option, tmp_path, before)
