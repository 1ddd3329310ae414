"""numba options and entry points for the plugin's calls. Its per-body kernels are called once per
body and step from :func:`rrbody.contact.kernel.plane_step`, with the plugin's arrays as arguments,
and compiled without numba's reference counting (:func:`rrbody._private.no_refcount` says why).
"""

from __future__ import annotations

from typing import Any

from rrbody._private import no_refcount, private_allowed

__all__ = ["NO_REFCOUNT", "fast_entry"]


#: keyword arguments for ``njit`` of a kernel that allocates no array
NO_REFCOUNT: dict[str, Any] = no_refcount()


def fast_entry(dispatcher: Any, *args: Any) -> tuple[Any, Any]:
    """Call ``dispatcher(*args)`` once; return the compiled entry point for these argument types and
    the call's result.

    Calling the entry point skips numba's per-call type dispatch (about 0.3 us of the ~1 us a
    many-argument call costs, measured); the arrays passed later must have the same types. Falls
    back to the dispatcher itself if numba's internals differ."""
    result = dispatcher(*args)
    if not private_allowed():  # RRBODY_NO_PRIVATE: numba's own dispatch (rrbody._private)
        return dispatcher, result
    try:
        sig = tuple(dispatcher.typeof_pyval(a) for a in args)
        return dispatcher.overloads[sig].entry_point, result
    except (AttributeError, KeyError, TypeError):  # pragma: no cover - numba internals
        return dispatcher, result
