"""The warm worker (rrbody.worker): a forwarded call behaves exactly like a plain run.

Each test runs the real console command in subprocesses, against a worker in a private folder.
What is checked: identical output and exit codes with and without the worker, that the call
really went through the worker (its request counter), relative paths and signals, automatic
start after a plain run, refusal of unsafe folders, stale sockets, idle exit, bad settings.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from rrbody import worker

pytestmark = pytest.mark.skipif(not worker._supported(), reason="needs Unix sockets with SCM_RIGHTS")

RRBODY = [sys.executable, "-m", "rrbody.cli"]
FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "pi", "--json"]
#: a run long enough to interrupt (frictionless, 1e7 s: ~3 min) that writes nothing before it ends
LONG = ["simulate", "--H", "0.2", "--friction", "none", "--k", "0", "--omega", "0.6", "--t-max", "1e7",
        "--dt-out", "1000", "--out", "long.csv"]


def _env(folder: Path, **extra: str) -> dict[str, str]:
    env = dict(os.environ, RRBODY_WORKER="on", RRBODY_WORKER_DIR=str(folder), RRBODY_WORKER_IDLE="120")
    env.update(extra)
    return env


def _run(argv: list[str], env: dict[str, str], cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(RRBODY + argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=300)


def _settings(env: dict[str, str]) -> worker.WorkerSettings:
    s = worker.settings(env)
    assert s is not None
    return s


def _wait_for(pred, timeout: float = 120.0) -> bool:  # noqa: ANN001
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.05)
    return False


def _children(pid: int) -> list[int]:
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(entry))
    return out


@pytest.fixture(scope="module")
def folder() -> Iterator[Path]:
    # short path on purpose: AF_UNIX socket paths are limited to ~100 bytes
    path = Path(tempfile.mkdtemp(prefix="rrw"))
    yield path
    for sock in path.glob("*/*.sock"):  # any worker a failed test left running
        worker.stop(worker.WorkerSettings(sock.parent, sock.stem, worker.DEFAULT_IDLE_S))
    shutil.rmtree(path, ignore_errors=True)


@pytest.fixture(scope="module")
def running(folder: Path) -> dict[str, str]:
    """Environment of callers served by one worker, started with `rrbody worker start`."""
    env = _env(folder / "main")
    p = _run(["worker", "start", "--json"], env)
    assert p.returncode == 0, p.stderr
    info = json.loads(p.stdout)
    assert info["running"] and info["pid"] > 0
    return env


def _info(s: worker.WorkerSettings) -> dict[str, Any]:
    info = worker.ping(s)
    assert info is not None, "the worker is not running"
    return info


def _served(env: dict[str, str]) -> int:
    return int(_info(_settings(env))["served"])


def test_forwarded_flip_time_equals_plain_run(running: dict[str, str]) -> None:
    before = _served(running)
    fast = _run(FLIP, running)
    assert _served(running) == before + 1  # it really went through the worker
    plain = _run(FLIP, dict(running, RRBODY_WORKER="off"))
    assert fast.returncode == plain.returncode == 0, fast.stderr + plain.stderr
    a, b = json.loads(fast.stdout), json.loads(plain.stdout)
    a.pop("wall_s"), b.pop("wall_s")
    assert a == b  # the same code on the same input: identical to the last bit


@pytest.mark.parametrize("argv, needle", [
    (["flip-time", "--H", "-1", "--k", "0.05", "--omega", "0.6"], "--H must lie in (0, 1e+06]"),
    (["critical-h", "--k", "0.01", "--omega", "0.3", "--bogus"], "unrecognized arguments: --bogus"),
])
def test_forwarded_bad_input_exit_2(running: dict[str, str], argv: list[str], needle: str) -> None:
    before = _served(running)
    p = _run(argv, running)
    assert _served(running) == before + 1
    assert p.returncode == 2 and needle in p.stderr and "Traceback" not in p.stderr and p.stdout == ""


def test_forwarded_paths_are_the_callers(running: dict[str, str], tmp_path: Path) -> None:
    argv = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "3", "--out", "a.csv"]
    p = _run(argv, running, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    q = _run(argv[:-1] + ["b.csv"], dict(running, RRBODY_WORKER="off"), cwd=tmp_path)
    assert q.returncode == 0, q.stderr
    # same samples; the first line (JSON metadata) differs only in the measured wall time
    assert (tmp_path / "a.csv").read_text().splitlines()[1:] == (tmp_path / "b.csv").read_text().splitlines()[1:]
    again = _run(argv, running, cwd=tmp_path)  # no clobbering without --force, as in a plain run
    assert again.returncode == 2 and "already exists" in again.stderr


def _start_long(env: dict[str, str], cwd: Path) -> subprocess.Popen[str]:
    before = _served(env)
    proc = subprocess.Popen(RRBODY + LONG, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    assert _wait_for(lambda: _served(env) == before + 1, 60.0)
    return proc


def test_ctrl_c_reaches_the_run(running: dict[str, str], tmp_path: Path) -> None:
    proc = _start_long(running, tmp_path)
    time.sleep(0.3)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "interrupted" in err
    assert list(tmp_path.iterdir()) == []  # no partial output
    pid = _info(_settings(running))["pid"]
    assert _wait_for(lambda: _children(pid) == [], 10.0)


def test_sigterm_and_vanished_caller(running: dict[str, str], tmp_path: Path) -> None:
    pid = _info(_settings(running))["pid"]
    proc = _start_long(running, tmp_path)
    proc.send_signal(signal.SIGTERM)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGTERM  # dies of the signal, like a plain run
    assert _wait_for(lambda: _children(pid) == [], 10.0)
    proc = _start_long(running, tmp_path)
    proc.kill()  # SIGKILL cannot be relayed: the run notices the closed connection instead
    proc.communicate(timeout=60)
    assert _wait_for(lambda: _children(pid) == [], 10.0)
    assert list(tmp_path.iterdir()) == []


def test_first_plain_run_starts_a_worker_and_stale_socket_is_ignored(folder: Path) -> None:
    env = _env(folder / "auto", RRBODY_WORKER_IDLE="60")
    s = _settings(env)
    stale = socket.socket(socket.AF_UNIX)
    stale.bind(str(s.socket))  # a socket file nobody listens on, as after a crash
    stale.close()
    p = _run(FLIP, env)
    assert p.returncode == 0 and json.loads(p.stdout)["reverse_rotation"] is True
    assert _wait_for(lambda: worker.ping(s) is not None)
    assert _info(s)["served"] == 0
    assert _run(FLIP, env).stdout.split('"wall_s"')[0] == p.stdout.split('"wall_s"')[0]
    assert _info(s)["served"] == 1
    assert worker.stop(s) and worker.ping(s) is None
    assert not s.socket.exists()


def test_idle_worker_exits_and_cleans_up(folder: Path) -> None:
    env = _env(folder / "idle", RRBODY_WORKER_IDLE="0.5")
    s = _settings(env)
    p = _run(["worker", "start", "--json"], env)
    assert p.returncode == 0, p.stderr
    assert _wait_for(lambda: not s.socket.exists(), 30.0)
    assert not worker._starting(s)  # its lock is released too
    status = json.loads(_run(["worker", "status", "--json"], env).stdout)
    assert status["running"] is False and status["enabled"] is True


def test_off_and_unsafe_folder_run_in_process(folder: Path, tmp_path: Path) -> None:
    off = _env(folder / "off", RRBODY_WORKER="off")
    assert worker.settings(off) is None
    assert _run(FLIP, off).returncode == 0
    assert not (folder / "off").exists()
    shared = folder / "shared"
    shared.mkdir(mode=0o777)
    shared.chmod(0o777)  # another user could plant a socket here: never used
    env = _env(shared)
    assert worker.settings(env) is None
    assert _run(FLIP, env).returncode == 0
    assert list(shared.iterdir()) == []


@pytest.mark.parametrize("var, value, needle", [
    ("RRBODY_WORKER", "maybe", "RRBODY_WORKER must be 'on' or 'off'"),
    ("RRBODY_WORKER_IDLE", "-5", "RRBODY_WORKER_IDLE must be seconds in (0, 604800]"),
    ("RRBODY_WORKER_IDLE", "soon", "got 'soon'"),
])
def test_bad_settings_exit_2(folder: Path, var: str, value: str, needle: str) -> None:
    env = _env(folder / "bad", **{var: value})
    with pytest.raises(ValueError, match=var):
        worker.settings(env)
    p = _run(FLIP, env)
    assert p.returncode == 2 and needle in p.stderr and "Traceback" not in p.stderr


def test_fingerprint_follows_sources_and_import_time_env(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "mod.py").write_text("x = 1\n")
    monkeypatch.setattr(worker, "_PACKAGE_DIR", tmp_path)
    base = worker.fingerprint({"HOME": "/a"})
    assert worker.fingerprint({"HOME": "/b", "PWD": "/c"}) == base  # unrelated variables: same worker
    assert worker.fingerprint({"NUMBA_DISABLE_JIT": "1"}) != base
    assert worker.fingerprint({"PYTHONPATH": "/x"}) != base
    st = (tmp_path / "mod.py").stat()
    os.utime(tmp_path / "mod.py", ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))
    assert worker.fingerprint({"HOME": "/a"}) != base  # edited sources: a new worker


def test_worker_command_start_status_stop(folder: Path) -> None:
    env = _env(folder / "cmd")
    assert _run(["worker", "status"], env).stdout.startswith("no worker running")
    assert _run(["worker", "start"], env).stdout.startswith("worker running: pid ")
    assert _run(["worker", "status"], env).stdout.startswith("worker running: pid ")
    stopped = _run(["worker", "stop", "--json"], env)
    assert stopped.returncode == 0 and json.loads(stopped.stdout) == {
        "running": False, "enabled": True, "stopped": True, "log": str(_settings(env).log)}
    assert _run(["worker", "stop"], env).stdout.startswith("no worker running")
    off = _run(["worker", "start"], dict(env, RRBODY_WORKER="off"))
    assert off.returncode == 2 and "RRBODY_WORKER is 'off'" in off.stderr and "Traceback" not in off.stderr
    assert _run(["worker", "status"], dict(env, RRBODY_WORKER="off")).stdout.startswith("worker off")
