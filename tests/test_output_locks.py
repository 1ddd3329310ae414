"""One writer per output whatever the cache folder, and the temporary files a killed writer leaves.

The lock of an output is a file beside it (rrbody.model.outlock), so two processes with different
``RRBODY_CACHE_DIR`` meet there; an output's temporary sibling (``.NAME.XXXXXXXX.part.SUFFIX``, rrbody.model.io)
is written under that lock, so the next writer of the same output knows one that a killed writer left is
stale and removes it, and a writer refused because another process holds the output removes nothing.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from rrbody import _cache
from rrbody.model import outlock
from rrbody.model.io import atomic_write_text

from .clirun import RRBODY, alive, env

LINUX = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


@pytest.fixture
def holder(tmp_path: Path) -> Iterator[Callable[[Path], subprocess.Popen[str]]]:
    """Start a process that holds the lock of a path (with its own cache folder) until the test ends."""
    procs: list[subprocess.Popen[str]] = []

    def hold(path: Path) -> subprocess.Popen[str]:
        p = subprocess.Popen([sys.executable, "-c", "import sys, time; from rrbody.model.outlock import claim; "
                              "claim(sys.argv[1]); print('held', flush=True); time.sleep(300)", str(path)],
                             env={**env(), _cache.ENV: str(tmp_path / "holder-cache")}, text=True,
                             stdout=subprocess.PIPE)
        procs.append(p)
        assert p.stdout is not None and p.stdout.readline().strip() == "held"
        return p

    yield hold
    for p in procs:
        p.kill()
        p.communicate(timeout=60)


def test_two_cache_folders_meet_at_one_lock(tmp_path: Path, holder, monkeypatch: pytest.MonkeyPatch) -> None:  # noqa: ANN001
    out = tmp_path / "f.csv"
    p = holder(out)
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "my-cache"))  # another cache folder than the holder's
    with pytest.raises(outlock.OutputBusy, match=rf"being written by process {p.pid}\b"):
        outlock.claim(out, name="--out")
    with pytest.raises(outlock.OutputBusy):
        outlock.claim(tmp_path / "." / "f.csv", name="--out")  # another spelling of the same output
    assert outlock.lock_path(out) == tmp_path / ".f.csv.rrbody-lock"
    assert not (tmp_path / "my-cache").exists()  # nothing of the lock in either cache folder
    p.kill()
    p.communicate(timeout=60)
    outlock.claim(out, name="--out")  # a dead holder's lock is free
    assert (tmp_path / ".f.csv.rrbody-lock").read_text().startswith(f"process {os.getpid()} ")
    outlock.release(out)
    assert not (tmp_path / ".f.csv.rrbody-lock").exists()


def _parts(folder: Path, name: str) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(f".{name}.") and ".part" in p.name)


def test_the_next_writer_removes_a_stale_part_of_its_own_output_only(tmp_path: Path) -> None:
    stale = tmp_path / ".x.csv.k3_9zq01.part.csv"  # the name mkstemp gives a temporary sibling of x.csv
    stale.write_text("half a table")
    others = {".x.csv.notes": "the user's", ".y.csv.k3_9zq01.part.csv": "another output's", ".x.csv.k3.part.csv":
              "not a name rrbody gives", "x.csv.k3_9zq01.part.csv": "no leading dot"}
    for n, text in others.items():
        (tmp_path / n).write_text(text)
    atomic_write_text(tmp_path / "x.csv", "t\n")
    assert not stale.exists() and (tmp_path / "x.csv").read_text() == "t\n"
    assert {n: (tmp_path / n).read_text() for n in others} == others
    assert not (tmp_path / ".x.csv.rrbody-lock").exists()


def test_a_part_is_kept_while_another_process_holds_its_output(tmp_path: Path, holder) -> None:  # noqa: ANN001
    out = tmp_path / "x.csv"
    p = holder(out)
    part = tmp_path / ".x.csv.k3_9zq01.part.csv"  # the holder's, being written
    part.write_text("being written")
    with pytest.raises(outlock.OutputBusy, match=rf"process {p.pid}\b"):
        atomic_write_text(out, "t\n", force=True)
    assert part.read_text() == "being written" and not out.exists()


@LINUX
def test_a_movie_killed_mid_encoding_leaves_no_part_after_the_next_run(tmp_path: Path) -> None:
    """The fault injector's case: ``rrbody simulate --movie`` killed (with its ffmpeg) while encoding leaves its
    temporary sibling; the next run to the same movie removes it and writes the movie."""
    pytest.importorskip("imageio_ffmpeg")
    sim = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--movie", "m.mp4"]
    a = subprocess.Popen([*RRBODY, *sim, "--t-max", "120"], cwd=tmp_path, env=env(), stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 600
        while not any((tmp_path / n).stat().st_size > 0 for n in _parts(tmp_path, "m.mp4")):  # frames encoded
            assert a.poll() is None, a.communicate()
            assert time.monotonic() < deadline, "the movie never began"
            time.sleep(0.05)
        os.killpg(a.pid, signal.SIGKILL)  # the command and its ffmpeg
        a.communicate(timeout=60)
    finally:
        if a.poll() is None:
            os.killpg(a.pid, signal.SIGKILL)
            a.communicate(timeout=60)
    left = _parts(tmp_path, "m.mp4")
    assert len(left) == 1 and not (tmp_path / "m.mp4").exists()
    deadline = time.monotonic() + 60
    while any(alive(int(d.name)) for d in Path("/proc").iterdir() if d.name.isdigit()
              and _in_group(int(d.name), a.pid)):
        assert time.monotonic() < deadline, "the killed movie's processes are still running"
        time.sleep(0.05)
    r = subprocess.run([*RRBODY, *sim, "--t-max", "2"], cwd=tmp_path, env=env(), capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    assert _parts(tmp_path, "m.mp4") == [] and (tmp_path / "m.mp4").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.mp4"]


def _in_group(pid: int, pgid: int) -> bool:
    try:
        return os.getpgid(pid) == pgid
    except OSError:
        return False
