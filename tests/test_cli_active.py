"""The active-matter features on the command line: ``simulate``'s active options give the Python
API's run (ODE and engine paths); ``rrbody active`` and ``rrbody active-ensemble`` give the box study's
numbers bit for bit, write their files (summary, movie, recording, table, figure), resume from a checkpoint,
and refuse every bad value of every new option in one line (exit 2, nothing written). In-process
(:func:`tests.clirun.run_here`); the first case of each bad-input list also through the real command."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from rrbody.analysis.active_study import Box, ensemble, run_box, seed_table, summary
from rrbody.analysis.simulate import simulate
from rrbody.model.active import Active
from rrbody.model.scene import scene_from_params
from rrbody.model.trajectory import jsonable
from tests.clirun import assert_bad_input, run_here

FREE = ["simulate", "--body", "disk", "--R0", "0.05", "--no-drive", "--friction", "viscous", "--k", "2",
        "--v0", "0.1,0", "--spin0", "1", "--t-max", "1", "--dt-out", "0.25"]
ACTIVE = ["--active-force", "0.2", "--active-angle", "pi/2", "--active-point", "0.02,0", "--drag", "0.5",
          "--rot-drag", "0.5"]
ACT = Active(force=0.2, angle=math.pi / 2, point=(0.02, 0.0), drag=0.5, rot_drag=0.5)
BOX = ["--n", "6", "--t-end", "1", "--packing", "0.3"]


def _api_scene() -> object:
    sc = scene_from_params(body="disk", R0=0.05, no_drive=True, friction="viscous", k=2.0, v0=(0.1, 0.0), spin0=1.0,
                           t_max=1.0)
    return dataclasses.replace(sc, active=ACT)


def _rows(path: Path) -> np.ndarray:
    """A trajectory CSV's numbers (its first line is JSON metadata, its second the column names)."""
    return np.loadtxt(path, delimiter=",", skiprows=2)


def test_simulate_runs_the_apis_active_body_on_both_paths(tmp_path: Path) -> None:
    ode, eng, passive = run_here([[*FREE, *ACTIVE, "--out", "ode.csv", "--json"],
                                  [*FREE, *ACTIVE, "--method", "engine", "--dt", "0.01", "--out", "eng.csv", "--json"],
                                  [*FREE, "--out", "passive.csv"]], cwd=tmp_path, real=0)
    for r in (ode, eng, passive):
        assert r.code == 0, r.err
    d = json.loads(ode.out)
    assert d["scene"]["active"] == {"force": 0.2, "angle": math.pi / 2, "point": [0.02, 0.0], "drag": 0.5,
                                    "rot_drag": 0.5, "diffusion": 0.0, "rot_diffusion": 0.0}
    sc = _api_scene()
    for name, kw in (("ode", {}), ("eng", {"method": "engine", "dt": 0.01})):
        api = simulate(sc, dt_out=0.25, **kw)
        api.save(tmp_path / f"api-{name}.csv")
        # the same scene and options: the same numbers, bit for bit (the CSV holds them as %.17g)
        assert np.array_equal(_rows(tmp_path / f"{name}.csv"), _rows(tmp_path / f"api-{name}.csv")), name
    assert not np.array_equal(_rows(tmp_path / "ode.csv"), _rows(tmp_path / "passive.csv"))  # the options act


def test_simulate_seeds_the_noise_on_both_paths(tmp_path: Path) -> None:
    """``--seed`` with noise: the API's run with ``Scene.seed`` bit for bit on the ODE and engine paths;
    another seed, another run."""
    noise = ["--rot-diffusion", "0.3", "--diffusion", "1e-3"]
    args = [[*FREE, *ACTIVE, *noise, "--seed", "3", *m, "--out", f"{n}.csv"]
            for n, m in (("ode", []), ("eng", ["--method", "engine", "--dt", "0.01"]))]
    args.append([*FREE, *ACTIVE, *noise, "--seed", "4", "--out", "ode4.csv"])
    for r in run_here(args, cwd=tmp_path, real=0):
        assert r.code == 0, r.err
    sc = dataclasses.replace(_api_scene(), active=dataclasses.replace(ACT, rot_diffusion=0.3, diffusion=1e-3), seed=3)
    for name, kw in (("ode", {}), ("eng", {"method": "engine", "dt": 0.01})):
        simulate(sc, dt_out=0.25, **kw).save(tmp_path / f"api-{name}.csv")
        assert np.array_equal(_rows(tmp_path / f"{name}.csv"), _rows(tmp_path / f"api-{name}.csv")), name
    assert not np.array_equal(_rows(tmp_path / "ode.csv"), _rows(tmp_path / "ode4.csv"))


def test_simulate_refuses_bad_active_options_in_one_line(tmp_path: Path) -> None:
    out = ["--out", "o.csv"]
    cases = [(["--active-force", "-1"], "--active-force"), (["--active-force", "nan"], "--active-force"),
             (["--active-force", "1", "--active-angle", "1e400"], "--active-angle"),
             (["--active-force", "1", "--active-point", "1"], "--active-point"),
             (["--active-force", "1", "--active-point", "1e7,0"], "--active-point"),
             (["--drag", "-1"], "--drag"), (["--rot-drag", "1e10"], "--rot-drag"),
             (["--diffusion", "0.1"], "--diffusion"), (["--rot-diffusion", "-1", "--rot-drag", "1"], "--rot-diffusion"),
             (["--rot-diffusion", "0.1", "--rot-drag", "1", "--seed", "-1"], "--seed"),
             (["--rot-diffusion", "0.1", "--rot-drag", "1", "--seed", "1.5"], "--seed"),
             (["--drag", "1", "--seed", "3"], "--seed"), (["--seed", "3"], "--seed"),
             (["--active-angle", "1"], "--active-angle"), (["--active-point", "0,1"], "--active-point")]
    runs = run_here([[*FREE, *extra, *out] for extra, _ in cases], cwd=tmp_path)
    for r, (_, option) in zip(runs, cases):
        assert_bad_input(r, option, tmp_path)
    driven, stoppable = run_here([["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1",
                                   "--drag", "1", *out],
                                  ["simulate", "--body", "disk", "--R0", "0.05", "--no-drive", "--k", "0.5",
                                   "--t-max", "1", "--active-force", "1e-4", *out]], cwd=tmp_path, real=0)
    assert_bad_input(driven, "--drag", tmp_path)  # a driven body's pivot holds it: named, not ignored
    # dry friction can stop this body (F <= mu m g) and the ODE path has no rest rule for it: refused, pointed
    # at the engine in the command line's words
    assert_bad_input(stoppable, "--method engine", tmp_path)


def _api_run(**kw: object) -> dict:
    return json.loads(json.dumps(jsonable(summary(run_box(Box(**kw))))))


def test_active_run_gives_the_apis_summary_and_writes_its_files(tmp_path: Path) -> None:
    full, again, other = run_here([["active", *BOX, "--seed", "3", "--out", "r.json", "--movie", "r.mp4",
                                    "--fps", "10", "--rerun", "r.rrd", "--rerun-every", "3", "--json"],
                                   ["active", *BOX, "--seed", "3", "--json"],
                                   ["active", *BOX, "--seed", "4", "--json"]],
                                  cwd=tmp_path, real=0)
    for r in (full, again, other):
        assert r.code == 0, r.err
    d = json.loads(full.out)
    assert d.pop("written") == {"out": "r.json", "movie": "r.mp4", "rerun": "r.rrd"}
    api = _api_run(n=6, t_end=1.0, packing=0.3, seed=3)
    assert d == api  # bit for bit: JSON floats round-trip exactly
    saved = json.loads((tmp_path / "r.json").read_text())
    assert saved.pop("rrbody_version") and saved == api
    assert {k: v for k, v in json.loads(again.out).items() if k != "written"} == api  # deterministic from its seed
    assert json.loads(other.out)["bodies"] != api["bodies"]  # and another seed is another run
    assert (tmp_path / "r.mp4").read_bytes()[4:8] == b"ftyp" and (tmp_path / "r.rrd").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json", "r.mp4", "r.rrd"]


def test_the_films_colour_only_established_episodes() -> None:
    from rrbody.render.active_film import episode_colours

    t = np.arange(6) * 0.1
    res = {"t": t, "spin": np.array([[1.0, -1.0], [-1.0, -1.0], [-1.0, 1.0], [1.0, 0.0], [-1.0, 0.0], [1.0, 1.0]]),
           "bodies": [{"sense": 1, "episodes": [{"t_start": 0.1, "t_end": 0.2}]}, {"sense": -1, "episodes": []}]}
    marks = episode_colours(res)
    # body 0: red inside its episode only (the reversed sample at 0.4 s is no episode: grey); body 1 (clockwise):
    # blue where it turns clockwise, grey elsewhere
    assert marks[:, 0].tolist() == [1.0, -1.0, -1.0, 1.0, 0.0, 1.0]
    assert marks[:, 1].tolist() == [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]


def test_active_refuses_bad_input_in_one_line(tmp_path: Path) -> None:
    (tmp_path / "old.json").write_text("{}")
    cases = [(["--n", "1"], "--n"), (["--n", "2.5"], "--n"), (["--packing", "0.9"], "--packing"),
             (["--activity", "0"], "--activity"), (["--mix", "1.5"], "--mix"), (["--seed", "-1"], "--seed"),
             (["--t-end", "0"], "--t-end"), (["--every", "0"], "--every"), (["--dt", "1"], "--dt"),
             (["--out", "x.txt"], "--out"), (["--out", "old.json"], "--out"), (["--movie", "x.avi"], "--movie"),
             (["--rerun", "x.mp4"], "--rerun"), (["--movie", "m.mp4", "--fps", "0"], "--fps"),
             (["--fps", "30"], "--fps"), (["--movie", "m.mp4", "--movie-speed", "-1"], "--movie-speed"),
             (["--rerun", "r.rrd", "--rerun-every", "0"], "--rerun-every"), (["--rerun-every", "2"], "--rerun-every"),
             (["--out", "a.json", "--movie", "a.json"], "--movie"), (["--wokers", "2"], "--wokers")]
    runs = run_here([["active", *BOX, *extra] for extra, _ in cases], cwd=tmp_path)
    for r, (_, option) in zip(runs, cases):
        assert_bad_input(r, option, tmp_path, {"old.json"})
    assert (tmp_path / "old.json").read_text() == "{}"


ENS = ["active-ensemble", "--n", "6", "--t-end", "1", "--packing", "0.2,0.3", "--activity", "2", "--seed", "0,1"]
POINTS = [Box(n=6, t_end=1.0, packing=p, activity=2.0, seed=s) for p in (0.2, 0.3) for s in (0, 1)]


def test_ensemble_gives_the_apis_rows_as_json_and_csv(tmp_path: Path) -> None:
    js, cs = run_here([[*ENS, "--out", "e.json", "--plot", "e.png", "--workers", "0", "--json"],
                       [*ENS, "--out", "e.csv", "--workers", "2"]], cwd=tmp_path, real=0)
    assert js.code == 0 and cs.code == 0, (js.err, cs.err)
    api = json.loads(json.dumps(jsonable(ensemble(POINTS, workers=0))))
    table = json.loads(json.dumps(jsonable(seed_table(api))))
    saved = json.loads((tmp_path / "e.json").read_text())
    assert saved["runs"] == api and saved["mean_over_seeds"] == table  # bit for bit, packing slowest, seed fastest
    d = json.loads(js.out)
    assert d == {"points": 4, "written": {"out": "e.json", "plot": "e.png"}, "table": table}
    assert [(r["packing"], r["seed"]) for r in api] == [(0.2, 0), (0.2, 1), (0.3, 0), (0.3, 1)]
    assert (tmp_path / "e.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = (tmp_path / "e.csv").read_text().splitlines()
    assert lines[0].startswith("# rrbody-active-ensemble: ")
    rows = list(csv.DictReader(lines[1:]))
    assert len(rows) == 2 * len(POINTS)  # a row per run and species
    for row in rows:
        st = api[int(row["i"])]["stats"][row["species"]]
        assert float(row["packing"]) == api[int(row["i"])]["packing"] and int(row["seed"]) == api[int(row["i"])]["seed"]
        for k, v in st.items():  # repr round-trips a float exactly; an undefined statistic is empty
            assert (v is None and row[k] == "") or float(row[k]) == v, (k, row[k], v)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["e.csv", "e.json", "e.png"]  # checkpoints removed


def test_ensemble_resumes_its_checkpoint(tmp_path: Path) -> None:
    ck = tmp_path / "e.json.checkpoint.jsonl"
    ensemble(POINTS, workers=0, checkpoint=ck)
    ck.write_text("\n".join(ck.read_text().splitlines()[:3]) + "\n")  # as if killed after two runs
    refused, = run_here([[*ENS, "--out", "e.json"]], cwd=tmp_path, real=0)
    assert_bad_input(refused, "--resume", tmp_path, {ck.name})  # neither --resume nor --force: named, kept
    resumed, = run_here([[*ENS, "--out", "e.json", "--resume", "--workers", "0"]], cwd=tmp_path, real=0)
    assert resumed.code == 0, resumed.err
    assert json.loads((tmp_path / "e.json").read_text())["runs"] == json.loads(json.dumps(jsonable(
        ensemble(POINTS, workers=0))))
    assert not ck.exists()
    other = run_here([[*ENS, "--seed", "5", "--out", "f.json", "--workers", "0"]], cwd=tmp_path, real=0)
    assert_bad_input(other[0], "--seed", tmp_path, {"e.json"})  # --seed given twice


def test_ensemble_refuses_bad_input_in_one_line(tmp_path: Path) -> None:
    ens = [a for a in ENS if a not in ("--seed", "0,1")]
    cases = [(["--packing", "0.2,0.9"], "--packing"), (["--activity", "2,0"], "--activity"),
             (["--seed", "0,0"], "--seed"), (["--seed", "0,x"], "--seed"), (["--seed", ","], "--seed"),
             (["--n", "1"], "--n"), (["--mix", "-0.1"], "--mix"), (["--t-end", "-1"], "--t-end"),
             (["--every", "1001"], "--every"), (["--dt", "0"], "--dt"), (["--workers", "-1"], "--workers"),
             (["--plot", "e.jpg"], "--plot"), (["--resume", "--force"], "--resume"),
             (["--scheduler", "foo"], "--scheduler"), (["--scheduler", "tcp://127.0.0.1:1"], "--scheduler")]
    runs = run_here([[*ens, *extra, "--out", "e.csv"] for extra, _ in cases]
                    + [[*ens, "--out", "e.txt"], ens], cwd=tmp_path)
    for r, (_, option) in zip(runs, [*cases, ([], "--out"), ([], "--out")]):
        assert_bad_input(r, option, tmp_path, set())


def test_ensemble_on_a_dask_scheduler_gives_the_local_rows(tmp_path: Path) -> None:
    """``--scheduler``: the runs on a Dask cluster (in this process, reached by its address), the same
    rows as on local processes."""
    from distributed import LocalCluster

    with LocalCluster(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster:
        (r,) = run_here([[*ENS, "--out", "d.json", "--scheduler", cluster.scheduler_address]], cwd=tmp_path, real=0)
    assert r.code == 0, r.err
    assert json.loads((tmp_path / "d.json").read_text())["runs"] == json.loads(json.dumps(jsonable(
        ensemble(POINTS, workers=0))))


def test_a_run_with_its_progress_bar_is_the_same_run(capsys) -> None:  # noqa: ANN001
    """``rrbody active`` on a terminal shows a bar over the steps (a watcher of the run): it counts every
    step and changes nothing in the run."""
    from rrbody.render.active_film import run_filmed

    box = Box(n=6, t_end=0.5, packing=0.3)
    res, rec, rrd = run_filmed(box, movie=False, progress=True)
    assert rec is None and rrd is None
    assert json.dumps(jsonable(summary(res))) == json.dumps(jsonable(summary(run_box(box))))
    assert "60/60" in capsys.readouterr().err  # 0.5 s at dt = 1/120 s
