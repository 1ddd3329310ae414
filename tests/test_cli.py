"""The `rrbody` command end to end (in-process): outputs, JSON, and exit code 2 on bad input."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from rrbody.model.trajectory import COLUMNS, Trajectory

from .reference import scipy_flip_time


def test_help_lists_commands(cli) -> None:  # noqa: ANN001
    r = cli("--help")
    assert r.code == 0
    for name in ("simulate", "flip-time", "critical-h", "scene", "demo"):
        assert name in r.out


def test_flip_time_json_matches_scipy(cli) -> None:  # noqa: ANN001
    r = cli("flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "pi", "--json")
    assert r.code == 0, r.err
    d = json.loads(r.out)
    assert {"t_f", "phi_min", "reverse_rotation"} <= d.keys()
    ref, _ = scipy_flip_time(0.2, 0.05, 0.6, math.pi, d["t_stop"])
    assert d["t_f"] == pytest.approx(ref, rel=1e-6)  # <= 1e-6 relative vs tight scipy
    assert d["reverse_rotation"] is True


def test_mu_g_d_equivalent_to_k(cli) -> None:  # noqa: ANN001
    a = json.loads(cli("flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json").out)
    # k = mu g / d = 0.1 * 2.5 / 5 with d = 5: H = l/d stays 0.2, the dynamics depend on k, H, w only
    b = json.loads(cli("flip-time", "--H", "0.2", "--mu", "0.1", "--g", "2.5", "--d", "5", "--omega", "0.6",
                       "--json").out)
    assert b["t_f"] == pytest.approx(a["t_f"], rel=1e-9)  # same equation; differences are round-off only


def test_friction_method_table_on_the_command_line(cli) -> None:  # noqa: ANN001
    base = ("flip-time", "--body", "disk", "--R0", "0.1", "--l", "0.2", "--k", "0.05", "--omega", "0.6", "--json")
    icr = json.loads(cli(*base, "--friction-method", "icr").out)
    table = json.loads(cli(*base, "--friction-method", "table").out)
    # the table is within 1e-10 of the quadrature's wrench (tests/test_icr_table.py); on this flip
    # (t_f ~ 10 s) that moves t_f by far less than 1e-8 relative
    assert table["t_f"] == pytest.approx(icr["t_f"], rel=1e-8)


def test_zero_friction_says_no_flip(cli) -> None:  # noqa: ANN001
    r = cli("flip-time", "--H", "0.2", "--k", "0", "--omega", "0.6", "--json")
    d = json.loads(r.out)
    assert d["t_f"] is None and "no flip" in d["regime"]


def test_critical_h_frictionless_six_digits(cli) -> None:  # noqa: ANN001
    d = json.loads(cli("critical-h", "--k", "0", "--omega", "0.3", "--json").out)
    assert round(d["H_c"], 6) == round(0.7927262347097797, 6)


def test_critical_h_dry_answers(cli) -> None:  # noqa: ANN001
    d = json.loads(cli("critical-h", "--k", "0.01", "--omega", "0.3", "--json").out)
    assert 0.3 < d["H_c"] < 0.7927  # friction shrinks the RR region (paper Fig. Hc)


def test_simulate_writes_loadable_csv(cli, tmp_path: Path) -> None:  # noqa: ANN001
    out = tmp_path / "traj.csv"
    r = cli("simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "pi", "--t-max", "20", "--dt-out",
            "0.05", "--out", str(out), "--json")
    assert r.code == 0, r.err
    tr = Trajectory.load(out)
    assert len(tr) == 401 and tr.t[-1] == pytest.approx(20.0)
    header = out.read_text().splitlines()[1].split(",")
    assert tuple(header) == COLUMNS
    assert tr.meta["scene"]["H"] == pytest.approx(0.2)
    # the CM stays at distance l = H d from P (rigid rod): exact kinematics, round-off only
    assert max(abs(math.hypot(x - xp, y - yp) - 0.2) for x, y, xp, yp in zip(tr.x_cm, tr.y_cm, tr.x_p, tr.y_p)) < 1e-12


def test_existing_output_not_clobbered(cli, tmp_path: Path) -> None:  # noqa: ANN001
    out = tmp_path / "traj.csv"
    out.write_text("precious")
    r = cli("simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "5", "--out", str(out))
    assert r.code == 2 and "--force" in r.err and out.read_text() == "precious"
    r = cli("simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "5", "--out", str(out), "--force")
    assert r.code == 0 and out.read_text().startswith("# rrbody-meta")


@pytest.mark.parametrize("argv,option", [
    (["flip-time", "--H", "-1", "--k", "0.05", "--omega", "0.6"], "--H"),
    (["flip-time", "--H", "0.2", "--k", "-0.05", "--omega", "0.6"], "--k"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0"], "--omega"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "nan"], "--omega"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "pi/0"], "--phi0"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "2pi/x"], "--phi0"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--friction", "wet"], "--friction"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--rtol", "1"], "--rtol"),
    (["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "-3"], "--t-max"),
    (["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6"], "--t-max"),
    (["flip-time", "--body", "ellipse", "--R0", "0.3", "--delta", "1.5", "--l", "0.2", "--k", "0.05",
      "--omega", "0.6"], "--delta"),
    (["flip-time", "--body", "disk", "--R0", "-1", "--k", "0.05", "--omega", "0.6"], "--R0"),
    (["critical-h", "--k", "-1", "--omega", "0.3"], "--k"),
    (["critical-h", "--k", "0.01"], "--omega"),
])
def test_bad_input_exit_2_names_option(cli, argv: list[str], option: str) -> None:  # noqa: ANN001
    r = cli(*argv)
    assert r.code == 2
    assert option in r.err
    assert "Traceback" not in r.err and r.out == ""


def test_console_script_exit_code_and_no_traceback() -> None:
    p = subprocess.run([sys.executable, "-m", "rrbody.cli", "flip-time", "--H", "0", "--k", "1", "--omega", "1"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--H" in p.stderr and "Traceback" not in p.stderr
