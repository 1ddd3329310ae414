"""Integration layer: the stepping loop, its methods and the event detector."""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined: numba caches them in rrbody's cache folder
