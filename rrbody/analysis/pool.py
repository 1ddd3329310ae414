"""Executors of sweep batches: this process, local worker processes, or a Dask cluster.

Process hygiene of the local pool:

- never more processes than batches (so never more than points), and at most
  ``LIMITS["workers"].hi``; :func:`plan_workers` warns above the core count;
- a worker dies with its parent however the parent ends (SIGTERM, SIGINT, ``kill -9``): on Linux
  the kernel sends it SIGKILL when the parent exits (``prctl(PR_SET_PDEATHSIG)``), and on every
  platform a watchdog thread in the worker polls ``os.getppid()`` and exits once the parent is gone;
- Ctrl-C reaches the whole process group, but workers ignore SIGINT: the parent alone handles it,
  stops the pool (running batches are terminated, queued ones cancelled) and re-raises;
- an exception in the parent (including KeyboardInterrupt) terminates the workers at once instead
  of waiting for their running batches.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from typing import Any

from rrbody.model.checks import check

__all__ = ["plan_workers", "iter_local", "iter_dask", "WATCHDOG_PERIOD_S"]

#: how often a worker checks that its parent is alive (s); bounds an orphan's life where prctl is missing
WATCHDOG_PERIOD_S = 0.2
_PR_SET_PDEATHSIG = 1

Batch = list[int]
Rows = list[dict[str, Any]]


def plan_workers(requested: int | None, n_batches: int) -> int:
    """Processes to start: ``requested`` (default: the core count), at most one per batch.

    Raises ValueError above ``LIMITS["workers"]``; warns (RuntimeWarning) when more processes than
    cores are asked for, since they only share the cores and slow each other."""
    cores = os.cpu_count() or 1
    if n_batches == 0 and requested is None:
        return 0  # nothing to do (a resumed sweep that was complete): no pool at all
    if requested is None:
        return max(1, min(cores, n_batches))
    n = int(check("workers", requested))
    if n > cores:
        warnings.warn(f"workers {n} is more than the {cores} cores of this machine; the processes will share them",
                      RuntimeWarning, stacklevel=3)
    return 0 if n == 0 else max(1, min(n, n_batches))


def _watch_parent(parent: int) -> None:
    while True:
        if os.getppid() != parent:
            os._exit(1)  # the parent is gone: no orphan keeps computing
        time.sleep(WATCHDOG_PERIOD_S)


def _worker_init(parent: int) -> None:
    """Initializer of every pool process (runs in the worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the parent handles Ctrl-C for the group
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the CLI's handler inherited through fork
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass  # the watchdog below still ends the worker
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True, name="rrbody-parent-watchdog").start()


def iter_local(run: Callable[[dict[str, Any], Batch], Rows], spec: dict[str, Any], batches: list[Batch],
               workers: int) -> Iterator[Rows]:
    """Results of ``run(spec, batch)`` for every batch, as they finish (``workers=0``: in order, here)."""
    if workers == 0:
        for b in batches:
            yield run(spec, b)
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed

    ex = ProcessPoolExecutor(max_workers=workers, initializer=_worker_init, initargs=(os.getpid(),))
    futs = [ex.submit(run, spec, b) for b in batches]
    clean = False
    try:
        for f in as_completed(futs):
            yield f.result()
        clean = True
    finally:
        if clean:
            ex.shutdown(wait=True)
        else:
            _terminate(ex)


def _terminate(ex: Any) -> None:
    """Stop a ProcessPoolExecutor now: cancel queued batches and kill the running ones."""
    procs = list(getattr(ex, "_processes", {}).values())  # no public handle before Python 3.14
    ex.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=5.0)
        if p.is_alive():
            p.kill()
            p.join(timeout=5.0)


def iter_dask(run: Callable[[dict[str, Any], Batch], Rows], spec: dict[str, Any], batches: list[Batch],
              scheduler: Any) -> Iterator[Rows]:
    """Results of ``run(spec, batch)`` on a Dask cluster (address or ``distributed.Client``)."""
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = [client.submit(run, spec, b, pure=False) for b in batches]
        try:
            for f in as_completed(futs):
                yield f.result()
        finally:
            client.cancel(futs)
    finally:
        if own:
            client.close()
