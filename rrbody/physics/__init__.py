"""Physics layer: the effects and the compiled kernels they use (friction wrench, ICR quadrature, area tables)."""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined: numba caches them in rrbody's cache folder
