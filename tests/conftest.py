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
_COMPILED = ("rrbody", "benchmarks")  # the trees whose kernels numba caches on disk (cache=True)


def _purge_stale_numba_cache() -> None:
    """Drop every kernel numba cached on disk once any source of the package changed.

    numba keys a cached function by the timestamp of its own file only: an edit to a kernel it
    inlines from another file (a right-hand side into the stepping loop) would leave the stale
    compiled copy in use. The sources' hash since the last purge is kept beside the caches."""
    h = hashlib.sha256()
    for tree in _COMPILED:
        for f in sorted((_ROOT / tree).rglob("*.py")):
            h.update(f.relative_to(_ROOT).as_posix().encode())
            h.update(f.read_bytes())
    stamp = _ROOT / "rrbody" / "__pycache__" / "numba-sources.sha256"
    digest = h.hexdigest()
    if stamp.is_file() and stamp.read_text() == digest:
        return
    for tree in _COMPILED:
        for f in (_ROOT / tree).rglob("__pycache__/*.nb[ic]"):
            f.unlink(missing_ok=True)
    stamp.parent.mkdir(exist_ok=True)
    stamp.write_text(digest)


def pytest_configure(config: pytest.Config) -> None:
    if not hasattr(config, "workerinput"):  # once, in the controller, before any worker compiles
        _purge_stale_numba_cache()


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
