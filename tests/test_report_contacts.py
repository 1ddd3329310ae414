"""The contact scenes (pressure, incline, polygon) follow the scene convention, and their report
sections put the exact value beside rrbody's (fast: minimal summaries, no runs)."""

from __future__ import annotations

import ast
import json
from pathlib import Path

import pytest

from rrbody.analysis.report import MY_SCENES, write_report
from rrbody.cli.scenes import list_scenes, scenes_dir

PRESSURE = {
    "spin_down": {name: {"alpha_exact": a, "alpha_measured": a * (1 + 3e-15), "rel_err": 3e-15}
                  for name, a in (("uniform", 39.24), ("ring", 58.86), ("annulus", 45.78), ("hertz", 34.6714019))},
    "stop_ratio": {"f": [0.0, 0.5, 1.0], "eps_exact": [0.653002, 0.774469, 1.0],
                   "sim": [{"f": 0.5, "eps0": 0.4, "eps_last": 0.774221}, {"f": 1.0, "eps0": 2.0,
                                                                           "eps_last": 1.00001}]},
    "disk_ratio": 0.6530017892, "hoop_ratio": 1.000000000000001}
INCLINE = {
    "alpha": 0.3805063771, "invariant": {"theta0_deg": [60, 150], "max_drift": [8.9e-15, 3.6e-13],
                                         "v_final_over_v0": [0.75, 0.0669872981078],
                                         "v_limit_over_v0": [0.75, 0.0669872981078]},
    "breakaway": {"push_at_break_over_limit": 1.001, "step_over_limit": 0.001},
    "held": {"steps": 100000, "bit_identical": True},
    "downhill_accel": {"exact": 0.9108356337584395, "plugin": 0.9108356337583781, "ode": 0.9108356337584391}}
POLYGON = {
    "omega": [0.2, 1.0, 20.0], "t_f": {"square": [None, 30.5, 628.19], "triangle": [None, 29.0, 595.03]},
    "l": 0.05, "k": 0.05, "Hc": {"k": [0.0, 1.0], "square": [0.79272624, 0.015868], "triangle": [0.79272624, 0.015877]},
    "Hc_rod_mass": [0.79272624, 0.0149],
    "box_spin_check": {"alpha_exact": 63.5269288507, "alpha_ode": 63.5269288507, "rel_err": 6.7e-16}}


@pytest.mark.parametrize("name", ["pressure", "incline"])
def test_contact_scene_convention(name: str) -> None:
    assert name in [n for n, _ in list_scenes()] and name in MY_SCENES
    tree = ast.parse((scenes_dir() / f"{name}.py").read_text())
    first = (ast.get_docstring(tree) or "").splitlines()[0]
    assert "no paper figure; real contacts" in first and len(first) < 130
    mains = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "main"]
    assert len(mains) == 1
    args = mains[0].args
    assert [a.arg for a in args.args] == ["out_dir"] and [a.arg for a in args.kwonlyargs] == ["force"]
    assert args.kw_defaults[0].value is True  # type: ignore[union-attr]


def test_contact_sections_put_exact_beside_rrbody(tmp_path: Path) -> None:
    for name, summary in (("pressure", PRESSURE), ("incline", INCLINE), ("polygon", POLYGON)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "summary.json").write_text(json.dumps(summary))
    (tmp_path / "incline" / "incline.png").write_bytes(b"")  # a figure present: linked; the others: said missing
    text = write_report(tmp_path).read_text()
    for heading in ("## pressure:", "## incline:", "## polygon:"):
        assert heading in text
    # pressure: each profile's exact rate beside the fitted one; the disk and hoop ratios; the washers' markers
    assert "| alpha, ring (lever R) (rad/s^2) | 58.86 | 58.86 (rel. err. 3.0e-15) |" in text
    assert ("| stop ratio v/(R Omega), disk (f = 0) | 0.653 (Farkas et al. 2003) | 0.653002 (kernel fixed point) |"
            in text)
    assert "| 0.5 | 0.774469 | 0.4 | 0.774221 |" in text
    assert "*(figure pressure/pressure.png not generated)*" in text
    # incline: the invariant's drift against 0, the acceleration on both paths, break-away, held
    assert "| theta0 = 150 deg: max relative drift of v (1 + cos theta) | 0 | 3.6e-13 |" in text
    assert "g (sin a - mu cos a) = 0.910835633758 | plugin 0.910835633758; ODE 0.910835633758 |" in text
    assert "| 1 (to one step, 0.001) | 1.001000 (the first push above the limit) |" in text
    assert "none: position, angle and velocity bit-identical" in text
    assert "![incline](incline/incline.png)" in text
    # polygon: t_f per body (a run without a flip is n/a, not a number), H_c per k with the rod mass, exact checks
    assert "| omega | square | triangle |" in text and "| 0.2 | n/a | n/a |" in text
    assert "| 20 | 628.19 | 595.03 |" in text
    assert "| k | rod mass | square | triangle |" in text and "| 1 | 0.0149 | 0.015868 | 0.015877 |" in text
    assert "| H_c(0), every body (no friction) | 0.79272623 | 0.79272624 to 0.79272624 |" in text
    assert "| 63.5269288507 | 63.5269288507 (ODE path, rel. err. 6.7e-16) |" in text
    # the contact scenes have their own sections, not a line in the generic list
    others = text.split("## Extended bodies")[1]
    assert "`pressure`" not in others and "`incline`" not in others
    assert write_report(tmp_path).read_text() == text  # no timing or date: a rewrite gives the same bytes


def test_contact_sections_say_not_run(tmp_path: Path) -> None:
    text = write_report(tmp_path).read_text()
    for heading in ("## pressure:", "## incline:", "## polygon:"):
        after = text.split(heading)[1]
        assert after.split("\n## ")[0].strip().endswith("*(not run)*")
