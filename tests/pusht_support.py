"""gym-pusht (and what its comparisons need) for the tests of rrbody.envs: installed only in make test's
oldest-versions venv (it pins pymunk < 7), where ``RRBODY_REQUIRE_PUSHT=1`` turns a skip into a failure."""
from __future__ import annotations

import importlib
import os
import warnings
from types import ModuleType

import pytest

REQUIRED = os.environ.get("RRBODY_REQUIRE_PUSHT") == "1"


def _load(module: str) -> ModuleType:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pygame's import notes (pkg_resources) are not the test's business
        return importlib.import_module(module)


def need(module: str) -> ModuleType:
    """``module`` (importing ``gym_pusht`` registers gym_pusht/PushT-v0), or a skip of the calling test;
    with RRBODY_REQUIRE_PUSHT=1 a missing one fails it."""
    try:
        return _load(module)
    except ImportError as e:
        if REQUIRED:
            pytest.fail(f"RRBODY_REQUIRE_PUSHT=1 but {module} cannot be imported: {e}")
        pytest.skip(f"{module} is not installed (RRBODY_REQUIRE_PUSHT=1 turns this skip into a failure)")


def have(module: str) -> bool:
    """Whether ``module`` imports (for a skip marker); with RRBODY_REQUIRE_PUSHT=1 a missing one raises,
    failing the collection of the file that asks."""
    try:
        _load(module)
    except ImportError:
        if REQUIRED:
            raise
        return False
    return True
