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
  of waiting for their running batches;
- a worker that dies (any signal: the out-of-memory killer's SIGKILL, a crash) stops the pool and
  raises :class:`ExecutorFault` saying how it died; so does a Dask scheduler that is lost mid-run;
- a forked worker does not keep its parent's output locks (:mod:`rrbody.model.outlock`): a lock
  ends with the process that took it.

A scheduler address is checked for its form (:func:`check_scheduler_address`) and reached
(:func:`connect_scheduler`) before a sweep writes anything.
"""

from __future__ import annotations

import os
import signal
import socket
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from typing import Any

from rrbody.model.checks import check

__all__ = ["plan_workers", "plan_batches", "iter_local", "iter_dask", "WATCHDOG_PERIOD_S", "ExecutorFault",
           "check_scheduler", "check_scheduler_address", "connect_scheduler", "SCHEDULER_TIMEOUT_S", "describe_exit"]

#: how often a worker checks that its parent is alive (s); bounds an orphan's life where prctl is missing
WATCHDOG_PERIOD_S = 0.2
#: how long a scheduler may take to answer before the sweep is refused (s)
SCHEDULER_TIMEOUT_S = 5.0
_PR_SET_PDEATHSIG = 1
_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx", "inproc")

Batch = list[int]
Rows = list[dict[str, Any]]


class ExecutorFault(RuntimeError):
    """The executor failed under a sweep (a worker process died, the Dask scheduler was lost); the
    message says what happened, in words for a user."""


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


def plan_batches(todo: list[int], batch_size: int | None, workers: int | None) -> list[Batch]:
    """``todo`` cut into batches of ``batch_size`` points (default: about 4 tasks per process, at most
    256 points each, so that per-task overhead stays small next to a point's cost)."""
    if batch_size is None:
        cores = os.cpu_count() or 1
        per = cores if workers is None else max(1, min(int(workers), cores))
        batch_size = max(1, min(256, -(-len(todo) // (4 * per))))
    return [list(todo[j:j + batch_size]) for j in range(0, len(todo), batch_size)]


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


def describe_exit(code: int | None) -> str:
    """How a process ended, from its exit code (negative: the signal that killed it)."""
    if code is None:
        return "ended abruptly"
    if code < 0:
        try:
            name = f" ({signal.Signals(-code).name})"
        except ValueError:
            name = ""
        return f"killed by signal {-code}{name}"
    return f"exited with status {code}"


def _dead_worker(codes: list[int | None]) -> str:
    """How the worker that broke the pool died. The pool itself sends SIGTERM to the others once one
    is gone, so an exit other than that one names the culprit; SIGTERM is the answer only if alone."""
    own = -int(signal.SIGTERM)
    for c in codes:
        if c is not None and c not in (0, own):
            return describe_exit(c)
    return describe_exit(own if own in codes else None)


def iter_local(run: Callable[[dict[str, Any], Batch], Rows], spec: dict[str, Any], batches: list[Batch],
               workers: int) -> Iterator[Rows]:
    """Results of ``run(spec, batch)`` for every batch, as they finish (``workers=0``: in order, here).

    A worker that dies raises :class:`ExecutorFault` naming how, once the pool is stopped."""
    if workers == 0:
        for b in batches:
            yield run(spec, b)
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    ex = ProcessPoolExecutor(max_workers=workers, initializer=_worker_init, initargs=(os.getpid(),))
    futs = [ex.submit(run, spec, b) for b in batches]
    procs = list((getattr(ex, "_processes", None) or {}).values())  # no public handle before Python 3.14
    clean = False
    try:
        for f in as_completed(futs):
            try:
                rows = f.result()
            except BrokenProcessPool:
                codes = [p.exitcode for p in procs]  # before our own termination adds SIGTERMs
                _terminate(ex, procs)
                codes += [p.exitcode for p in procs]  # the culprit's, if it was not reaped yet above
                raise ExecutorFault(f"a worker process died ({_dead_worker(codes)})") from None
            yield rows
        clean = True
    finally:
        if clean:
            ex.shutdown(wait=True)
        else:
            _terminate(ex, procs)


def _terminate(ex: Any, procs: list[Any]) -> None:
    """Stop a ProcessPoolExecutor now: cancel queued batches and kill the running ones (idempotent)."""
    ex.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=5.0)
        if p.is_alive():
            p.kill()
            p.join(timeout=5.0)


def check_scheduler_address(address: object) -> str:
    """``address`` if it has the form of a Dask scheduler address, ``SCHEME://HOST:PORT``; else a
    ValueError naming ``scheduler`` (no connection is tried here)."""
    ok = isinstance(address, str) and not any(c.isspace() for c in address)
    scheme, sep, rest = address.partition("://") if isinstance(address, str) else ("", "", "")
    ok = ok and bool(sep) and scheme in _SCHEMES and bool(rest)
    if ok and scheme != "inproc":  # inproc://... names a cluster inside this process
        host, colon, port = rest.rpartition(":")
        bracketed = host.startswith("[") == host.endswith("]")
        ok = (bool(colon and host) and bracketed and "/" not in host and port.isdigit() and port.isascii()
              and 1 <= int(port) <= 65535)
    if not ok:
        raise ValueError(f"scheduler must be a Dask scheduler address SCHEME://HOST:PORT (SCHEME one of "
                         f"{', '.join(_SCHEMES)}; PORT in [1, 65535]), e.g. tcp://127.0.0.1:8786, got {address!r}")
    return str(address)


def check_scheduler(scheduler: Any) -> None:
    """``scheduler`` is a ``distributed.Client`` or a well-formed address (:func:`check_scheduler_address`)."""
    if not isinstance(scheduler, str):
        try:
            from distributed import Client

            if isinstance(scheduler, Client):
                return
        except ImportError:
            pass  # then it cannot be a Client: the address check below names the value
    check_scheduler_address(scheduler)


def connect_scheduler(address: str, *, timeout: float = SCHEDULER_TIMEOUT_S) -> Any:
    """A ``distributed.Client`` connected to the scheduler at ``address`` (checked by
    :func:`check_scheduler_address`), or a ValueError naming ``scheduler`` if none answers within
    ``timeout`` seconds. A refused TCP connection fails at once, without Dask's retries."""
    address = check_scheduler_address(address)
    scheme, _, rest = address.partition("://")
    hint = "start one (`dask scheduler`) or run on local processes"
    if scheme in ("tcp", "tls", "ws", "wss"):
        host, _, port = rest.rpartition(":")
        try:
            socket.create_connection((host.strip("[]"), int(port)), timeout=timeout).close()
        except OSError as e:
            why = e.strerror or type(e).__name__
            raise ValueError(f"scheduler: no Dask scheduler answers at {address!r} ({why}); {hint}") from None
    from distributed import Client

    try:
        return Client(address, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as e:
        raise ValueError(f"scheduler: cannot connect to a Dask scheduler at {address!r} within {timeout:g} s "
                         f"({type(e).__name__}: {e}); {hint}") from None


def iter_dask(run: Callable[[dict[str, Any], Batch], Rows], spec: dict[str, Any], batches: list[Batch],
              client: Any) -> Iterator[Rows]:
    """Results of ``run(spec, batch)`` on a Dask cluster through ``client`` (a ``distributed.Client``,
    e.g. from :func:`connect_scheduler`; whoever made it closes it).

    A scheduler lost mid-run (its futures cancelled, the connection closed) or a Dask worker that
    keeps dying raises :class:`ExecutorFault`."""
    from concurrent.futures import CancelledError

    from distributed import as_completed

    where = getattr(getattr(client, "scheduler", None), "address", None) or "its address"
    futs: list[Any] = []
    try:
        futs = [client.submit(run, spec, b, pure=False) for b in batches]
        for f in as_completed(futs, loop=client.loop):  # this client's loop: it need not be the default
            try:
                rows = f.result()
            except (CancelledError, OSError, TimeoutError) as e:
                raise ExecutorFault(f"lost the Dask scheduler at {where} ({type(e).__name__}; client "
                                    f"{client.status})") from None
            except Exception as e:
                if type(e).__name__ != "KilledWorker":
                    raise
                raise ExecutorFault(f"Dask workers died computing a batch ({e})") from None
            yield rows
    finally:
        try:
            if client.status == "running":
                client.cancel(futs)
        except Exception:  # noqa: BLE001 - a lost scheduler cannot be told anything; nothing to undo
            pass
