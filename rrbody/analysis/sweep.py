"""Parameter sweeps: flip time, H_c, the RR test, Lyapunov maps (chaos) over 1-D/2-D grids or lists of scenes.

A :class:`rrbody.analysis.sweep_spec.Sweep` names a base scene, the axes to vary and the quantity to
compute, and checks them when it is built (its sibling :mod:`rrbody.analysis.sweep_spec`: the
parameters, the axes, the validation). This module runs it: :func:`run_sweep` evaluates every point
(:func:`evaluate_point`) on an executor:

- local processes (default; at most one per batch and per core by default; see :mod:`rrbody.analysis.pool`),
- a Dask cluster when ``scheduler`` is a scheduler address (``tcp://host:8786``) or a
  ``distributed.Client``,
- ``workers=0``: in this process (debugging, tests).

Points are sent in batches (``batch_size`` points per task): little overhead next to ~1 ms a point.

Checkpoint and resume
---------------------
Finished points stream to ``<out>.checkpoint.jsonl``: a JSON header line (the sweep
specification and the rrbody version) then one JSON line per point, flushed and fsync'ed as each
batch finishes. The file is append-only, so a kill can at worst leave one truncated last line;
``resume=True`` drops it, checks that the header matches the requested sweep (a different scene,
grid, quantity, options or rrbody version raises ValueError rather than mixing results) and
computes only the missing points. The table is written atomically and the checkpoint removed. Results
do not depend on the executor, the batch size or interruptions (each point is deterministic).

Output: ``.csv`` or ``.nc`` with a ``<out>.json`` sidecar (formats: :mod:`rrbody.analysis.sweep_store`).

One writer, clean faults: a sweep locks its table, checkpoint and sidecar (:mod:`rrbody.model.outlock`)
before it looks at them, so a second sweep to one output is refused at once (``OutputBusy``, naming
the other process), whatever ``force`` or ``resume`` say; a killed sweep's lock is free for ``resume``.
A dead worker, a lost Dask scheduler or a full disk raises :class:`SweepFault` (points saved; resume).

Validation: :func:`run_sweep` checks the outputs, the options and the scheduler (its address, then
that it answers) before any work or file; the sweep itself was checked when it was built.
"""

from __future__ import annotations

import contextlib
import math
import os
from pathlib import Path
from typing import Any

from rrbody.analysis.sweep_spec import Sweep, critical_h_args, make_scene, sweep_from_spec
from rrbody.analysis.sweep_store import (
    check_outputs,
    checkpoint_path,
    count_rows,
    load_sweep,
    output_files,
    read_checkpoint,
    read_meta,
    stream_checkpoint,
    write_output,
)
from rrbody.model.checks import check

__all__ = ["run_sweep", "load_sweep", "evaluate_point", "checkpoint_path", "SweepInterrupted", "SweepStopped",
           "SweepFault", "read_meta", "run_fresh_or_resume", "progress_bar"]


class SweepInterrupted(RuntimeError):
    """Raised by the test hook ``_stop_after``: the sweep stopped as if killed, checkpoint intact."""


class SweepStopped(KeyboardInterrupt):
    """Ctrl-C or SIGTERM stopped a sweep: ``done`` of ``total`` points are in ``checkpoint``; run the
    same sweep again with ``resume=True`` (``--resume``) to compute the rest."""

    def __init__(self, done: int, total: int, checkpoint: Path) -> None:
        super().__init__(f"{done} of {total} points saved in {str(checkpoint)!r}")
        self.done, self.total, self.checkpoint = done, total, checkpoint


class SweepFault(RuntimeError):
    """A fault ended a sweep (``what``: a worker process died, the Dask scheduler was lost, the disk is
    full): ``done`` of ``total`` points are in ``checkpoint``; the same sweep with ``resume=True``
    (``--resume``) computes the rest."""

    def __init__(self, what: str, done: int, total: int, checkpoint: Path) -> None:
        super().__init__(f"{what}; {done} of {total} points are saved in {str(checkpoint)!r}; run the same sweep "
                         "with resume=True to finish it")
        self.what, self.done, self.total, self.checkpoint = what, done, total, checkpoint


# ---- evaluating one point --------------------------------------------------------------------
def evaluate_point(sweep: Sweep, values: dict[str, float]) -> dict[str, Any]:
    """Compute the sweep's quantity at one point; errors become a row with an ``error`` message."""
    from rrbody.analysis.flip import critical_h, flip_time, reverse_rotation_exists

    opts = dict(sweep.options)
    try:
        scene = make_scene(sweep, values)
        if sweep.quantity == "critical_h":
            hc = critical_h(**critical_h_args(scene), **opts)
            return {"H_c": hc, "error": ""}
        if sweep.quantity == "chaos":
            from rrbody.analysis.chaos_map import chaos_point

            return {**chaos_point(scene, **opts), "error": ""}
        if sweep.quantity == "rr":
            return {"reverse_rotation": bool(reverse_rotation_exists(scene, **opts)), "error": ""}
        if sweep.quantity == "rest":
            from rrbody.analysis.simulate import simulate

            t_max = float(opts.pop("t_max"))
            tr = simulate(scene, t_max=t_max, dt_out=t_max, **opts)
            ev = tr.events
            return {"t_stop": ev.get("t_stop"), "distance": ev.get("distance"), "turn": ev.get("turn"),
                    "status": tr.meta.get("status"), "error": ""}
        r = flip_time(scene, **opts)
        # no minimum of phi: no phi_min and no t_phi_min (empty cells, null in the checkpoint), never NaN text
        no_min = math.isnan(r.t_phi_min)
        return {"t_f": r.t_f, "phi_min": None if no_min else r.phi_min, "t_phi_min": None if no_min else r.t_phi_min,
                "reverse_rotation": bool(r.reverse_rotation), "T1": r.T1, "settled": bool(r.settled),
                "n_steps": int(r.n_steps), "regime": r.regime, "error": ""}
    except ValueError as e:
        return {**{c: None for c in sweep.columns}, "error": str(e)}


def _run_batch(spec: dict[str, Any], indices: list[int]) -> list[dict[str, Any]]:
    """Worker entry point (module level, so it pickles): evaluate the points ``indices``."""
    sweep = sweep_from_spec(spec)
    return [{"i": i, **evaluate_point(sweep, sweep.point(i))} for i in indices]


# ---- running ---------------------------------------------------------------------------------
def run_sweep(sweep: Sweep, out: str | os.PathLike[str], *, resume: bool = False, force: bool = False,
              scheduler: Any = None, workers: int | None = None, batch_size: int | None = None,
              progress: bool = True, _stop_after: int | None = None) -> Path:
    """Evaluate ``sweep`` and write ``out`` (``.csv`` or ``.nc``); returns the path.

    ``resume``: continue from ``<out>.checkpoint.jsonl`` (only missing points are computed); without
    it an existing checkpoint or output needs ``force`` (start afresh); not both. An output another
    process writes is refused (``OutputBusy``) whatever the flags. ``workers``: local processes
    (default: the core count; never more than batches; 0: this process; above the cores a
    RuntimeWarning). Ctrl-C raises :class:`SweepStopped`, a fault :class:`SweepFault` (the pool is
    stopped at once). ``scheduler``: Dask address (checked, then reached, before anything is written)
    or Client (overrides ``workers``). ``batch_size``: points per task (default: ~4 tasks per worker,
    <= 256). ``_stop_after``: test hook, raise :class:`SweepInterrupted` after that many points.
    """
    from rrbody.analysis.pool import check_scheduler, connect_scheduler, plan_batches, plan_workers
    from rrbody.model.outlock import claimed

    out_p = Path(out)
    if batch_size is not None:
        batch_size = int(check("batch_size", batch_size))
    if workers is not None and scheduler is None:
        check("workers", workers)
    if scheduler is not None:
        check_scheduler(scheduler)
    # what no other writer can change first (a missing folder is named as such), then the lock, then
    # the rest under it: an output another process writes is refused whatever force or resume say
    check_outputs(out_p, grid=sweep.mode == "grid", resume=resume, force=force, existing=False)
    with claimed(output_files(out_p)):
        check_outputs(out_p, grid=sweep.mode == "grid", resume=resume, force=force)
        ck = checkpoint_path(out_p)
        spec = sweep.spec()
        done: dict[int, dict[str, Any]] = {}
        if resume and ck.exists():
            done = read_checkpoint(ck, spec)
        elif resume and out_p.exists():
            if read_meta(out_p).get("spec") != spec:
                raise ValueError(f"resume: {str(out_p)!r} holds a different sweep; refusing to mix results")
            return out_p  # already complete
        batches = plan_batches([i for i in range(sweep.size) if i not in done], batch_size, workers)
        n_workers = 0 if scheduler is not None else plan_workers(workers, len(batches))
        client = connect_scheduler(scheduler) if isinstance(scheduler, str) else scheduler
        try:
            return _compute(sweep, out_p, done, batches, client, n_workers, progress, _stop_after)
        finally:
            if client is not scheduler:
                client.close()


def _compute(sweep: Sweep, out: Path, done: dict[int, dict[str, Any]], batches: list[list[int]], client: Any,
             n_workers: int, progress: bool, stop_after: int | None) -> Path:
    """Run the batches into the checkpoint, then write the table (the caller validated and locked the
    outputs). A fault becomes :class:`SweepFault`, Ctrl-C :class:`SweepStopped`."""
    from rrbody.analysis.pool import ExecutorFault, iter_dask, iter_local

    ck = checkpoint_path(out)
    spec = sweep.spec()
    it = (iter_dask(_run_batch, spec, batches, client) if client is not None
          else iter_local(_run_batch, spec, batches, n_workers))
    bar = progress_bar(sweep.size, len(done), progress, sweep.quantity)
    n_new = 0
    try:
        for n in stream_checkpoint(ck, spec, it, done):
            n_new += n
            if bar is not None:
                bar.update(n)
            if stop_after is not None and n_new >= stop_after:
                raise SweepInterrupted(f"stopped after {n_new} points (test hook)")
        write_output(sweep, done, out, force=True)
        ck.unlink()
    except KeyboardInterrupt:
        raise SweepStopped(count_rows(ck), sweep.size, ck) from None
    except (ExecutorFault, OSError) as e:  # a dead worker, a lost scheduler; a full disk, named where known
        what = (str(e) if isinstance(e, ExecutorFault) else
                f"{e.strerror or e}: {str(e.filename)!r}" if e.filename else f"{e.strerror or e}")
        raise SweepFault(what, count_rows(ck), sweep.size, ck) from None
    finally:
        with contextlib.suppress(Exception):
            it.close()  # type: ignore[attr-defined]
        if bar is not None:
            bar.close()
    return out


def progress_bar(total: int, initial: int, progress: bool, desc: str) -> Any:
    """A tqdm bar over ``total`` points (``initial`` of them done, ``desc`` after "sweep "), or None
    without ``progress`` (tqdm is then not imported)."""
    if not progress:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, desc=f"sweep {desc}", unit="pt", dynamic_ncols=True)


def run_fresh_or_resume(sweep: Sweep, out: str | os.PathLike[str], *, workers: int | None = None,
                        progress: bool = False) -> Any:
    """For scene scripts: recompute ``out`` from scratch, unless an interrupted run left a
    checkpoint for the same sweep, which is then resumed. Returns :func:`load_sweep` of the result."""
    ck = checkpoint_path(out)
    path = run_sweep(sweep, out, resume=ck.exists(), force=not ck.exists(), workers=workers, progress=progress)
    return load_sweep(path)
