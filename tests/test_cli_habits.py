"""Finding class "CLI habits": negative numbers and expressions as option
values, the deg suffix and the degrees warning, did-you-mean, all missing options at once, and a
unit and range in every option's help. In-process (:func:`tests.clirun.run_here`; the first bad input
of each test also through the real command, which must answer the same; the help check reads the parser)."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from .clirun import assert_bad_input, run_here, run_many

FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"]


def test_negative_values_and_expressions(tmp_path: Path) -> None:
    spellings = [["--phi0", "-pi/2"], ["--phi0", "-0.5*pi"], ["--phi0=-pi/2"], ["--phi0", "-90deg"],
                 ["--phi0", f"{-math.pi / 2!r}"]]
    rs = run_here([[*FLIP, *s] for s in spellings], cwd=tmp_path, real=0)  # good input: computed in-process
    assert all(r.code == 0 and r.err == "" for r in rs), [r.err for r in rs]
    res = [json.loads(r.out) for r in rs]
    # -pi/2 in every spelling is the same float (math.radians(-90) == -pi/2 exactly), so the same t_f
    assert len({d["phi0"] for d in res}) == 1 and res[0]["phi0"] == -math.pi / 2
    assert len({d["t_f"] for d in res}) == 1
    # a negative value that is out of range is reported as such, not as "expected one argument"
    (r,) = run_here([["flip-time", "--H", "-0.2", "--k", "0.05", "--omega", "0.6"]], cwd=tmp_path)
    assert_bad_input(r, "--H", tmp_path, set())
    assert "must be in" in r.err


def test_degrees(tmp_path: Path) -> None:
    # the warning is printed by the parser (rrbody.cli.args), so it is on stderr in-process as well
    a, b, c = run_here([[*FLIP, "--phi0", "180deg"], [*FLIP, "--phi0", "pi"], [*FLIP, "--phi0", "180"]], cwd=tmp_path,
                       real=0)
    assert a.code == b.code == c.code == 0
    assert json.loads(a.out)["t_f"] == json.loads(b.out)["t_f"]  # radians(180) == pi exactly
    assert a.err == "" and b.err == ""
    assert c.err.count("\n") == 1 and "warning: --phi0 180 is read as 180 rad" in c.err and "180deg" in c.err


def test_did_you_mean_and_missing_options(tmp_path: Path) -> None:
    rs = run_here([["flip-time", "--H", "0.2", "--k", "0.05", "--omgea", "0.6"],
                   ["flip-time"],
                   ["flip-time", "--body", "ellipse"],
                   ["simulate", "--H", "0.2"],
                   ["critical-h"],
                   ["flip-tme", "--H", "0.2"],
                   ["sweep", "--H", "0.2"],
                   ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--H=0.3"]], cwd=tmp_path)
    assert_bad_input(rs[0], "--omgea", tmp_path, set())
    assert "did you mean --omega?" in rs[0].err
    for r, names in zip(rs[1:5], [("--H", "--omega", "--k"), ("--R0", "--omega", "--k"),
                                  ("--omega", "--k", "--t-max"), ("--k", "--omega")]):
        assert_bad_input(r, "missing required options", tmp_path, set())
        assert all(n in r.err for n in names), r.err  # every missing option at once
    assert_bad_input(rs[5], "flip-tme", tmp_path, set())
    assert "did you mean flip-time?" in rs[5].err
    assert_bad_input(rs[6], "missing required options: --axis, --out", tmp_path, set())
    assert_bad_input(rs[7], "--H is given twice", tmp_path, set())  # not "the last one wins" in silence


def _options(parser: argparse.ArgumentParser) -> list[tuple[str, argparse.Action]]:
    out = []
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            for name, sp in a.choices.items():
                out += [(f"{name} {o}", x) for o, x in _options(sp)]
        elif a.option_strings and a.help != argparse.SUPPRESS:
            out.append((a.option_strings[-1], a))
    return out


def test_every_option_has_help_and_numeric_ones_unit_and_range() -> None:
    from rrbody.cli.args import OPTION_PARAMS
    from rrbody.cli.main import build_parser
    from rrbody.model.checks import LIMITS

    opts = _options(build_parser())
    assert len(opts) > 60
    for name, action in opts:
        assert action.help, f"{name} has no help"
        opt = name.split()[-1]
        valid = getattr(action, "valid", None)  # a range from another checked table (rrbody.cli.args.ranged)
        if valid is not None:
            assert valid in action.help, (name, action.help)
        elif opt in OPTION_PARAMS:
            assert LIMITS[OPTION_PARAMS[opt]].text() in action.help, (name, action.help)
        elif action.type is not None:  # any other valued option must name what it takes
            raise AssertionError(f"{name} takes a value but has no range in the model's table")


def test_cli_quantities_match_the_sweep_engine() -> None:
    from rrbody.analysis.sweep_spec import QUANTITIES
    from rrbody.cli.sweep import QUANTITY_NAMES

    assert QUANTITY_NAMES == tuple(QUANTITIES)


def test_a_refused_value_is_one_line_without_the_degrees_warning(tmp_path: Path) -> None:
    """The degrees warning waits until the input is checked: a value out of range (``--phi0 1e7``, a whole
    number, so also a likely degree), or another option refused beside a likely degree, is the error's
    one line alone; a good command still warns, once. The real command and in-process, single and batch."""
    bad = [[*FLIP, "--phi0", "1e7"], [*FLIP, "--phi0", "180", "--t-max", "-1"]]
    real = run_many(bad, cwd=tmp_path)
    here = run_here(bad, cwd=tmp_path, real=0)
    for r, opt in zip([*real, *here], ["--phi0", "--t-max"] * 2):
        assert_bad_input(r, opt, tmp_path, set())
        assert r.err.count("\n") == 1 and "warning" not in r.err, r.err
    lines = tmp_path / "in.jsonl"
    lines.write_text('{"phi0": 1e7}\n{"phi0": 180}\n')
    (b,) = run_many([[*FLIP, "--batch", str(lines)]], cwd=tmp_path)
    assert b.code == 2 and "--phi0 must be in" in json.loads(b.out.splitlines()[0])["error"]
    assert b.err.count("warning: --phi0 180 is read as 180 rad") == 1 and b.err.count("\n") == 1, b.err
