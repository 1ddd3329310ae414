"""Finding class "tracebacks": subnormal and absurd magnitudes get the same
one-line error as negatives (no ZeroDivisionError), and a closed pipe ends quietly. The closed pipe
through the real CLI in subprocesses; the bad values in-process (:func:`tests.clirun.run_here`, the
first of each test also through the real command, which must answer the same)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from .clirun import RRBODY, assert_bad_input, env, run_here

FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6"]


def _with(base: list[str], option: str, value: str) -> list[str]:
    argv = list(base)
    if option in argv:
        argv[argv.index(option) + 1] = value
    else:
        argv += [option, value]
    return argv


# each value: subnormal, tiny, negative, zero, absurdly large; the same message shape for all
MAGNITUDES = ["1e-320", "5e-324", "1e-300", "-1", "0", "1e300"]


@pytest.mark.parametrize("option", ["--H", "--omega", "--d", "--R0"])
def test_subnormal_and_absurd_magnitudes(option: str, tmp_path: Path) -> None:
    base = FLIP if option != "--R0" else ["flip-time", "--body", "disk", "--R0", "0.3", "--l", "0.2", "--k", "0.05",
                                          "--omega", "0.6"]
    rs = run_here([_with(base, option, v) for v in MAGNITUDES], cwd=tmp_path)
    for r in rs:
        assert_bad_input(r, option, tmp_path, set())
        assert " must be in [" in r.err  # name, valid range and unit, like a negative value


def test_friction_subnormal_and_sim_options(tmp_path: Path) -> None:
    sim = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1"]
    cases = [(_with(FLIP, "--k", "1e-320"), "--k"), (_with(FLIP, "--k", "1e-320"), "--k"),
             (_with(sim, "--dt-out", "1e-320"), "--dt-out"), (_with(sim, "--t-max", "1e-320"), "--t-max"),
             (_with(FLIP, "--rtol", "1e-320"), "--rtol"), (_with(FLIP, "--phi-dot0", "1e-320"), "--phi-dot0"),
             (["critical-h", "--k", "1e-320", "--omega", "0.3"], "--k"),
             (["critical-h", "--k", "0.01", "--omega", "1e-320"], "--omega"),
             (_with(sim, "--t-max", "1e8"), "--dt-out")]  # 3e9 samples at the default interval: refused at once
    for r, (_, opt) in zip(run_here([a for a, _ in cases], cwd=tmp_path), cases):
        assert_bad_input(r, opt, tmp_path, set())


@pytest.mark.parametrize("command", [
    [*FLIP, "--json"],
    ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "5", "--json"],
])
def test_broken_pipe_ends_quietly(command: list[str], tmp_path: Path) -> None:
    """`rrbody ... --json | head -c 10` raised BrokenPipeError about one run in two: run it 6 times."""
    cmd = " ".join([*RRBODY, *command])
    for _ in range(6):
        p = subprocess.run(["bash", "-c", f"set -o pipefail; {cmd} | head -c 10"], capture_output=True, text=True,
                           env=env(), cwd=tmp_path, timeout=120)
        assert p.stderr == "", p.stderr  # no traceback, no "Exception ignored" either
        assert len(p.stdout) == 10
        assert p.returncode in (0, 141)  # 141: like a command ended by SIGPIPE (128 + 13)


def test_broken_pipe_in_batch_mode_ends_quietly(tmp_path: Path) -> None:
    """Batch mode writes and flushes a line per answer, so the reader's exit is met mid-stream."""
    lines = tmp_path / "lines.jsonl"
    lines.write_text('{"H": 0.2, "k": 0.05, "omega": 0.6}\n' * 200)
    cmd = " ".join([*RRBODY, "flip-time", "--batch", str(lines)])
    for _ in range(3):
        p = subprocess.run(["bash", "-c", f"set -o pipefail; {cmd} | head -c 10"], capture_output=True, text=True,
                           env=env(), cwd=tmp_path, timeout=300)
        assert p.stderr == "", p.stderr
        assert len(p.stdout) == 10 and p.returncode == 141
