"""Issue 29, sweeps: one writer per output, faults end in one line, nothing written before refused.

- two sweeps to one output at once: the second is refused (exit 2, one line naming the first
  process), whatever --force or --resume say, and whatever cache folder each uses, and the first
  finishes with its own numbers;
- a lock left by a sweep killed with kill -9 is taken over by --resume;
- a worker killed with kill -9, a lost Dask scheduler, a full disk: one line naming what happened,
  the points saved and the exact --resume command, exit 1, no traceback, no process left;
- a malformed or unreachable --scheduler, contradictory options: exit 2 before any file exists.

Real CLI in subprocesses where processes matter (Linux /proc), in-process where a fault is injected and
for the bad inputs (:func:`tests.clirun.run_here`: the first of each test also through the real command,
which must answer the same).
"""

from __future__ import annotations

import errno
import math
import os
import shlex
import shutil
import signal
import subprocess
import sys
import time
import types
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import rrbody.analysis.sweep as sw
import rrbody.analysis.sweep_store as store
from rrbody.analysis.sweep import SweepFault, checkpoint_path, load_sweep, read_meta, run_sweep
from rrbody.analysis.sweep_spec import Sweep

from .clirun import RRBODY, alive, assert_bad_input, children, env, run_here, run_many

LINUX = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
#: a flip-time point of ~1e6 steps (about 2 s warm), and one of a few ms
SLOW_K, FAST_K = "1e-9", "0.5"
SLOW = ["--H", "0.2", "--omega", "1", "--t-max", "1e5", "--batch-size", "1"]


def small_sweep(k: float = 7.5) -> Sweep:
    """12 cheap points (~1 ms each)."""
    return Sweep(base={"H": 0.25, "k": k, "phi0": math.pi}, axes={"omega": np.geomspace(0.5, 20.0, 12)})


def _start(argv: list[str], cwd: Path, environ: dict[str, str] | None = None) -> subprocess.Popen[str]:
    return subprocess.Popen([*RRBODY, *argv], cwd=cwd, env=environ or env(), text=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)


def _wait_for(cond: Callable[[], bool], what: str, p: subprocess.Popen[str] | None = None,
              timeout: float = 240.0) -> None:
    """Poll ``cond`` (the first numba compile in a cold cache can take tens of seconds)."""
    t0 = time.monotonic()
    while not cond():
        if p is not None and p.poll() is not None:
            raise AssertionError(f"the sweep ended before {what}: {p.communicate()}")
        if time.monotonic() - t0 > timeout:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def _rows(ck: Path) -> int:
    """Complete point lines in a checkpoint."""
    return store.count_rows(ck) if ck.exists() else 0


def _one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("rrbody: warning:")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def _reap(p: subprocess.Popen[str], kids: set[int]) -> bool:
    """Stop ``p`` and its pool if still running (a failing test leaves nothing); True if all were gone."""
    gone = p.poll() is not None and not any(alive(c) for c in kids)
    for pid in [p.pid, *kids]:
        if alive(pid):
            os.kill(pid, signal.SIGKILL)
    p.communicate(timeout=60)
    return gone


def _all_gone(pids: set[int], timeout: float = 10.0) -> bool:
    t0 = time.monotonic()
    while any(alive(c) for c in pids):
        if time.monotonic() - t0 > timeout:
            return False
        time.sleep(0.05)
    return True


# ---- one writer per output -------------------------------------------------------------------
def _own_cache(folder: Path) -> dict[str, str]:
    """The environment of an rrbody whose cache folder is ``folder`` (``RRBODY_CACHE_DIR``), seeded with a
    copy of this session's kernels for these sources where it has them (nothing to compile)."""
    from rrbody import _cache

    mine = _cache.kernels_dir()
    if mine.is_dir():
        shutil.copytree(mine, folder / "kernels" / mine.name, ignore=shutil.ignore_patterns("*.tmp.*"))
    folder.mkdir(parents=True, exist_ok=True)
    return {**env(), _cache.ENV: str(folder)}


@LINUX
@pytest.mark.parametrize("caches", ["one cache", "two caches"])
def test_second_sweep_to_the_same_output_is_refused_and_the_first_finishes(tmp_path: Path, caches: str) -> None:
    """With one cache folder, or each process its own (two shells, or a scheduler that gives each job its
    own cache): B is refused while A runs, writes and removes nothing, and the table is A's grid."""
    work = tmp_path / "work"
    work.mkdir()
    env_a, env_b = ((env(), env()) if caches == "one cache" else
                    (_own_cache(tmp_path / "cache-a"), _own_cache(tmp_path / "cache-b")))
    out = work / "cx.csv"
    ck = checkpoint_path(out)
    a = _start(["sweep", *SLOW, "--axis", f"k={SLOW_K},{SLOW_K},{SLOW_K},{SLOW_K}", "--workers", "1", "--out",
                str(out), "--force"], work, env_a)  # seconds of work: B is tried while A runs
    kids: set[int] = set()
    try:
        _wait_for(ck.exists, "A's checkpoint", a)
        kids = children(a.pid)
        before = sorted(p.name for p in work.iterdir())
        other = ["sweep", "--H", "0.25", "--k", "7.5", "--axis", "omega=0.5,1", "--workers", "0", "--out", str(out)]
        rs = run_many([[*other, "--force"], [*other, "--resume"], other], cwd=work, parallel=3, environ=env_b)
        assert a.poll() is None, "A ended before B was tried: the test did not overlap the two sweeps"
        for r in rs:
            assert_bad_input(r, "--out")
            line = _one_line(r.err)
            assert f"process {a.pid}" in line and "being written" in line, line
        assert sorted(p.name for p in work.iterdir()) == before  # B wrote and removed nothing
        _, err = a.communicate(timeout=600)
        assert a.returncode == 0, err
    finally:
        _reap(a, kids)
    meta = read_meta(out)
    assert meta["spec"]["base"]["H"] == 0.2 and meta["spec"]["axes"] == {"k": [1e-9] * 4}  # A's sweep
    rows = load_sweep(out)
    assert len(rows) == 4 and all(r["error"] == "" and float(r["T1"]) > 0 for r in rows)
    assert not ck.exists() and _all_gone(kids)
    assert sorted(p.name for p in work.iterdir()) == ["cx.csv", "cx.csv.json"]  # no lock file left beside it


@LINUX
def test_lock_of_a_killed_sweep_is_taken_over_by_resume(tmp_path: Path) -> None:
    out = tmp_path / "k.csv"
    ck = checkpoint_path(out)
    argv = ["sweep", *SLOW, "--axis", f"k={SLOW_K},{FAST_K}", "--workers", "1", "--out", str(out)]
    a = _start(argv, tmp_path)
    kids: set[int] = set()
    try:
        _wait_for(ck.exists, "the checkpoint", a)
        kids = children(a.pid)
        os.kill(a.pid, signal.SIGKILL)
        a.wait(timeout=60)
        # at once, without waiting for the pool: a forked worker must not keep its parent's lock
        (r,) = run_many([[*argv, "--resume"]], cwd=tmp_path)
        assert r.code == 0, r.err
    finally:
        _reap(a, kids)
    assert [float(x["k"]) for x in load_sweep(out)] == [1e-9, 0.5] and not ck.exists()
    assert _all_gone(kids)


def test_python_api_refuses_an_output_another_process_writes(tmp_path: Path) -> None:
    """run_sweep and run_fresh_or_resume: refused whatever the flags, nothing written; free once the holder is gone."""
    out = tmp_path / "s.csv"
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from rrbody.model.outlock import claim; "
                               "claim(sys.argv[1]); print('held', flush=True); time.sleep(120)", str(out)],
                              env=env(), text=True, stdout=subprocess.PIPE)
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        before = sorted(tmp_path.iterdir())  # the holder's lock file, beside the output
        for kw in ({}, {"force": True}, {"resume": True}):
            with pytest.raises(ValueError, match=rf"being written by process {holder.pid}\b"):
                run_sweep(small_sweep(), out, workers=0, progress=False, **kw)  # type: ignore[arg-type]
        with pytest.raises(ValueError, match=f"process {holder.pid}"):
            sw.run_fresh_or_resume(small_sweep(), out)
        assert sorted(tmp_path.iterdir()) == before
    finally:
        holder.kill()
        holder.communicate(timeout=60)
    run_sweep(small_sweep(), out, workers=0, progress=False)  # the dead holder's lock is free
    assert len(load_sweep(out)) == 12


# ---- faults end in one line --------------------------------------------------------------------
@LINUX
def test_killed_worker_is_one_line_with_the_resume_command(tmp_path: Path) -> None:
    out = tmp_path / "w.csv"
    ck = checkpoint_path(out)
    argv = ["sweep", *SLOW, "--axis", f"k={FAST_K},{SLOW_K},{SLOW_K},{SLOW_K}", "--workers", "2", "--out", "w.csv",
            "--force"]
    a = _start(argv, tmp_path)
    kids: set[int] = set()
    try:
        _wait_for(lambda: _rows(ck) >= 1, "the first point", a)  # the fast point is saved; the slow ones run
        kids = children(a.pid)
        assert len(kids) == 2, kids
        os.kill(min(kids), signal.SIGKILL)  # what the out-of-memory killer does
        _, err = a.communicate(timeout=120)
    finally:
        gone = _reap(a, kids)
    assert gone, "a process was left behind"
    assert a.returncode == 1, err
    line = _one_line(err)
    saved = _rows(ck)
    assert saved >= 1 and not out.exists()
    assert line.startswith("rrbody sweep: error: a worker process died (killed by signal 9 (SIGKILL)); "), line
    assert f"; {saved} of 4 points are saved in 'w.csv.checkpoint.jsonl'; finish with: rrbody sweep " in line, line
    # the command printed is this sweep's, with --resume for --force
    from rrbody.cli.args import parse
    from rrbody.cli.main import build_parser

    words = shlex.split(line.split("finish with: ", 1)[1])
    assert words[:2] == ["rrbody", "sweep"] and "--force" not in words
    new, old = parse(build_parser(), words[1:]), parse(build_parser(), argv)
    assert new.resume and not new.force
    for k in ("H", "omega", "t_max", "batch_size", "axis", "workers", "out", "k", "phi0", "d", "accuracy"):
        assert repr(getattr(new, k)) == repr(getattr(old, k)), k


def _die(spec: dict, batch: list[int]) -> list[dict]:
    """A batch whose worker process ends at once (module level, so that the pool can call it)."""
    os._exit(3)


def test_dead_worker_of_the_local_pool_is_named() -> None:
    from rrbody.analysis.pool import ExecutorFault, iter_local

    with pytest.raises(ExecutorFault, match=r"^a worker process died \(exited with status 3\)$"):
        list(iter_local(_die, {}, [[0], [1]], 1))


def _full_disk_after(n_ok: int) -> types.ModuleType:
    """``os`` whose ``write`` stores ``n_ok`` writes, then half of one, then fails with ENOSPC."""
    calls = [0]
    fake = types.ModuleType("os")
    fake.__dict__.update(os.__dict__)

    def write(fd: int, data: bytes) -> int:
        calls[0] += 1
        if calls[0] <= n_ok:
            return os.write(fd, data)
        if calls[0] == n_ok + 1:
            return os.write(fd, data[: len(data) // 2])  # a short write: the disk filled up mid-line
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    fake.write = write  # type: ignore[attr-defined]
    return fake


def test_full_disk_on_the_checkpoint_then_resume(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    ref = run_sweep(small_sweep(), tmp_path / "ref.csv", workers=0, progress=False)
    out = tmp_path / "s.csv"
    ck = checkpoint_path(out)
    monkeypatch.setattr(store, "os", _full_disk_after(1))
    with pytest.raises(SweepFault) as e:
        run_sweep(small_sweep(), out, workers=0, batch_size=3, progress=False)
    monkeypatch.undo()
    assert e.value.what == f"No space left on device: {str(ck)!r}"
    # batch 1 is saved; batch 2 half written (one whole line and a cut one, which does not count)
    assert e.value.done == 4 == _rows(ck) and e.value.total == 12 and not ck.read_text().endswith("\n")
    assert "4 of 12 points are saved" in str(e.value) and "resume=True" in str(e.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ref.csv", "ref.csv.json", ck.name]
    run_sweep(small_sweep(), out, workers=0, resume=True, progress=False)
    assert out.read_text() == ref.read_text()


def test_full_disk_on_the_output_is_one_line_and_its_command_finishes(tmp_path: Path, cli,  # type: ignore[no-untyped-def]
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    argv = ["sweep", "--H", "0.25", "--k", "7.5", "--axis", "omega=0.5:2:4", "--phi-dot0=-1", "--workers", "0",
            "--out", str(tmp_path / "o.csv")]
    assert cli(*argv[:-1], str(tmp_path / "ref.csv")).code == 0

    def full(sweep: Sweep, done: dict, out: Path, *, force: bool) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(out))

    monkeypatch.setattr(sw, "write_output", full)
    r = cli(*argv)
    monkeypatch.undo()
    assert r.code == 1 and r.out == "", r.err
    line = _one_line(r.err)
    ck = checkpoint_path(tmp_path / "o.csv")
    assert line.startswith(f"rrbody sweep: error: No space left on device: {str(tmp_path / 'o.csv')!r}; 4 of 4 "
                           f"points are saved in {str(ck)!r}; finish with: rrbody sweep "), line
    words = shlex.split(line.split("finish with: ", 1)[1])
    assert "--phi-dot0=-1.0" in words and words[-1] == "--resume"
    r = cli(*words[1:])  # the printed command, as a user would paste it
    assert r.code == 0, r.err
    assert (tmp_path / "o.csv").read_text() == (tmp_path / "ref.csv").read_text() and not ck.exists()


_CLUSTER = """
import sys, time
from distributed import LocalCluster
c = LocalCluster(processes=False, protocol="tcp", n_workers=1, threads_per_worker=1, dashboard_address=None)
print(c.scheduler_address, flush=True)
time.sleep(300)
"""


@LINUX
def test_lost_dask_scheduler_is_one_line(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    cluster = subprocess.Popen([sys.executable, "-c", _CLUSTER], env=env(), text=True, stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, start_new_session=True)
    a: subprocess.Popen[str] | None = None
    try:
        assert cluster.stdout is not None
        address = cluster.stdout.readline().strip()
        assert address.startswith("tcp://"), address
        out = tmp_path / "d.csv"
        ks = ",".join([FAST_K] + [SLOW_K] * 4)  # after the first point, seconds of work remain
        a = _start(["sweep", *SLOW, "--axis", f"k={ks}", "--scheduler", address, "--out", "d.csv"], tmp_path)
        _wait_for(lambda: _rows(checkpoint_path(out)) >= 1, "the first point", a)
        os.kill(cluster.pid, signal.SIGKILL)
        _, err = a.communicate(timeout=120)
        assert a.returncode == 1, err
        line = _one_line(err)
        assert line.startswith(f"rrbody sweep: error: lost the Dask scheduler at {address} "), line
        saved = _rows(checkpoint_path(out))
        assert f"; {saved} of 5 points are saved in 'd.csv.checkpoint.jsonl'; finish with: rrbody sweep " in line, line
        assert f"--scheduler {address}" in line and line.endswith(" --resume"), line
        assert not out.exists()
    finally:
        for p in (cluster, a):
            if p is not None and p.poll() is None:
                p.kill()
            if p is not None:
                p.communicate(timeout=60)


# ---- validated before anything is written -----------------------------------------------------
def test_bad_or_unreachable_scheduler_writes_nothing(tmp_path: Path) -> None:
    base = ["sweep", "--H", "0.25", "--k", "7.5", "--axis", "omega=0.5,1", "--out", str(tmp_path / "s.csv")]
    bad = ["foo", "tcp://host", "tcp://127.0.0.1:99999", "http://127.0.0.1:8786", "tcp://127.0.0.1:1",
           "tcp://nowhere.invalid:8786", ""]
    rs = run_here([[*base, "--scheduler", b] for b in bad], cwd=tmp_path)
    for r in rs:
        assert_bad_input(r, "--scheduler", tmp_path, set())  # no checkpoint left to block the next sweep
    (r,) = run_here([[*base, "--workers", "0"]], cwd=tmp_path, real=0)  # a plain sweep to that path works
    assert r.code == 0, r.err
    assert len(load_sweep(tmp_path / "s.csv")) == 2


def test_python_api_checks_the_scheduler_before_any_file(tmp_path: Path) -> None:
    for bad, match in (("tcp://127.0.0.1", "scheduler must be"), (8786, "scheduler must be"),
                       ("tcp://127.0.0.1:1", "no Dask scheduler answers")):
        with pytest.raises(ValueError, match=match):
            run_sweep(small_sweep(), tmp_path / "s.csv", scheduler=bad, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_contradictory_options_name_both(tmp_path: Path) -> None:
    out = ["--out", str(tmp_path / "s.csv"), "--workers", "0"]
    rod = ["sweep", "--H", "0.2", "--k", "0.05"]
    cases = [
        ([*rod, "--omega", "0.6", "--axis", "omega=0.6,0.7", *out], ("--omega", "--axis omega")),
        ([*rod, "--omega", "0.6", "--phi0", "pi", "--axis", "phi0=1,2", *out], ("--phi0", "--axis phi0")),
        (["sweep", "--k", "0.05", "--omega", "0.6", "--H", "0.2", "--axis", "H=0.2,0.3", *out], ("--H", "--axis H")),
        ([*rod, "--omega", "0.6", "--axis", "phi_dot0=1,2", "--phi-dot0", "1", *out], ("--phi-dot0",
                                                                                       "--axis phi_dot0")),
        ([*rod, "--axis", "omega=0.6,0.7", "--resume", "--force", *out], ("--resume", "--force")),
    ]
    for r, (_, names) in zip(run_here([a for a, _ in cases], cwd=tmp_path), cases):
        assert_bad_input(r, names[0], tmp_path, set())
        assert names[1] in r.err and "contradict" in r.err, r.err
    # an axis over an option left at its default is no contradiction
    (r,) = run_here([[*rod, "--omega", "0.6", "--axis", "phi0=1,2", *out]], cwd=tmp_path, real=0)
    assert r.code == 0, r.err


def test_python_api_refuses_contradictions(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="base and axes both give omega"):
        Sweep(base={"H": 0.2, "k": 1.0, "omega": 0.6}, axes={"omega": [1.0]})
    with pytest.raises(ValueError, match="resume and force contradict"):
        run_sweep(small_sweep(), tmp_path / "s.csv", resume=True, force=True, workers=0, progress=False)
    assert list(tmp_path.iterdir()) == []
