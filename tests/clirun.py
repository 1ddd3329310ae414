"""Run the real ``rrbody`` command in subprocesses (several at once) and check the error contract.

The contract (docs/cli.md, "The error contract"): bad input prints one line on stderr that names the option, no
traceback, nothing on stdout, nothing written, exit status 2, and no process left behind.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

RRBODY = [sys.executable, "-m", "rrbody.cli"]
#: a slow flip-time point (~1e5 s of weak friction, ~1e6 steps: seconds of work) for pool tests
SLOW = ["--omega", "1", "--k", "1e-9", "--t-max", "1e5"]


@dataclass
class Run:
    argv: list[str]
    code: int
    out: str
    err: str


def env() -> dict[str, str]:
    return dict(os.environ, MPLBACKEND="Agg", PYTHONWARNINGS="ignore::DeprecationWarning")


def run_many(argvs: list[list[str]], *, cwd: Path | None = None, parallel: int = 3, timeout: float = 300.0,
             stdin: str | None = None, environ: dict[str, str] | None = None) -> list[Run]:
    """Run ``rrbody ARGV`` for every ARGV, ``parallel`` at a time; results in input order (``environ``:
    the processes' environment, default :func:`env`)."""
    results: list[Run | None] = [None] * len(argvs)
    pending = list(enumerate(argvs))
    running: list[tuple[int, subprocess.Popen[str], float]] = []
    while pending or running:
        while pending and len(running) < parallel:
            i, a = pending.pop(0)
            p = subprocess.Popen([*RRBODY, *a], cwd=cwd, env=environ or env(), text=True, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, stdin=subprocess.PIPE if stdin is not None else None)
            running.append((i, p, time.monotonic()))
        i, p, t0 = running.pop(0)
        out, err = p.communicate(stdin, timeout=max(1.0, timeout - (time.monotonic() - t0)))
        results[i] = Run(argvs[i], p.returncode, out, err)
    return [r for r in results if r is not None]


def assert_bad_input(r: Run, option: str, folder: Path | None = None, before: set[str] | None = None) -> None:
    """Exit 2, one stderr line naming ``option``, no traceback, nothing on stdout or in ``folder``."""
    lines = [ln for ln in r.err.splitlines() if ln.strip() and not ln.startswith("rrbody: warning:")]
    assert r.code == 2, (r.argv, r.code, r.err)
    assert len(lines) == 1, (r.argv, r.err)
    assert option in lines[0], (r.argv, lines[0])
    assert lines[0].startswith("rrbody"), lines[0]
    assert "Traceback" not in r.err and r.out == "", (r.argv, r.out, r.err)
    if folder is not None:
        assert {p.name for p in folder.iterdir()} == (before or set()), (r.argv,
                                                                         sorted(p.name for p in folder.iterdir()))


def children(pid: int) -> set[int]:
    """Live (non-zombie) processes whose parent is ``pid`` (Linux /proc)."""
    out = set()
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()
        if fields[0] != "Z" and int(fields[1]) == pid:
            out.add(int(d.name))
    return out


def alive(pid: int) -> bool:
    """True while ``pid`` exists and is not a zombie."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def run_here(argvs: list[list[str]], *, cwd: Path | None = None, real: int = 1, timeout: float = 300.0) -> list[Run]:
    """Run ``rrbody ARGV`` for every ARGV in this process, in ``cwd``; results in input order.

    In-process is :func:`rrbody.cli.main.main`, what the ``rrbody`` command runs less the process-wide
    settings of its ``entry`` (warnings shown as one line, SIGTERM, a closed pipe): its return value (or
    argparse's ``SystemExit``) is the exit status, its printed stdout and stderr the streams. A process
    costs ~0.6 s of start-up; in-process, nothing. So that the real command stays under test, the first
    ``real`` ARGVs run first as ``rrbody`` in a subprocess (:func:`run_many`), which must give the same
    exit status, stdout and stderr (its ``rrbody: warning:`` lines aside, which only ``entry`` prints).
    Those first ARGVs must write nothing (bad input), since both runs see the same folder. A call that
    blocks (say, opening a FIFO it should have refused) fails after ``timeout`` s, as in a subprocess."""
    import contextlib
    import io
    import signal
    import threading

    from rrbody.cli.main import main

    there = run_many(argvs[:real], cwd=cwd, timeout=timeout)

    def expired(signum: int, frame: object) -> None:
        raise TimeoutError(f"rrbody {' '.join(argv)} ran past {timeout} s")

    guard = threading.current_thread() is threading.main_thread()  # signals reach the main thread only
    runs = []
    for argv in argvs:
        out, err = io.StringIO(), io.StringIO()
        old = signal.signal(signal.SIGALRM, expired) if guard else None
        if guard:
            signal.setitimer(signal.ITIMER_REAL, timeout)
        try:
            with contextlib.chdir(cwd or Path.cwd()), contextlib.redirect_stdout(out), \
                    contextlib.redirect_stderr(err):
                try:
                    code = main(list(argv))
                except SystemExit as e:  # argparse errors exit 2 through SystemExit
                    code = e.code if isinstance(e.code, int) else 0 if e.code is None else 1
        finally:
            if guard:
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGALRM, old)
        runs.append(Run(argv, code, out.getvalue(), err.getvalue()))

    def seen(r: Run) -> tuple[int, str, list[str]]:
        return r.code, r.out, [ln for ln in r.err.splitlines() if not ln.startswith("rrbody: warning:")]

    for here, proc in zip(runs, there):
        assert seen(here) == seen(proc), (here, proc)
    return runs
