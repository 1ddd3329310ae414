"""Parameter sweeps: flip time, H_c, the RR test, Lyapunov maps (chaos) over 1-D/2-D grids or lists of scenes.

A :class:`Sweep` names a base scene, the axes to vary and the quantity to compute. :func:`run_sweep`
evaluates every point on an executor:

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

Parameters of the base scene
----------------------------
Any scene: the flat parameters of :func:`rrbody.model.scene.scene_from_params` (``body`` = rod,
disk or ellipse; ``H`` or ``l``, ``R0``, ``delta``, ``orientation``, ``omega``, ``d``, ``k`` or
``mu``/``g``, ``friction``, ``phi0``, ``phi_dot0``, ``t_max``, ``friction_method``, ``samples``,
``no_drive``, ``v0``, ``spin0``), whose numeric ones axes vary by name; or a full
``Scene.describe()`` dictionary under the key ``"scene"``, whose entries axes vary by dotted path
(``"drive.omega"``, ``"friction.coeff"``, ``"l"``, ``"R_A"``, ``"phi0"``, ...). Free bodies
(``no_drive``) have the quantity ``rest`` (stop time, distance, turn; needs the option ``t_max``).

Validation
----------
A :class:`Sweep` checks its options and every value of every axis when it is built (each value
with the base and the other axes' first values); :func:`run_sweep` checks the outputs, the options
and the scheduler (its address, then that it answers) before any work or file.
"""

from __future__ import annotations

import contextlib
import copy
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rrbody._version import __version__
from rrbody.analysis.chaos_map import CHAOS_COLUMNS, CHAOS_OPTIONS, check_chaos_options, check_chaos_scene
from rrbody.analysis.sweep_store import check_outputs, checkpoint_path, count_rows, load_sweep, output_files, \
    read_checkpoint, read_meta, stream_checkpoint, write_output
from rrbody.model.checks import MissingParameters, check, check_choice
from rrbody.model.scene import NUMERIC_SCENE_PARAMS, SCENE_PARAMS

__all__ = ["Sweep", "QUANTITIES", "run_sweep", "load_sweep", "make_scene", "evaluate_point", "checkpoint_path",
           "SweepInterrupted", "SweepStopped", "SweepFault", "read_meta", "run_fresh_or_resume", "AXIS_PARAMS"]

#: quantity -> result columns it produces (in order)
QUANTITIES: dict[str, tuple[str, ...]] = {
    "flip_time": ("t_f", "phi_min", "t_phi_min", "reverse_rotation", "T1", "settled", "n_steps", "regime"),
    "critical_h": ("H_c",),
    "rr": ("reverse_rotation",),
    "rest": ("t_stop", "distance", "turn", "status"),
    "chaos": CHAOS_COLUMNS,
}
_OPTION_KEYS = {"flip_time": ("accuracy", "rtol", "t_max"),
                "critical_h": ("accuracy", "rtol", "tol", "H_lo", "H_hi", "n_scan"),
                "rr": ("accuracy", "rtol"),
                "rest": ("accuracy", "rtol", "t_max"),
                "chaos": CHAOS_OPTIONS}
_OPTION_LIMITS = {"rtol": "rtol", "t_max": "t_max", "tol": "tol", "H_lo": "H", "H_hi": "H"}


#: parameters a flat sweep may put on an axis: every numeric scene parameter
AXIS_PARAMS: tuple[str, ...] = NUMERIC_SCENE_PARAMS


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


@dataclass(frozen=True)
class Sweep:
    """What to compute.

    Parameters
    ----------
    base : dict
        Fixed scene parameters: the flat parameters of ``scene_from_params`` (any body), or
        ``{"scene": Scene.describe()}``.
    axes : dict name -> sequence of float
        The varied parameters, in order. ``mode="grid"``: the Cartesian product (the first axis
        varies slowest); ``mode="list"``: the axes are zipped (equal lengths), one point per index.
    quantity : {"flip_time", "critical_h", "rr", "rest", "chaos"}
        ``critical_h`` varies the rod-mass ``k``, ``omega``, ``phi0``, ``friction`` (H is the answer);
        ``rest`` is for free bodies (``no_drive``); ``chaos``: the maximal Lyapunov exponent and the
        fraction of time in reverse rotation (:mod:`rrbody.analysis.chaos_map`).
    options : dict
        Passed to the analysis: ``accuracy``, ``rtol``; ``t_max`` (flip_time, rest); ``tol``,
        ``H_lo``, ``H_hi``, ``n_scan`` (critical_h); ``periods`` or ``t_max``, ``transient``,
        ``rtol``, ``d0``, ``rr_samples``, ``estimate`` (chaos).
    """

    base: dict[str, Any]
    axes: dict[str, tuple[float, ...]]
    quantity: str = "flip_time"
    mode: str = "grid"
    options: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_choice("quantity", self.quantity, tuple(QUANTITIES))
        check_choice("mode", self.mode, ("grid", "list"))
        if not isinstance(self.axes, dict) or not self.axes:
            raise ValueError(f"axes must be a non-empty dict name -> values, got {self.axes!r}")
        axes: dict[str, tuple[float, ...]] = {}
        for name, vals in self.axes.items():
            try:
                tv = tuple(float(v) for v in np.atleast_1d(np.asarray(vals, dtype=float)))
            except (TypeError, ValueError):
                raise ValueError(f"axes[{name!r}] must be numbers, got {vals!r}") from None
            if not tv:
                raise ValueError(f"axes[{name!r}] must hold at least one value, got {vals!r}")
            if not all(math.isfinite(v) for v in tv):
                raise ValueError(f"axes[{name!r}] must be finite numbers, got {vals!r}")
            axes[str(name)] = tv
        object.__setattr__(self, "axes", axes)
        if self.mode == "list" and len({len(v) for v in axes.values()}) != 1:
            raise ValueError(f"mode='list' needs axes of equal length, got lengths "
                             f"{ {n: len(v) for n, v in axes.items()} }")
        self._check_options()
        if "scene" in self.base:
            if self.quantity == "critical_h":
                raise ValueError("quantity 'critical_h' needs rod-mass base parameters (k, omega, ...), not a scene")
        else:
            bad = [k for k in self.base if k not in SCENE_PARAMS]
            if bad:
                raise ValueError(f"sweep parameters must be among {', '.join(SCENE_PARAMS)}, got {bad!r}")
            bad = [k for k in axes if k not in AXIS_PARAMS]
            if bad:
                raise ValueError(f"axes must be among {', '.join(AXIS_PARAMS)}, got {bad!r}")
            both = [k for k in axes if k in self.base]
            if both:
                raise ValueError(f"base and axes both give {', '.join(both)} (base {both[0]}={self.base[both[0]]!r}); "
                                 "an axis sets its parameter at every point: give each parameter in one place")
        self._check_points()

    def _check_options(self) -> None:
        bad = [k for k in self.options if k not in _OPTION_KEYS[self.quantity]]
        if bad:
            raise ValueError(f"options for {self.quantity} must be among {', '.join(_OPTION_KEYS[self.quantity])}, "
                             f"got {bad!r}")
        if self.quantity == "chaos":  # its own options (periods, transient, ...): rrbody.analysis.chaos_map
            check_chaos_options(self.options)
            return
        for k, v in self.options.items():
            if k == "accuracy":
                check_choice("accuracy", v, ("draft", "default", "paper"))
            elif k == "n_scan":
                check("samples", v, label="n_scan")
            elif v is not None:
                check(_OPTION_LIMITS[k], v, label=k)
        if self.quantity == "rest" and self.options.get("t_max") is None:
            raise ValueError("t_max must be given for quantity 'rest' (the horizon of a free body, s)")

    def _check_points(self) -> None:
        """Build the scene of every axis value (the other axes at their first values), before any work:
        a bad value fails now, naming its axis, not as an error row after hours."""
        first = self.point(0)
        for name, vals in self.axes.items():
            for v in dict.fromkeys(vals):
                try:
                    scene = make_scene(self, {**first, name: v})
                except MissingParameters as e:
                    raise MissingParameters(e.names, prefix="base must give every parameter of the scene that is "
                                                           "not on an axis") from None
                except ValueError as e:
                    raise ValueError(f"axis {name}: {e}" if name in str(e).split(" ")[0] else str(e)) from None
                if self.quantity == "rest" and scene.driven:
                    raise ValueError("quantity 'rest' needs a free body (no_drive=True)")
                if self.quantity != "rest" and not scene.driven:
                    raise ValueError(f"quantity {self.quantity!r} needs a driven scene; for a free body use 'rest'")
                if self.quantity == "chaos":
                    check_chaos_scene(scene, self.options)

    @property
    def columns(self) -> tuple[str, ...]:
        """The result columns of the quantity."""
        return QUANTITIES[self.quantity]

    @property
    def shape(self) -> tuple[int, ...]:
        if self.mode == "list":
            return (len(next(iter(self.axes.values()))),)
        return tuple(len(v) for v in self.axes.values())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def point(self, i: int) -> dict[str, float]:
        """Axis values of point ``i`` (row-major index over the grid)."""
        names = list(self.axes)
        if self.mode == "list":
            return {n: self.axes[n][i] for n in names}
        idx = np.unravel_index(i, self.shape)
        return {n: self.axes[n][int(j)] for n, j in zip(names, idx)}

    def spec(self) -> dict[str, Any]:
        """JSON-ready description; two sweeps with equal specs compute identical results."""
        from rrbody.model.trajectory import _jsonable

        return _jsonable({"base": self.base, "axes": self.axes, "quantity": self.quantity, "mode": self.mode,
                          "options": self.options, "rrbody_version": __version__})


# ---- evaluating one point --------------------------------------------------------------------
def _set_path(d: dict[str, Any], path: str, value: float) -> None:
    keys = path.split(".")
    cur = d
    for k in keys[:-1]:
        if not isinstance(cur.get(k), dict):
            raise ValueError(f"axis {path!r}: {k!r} is not a group in the scene description")
        cur = cur[k]
    if keys[-1] not in cur:
        raise ValueError(f"axis {path!r}: {keys[-1]!r} is not a scene parameter (have {sorted(cur)})")
    cur[keys[-1]] = value


def make_scene(sweep: Sweep, values: dict[str, float]) -> Any:
    """The Scene of one sweep point (base parameters overridden by the axis ``values``)."""
    from rrbody.model.scene import Scene, scene_from_params

    if "scene" in sweep.base:
        desc = copy.deepcopy(sweep.base["scene"])
        for name, v in values.items():
            _set_path(desc, name, v)
        if "phi_dot0" in desc and "phi_dot0" not in values and sweep.base.get("impulsive", True):
            desc["phi_dot0"] = None  # keep the impulsive start consistent with the varied parameters
        return Scene.from_description(desc)
    kw = {**sweep.base, **values}
    if "samples" in kw:
        kw["samples"] = int(kw["samples"]) if float(kw["samples"]).is_integer() else kw["samples"]
    if sweep.quantity == "critical_h":
        kw.setdefault("H", 0.5)  # placeholder for validation only: H is the unknown
    return scene_from_params(**kw)


def evaluate_point(sweep: Sweep, values: dict[str, float]) -> dict[str, Any]:
    """Compute the sweep's quantity at one point; errors become a row with an ``error`` message."""
    from rrbody.analysis.flip import critical_h, flip_time, reverse_rotation_exists

    opts = dict(sweep.options)
    try:
        scene = make_scene(sweep, values)
        if sweep.quantity == "critical_h":
            hc = critical_h(scene.k, scene.omega, phi0=scene.phi0, friction=scene.friction.law, **opts)
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
        return {"t_f": r.t_f, "phi_min": r.phi_min, "t_phi_min": r.t_phi_min, "reverse_rotation": bool(r.reverse_rotation),
                "T1": r.T1, "settled": bool(r.settled), "n_steps": int(r.n_steps), "regime": r.regime, "error": ""}
    except ValueError as e:
        return {**{c: None for c in sweep.columns}, "error": str(e)}


def _run_batch(spec: dict[str, Any], indices: list[int]) -> list[dict[str, Any]]:
    """Worker entry point (module level, so it pickles): evaluate the points ``indices``."""
    sweep = _sweep_from_spec(spec)
    return [{"i": i, **evaluate_point(sweep, sweep.point(i))} for i in indices]


def _sweep_from_spec(spec: dict[str, Any]) -> Sweep:
    return Sweep(base=spec["base"], axes={k: tuple(v) for k, v in spec["axes"].items()}, quantity=spec["quantity"],
                 mode=spec["mode"], options=spec["options"])


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
    bar = _bar(sweep.size, len(done), progress, sweep.quantity)
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


def _bar(total: int, initial: int, progress: bool, desc: str) -> Any:
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
