"""Gauss-Legendre rules for the instantaneous-centre quadrature (:mod:`rrbody.physics.icr`; its panels:
:mod:`rrbody.physics.icr_panels`, which loads these rules).

The kernels need the packed rules as compile-time constants when their module is imported; building
them up to 512 nodes costs ~0.1 s, so they are stored next to numba's cache on first use and loaded
from there afterwards (~1 ms), keeping ``import rrbody.integrate`` cheap.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["quadrature_tables"]


def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n (vectorised, O(n^2);
    numpy's eigenvalue-based leggauss costs O(n^3), 0.3 s of import time for the larger rules)."""
    k = np.arange(1, n + 1)
    x = np.cos(np.pi * (k - 0.25) / (n + 0.5))
    for _ in range(100):
        p0 = np.ones_like(x)
        p1 = x.copy()
        for j in range(2, n + 1):
            p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
        dp = n * (x * p1 - p0) / (x * x - 1.0)
        dx = p1 / dp
        x = x - dx
        if np.max(np.abs(dx)) < 1e-16:
            break
    p0 = np.ones_like(x)
    p1 = x.copy()
    for j in range(2, n + 1):
        p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
    dp = n * (x * p1 - p0) / (x * x - 1.0)
    w = 2.0 / ((1.0 - x * x) * dp * dp)
    return x[::-1].copy(), w[::-1].copy()


def _tables(node_counts: tuple[int, ...], x_end: float) -> tuple[np.ndarray, ...]:
    """Packed Gauss-Legendre rules on [-1, 1] for every allowed node count, plus sin/cos of the
    nodes scaled to the full panel [-pi/2, pi/2] and the middle panel [-(pi/2 - X_END), pi/2 - X_END]."""
    sizes = np.array(node_counts, dtype=np.int64)
    offs = np.zeros(len(sizes) + 1, dtype=np.int64)
    offs[1:] = np.cumsum(sizes)
    x = np.empty(offs[-1])
    w = np.empty(offs[-1])
    for i, n in enumerate(sizes):
        xi, wi = _gauss_legendre(int(n))
        x[offs[i]:offs[i + 1]] = xi
        w[offs[i]:offs[i + 1]] = wi
    half = 0.5 * math.pi
    mid = half - x_end
    return sizes, offs, x, w, np.sin(half * x), np.cos(half * x), np.sin(mid * x), np.cos(mid * x)


def quadrature_tables(node_counts: tuple[int, ...], x_end: float) -> tuple[np.ndarray, ...]:
    """:func:`_tables`, stored in rrbody's cache folder (``rrbody._cache.tables_dir``) on first use:
    building the rules up to 512 nodes costs ~0.1 s, loading them ~1 ms (the kernels need them as
    compile-time constants at import)."""
    import hashlib

    from rrbody._cache import stored_arrays, tables_dir

    key = hashlib.sha1(repr((tuple(node_counts), x_end, "gauss-legendre-newton-1")).encode()).hexdigest()[:16]
    return stored_arrays(tables_dir() / f"icr_tables-{key}.npz", lambda: _tables(node_counts, x_end),
                         valid=lambda arrays: len(arrays) == 8)
