"""The one switch for rrbody's uses of other libraries' private internals (rrbody._private): with
``RRBODY_NO_PRIVATE=1`` every fast path named in docs/versions.md takes its public takeover.

Each check runs in a fresh process (the switch is read at import, and the kernels read it when they
compile). ``make test`` also runs a stated part of the suite with the switch set (``PUBLIC_TESTS`` in
the Makefile), where the exact references and the bit-for-bit comparisons of the routes must hold.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

pytest.importorskip("pymunk")

PROBE = r"""
import json, numba, pymunk
from numba.core import caching
from rrbody import _cache, _private
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.engine.memory.bodymem import layout
from rrbody.cli.lean import preload_cython_blas
import sys

impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")
preload_cython_blas()
print(json.dumps({
    "allowed": _private.private_allowed(),
    "layout": layout() is not None,
    "no_refcount": NO_REFCOUNT,
    "locator": any(c.__name__ == "RrbodyCacheLocator" for c in impl._locator_classes),
    "hash": _cache.source_hash(),
    "blas_alone": "scipy.linalg.cython_blas" in sys.modules and "scipy.linalg" not in sys.modules,
}))
"""


def _probe(switch: str | None) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "RRBODY_NO_PRIVATE"}
    if switch is not None:
        env["RRBODY_NO_PRIVATE"] = switch
    out = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_the_switch_turns_every_private_fast_path_off() -> None:
    on = _probe(None)
    off = _probe("1")
    if not on["allowed"]:
        pytest.skip("this run has RRBODY_NO_PRIVATE set in its own environment")
    # on: the fast paths the suite's packages offer
    assert on["layout"] and on["no_refcount"] == {"_nrt": False} and on["locator"]
    # off: each takeover
    assert off == {**off, "allowed": False, "layout": False, "no_refcount": {}, "locator": False, "blas_alone": False}
    # kernels compiled with the switch are cached apart
    assert off["hash"] != on["hash"]


def test_zero_and_empty_leave_it_on() -> None:
    assert _probe("0")["allowed"] and _probe("")["allowed"]


def test_another_value_is_refused_with_its_name_and_the_valid_ones() -> None:
    """``RRBODY_NO_PRIVATE=false`` must not quietly turn the fast paths off (nor leave them on)."""
    env = {**os.environ, "RRBODY_NO_PRIVATE": "false"}
    out = subprocess.run([sys.executable, "-c", "from rrbody._private import private_allowed; private_allowed()"],
                         env=env, capture_output=True, text=True)
    assert out.returncode != 0
    assert ("ValueError: RRBODY_NO_PRIVATE must be 1 (private fast paths off), 0 or unset (on), got 'false'"
            in out.stderr)
