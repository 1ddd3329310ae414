"""Sweeps: resume after an interruption, Dask vs local processes, refusal to mix results, output formats."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import rrbody.analysis.sweep as sw
from rrbody.analysis.sweep import SweepInterrupted, checkpoint_path, load_sweep, read_meta, run_sweep
from rrbody.analysis.sweep_spec import Sweep


def small_sweep(k: float = 7.5) -> Sweep:
    # 12 cheap points (~1 ms each): low-to-moderate omega at the tfxwpm2 parameters
    return Sweep(base={"H": 0.25, "k": k, "phi0": math.pi}, axes={"omega": np.geomspace(0.5, 20.0, 12)})


def test_interrupted_then_resumed_equals_uninterrupted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    ref = run_sweep(small_sweep(), tmp_path / "ref.csv", workers=0, progress=False)
    out = tmp_path / "cut.csv"
    with pytest.raises(SweepInterrupted):
        run_sweep(small_sweep(), out, workers=0, batch_size=2, progress=False, _stop_after=4)
    ck = checkpoint_path(out)
    assert ck.exists() and not out.exists()
    # A kill in the middle of a write leaves a truncated last line: it must be dropped and recomputed.
    with open(ck, "a") as fh:
        fh.write('{"i": 7, "t_f": 1.2')
    calls: list[float] = []
    real = sw.evaluate_point

    def counting(sweep: Sweep, values: dict[str, float]) -> dict:
        calls.append(values["omega"])
        return real(sweep, values)

    monkeypatch.setattr(sw, "evaluate_point", counting)
    run_sweep(small_sweep(), out, workers=0, batch_size=2, resume=True, progress=False)
    assert len(calls) == 12 - 4  # finished points are not recomputed
    assert out.read_text() == ref.read_text()
    assert not ck.exists()


def test_resume_refuses_changed_parameters(tmp_path: Path) -> None:
    out = tmp_path / "s.csv"
    with pytest.raises(SweepInterrupted):
        run_sweep(small_sweep(), out, workers=0, batch_size=3, progress=False, _stop_after=3)
    with pytest.raises(ValueError, match="different sweep"):
        run_sweep(small_sweep(k=12.5), out, workers=0, resume=True, progress=False)
    # the refused attempt must not have damaged the checkpoint: the right sweep still resumes
    run_sweep(small_sweep(), out, workers=0, resume=True, progress=False)
    assert len(load_sweep(out)) == 12


def test_fresh_run_refuses_existing_checkpoint(tmp_path: Path) -> None:
    out = tmp_path / "s.csv"
    with pytest.raises(SweepInterrupted):
        run_sweep(small_sweep(), out, workers=0, batch_size=3, progress=False, _stop_after=3)
    with pytest.raises(ValueError, match="checkpoint"):
        run_sweep(small_sweep(), out, workers=0, progress=False)


def test_dask_local_cluster_matches_local_processes(tmp_path: Path) -> None:
    from distributed import LocalCluster

    local = run_sweep(small_sweep(), tmp_path / "local.csv", workers=2, batch_size=3, progress=False)
    with LocalCluster(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster:
        dask = run_sweep(small_sweep(), tmp_path / "dask.csv", scheduler=cluster.scheduler_address, batch_size=5,
                         progress=False)
    # identical, not merely close: every point is the same deterministic computation
    assert dask.read_text() == local.read_text()


def test_two_d_grid_netcdf(tmp_path: Path) -> None:
    s = Sweep(base={"k": 1.5}, axes={"omega": [0.5, 2.0, 5.0], "H": [0.1, 0.3]})
    out = run_sweep(s, tmp_path / "g.nc", workers=0, progress=False)
    ds = load_sweep(out)
    assert ds["t_f"].dims == ("omega", "H") and ds["t_f"].shape == (3, 2)
    assert list(ds["H"].values) == [0.1, 0.3]
    meta = read_meta(out)
    assert meta["spec"]["base"] == {"k": 1.5} and meta["rrbody_version"]
    # the grid value at (omega=2, H=0.3) is the flip time of that scene
    from rrbody.analysis.flip import flip_time
    from rrbody.model.scene import rod_mass_scene

    assert float(ds["t_f"].sel(omega=2.0, H=0.3)) == flip_time(rod_mass_scene(0.3, 1.5, 2.0)).t_f


def test_critical_h_list_sweep(tmp_path: Path) -> None:
    s = Sweep(base={"omega": 0.3, "friction": "dry"}, axes={"k": [0.0, 0.01]}, quantity="critical_h", mode="list",
              options={"tol": 1e-7})
    rows = load_sweep(run_sweep(s, tmp_path / "hc.csv", workers=0, progress=False))
    # k = 0 is the frictionless case: exact H_c(0) = 0.79272623 (elliptic-integral root), tol 1e-7 on H
    assert abs(float(rows[0]["H_c"]) - 0.79272623) < 2e-7
    assert float(rows[1]["H_c"]) < float(rows[0]["H_c"])


@pytest.mark.parametrize("kwargs, match", [
    ({"base": {"H": 0.2, "k": 1.0}, "axes": {"omega": [1.0]}, "quantity": "speed"}, "quantity"),
    ({"base": {"H": 0.2, "k": 1.0}, "axes": {}}, "axes"),
    ({"base": {"H": 0.2, "k": 1.0}, "axes": {"mass": [1.0]}}, "axes must be among"),
    ({"base": {"H": 0.2}, "axes": {"omega": [1.0]}}, "base must give"),
    ({"base": {"H": -0.2, "k": 1.0}, "axes": {"omega": [1.0]}}, "H"),
    ({"base": {"H": 0.2, "k": 1.0}, "axes": {"omega": [1.0, 2.0], "k": [1.0]}, "mode": "list"}, "equal length"),
])
def test_bad_sweeps_are_refused(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        Sweep(**kwargs)


def test_bad_output_suffix(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="csv or .nc"):
        run_sweep(small_sweep(), tmp_path / "x.txt", workers=0, progress=False)


def test_cli_sweep_and_report(tmp_path: Path, cli) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "tf.csv"
    r = cli("sweep", "--H", "0.25", "--k", "7.5", "--axis", "omega=0.5:2:4", "--workers", "0", "--out", str(out),
            "--json")
    assert r.code == 0, r.err
    rows = load_sweep(out)
    assert [float(x["omega"]) for x in rows] == [0.5, 1.0, 1.5, 2.0]
    r = cli("sweep", "--H", "0.25", "--k", "7.5", "--axis", "omega=0.5:2:4", "--workers", "0", "--out", str(out))
    assert r.code == 2 and "already exists" in r.err  # never clobbers without --force
    r = cli("sweep", "--H", "0.25", "--axis", "omega=1,2", "--workers", "0", "--out", str(tmp_path / "x.csv"))
    assert r.code == 2 and "missing required options: --k" in r.err
    # the report builds from whatever scene outputs exist (none here) without failing
    r = cli("report", "--results", str(tmp_path))
    assert r.code == 0, r.err
    assert "not run" in (tmp_path / "REPORT.md").read_text()


def test_extended_body_sweep_resumes_and_matches_flip_time(tmp_path: Path) -> None:
    """Sweeps over any scene: a disk over l and phi0 with the same resume machinery."""
    from rrbody.analysis.flip import flip_time
    from rrbody.model.scene import scene_from_params

    base = {"body": "disk", "R0": 0.2, "k": 0.05, "omega": 0.6}
    s = Sweep(base=base, axes={"l": [0.1, 0.3], "phi0": [math.pi, -math.pi / 2]}, options={"accuracy": "draft"})
    ref = run_sweep(s, tmp_path / "ref.csv", workers=0, progress=False)
    out = tmp_path / "cut.csv"
    with pytest.raises(SweepInterrupted):
        run_sweep(s, out, workers=0, batch_size=1, progress=False, _stop_after=2)
    run_sweep(s, out, workers=0, batch_size=1, resume=True, progress=False)
    assert out.read_text() == ref.read_text()
    rows = load_sweep(out)
    # each row is the flip time of that scene, the same computation bit for bit
    sc = scene_from_params(**base, l=0.3, phi0=-math.pi / 2)
    assert float(rows[3]["t_f"]) == flip_time(sc, accuracy="draft").t_f


def test_sweep_refuses_bad_axis_values_before_any_file(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"^axis delta: delta must be in \(-1, 1\)"):
        Sweep(base={"body": "ellipse", "R0": 0.3, "l": 0.2, "k": 0.01, "omega": 0.6}, axes={"delta": [0.0, 1.5]})
    with pytest.raises(ValueError, match=r"^rtol must be in"):
        Sweep(base={"H": 0.2, "k": 0.1}, axes={"omega": [1.0]}, options={"rtol": 1.0})
    assert list(tmp_path.iterdir()) == []
