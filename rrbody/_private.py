"""One switch for every fast path of rrbody that relies on another library's private internals.

rrbody is faster where it reads pymunk's and numba's insides, and each such use has a public
takeover that gives the same numbers (docs/versions.md lists them). Setting the environment variable
``RRBODY_NO_PRIVATE=1`` (before rrbody is imported) turns all of them off at once, so the takeovers
can be run together, as ``make test`` does for a stated part of the suite:

- pymunk's struct memory (:func:`rrbody.engine.memory.bodymem.layout` returns None: the plugin and the
  recorder read and write through ``pymunk.batch`` or the bodies' properties);
- Chipmunk's setters for a driven body's driver (the driver's public ``velocity`` and ``position``);
- numba's cache locators (rrbody's kernels are cached by numba's own locators, next to their
  sources or in numba's user-wide folder, and keyed by the files' time stamps);
- numba's ``_nrt=False`` option (:func:`rrbody._private.no_refcount` gives no option);
- the start-up trim that loads scipy's ``cython_blas`` alone (:mod:`rrbody.cli.lean`: nothing is loaded).

The kernels compiled with the switch set are cached apart from the others (the switch is part of
:func:`rrbody._cache.source_hash`), so a run with it never loads a kernel compiled without it.
"""

from __future__ import annotations

import functools
import os
from typing import Any

__all__ = ["ENV", "private_allowed", "no_refcount"]

#: the environment variable that turns rrbody's uses of private internals off ("1"; unset, "" or "0": on)
ENV = "RRBODY_NO_PRIVATE"


def private_allowed() -> bool:
    """Whether rrbody may use other libraries' private internals (False where ``RRBODY_NO_PRIVATE`` is
    ``"1"``; True where it is unset, ``""`` or ``"0"``; any other value is a ValueError naming it). Read at each call;
    the kernels read it once, when they compile."""
    value = os.environ.get(ENV, "")
    if value not in ("", "0", "1"):  # ("false" would otherwise turn them off: say so instead)
        raise ValueError(f"{ENV} must be 1 (private fast paths off), 0 or unset (on), got {value!r}")
    return value != "1"


@functools.lru_cache(maxsize=1)
def no_refcount() -> dict[str, Any]:
    """Keyword arguments for ``njit`` of a kernel that allocates no array and keeps none: numba's
    reference counting off (its undocumented ``_nrt=False``; dropped, the kernels compile as usual).
    The count is an atomic increment and decrement per array passed on, in every call of the per-body
    kernels (what it costs the plugin's step: ``benchmarks/private.py``). numba is imported only when
    called."""
    if not private_allowed():  # RRBODY_NO_PRIVATE (rrbody._private)
        return {}
    try:
        from numba.core.cpu import CPUTargetOptions
    except ImportError:  # pragma: no cover - depends on the numba version
        return {}
    return {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
