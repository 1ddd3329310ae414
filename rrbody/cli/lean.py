"""Start-up trimming for the ``rrbody`` process: load only what a command uses.

numba's CPU target, when it first starts in a process (the first compiled or cached call), runs
``import scipy.linalg.cython_blas`` to see whether BLAS is available (``numba/np/arraymath.py``).
Python imports the whole package ``scipy.linalg`` first (~0.15 s of linear-algebra modules that no
rrbody command uses). :func:`preload_cython_blas` loads that one extension module under its own
name, which is all numba needs, so ``scipy.linalg`` stays unimported; a later ``import
scipy.linalg`` still works and finds the same module. If anything differs from what is expected,
it does nothing and numba imports scipy.linalg as usual.
"""

from __future__ import annotations

import sys

__all__ = ["preload_cython_blas"]


def preload_cython_blas() -> None:
    """Put ``scipy.linalg.cython_blas`` in ``sys.modules`` without importing ``scipy.linalg``."""
    from rrbody._private import private_allowed

    name = "scipy.linalg.cython_blas"
    if not private_allowed():  # RRBODY_NO_PRIVATE: numba imports scipy.linalg itself (rrbody._private)
        return
    if name in sys.modules or "scipy.linalg" in sys.modules:
        return
    try:
        import importlib.machinery
        import importlib.util
        import os

        import scipy

        spec = importlib.machinery.PathFinder.find_spec("cython_blas", [os.path.join(scipy.__path__[0], "linalg")])
        if spec is None or spec.loader is None:
            return
        spec.name = name
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    except Exception:  # noqa: BLE001 - an optimisation only: on any surprise leave the import to numba
        sys.modules.pop(name, None)
