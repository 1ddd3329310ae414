"""Finding class "processes": no command leaves a process behind; the
sweep pool never has more processes than points; its processes die with their parent on SIGTERM,
SIGINT and kill -9; an interrupted sweep says how to --resume. Real CLI, in subprocesses (Linux /proc)."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

from .clirun import RRBODY, SLOW, alive, children, env, run_many

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


def _start_sweep(tmp_path: Path, n_points: int, workers: int,
                 point: list[str] = SLOW) -> tuple[subprocess.Popen[str], Path]:
    out = tmp_path / "s.csv"
    hs = ",".join(str(0.2 + 0.01 * i) for i in range(n_points))
    # Ctrl-C as from a terminal: a suite run as a background job (`make test &`) inherits SIGINT ignored,
    # and Python, like every program, keeps an inherited SIG_IGN, so the sweep would never see it
    p = subprocess.Popen([*RRBODY, "sweep", "--axis", f"H={hs}", *point, "--workers", str(workers), "--batch-size",
                          "1", "--out", str(out)], env=env(), text=True, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    return p, out


def _wait_children(pid: int, want: int, timeout: float = 60.0) -> set[int]:
    t0 = time.monotonic()
    seen: set[int] = set()
    while time.monotonic() - t0 < timeout:
        seen = children(pid)
        if len(seen) >= want:
            return seen
        time.sleep(0.05)
    return seen


def _all_gone(pids: set[int], timeout: float = 10.0) -> bool:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if not any(alive(c) for c in pids):
            return True
        time.sleep(0.05)
    return False


def test_pool_never_larger_than_points(tmp_path: Path) -> None:
    # points of a tenth of SLOW's span (~1e5 steps, a fraction of a second each): the sweep runs to its
    # end here, and its workers live through their start-up (~0.5 s, polled every 0.02 s) whatever the points
    p, out = _start_sweep(tmp_path, n_points=3, workers=8, point=[*SLOW[:-1], "1e4"])
    most: set[int] = set()
    while p.poll() is None:
        kids = children(p.pid)
        if len(kids) > len(most):
            most = kids
        time.sleep(0.02)
    _, err = p.communicate()
    assert p.returncode == 0, err
    assert 1 <= len(most) <= 3  # 3 points: at most 3 processes although 8 were asked for
    if (os.cpu_count() or 1) < 8:
        assert "rrbody: warning: --workers 8 is more than the" in err
    assert "Traceback" not in err and out.exists()


def test_workers_upper_bound_is_a_one_line_error(tmp_path: Path) -> None:
    (r,) = run_many([["sweep", "--H", "0.2", "--k", "1", "--axis", "omega=1,2", "--workers", "100000", "--out",
                      str(tmp_path / "s.csv")]])
    assert r.code == 2 and "--workers must be an integer in [0, 256]" in r.err and "Traceback" not in r.err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGKILL])
def test_pool_dies_with_its_parent(tmp_path: Path, sig: signal.Signals) -> None:
    p, out = _start_sweep(tmp_path, n_points=4, workers=2)
    kids = _wait_children(p.pid, 2)
    assert kids, "the sweep started no worker process"
    time.sleep(0.3)  # let the workers get into their first point
    os.kill(p.pid, sig)
    p.wait(timeout=60)
    gone = _all_gone(kids)
    for c in kids:  # clean up if the test is about to fail, so that no orphan outlives it
        if alive(c):
            os.kill(c, signal.SIGKILL)
    assert gone, f"orphans were left after {sig.name} of the parent"
    _, err = p.communicate(timeout=60)
    if sig != signal.SIGKILL:
        # the parent itself ends cleanly: one line that says how to continue, no traceback
        assert p.returncode == 130, err
        assert "--resume" in err and "Traceback" not in err
        assert not out.exists()  # no partial output; the checkpoint keeps the finished points
        assert (tmp_path / "s.csv.checkpoint.jsonl").exists()


def test_single_commands_leave_no_process(tmp_path: Path) -> None:
    """The old background worker re-parented itself to PID 1: nothing may outlive a command now."""
    before = {int(d.name) for d in Path("/proc").iterdir() if d.name.isdigit()}
    rs = run_many([["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"],
                   ["critical-h", "--k", "0.01", "--omega", "0.3", "--json"],
                   ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1", "--json"]], cwd=tmp_path)
    assert all(r.code == 0 for r in rs), [r.err for r in rs]
    time.sleep(0.2)
    new = {int(d.name) for d in Path("/proc").iterdir() if d.name.isdigit()} - before
    mine = []
    for pid in new:
        try:  # other people's processes share the machine: only those started in tmp_path count
            cwd = os.readlink(f"/proc/{pid}/cwd")
            cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if cwd == str(tmp_path) and alive(pid):
            mine.append(cmd)
    assert mine == []
