"""numba options for the plugin's kernels. Its per-body kernels are called once per
body and step from :func:`rrbody.contact.kernel.plane_step`, with the plugin's arrays as arguments,
and compiled without numba's reference counting (:func:`rrbody._private.no_refcount` says why).
"""

from __future__ import annotations

from typing import Any

from rrbody._private import no_refcount

__all__ = ["NO_REFCOUNT"]


#: keyword arguments for ``njit`` of a kernel that allocates no array
NO_REFCOUNT: dict[str, Any] = no_refcount()
