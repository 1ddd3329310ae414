"""``--stepper`` on flip-time and simulate: the ODE stepping methods agree to the default accuracy's
stated error, bad values and --method engine are refused by the error contract, batch lines take it."""

from __future__ import annotations

import json
from pathlib import Path

from tests.clirun import run_here

PHIXTPM = ["--H", "0.2", "--k", "0.05", "--omega", "0.6"]
#: the default accuracy's stated error on t_f (docs/accuracy.md, the presets: `default` puts t_f within
#: 1e-6 relative of the reference on every benchmark case)
DEFAULT_TF_ERROR = 1e-6


def test_steppers_agree_and_bad_values_exit_2(tmp_path: Path) -> None:
    batch = tmp_path / "lines.jsonl"
    batch.write_text(json.dumps({"stepper": "radau", "H": 0.2, "k": 0.05, "omega": 0.6}) + "\n")
    out = tmp_path / "free.csv"
    runs = run_here([["flip-time", *PHIXTPM, "--stepper", "euler"],  # bad input first: also the real command
                     ["flip-time", *PHIXTPM, "--json"],
                     ["flip-time", *PHIXTPM, "--stepper", "radau", "--json"],
                     ["flip-time", *PHIXTPM, "--stepper", "dop853", "--json"],
                     ["flip-time", *PHIXTPM, "--stepper", "radau", "--method", "engine"],
                     ["flip-time", "--batch", str(batch)],
                     ["simulate", *PHIXTPM, "--t-max", "2", "--stepper", "dop853", "--json"],
                     ["simulate", "--no-drive", "--body", "disk", "--R0", "0.1", "--k", "0.05", "--omega", "0.6",
                      "--v0", "1,0", "--t-max", "1", "--stepper", "radau", "--out", str(out)]], cwd=tmp_path)
    bad, default, radau, dop853, engine, line, sim, free = runs
    tf = {}
    for name, r in (("default", default), ("radau", radau), ("dop853", dop853)):
        assert r.code == 0, (name, r.err)
        tf[name] = json.loads(r.out)["t_f"]
    assert tf["default"] is not None
    for name in ("radau", "dop853"):
        assert abs(tf[name] - tf["default"]) / tf["default"] < DEFAULT_TF_ERROR, tf
    # the error contract: one line naming the option and the valid values, exit 2, nothing on stdout
    assert bad.code == 2 and bad.out == "" and len(bad.err.strip().splitlines()) == 1
    assert "--stepper" in bad.err and all(m in bad.err for m in ("auto", "dop853", "radau", "rodas"))
    assert engine.code == 2 and engine.out == "" and "--stepper" in engine.err and "--method ode" in engine.err
    assert "Traceback" not in bad.err + engine.err
    # a batch line with "stepper" is the single call with --stepper
    assert line.code == 0, line.err
    assert json.loads(line.out)["t_f"] == tf["radau"]
    assert sim.code == 0 and json.loads(sim.out)["meta"]["status"] == "reached t_end"
    # Radau IIA is the driven body's method: a free body refuses it by the contract, writing nothing
    assert free.code == 2 and "--stepper must be one of 'auto', 'dop853', 'rodas'" in free.err and not out.exists()


def test_stepper_choices_are_the_loops_methods() -> None:
    from rrbody.cli.options import STEPPERS
    from rrbody.integrate.loop import STEP_METHODS

    assert set(STEPPERS) == set(STEP_METHODS)


def test_free_body_steppers_reach_the_same_rest() -> None:
    """simulate passes ``stepper`` on to free bodies (RODAS4 takes other steps than DOP853: measured 608
    against 83) and the methods agree on the stop time (measured 2e-10 relative at the default rtol
    1e-10; the bound is 100 rtol)."""
    from rrbody.analysis.simulate import simulate
    from rrbody.model.bodies import Disk
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene

    sc = Scene(body=Disk(R=0.1), drive=None, friction=Friction.from_k("dry", 0.05, 1.0), v0=(1.0, 0.0), spin0=5.0)
    runs = {s: simulate(sc, t_max=30.0, dt_out=0.5, stepper=s) for s in ("auto", "dop853", "rodas")}
    ts = {s: tr.events["t_stop"] for s, tr in runs.items()}
    assert all(t is not None for t in ts.values())
    assert runs["rodas"].meta["n_steps"] != runs["dop853"].meta["n_steps"]
    assert abs(ts["rodas"] - ts["dop853"]) / ts["dop853"] < 1e-8, ts
