"""A growable array of rows (the plugin's body tables, the recorder's frames): appending is amortised
O(1) per row, and the rows in use are a C-contiguous view the compiled kernels take."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Rows"]


class Rows:
    """The first ``n`` rows of an array whose capacity doubles when full: appending k rows costs O(k)
    amortised (no copy of the rows already there, except at the log2(n) reallocations)."""

    def __init__(self, width: int | tuple[int, ...] | None, dtype: Any = np.float64, capacity: int = 16) -> None:
        # width: each row's shape (None: scalars; an int: a vector; a tuple: an array, e.g. a frame)
        shape = () if width is None else (width,) if isinstance(width, int) else tuple(width)
        self.buf = np.zeros((capacity, *shape), dtype=dtype)
        self.n = 0
        self.reallocs = 0  # how many times the storage moved (tests check it grows like log n)

    def append(self, rows: np.ndarray) -> int:
        """Append ``rows`` (shape (k, width), or (k,) for a 1-D array); return the first new row's index."""
        k = rows.shape[0]
        start = self._reserve(k)
        self.buf[start:start + k] = rows
        return start

    def append_one(self, row: Any) -> int:
        """Append one row (a scalar for a 1-D array); return its index."""
        start = self._reserve(1)
        self.buf[start] = row
        return start

    def ensure(self, rows: int, *, touch: bool = False) -> None:
        """Room for ``rows`` rows in ``buf`` (the capacity doubles; the first ``n`` rows are kept).
        ``touch``: write every new row now, so that the operating system maps the memory here and not
        at the first write of each row (a fresh page's first write costs far more than a copy)."""
        if rows > self.buf.shape[0]:
            new = np.zeros((max(rows, 2 * self.buf.shape[0]), *self.buf.shape[1:]), dtype=self.buf.dtype)
            new[:self.n] = self.buf[:self.n]
            if touch:
                new[self.n:].fill(0)  # np.zeros maps pages lazily: fault them in now
            self.buf = new
            self.reallocs += 1

    def _reserve(self, k: int) -> int:
        start = self.n
        self.ensure(start + k)
        self.n = start + k
        return start

    @property
    def view(self) -> np.ndarray:
        """The rows in use (a C-contiguous view: what the compiled kernels take)."""
        return self.buf[:self.n]
