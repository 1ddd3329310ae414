"""Shared fixtures: the CLI run in-process, with its exit code, stdout and stderr."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

import pytest

# Matplotlib must never try to open a window in tests.
os.environ.setdefault("MPLBACKEND", "Agg")


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
