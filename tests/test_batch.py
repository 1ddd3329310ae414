"""Batch mode: one JSON object of options per line in, one JSON result per line out, in
order and flushed; a bad line yields {"error", "line"} and the rest still run; exit 2 if any line
failed; results equal the single calls' bit for bit. Also what the flip-time path imports."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from .clirun import RRBODY, env, run_here, run_many

LINES = [
    {"H": 0.2, "k": 0.05, "omega": 0.6},
    {"H": 0.25, "k": 7.5, "omega": 2.0, "phi0": "-pi/2"},
    {"H": 0.2, "k": 0.05, "omega": 0.6, "friction": "viscous", "accuracy": "draft"},
    {"body": "disk", "R0": 0.2, "l": 0.1, "k": 0.05, "omega": 0.6, "accuracy": "draft"},
    {"H": 0.2, "k": 0.0, "omega": 0.6},
]


def _argv(d: dict) -> list[str]:
    out = []
    for k, v in d.items():
        out += [f"--{k}", str(v)]
    return out


def _strip(d: dict) -> dict:
    return {k: v for k, v in d.items() if k != "wall_s"}  # a timing, the only field that may differ


def test_flip_time_batch_equals_single_calls(tmp_path: Path) -> None:
    f = tmp_path / "in.jsonl"
    bad = ['{"H": -1, "k": 0.05, "omega": 0.6}', "not json", '{"H": 0.2, "k": 0.05, "omgea": 0.6}', "[1, 2]"]
    text = [json.dumps(LINES[0]), json.dumps(LINES[1]), bad[0], json.dumps(LINES[2]), "", bad[1],
            "# a comment", json.dumps(LINES[3]), bad[2], bad[3], json.dumps(LINES[4])]
    f.write_text("\n".join(text) + "\n")
    single = [["flip-time", *_argv(d), "--json"] for d in LINES]
    batch, real = run_many([["flip-time", "--batch", str(f)], single[0]], cwd=tmp_path)
    # the single calls in this process (clirun.run_here: rrbody's main, no process start of ~0.6 s each);
    # the first also ran above as the real command, which answers the same
    singles = run_here(single, cwd=tmp_path, real=0)
    assert real.code == singles[0].code == 0 and _strip(json.loads(real.out)) == _strip(json.loads(singles[0].out))
    assert batch.code == 2 and "Traceback" not in batch.err
    out = [json.loads(ln) for ln in batch.out.splitlines()]
    assert len(out) == 9  # one per non-blank, non-comment line, in order
    ok = [o for o in out if "error" not in o]
    assert [_strip(o) for o in ok] == [_strip(json.loads(s.out)) for s in singles]
    errors = {o["line"]: o["error"] for o in out if "error" in o}
    assert sorted(errors) == [3, 6, 9, 10]
    assert errors[3].startswith("--H must be in [1e-6, 1e6]")
    assert "not JSON" in errors[6] and "did you mean --omega?" in errors[9] and "JSON object" in errors[10]


def test_critical_h_and_simulate_batches(tmp_path: Path) -> None:
    c_in = tmp_path / "c.jsonl"
    c_in.write_text('{"k": 0.01, "omega": 0.3, "tol": 1e-6}\n{"k": 0, "omega": 0.3, "tol": 1e-6}\n')
    s_in = tmp_path / "s.jsonl"
    s_in.write_text('{"H": 0.2, "k": 0.05, "omega": 0.6, "t-max": 3}\n{"H": 0.2, "k": 0.05, "omega": 0.6, '
                    '"t_max": 2, "dt-out": 0.5}\n')
    rs = run_many([["critical-h", "--batch", str(c_in)], ["critical-h", "--k", "0.01", "--omega", "0.3", "--tol",
                                                          "1e-6", "--json"],
                   ["simulate", "--json", "--batch", str(s_in)],
                   ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "2", "--dt-out", "0.5",
                    "--json"],
                   ["simulate", "--batch", str(s_in)]], cwd=tmp_path)
    assert rs[0].code == 0 and json.loads(rs[0].out.splitlines()[0]) == json.loads(rs[1].out)
    assert rs[2].code == 0
    sims = [json.loads(ln) for ln in rs[2].out.splitlines()]
    strip = lambda d: {**d, "meta": {k: v for k, v in d["meta"].items() if k != "wall_s"}}  # noqa: E731
    assert strip(sims[1]) == strip(json.loads(rs[3].out))
    assert sims[0]["t_end"] == 3.0 and sims[1]["t_end"] == 2.0
    assert rs[4].code == 2 and "--batch needs --json" in rs[4].err


def test_stdin_is_streamed_line_by_line(tmp_path: Path) -> None:
    """Each answer is flushed before the next line is read: a caller can talk to it through a pipe."""
    p = subprocess.Popen([*RRBODY, "flip-time", "--batch", "-", "--accuracy", "draft"], env=env(), text=True,
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path)
    assert p.stdin is not None and p.stdout is not None
    answers = []
    for d in LINES[:3]:
        p.stdin.write(json.dumps(d) + "\n")
        p.stdin.flush()
        answers.append(json.loads(p.stdout.readline()))  # would block forever without the flush
    p.stdin.close()
    assert p.wait(timeout=60) == 0
    assert [a["omega"] for a in answers] == [0.6, 2.0, 0.6] and answers[1]["phi0"] < 0


def test_flip_time_imports_only_what_it_uses(tmp_path: Path) -> None:
    code = ("import sys\nfrom rrbody.cli.main import main\n"
            "assert main(['flip-time', '--H', '0.2', '--k', '0.05', '--omega', '0.6', '--json']) == 0\n"
            "bad = [m for m in ('scipy.linalg', 'rrbody.analysis.sweep', 'rrbody.analysis.sweep_spec', "
            "'rrbody.analysis.pool', 'rrbody.engine', 'matplotlib', 'pymunk', 'xarray', 'distributed', "
            "'rrbody.render.mp4') if m in sys.modules]\n"
            "print(bad, file=sys.stderr)\nassert not bad\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env(), cwd=tmp_path,
                       timeout=120)
    assert p.returncode == 0, p.stderr
