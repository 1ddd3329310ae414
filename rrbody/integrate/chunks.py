"""Running a compiled stepping loop in chunks from Python: a progress bar and Ctrl-C between chunks.

The loop (:func:`rrbody.integrate.loop.advance_for`) returns after at most ``n`` accepted steps
with code 5 ("chunk done"); its state vector carries time and counters from one call to the next.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rrbody.integrate.loop import L_NSTEP, L_T

__all__ = ["run_in_chunks"]


def run_in_chunks(run: Any, st: np.ndarray, max_steps: int, *, progress: bool, total: float | None,
                  desc: str, chunk: int = 200_000) -> int:
    """Call ``run(n)`` (the compiled loop, at most ``n`` accepted steps) until it returns another code
    than 5 ("chunk done"), or return 3 once ``max_steps`` accepted steps are spent. Compiled chunks
    let a progress bar (simulated time, ``total`` s) update and Ctrl-C be honoured between them."""
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, desc=desc, unit="s(sim)", leave=False, dynamic_ncols=True)
    try:
        while True:
            left = max_steps - int(st[L_NSTEP])
            if left <= 0:
                return 3
            before = st[L_T]
            status = run(min(chunk, left))
            if bar is not None:
                bar.update(st[L_T] - before)
            if status != 5:
                return status
    finally:
        if bar is not None:
            bar.close()
