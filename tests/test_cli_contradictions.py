"""Validate everything before anything is written or computed: options that contradict
each other are named both; an empty or over-long output path is bad input (exit 2, one line), not
"no output" nor a raw OS message after the run; outputs that are one file (any spelling, hard or
symbolic link) are refused; every numeric value is finite at every step of parsing; one writer per
output (a second rrbody process aiming at a path in use is refused, naming the first; a lock left by
a killed process is taken over). Also the wording a shell user sees: --help without reST markup,
``--force`` rather than ``force=True``, ``wrote traj.csv (trajectory CSV)``.

Real CLI in subprocesses for the writers and their locks; the bad inputs in-process
(:func:`tests.clirun.run_here`, the first of each test also through the real command, which must answer
the same); the parser's help and the message helpers read in-process."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

from .clirun import RRBODY, alive, assert_bad_input, env, run_here, run_many

FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6"]
SIM = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1"]
#: a simulate run of a few seconds warm (~1e6 steps of weak friction, 3,000 samples written)
LONG_SIM = ["simulate", "--H", "0.2", "--omega", "1", "--k", "1e-9", "--t-max", "3e5", "--dt-out", "100"]


def test_contradictory_options_are_named_both(tmp_path: Path) -> None:
    cases = [
        ([*FLIP, "--friction", "none"], ("--friction none", "--k")),
        (["flip-time", "--H", "0.2", "--mu", "0.1", "--omega", "0.6", "--friction", "none"], ("--friction none",
                                                                                              "--mu")),
        ([*FLIP, "--mu", "0.1"], ("--k", "--mu")),
        ([*FLIP, "--g", "3"], ("--g", "--mu")),
        ([*FLIP, "--dt", "1e-3"], ("--dt", "--method ode")),
        ([*FLIP, "--method", "engine", "--rtol", "1e-9"], ("--rtol", "--method engine")),
        ([*FLIP, "--R0", "0.3"], ("--R0", "--body rod")),
        ([*FLIP, "--v0", "1,0"], ("--v0", "--no-drive")),
        ([*SIM, "--fps", "10"], ("--fps", "--movie")),
        (["critical-h", "--k", "0.01", "--omega", "0.3", "--friction", "none"], ("--friction none", "--k")),
    ]
    rs = run_here([argv for argv, _ in cases], cwd=tmp_path)
    for r, (_, names) in zip(rs, cases):
        assert_bad_input(r, names[0], tmp_path, set())
        assert names[1] in r.err, r.err


def test_empty_and_overlong_paths_are_bad_input(tmp_path: Path) -> None:
    long_name = "x" * 250 + ".csv"  # NAME_MAX is 255 bytes here; the temporary sibling needs more
    long_dir = str(tmp_path / ("d" * 300) / "t.csv")  # a folder name beyond NAME_MAX
    long_path = str(tmp_path / "/".join(["y" * 100] * 45) / "t.csv")  # beyond PATH_MAX (4096 bytes)
    argvs = [[*SIM, "--out", ""], [*SIM, "--movie", ""], [*SIM, "--rerun", ""], [*SIM, "--out", "  "],
             [*SIM, "--out", str(tmp_path / long_name)], [*SIM, "--out", long_dir], [*SIM, "--out", long_path],
             [*SIM, "--json", "--batch", ""]]
    options = ["--out", "--movie", "--rerun", "--out", "--out", "--out", "--out", "--batch"]
    rs = run_here(argvs, cwd=tmp_path)
    for r, opt in zip(rs, options):
        assert_bad_input(r, opt, tmp_path, set())
    assert all("empty path" in r.err for r in rs[:4])
    assert all("bytes long" in r.err and "too long" not in r.err for r in rs[4:7])


def test_outputs_that_are_one_file_are_refused(tmp_path: Path) -> None:
    (tmp_path / "m.mp4").write_bytes(b"old")
    os.link(tmp_path / "m.mp4", tmp_path / "hard.mp4")
    (tmp_path / "soft.mp4").symlink_to("m.mp4")
    before = {p.name for p in tmp_path.iterdir()}
    pairs = [("o.mp4", "o.mp4"), ("./o.mp4", "o.mp4"), ("sub/../o.mp4", "o.mp4"), ("hard.mp4", "m.mp4"),
             ("soft.mp4", "m.mp4"), (str(tmp_path / "m.mp4"), "m.mp4")]
    (tmp_path / "sub").mkdir()
    before.add("sub")
    argvs = [[*SIM, "--out", a, "--movie", b, "--force"] for a, b in pairs]
    argvs.append([*SIM, "--out", "r.rrd", "--rerun", "./r.rrd"])
    for r in run_here(argvs, cwd=tmp_path):
        assert_bad_input(r, "--out and --", tmp_path, before)
        assert "same file" in r.err
    assert (tmp_path / "m.mp4").read_bytes() == b"old"


def test_numbers_are_finite_at_every_step(tmp_path: Path) -> None:
    cases = [("--phi0", "1e308pi/10"),      # the product overflows, whatever the quotient
             ("--phi0", "1e-300pi/1e300"),  # the quotient underflows to a silent 0
             ("--phi0", "1/1e400"),         # a literal beyond the float range (1/inf would be a silent 0)
             ("--phi0", "1e400deg"),
             ("--phi0", "1e-400"),
             ("--k", "1e-400"),             # a nonzero literal read as 0 would mean "no friction"
             ("--H", "1e400"),
             ("--v0", "1e-400,0"),
             ("--max-steps", "1e400")]
    argvs = []
    for option, value in cases:
        argv = [*FLIP]
        if option in argv:
            argv[argv.index(option) + 1] = value
        else:
            argv += [option, value] if option != "--v0" else ["--no-drive", "--t-max", "1", option, value]
        argvs.append(argv)
    for r, (option, _) in zip(run_here(argvs, cwd=tmp_path), cases):
        assert_bad_input(r, option, tmp_path, set())


def test_help_shows_no_rest_markup() -> None:
    from rrbody.cli.args import commands, subparser
    from rrbody.cli.main import build_parser

    p = build_parser()
    texts = {"rrbody": p.format_help()}
    for c in commands(p):
        sp = subparser(p, c)
        assert sp is not None
        texts[c] = sp.format_help()
    for name, text in texts.items():
        for mark in ("``", ":func:", ":class:", ":mod:", ":data:", "`"):
            assert mark not in text, (name, mark)


def test_the_shell_is_told_force_and_python_force_true(tmp_path: Path) -> None:
    from rrbody.cli.args import option_message
    from rrbody.model.io import check_writable

    f = tmp_path / "t.csv"
    f.write_text("old")
    with pytest.raises(ValueError, match="pass force=True to overwrite") as e:
        check_writable(f, name="out")
    assert "--force" not in str(e.value)
    assert option_message(str(e.value)).startswith("--out:") and "pass --force to overwrite" in option_message(
        str(e.value))
    assert option_message("out: checkpoint exists; pass resume=True (--resume) to continue it or force=True "
                          "(--force) to start afresh").endswith("pass --resume to continue it or --force to start "
                                                                "afresh")
    (r,) = run_many([[*SIM, "--out", str(f)]], cwd=tmp_path)
    assert_bad_input(r, "--out", tmp_path, {"t.csv"})
    assert "--force" in r.err and "force=True" not in r.err


def _lock_seen(pid: int, out: Path) -> bool:
    """True once process ``pid`` has taken the lock of ``out`` (rrbody.model.outlock writes its pid into the
    lock file it holds, beside the output)."""
    from rrbody.model.outlock import lock_path

    try:
        return lock_path(out).read_text().startswith(f"process {pid} ")
    except OSError:
        return False


def _start(argv: list[str], cwd: Path) -> subprocess.Popen[str]:
    return subprocess.Popen([*RRBODY, *argv], cwd=cwd, env=env(), text=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)


def _wait_for_lock(p: subprocess.Popen[str], out: Path) -> None:
    deadline = time.monotonic() + 120  # the first run of a fresh tree compiles its kernels after the claim
    while not _lock_seen(p.pid, out):
        assert p.poll() is None, ("the first writer ended before it was seen holding its lock", p.communicate())
        assert time.monotonic() < deadline, "the first writer never took its lock"
        time.sleep(0.05)


def test_one_writer_per_output(tmp_path: Path) -> None:
    first = _start([*LONG_SIM, "--out", "same.csv"], tmp_path)
    try:
        _wait_for_lock(first, tmp_path / "same.csv")
        # the second writer, with other parameters and --force, another spelling of the same path
        (second,) = run_many([[*SIM, "--out", "./same.csv", "--force"]], cwd=tmp_path)
        out, err = first.communicate(timeout=300)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert_bad_input(second, "--out", None)
    assert f"process {first.pid} " in second.err and "being written" in second.err
    assert first.returncode == 0, err
    assert out.strip().endswith("wrote same.csv (trajectory CSV)")  # a sentence, not "wrote out: same.csv"
    assert [p.name for p in tmp_path.iterdir()] == ["same.csv"]  # no temporary file left behind
    head = (tmp_path / "same.csv").read_text().splitlines()[0]
    assert '"k": 1e-09' in head  # the first writer's numbers, intact


def test_a_killed_writers_lock_is_taken_over(tmp_path: Path) -> None:
    first = _start([*LONG_SIM, "--out", "same.csv"], tmp_path)
    try:
        _wait_for_lock(first, tmp_path / "same.csv")
        os.kill(first.pid, signal.SIGKILL)
        first.wait(timeout=60)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert not alive(first.pid)
    (r,) = run_many([[*SIM, "--out", "same.csv"]], cwd=tmp_path)  # no --force: nothing was left to overwrite
    assert r.code == 0, r.err
    assert [p.name for p in tmp_path.iterdir()] == ["same.csv"]
