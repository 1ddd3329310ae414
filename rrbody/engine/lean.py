"""numba options for the plugin's per-body kernels: called once per body and step from
:func:`rrbody.engine.kernel.plane_step`, with the plugin's arrays as arguments.

numba's runtime counts references to every array passed into a compiled function (an atomic
increment and decrement per array and call). These kernels allocate nothing and keep no array, so
the counting buys nothing; compiled without the runtime (numba's ``_nrt=False``) the plugin's step
for 1,000 bodies ran 9-10 % faster (measured, interleaved A/B, best of 7 runs of 100 steps:
445 -> 405 us). ``_nrt`` is an option numba does not document: if a numba release drops it the
kernels are compiled as usual (same results, the count back).
"""

from __future__ import annotations

from typing import Any

__all__ = ["NO_REFCOUNT"]


def _options() -> dict[str, Any]:
    try:
        from numba.core.cpu import CPUTargetOptions
    except ImportError:  # pragma: no cover - depends on the numba version
        return {}
    return {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}


#: keyword arguments for ``njit`` of a kernel that allocates no array
NO_REFCOUNT: dict[str, Any] = _options()
