"""Shared fixtures: the CLI run in-process, with its exit code, stdout and stderr."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

# Matplotlib must never try to open a window in tests.
os.environ.setdefault("MPLBACKEND", "Agg")

_ROOT = Path(__file__).resolve().parents[1]
_COMPILED = ("rrbody", "benchmarks", "tests")  # the trees whose sources cached test and benchmark kernels may inline
#: the trees whose own numba caches hold kernels compiled from rrbody's (purged when any source changes)
_PURGED = ("benchmarks", "tests")


def _purge_stale_numba_cache() -> None:
    """Drop the kernels the benchmarks and the tests cached on disk once any source of rrbody, the
    benchmarks or the tests changed.

    numba keys a cached function by the timestamp of its own file only: an edit to a kernel it
    inlines or links from another file (rrbody's right-hand side into the benchmarks' lean loop, the
    wrench table into a test's loop over twists) would leave the stale compiled copy in use, and the
    test would check the old kernel. rrbody's own kernels need no purge: they are cached under a hash
    of the package's sources (``rrbody._cache.kernels_dir``). The sources' hash since the last purge
    is kept beside the benchmarks' caches."""
    h = hashlib.sha256()
    for tree in _COMPILED:
        for f in sorted((_ROOT / tree).rglob("*.py")):
            h.update(f.relative_to(_ROOT).as_posix().encode())
            h.update(f.read_bytes())
    stamp = _ROOT / "benchmarks" / "__pycache__" / "numba-sources.sha256"
    digest = h.hexdigest()
    if stamp.is_file() and stamp.read_text() == digest:
        return
    for tree in _PURGED:
        for f in (_ROOT / tree).rglob("__pycache__/*.nb[ic]"):
            f.unlink(missing_ok=True)
    stamp.parent.mkdir(exist_ok=True)
    stamp.write_text(digest)


def pytest_configure(config: pytest.Config) -> None:
    if not hasattr(config, "workerinput"):  # once, in the controller, before any worker compiles
        _purge_stale_numba_cache()


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The longest tests (marked ``slow``: a fresh venv, the README's snippets) first, the rest in
    file order. pytest-xdist (``make test``: ``-n 2 --dist loadgroup``) hands out the groups of tests
    that run in one worker first (``xdist_group``: the files that build wrench tables), then every
    other test, one at a time, in this order, so none of the long ones starts last, with the other
    worker idle until it ends. Every test still runs."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)  # stable: file order kept
    from rrbody._private import ENV, private_allowed

    if not private_allowed():  # the run of the takeovers alone (make test's PUBLIC_TESTS): nothing to compare
        skip = pytest.mark.skip(reason=f"{ENV} is set: the private fast path this test compares is off")
        for item in items:
            if item.get_closest_marker("private") is not None:
                item.add_marker(skip)


@dataclass
class CliRun:
    code: int
    out: str
    err: str


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., CliRun]:
    from rrbody.cli.main import main

    def run(*argv: str) -> CliRun:
        try:
            code = main(list(argv))
        except SystemExit as e:  # argparse errors exit 2 through SystemExit
            code = int(e.code or 0)
        cap = capsys.readouterr()
        return CliRun(code, cap.out, cap.err)

    return run
