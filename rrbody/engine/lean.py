"""numba options and entry points for the plugin's calls. Its per-body kernels are called once per
body and step from :func:`rrbody.engine.kernel.plane_step`, with the plugin's arrays as arguments.

numba's runtime counts references to every array passed into a compiled function (an atomic
increment and decrement per array and call). These kernels allocate nothing and keep no array, so
the counting buys nothing; compiled without the runtime (numba's ``_nrt=False``) the plugin's step
for 1,000 bodies ran 9-10 % faster (measured, interleaved A/B, best of 7 runs of 100 steps:
445 -> 405 us). ``_nrt`` is an option numba does not document: if a numba release drops it the
kernels are compiled as usual (same results, the count back).
"""

from __future__ import annotations

from typing import Any

__all__ = ["NO_REFCOUNT", "fast_entry"]


def _options() -> dict[str, Any]:
    try:
        from numba.core.cpu import CPUTargetOptions
    except ImportError:  # pragma: no cover - depends on the numba version
        return {}
    return {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}


#: keyword arguments for ``njit`` of a kernel that allocates no array
NO_REFCOUNT: dict[str, Any] = _options()


def fast_entry(dispatcher: Any, *args: Any) -> tuple[Any, Any]:
    """Call ``dispatcher(*args)`` once; return the compiled entry point for these argument types and
    the call's result.

    Calling the entry point skips numba's per-call type dispatch (about 0.3 us of the ~1 us a
    many-argument call costs, measured); the arrays passed later must have the same types. Falls
    back to the dispatcher itself if numba's internals differ."""
    result = dispatcher(*args)
    try:
        sig = tuple(dispatcher.typeof_pyval(a) for a in args)
        return dispatcher.overloads[sig].entry_point, result
    except (AttributeError, KeyError, TypeError):  # pragma: no cover - numba internals
        return dispatcher, result
