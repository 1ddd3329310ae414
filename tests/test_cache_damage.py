"""A damaged or foreign file in rrbody's cache folder never ends a command in a traceback.

Every kind of file the folder holds (rrbody._cache, docs/compile.md): numba's index (``.nbi``) and data
(``.nbc``) files of a kernel, the kernel folder's ``BUILD.json``, the quadrature tables
(``tables/*.npz``) and the plugin's wrench tables (``kernels/<version>-<hash>/tables/*.npz``), each
truncated, overwritten with garbage, replaced by a folder, made unreadable (not as root, who reads
anything) or, for the tables, replaced by another table's file. The real command (``python -m
rrbody.cli``, with ``RRBODY_CACHE_DIR`` set to a copy of a filled cache) then succeeds with the answer
of the undamaged cache, and the file is rebuilt: the next run loads it. A damaged file that cannot even
be removed ends the command with one line naming it and ``rrbody cache clear``, exit status 1.

The output locks live beside the outputs (rrbody.model.outlock), not in the cache folder: a lock a killed
writer left is taken over, and a file in a lock's place that rrbody did not write is never replaced (one
line naming it, exit 2). ``rrbody cache clear`` removes what rrbody wrote in the cache folder and nothing
else, says what it removed and what it kept, and a path it cannot remove is one line naming it, exit 1.
"""

from __future__ import annotations

import json
import os
import random
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rrbody import _cache

RRBODY = [sys.executable, "-m", "rrbody.cli"]
FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--phi0", "pi", "--json"]
#: a box of disks and L-shapes: the disks read the disk's wrench table from the kernel folder
ACTIVE = ["active", "--n", "6", "--packing", "0.3", "--t-end", "0.2", "--seed", "1", "--json"]
SIMULATE = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1", "--out", "x.csv"]
ROOT = Path(__file__).resolve().parents[1]
DAMAGES = ("truncated", "garbage", "folder", "unreadable")


def _run(cache: Path, argv: list[str], *, cwd: Path, debug: bool = False,
         prelude: str = "") -> subprocess.CompletedProcess[str]:
    """``rrbody ARGV`` in a subprocess on the cache folder ``cache`` (numba's cache log on stdout with
    ``debug``; ``prelude``: Python run before the command, to inject a failure)."""
    env = dict(os.environ, **{_cache.ENV: str(cache), "MPLBACKEND": "Agg"})
    env.pop("NUMBA_DEBUG_CACHE", None)
    if debug:
        env["NUMBA_DEBUG_CACHE"] = "1"
    env["PYTHONPATH"] = str(ROOT) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    code = f"import sys\n{prelude}\nfrom rrbody.cli.main import entry\nsys.exit(entry(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *argv], env=env, cwd=cwd, capture_output=True, text=True,
                          timeout=1800)


def _answer(r: subprocess.CompletedProcess[str]) -> dict:
    """The command's JSON (numba's cache log lines left out), without what is timing."""
    d = json.loads("\n".join(ln for ln in r.stdout.splitlines() if not ln.startswith("[cache]")))
    return {k: v for k, v in d.items() if "wall" not in k and "time_s" not in k}


def _loaded(r: subprocess.CompletedProcess[str], what: str) -> list[Path]:
    """The files numba's cache log says it loaded (``what``: "index" or "data")."""
    return [Path(ln.split(" from ", 1)[1].strip().strip("'\"")) for ln in r.stdout.splitlines()
            if ln.startswith(f"[cache] {what} loaded from")]


@pytest.fixture(scope="module")
def filled(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """A cache folder the three commands have run on (from a copy of this session's kernels for these
    sources, if it has them: else compiled here), their answers, and for FLIP the smallest function it
    loads from the cache (index and data file: the quickest to compile again)."""
    root = tmp_path_factory.mktemp("filled")
    cache, work = root / "cache", root / "work"
    work.mkdir()
    mine = _cache.kernels_dir()
    if mine.is_dir():
        shutil.copytree(mine, cache / "kernels" / mine.name, ignore=shutil.ignore_patterns("*.tmp.*", "tables"))
    answers = {}
    for name, argv in (("flip", FLIP), ("active", ACTIVE), ("simulate", SIMULATE)):
        r = _run(cache, argv, cwd=work)
        assert r.returncode == 0, r.stderr
        answers[name] = _answer(r) if name != "simulate" else (work / "x.csv").read_text()
    r = _run(cache, FLIP, cwd=work, debug=True)
    assert "data saved" not in r.stdout  # everything it needs is in the cache now
    data = min(_loaded(r, "data"), key=lambda p: p.stat().st_size)
    base = data.name.split(".")[0]
    index = next(p for p in _loaded(r, "index") if p.name.split(".")[0] == base and p.parent == data.parent)
    return {"cache": cache, "answers": answers, "nbi": index, "nbc": data}


def _copy(filled: dict, tmp_path: Path) -> tuple[Path, Path]:
    cache, work = tmp_path / "cache", tmp_path / "work"
    shutil.copytree(filled["cache"], cache)
    work.mkdir()
    return cache, work


def _damage(path: Path, how: str) -> None:
    if how == "unreadable" and os.geteuid() == 0:
        pytest.skip("root reads a file whatever its permissions")
    data = path.read_bytes()
    if how == "truncated":
        path.write_bytes(data[:len(data) // 2])
    elif how == "garbage":
        path.write_bytes(random.Random(7).randbytes(max(len(data), 64)))
    elif how == "folder":
        path.unlink()
        path.mkdir()
        (path / "inside").write_text("a folder with a file in it, where the cache file was")
    elif how == "unreadable":
        path.chmod(0)
    else:  # another table's file in this one's place: a well-formed table that names another place
        shutil.copyfile(how, path)


def _clean(r: subprocess.CompletedProcess[str]) -> None:
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr and "error" not in r.stderr.lower(), r.stderr


@pytest.mark.parametrize("kind", ["nbi", "nbc"])
@pytest.mark.parametrize("how", DAMAGES)
def test_a_damaged_kernel_file_is_compiled_again(filled: dict, tmp_path: Path, kind: str, how: str) -> None:
    cache, work = _copy(filled, tmp_path)
    target = cache / filled[kind].relative_to(filled["cache"])
    _damage(target, how)
    r = _run(cache, FLIP, cwd=work)
    _clean(r)
    assert _answer(r) == filled["answers"]["flip"]
    again = _run(cache, FLIP, cwd=work, debug=True)  # rebuilt: the next run loads it and saves nothing
    _clean(again)
    assert target.is_file() and "data saved" not in again.stdout
    assert cache / filled["nbi"].relative_to(filled["cache"]) in _loaded(again, "index")


@pytest.mark.parametrize("how", ["truncated", "garbage", "folder"])
def test_a_damaged_build_file_changes_nothing(filled: dict, tmp_path: Path, how: str) -> None:
    """``BUILD.json`` marks a kernel folder an install compiled as complete; only its presence is read."""
    cache, work = _copy(filled, tmp_path)
    build = cache / "kernels" / _cache.kernels_dir().name / _cache.BUILD_FILE
    build.write_text(json.dumps({"numba": "0.0.0", "python": "3", "machine": "x"}))
    _damage(build, how)
    r = _run(cache, FLIP, cwd=work)
    _clean(r)
    assert _answer(r) == filled["answers"]["flip"]


def _tables(cache: Path) -> tuple[Path, Path]:
    """The quadrature table FLIP reads and the wrench table ACTIVE's disks read."""
    (quad,) = (cache / "tables").glob("icr_tables-*.npz")
    wrench = sorted((cache / "kernels" / _cache.kernels_dir().name / "tables").glob("*.npz"))[0]
    return quad, wrench


@pytest.mark.parametrize("which", ["quadrature", "wrench"])
@pytest.mark.parametrize("how", [*DAMAGES, "foreign"])
def test_a_damaged_table_is_built_again(filled: dict, tmp_path: Path, which: str, how: str) -> None:
    cache, work = _copy(filled, tmp_path)
    quad, wrench = _tables(cache)
    target, other = (quad, wrench) if which == "quadrature" else (wrench, quad)
    _damage(target, str(other) if how == "foreign" else how)
    name, argv = ("flip", FLIP) if which == "quadrature" else ("active", ACTIVE)
    r = _run(cache, argv, cwd=work)
    _clean(r)
    assert _answer(r) == filled["answers"][name]
    with np.load(target, allow_pickle=False) as z:  # rebuilt and stored again, naming its own place
        assert str(z["stamp"][()]) == target.relative_to(cache).as_posix()


def _lock(work: Path) -> Path:
    from rrbody.model import outlock

    return outlock.lock_path(work / "x.csv")


@pytest.mark.parametrize("left", ["", "process 1 (rrbody simulate ...)\n", "proc"])
def test_a_lock_file_a_killed_writer_left_is_taken_over(filled: dict, tmp_path: Path, left: str) -> None:
    """Empty (killed while claiming), whole, or cut short: the next writer takes it and removes it."""
    cache, work = _copy(filled, tmp_path)
    _lock(work).write_text(left)
    r = _run(cache, SIMULATE, cwd=work)
    _clean(r)
    assert (work / "x.csv").read_text() == filled["answers"]["simulate"]
    assert sorted(p.name for p in work.iterdir()) == ["x.csv"]


@pytest.mark.parametrize("how", ["garbage", "folder", "link"])
def test_a_file_in_a_locks_place_that_rrbody_did_not_write_is_left_alone(filled: dict, tmp_path: Path,
                                                                         how: str) -> None:
    """It may be the user's: one line naming it, exit 2, nothing written, and it is as it was."""
    cache, work = _copy(filled, tmp_path)
    lock = _lock(work)
    if how == "link":
        (work / "target").write_text("the user's notes\n")
        lock.symlink_to(work / "target")
    else:
        lock.write_text("the user's notes\n")
        _damage(lock, how)
    before = {p.name: (p.read_bytes() if p.is_file() else None) for p in work.iterdir()}
    r = _run(cache, SIMULATE, cwd=work)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and str(lock) in lines[0] and "--out" in lines[0], r.stderr
    assert {p.name: (p.read_bytes() if p.is_file() else None) for p in work.iterdir()} == before


def test_a_damaged_file_that_cannot_be_removed_is_one_line_and_exit_1(filled: dict, tmp_path: Path) -> None:
    """A folder in a table's place that cannot be removed (a removal that fails, injected: as root
    nothing here resists it): one line naming it and ``rrbody cache clear``, exit 1, nothing written."""
    cache, work = _copy(filled, tmp_path)
    quad, _ = _tables(cache)
    quad.unlink()
    quad.mkdir()
    (quad / "inside").write_text("x")
    fail = "import shutil\ndef _no(*a, **k): raise PermissionError(13, 'Permission denied')\nshutil.rmtree = _no"
    r = _run(cache, FLIP, cwd=work, prelude=fail)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 1 and len(lines) == 1, r.stderr
    assert str(quad) in lines[0] and "rrbody cache clear" in lines[0] and "Traceback" not in r.stderr
    assert r.stdout == "" and list(work.iterdir()) == []


def _layout(cache: Path, monkeypatch: pytest.MonkeyPatch, *, others: bool = True) -> tuple[list[Path], list[Path]]:
    """A cache folder with what rrbody writes there, made by rrbody's own functions or in their names
    (kernels of these sources and of another version, a quadrature table, an earlier version's output
    lock), and what it never writes (a file beside them, a file in each of its folders, another
    program's folder; none without ``others``). Returns (rrbody's, the others)."""
    monkeypatch.setenv(_cache.ENV, str(cache))
    kernels = _cache.kernels_dir()
    (kernels / "physics").mkdir(parents=True)
    (kernels / "physics" / "wrench.f-12.py311.nbi").write_bytes(b"\x00" * 1000)
    old = kernels.parent / ("0.0.1-" + "0123456789abcdef")
    old.mkdir()
    (old / _cache.BUILD_FILE).write_text("{}")
    table = _cache.tables_dir() / "icr_tables-test.npz"
    _cache.stored_arrays(table, lambda: (np.arange(1000.0),))
    lock = _cache.locks_dir() / ("ab" * 16 + ".lock")
    lock.parent.mkdir()
    lock.write_text("process 1 (x)\n")
    foreign = [cache / "notes.txt", kernels.parent / "README", _cache.tables_dir() / "mine.csv",
               _cache.locks_dir() / "keep.txt", cache / "other" / "data.bin"] if others else []
    for f in foreign:
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text("not rrbody's")
    return [kernels, old, table, lock], foreign


def test_cache_clear_removes_only_what_rrbody_wrote(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A cache folder pointed at a shared one (``RRBODY_CACHE_DIR=~/.cache``): rrbody's kernels, tables and
    free lock files go, the rest stays, and the command says both; an earlier version's lock file that a
    process holds stays too."""
    import fcntl

    cache = tmp_path / "cache"
    ours, foreign = _layout(cache, monkeypatch)
    held = _cache.locks_dir() / ("cd" * 16 + ".lock")
    held.write_text("process 2 (y)\n")
    size = sum(f.stat().st_size for p in ours for f in ([p] if p.is_file() else p.rglob("*")) if f.is_file())
    with open(held) as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        r = _run(cache, ["cache", "clear"], cwd=tmp_path)
        again = _run(cache, ["cache", "clear", "--json"], cwd=tmp_path)
    _clean(r)
    assert not any(os.path.lexists(p) for p in ours)
    assert all(f.read_text() == "not rrbody's" for f in foreign) and held.is_file()
    line = r.stdout.strip()
    assert line.startswith(f"cleared {cache}: removed kernels/ (2 entries), locks/ (1 entry), tables/ (1 entry) "
                           f"({size / 1e6:.1f} MB freed)"), line
    assert "kept what rrbody did not write" in line and "notes.txt" in line, line
    _clean(again)
    rep = json.loads(again.stdout)
    assert rep["removed"] == [] and rep["freed_bytes"] == 0 and rep["failed"] == []
    assert f"locks/{held.name} (a lock in use)" in rep["kept"] and "notes.txt" in rep["kept"]


#: a file system that refuses every removal (EROFS), for a run as root, whom permissions do not stop
_READ_ONLY = """import errno, os
def _refused(path, *a, **k):
    raise OSError(errno.EROFS, "Read-only file system", path)
os.unlink = os.remove = os.rmdir = _refused"""


def test_cache_clear_that_cannot_remove_says_so(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A read-only cache folder of rrbody's files only (made so with permissions; as root, who removes
    anyway, by a refusal injected into every removal): one line naming a path it could not remove, exit 1,
    no "cleared"."""
    cache = tmp_path / "cache"
    ours, foreign = _layout(cache, monkeypatch, others=False)
    folders = [d for d in [cache, *cache.rglob("*")] if d.is_dir()]
    prelude = _READ_ONLY if os.geteuid() == 0 else ""
    try:
        if not prelude:
            for d in folders:
                d.chmod(0o555)
        r = _run(cache, ["cache", "clear"], cwd=tmp_path, prelude=prelude)
    finally:
        for d in folders:
            d.chmod(0o755)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 1 and len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    assert lines[0].startswith(f"rrbody cache: error: could not remove {cache}/"), lines[0]
    assert "cleared" not in r.stdout and "removed 0 of rrbody's entries (0.0 MB freed)" in lines[0], lines[0]
    assert all(os.path.lexists(p) for p in [*ours, *foreign])


def test_other_programs_numba_caches_keep_numbas_behaviour(tmp_path: Path) -> None:
    """rrbody treats only its own kernels' damaged files as misses: a function of another program, with
    rrbody imported, still meets numba's own error on a truncated index."""
    (tmp_path / "userfn.py").write_text("from numba import njit\n\n@njit(cache=True)\ndef f(x):\n    return x + 1\n")
    code = "import rrbody.physics, userfn; print(userfn.f(1))"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), str(ROOT)]), NUMBA_CACHE_DIR=str(tmp_path / "nb"))
    first = subprocess.run([sys.executable, "-c", code], env=env, cwd=tmp_path, capture_output=True, text=True,
                           timeout=600)
    assert first.returncode == 0 and first.stdout.strip() == "2", first.stderr
    (index,) = (tmp_path / "nb").rglob("*.nbi")
    index.write_bytes(index.read_bytes()[:10])
    second = subprocess.run([sys.executable, "-c", code], env=env, cwd=tmp_path, capture_output=True, text=True,
                            timeout=600)
    assert second.returncode != 0 and "Error" in second.stderr


def test_a_file_in_the_place_of_a_kernel_folder_is_removed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """numba's locator makes the folder of a kernel's files; a file on the way (damage) is removed first,
    then the folder made (rrbody._cache._clear_way, called where that fails); a folder on the way stays."""
    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    kernels = tmp_path / "kernels"
    kernels.mkdir()
    (kernels / "keep").write_text("a file beside the way")
    (kernels / "v-hash").write_text("a file where the kernel folder belongs")
    _cache._clear_way(kernels / "v-hash" / "physics")
    assert not (kernels / "v-hash").exists() and (kernels / "keep").is_file() and kernels.is_dir()
    (kernels / "v-hash" / "physics").mkdir(parents=True)  # what numba's ensure_cache_path then does
