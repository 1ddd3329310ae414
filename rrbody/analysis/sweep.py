"""Parameter sweeps: flip time, H_c or the RR test over 1-D/2-D grids or lists of scene parameters.

A :class:`Sweep` names a base scene, the axes to vary and the quantity to compute. :func:`run_sweep`
evaluates every point on an executor:

- local processes (default; ``concurrent.futures.ProcessPoolExecutor`` over all cores),
- a Dask cluster when ``scheduler`` is a scheduler address (``tcp://host:8786``) or a
  ``distributed.Client``,
- ``workers=0``: in this process (debugging, tests).

Points are sent in batches (``batch_size`` points per task) so that per-task overhead stays small
next to the ~1 ms a typical flip time costs.

Checkpoint and resume
---------------------
Finished points stream to ``<out>.checkpoint.jsonl``: a JSON header line (the sweep
specification and the rrbody version) then one JSON line per point, flushed and fsync'ed as each
batch finishes. The file is append-only, so a kill can at worst leave one truncated last line;
``resume=True`` drops it, checks that the header matches the requested sweep (a different scene,
grid, quantity, options or rrbody version raises ValueError rather than mixing results) and
computes only the missing points. The final table is written atomically (:mod:`rrbody.io`) and
the checkpoint removed. Results do not depend on the executor, the batch size or interruptions:
each point is an independent deterministic computation.

Output
------
``.csv``: one row per point (axis values, then results); the first line is
``# rrbody-sweep: {json}`` with the specification, the axes (the grid metadata) and the rrbody
version. ``.nc``: a NetCDF file (xarray, h5netcdf engine) with one dimension per grid axis and the
same metadata in the attribute ``rrbody_sweep`` (NetCDF4 via h5netcdf when h5py is installed, else
NetCDF3 via scipy). A ``<out>.json`` sidecar repeats the metadata.

Parameters of the base scene
----------------------------
Either the rod-mass keywords of :func:`rrbody.scene.rod_mass_scene` (``H``, ``k``, ``omega``,
``phi0``, ``friction``, ``d``, ``phi_dot0``, ``t_max``), which axes may vary by name; or a full
``Scene.describe()`` dictionary under the key ``"scene"``, whose entries axes vary by dotted path
(``"drive.omega"``, ``"friction.coeff"``, ``"l"``, ``"R_A"``, ``"phi0"``, ...).
"""

from __future__ import annotations

import contextlib
import copy
import csv
import json
import math
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rrbody._version import __version__

__all__ = ["Sweep", "QUANTITIES", "run_sweep", "load_sweep", "make_scene", "evaluate_point", "checkpoint_path",
           "SweepInterrupted", "add_parser", "read_meta", "run_fresh_or_resume"]

#: quantity -> result columns it produces (in order)
QUANTITIES: dict[str, tuple[str, ...]] = {
    "flip_time": ("t_f", "phi_min", "t_phi_min", "reverse_rotation", "T1", "settled", "n_steps", "regime"),
    "critical_h": ("H_c",),
    "rr": ("reverse_rotation",),
}
_ROD_KEYS = ("H", "k", "omega", "phi0", "friction", "d", "phi_dot0", "t_max")
_OPTION_KEYS = {"flip_time": ("accuracy", "rtol", "t_max"),
                "critical_h": ("accuracy", "rtol", "tol", "H_lo", "H_hi", "n_scan"),
                "rr": ("accuracy", "rtol")}
_HEADER = "# rrbody-sweep: "


class SweepInterrupted(RuntimeError):
    """Raised by the test hook ``_stop_after``: the sweep stopped as if killed, checkpoint intact."""


@dataclass(frozen=True)
class Sweep:
    """What to compute.

    Parameters
    ----------
    base : dict
        Fixed scene parameters: rod-mass keywords, or ``{"scene": Scene.describe()}``.
    axes : dict name -> sequence of float
        The varied parameters, in order. ``mode="grid"``: the Cartesian product (the first axis
        varies slowest); ``mode="list"``: the axes are zipped (equal lengths), one point per index.
    quantity : {"flip_time", "critical_h", "rr"}
        ``critical_h`` varies the rod-mass ``k``, ``omega``, ``phi0``, ``friction`` (H is the answer).
    options : dict
        Passed to the analysis: ``accuracy``, ``rtol``; ``t_max`` (flip_time); ``tol``, ``H_lo``,
        ``H_hi``, ``n_scan`` (critical_h).
    """

    base: dict[str, Any]
    axes: dict[str, tuple[float, ...]]
    quantity: str = "flip_time"
    mode: str = "grid"
    options: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.quantity not in QUANTITIES:
            raise ValueError(f"quantity must be one of {', '.join(QUANTITIES)}, got {self.quantity!r}")
        if self.mode not in ("grid", "list"):
            raise ValueError(f"mode must be 'grid' or 'list', got {self.mode!r}")
        if not isinstance(self.axes, dict) or not self.axes:
            raise ValueError(f"axes must be a non-empty dict name -> values, got {self.axes!r}")
        axes: dict[str, tuple[float, ...]] = {}
        for name, vals in self.axes.items():
            tv = tuple(float(v) for v in np.atleast_1d(np.asarray(vals, dtype=float)))
            if not tv:
                raise ValueError(f"axes[{name!r}] must hold at least one value, got {vals!r}")
            if not all(math.isfinite(v) for v in tv):
                raise ValueError(f"axes[{name!r}] must be finite numbers, got {vals!r}")
            axes[str(name)] = tv
        object.__setattr__(self, "axes", axes)
        if self.mode == "list" and len({len(v) for v in axes.values()}) != 1:
            raise ValueError(f"mode='list' needs axes of equal length, got lengths "
                             f"{ {n: len(v) for n, v in axes.items()} }")
        bad = [k for k in self.options if k not in _OPTION_KEYS[self.quantity]]
        if bad:
            raise ValueError(f"options for {self.quantity} must be among {', '.join(_OPTION_KEYS[self.quantity])}, "
                             f"got {bad!r}")
        if "scene" in self.base:
            if self.quantity == "critical_h":
                raise ValueError("quantity 'critical_h' needs rod-mass base parameters (k, omega, ...), not a scene")
        else:
            bad = [k for k in (*self.base, *axes) if k not in _ROD_KEYS]
            if bad:
                raise ValueError(f"rod-mass sweep parameters must be among {', '.join(_ROD_KEYS)}, got {bad!r}")
        # Validate one point now, so that a bad parameter fails before any work is scheduled.
        try:
            make_scene(self, self.point(0))
        except TypeError as e:
            raise ValueError(f"base must give every rod-mass parameter not on an axis (H, k, omega): {e}") from None

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
    from rrbody.model.scene import Scene, rod_mass_scene

    if "scene" in sweep.base:
        desc = copy.deepcopy(sweep.base["scene"])
        for name, v in values.items():
            _set_path(desc, name, v)
        if "phi_dot0" in desc and "phi_dot0" not in values and sweep.base.get("impulsive", True):
            desc["phi_dot0"] = None  # keep the impulsive start consistent with the varied parameters
        return Scene.from_description(desc)
    kw = {**sweep.base, **values}
    if sweep.quantity == "critical_h":
        kw.setdefault("H", 0.5)  # placeholder for validation only: H is the unknown
    return rod_mass_scene(**kw)


def evaluate_point(sweep: Sweep, values: dict[str, float]) -> dict[str, Any]:
    """Compute the sweep's quantity at one point; errors become a row with an ``error`` message."""
    from rrbody.analysis.flip import critical_h, flip_time, reverse_rotation_exists

    opts = dict(sweep.options)
    try:
        if sweep.quantity == "critical_h":
            kw = {**sweep.base, **values}
            hc = critical_h(float(kw["k"]), float(kw["omega"]), phi0=float(kw.get("phi0", math.pi)),
                            friction=str(kw.get("friction", "dry")), **opts)
            return {"H_c": hc, "error": ""}
        scene = make_scene(sweep, values)
        if sweep.quantity == "rr":
            return {"reverse_rotation": bool(reverse_rotation_exists(scene, **opts)), "error": ""}
        r = flip_time(scene, **opts)
        return {"t_f": r.t_f, "phi_min": r.phi_min, "t_phi_min": r.t_phi_min, "reverse_rotation": bool(r.reverse_rotation),
                "T1": r.T1, "settled": bool(r.settled), "n_steps": int(r.n_steps), "regime": r.regime, "error": ""}
    except ValueError as e:
        return {**{c: None for c in QUANTITIES[sweep.quantity]}, "error": str(e)}


def _run_batch(spec: dict[str, Any], indices: list[int]) -> list[dict[str, Any]]:
    """Worker entry point (module level, so it pickles): evaluate the points ``indices``."""
    sweep = _sweep_from_spec(spec)
    return [{"i": i, **evaluate_point(sweep, sweep.point(i))} for i in indices]


def _sweep_from_spec(spec: dict[str, Any]) -> Sweep:
    return Sweep(base=spec["base"], axes={k: tuple(v) for k, v in spec["axes"].items()}, quantity=spec["quantity"],
                 mode=spec["mode"], options=spec["options"])


# ---- checkpoint ------------------------------------------------------------------------------
def checkpoint_path(out: str | os.PathLike[str]) -> Path:
    """The checkpoint beside ``out``: ``<out>.checkpoint.jsonl``."""
    p = Path(out)
    return p.with_name(p.name + ".checkpoint.jsonl")


def _read_checkpoint(path: Path, spec: dict[str, Any]) -> dict[int, dict[str, Any]]:
    """Finished rows of a checkpoint; refuses one written for a different sweep. A truncated last
    line (a kill mid-write) is dropped and the file rewritten without it."""
    text = path.read_text()
    lines = text.split("\n")
    if not lines or not lines[0].strip():
        return {}
    try:
        head = json.loads(lines[0])
    except json.JSONDecodeError:
        raise ValueError(f"checkpoint {str(path)!r} has no valid header; delete it to start afresh") from None
    if head != spec:
        diff = sorted(k for k in set(head) | set(spec) if head.get(k) != spec.get(k))
        raise ValueError(f"resume: checkpoint {str(path)!r} was written for a different sweep (differs in "
                         f"{', '.join(diff)}: was {', '.join(f'{k}={head.get(k)!r}' for k in diff)}); refusing to "
                         "mix results. Use a new output path, or delete the checkpoint to start afresh")
    rows: dict[int, dict[str, Any]] = {}
    good = [lines[0]]
    for ln in lines[1:]:
        if not ln.strip():
            continue
        try:
            row = json.loads(ln)
            rows[int(row["i"])] = row
            good.append(ln)
        except (json.JSONDecodeError, KeyError, TypeError, ValueError):
            continue  # a partial line from an interrupted write: recompute that point
    clean = "\n".join(good) + "\n"
    if clean != text:
        from rrbody.model.io import atomic_write_text

        atomic_write_text(path, clean, force=True, name="checkpoint")
    return rows


# ---- executors -------------------------------------------------------------------------------
def _batches(todo: Sequence[int], size: int) -> list[list[int]]:
    return [list(todo[j:j + size]) for j in range(0, len(todo), size)]


def _iter_local(spec: dict[str, Any], batches: list[list[int]], workers: int) -> Iterator[list[dict[str, Any]]]:
    if workers == 0:
        for b in batches:
            yield _run_batch(spec, b)
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed

    with ProcessPoolExecutor(max_workers=workers) as ex:
        futs = [ex.submit(_run_batch, spec, b) for b in batches]
        try:
            for f in as_completed(futs):
                yield f.result()
        finally:
            for f in futs:
                f.cancel()


def _iter_dask(spec: dict[str, Any], batches: list[list[int]], scheduler: Any) -> Iterator[list[dict[str, Any]]]:
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = [client.submit(_run_batch, spec, b, pure=False) for b in batches]
        try:
            for f in as_completed(futs):
                yield f.result()
        finally:
            client.cancel(futs)
    finally:
        if own:
            client.close()


# ---- running ---------------------------------------------------------------------------------
def run_sweep(sweep: Sweep, out: str | os.PathLike[str], *, resume: bool = False, force: bool = False,
              scheduler: Any = None, workers: int | None = None, batch_size: int | None = None,
              progress: bool = True, _stop_after: int | None = None) -> Path:
    """Evaluate ``sweep`` and write ``out`` (``.csv`` or ``.nc``); returns the path.

    ``resume``: continue from ``<out>.checkpoint.jsonl`` (only missing points are computed).
    Without ``resume`` an existing checkpoint or output is refused unless ``force`` (which starts
    afresh). ``workers``: local processes (default: all cores; 0 runs in this process).
    ``scheduler``: Dask scheduler address or Client (overrides ``workers``). ``batch_size``:
    points per task (default: about 4 tasks per worker, at most 256 points). ``_stop_after``:
    test hook, raise :class:`SweepInterrupted` once that many points are checkpointed.
    """
    from rrbody.model.io import atomic_write_text, check_writable

    out_p = Path(out)
    if out_p.suffix not in (".csv", ".nc"):
        raise ValueError(f"out must end in .csv or .nc, got {str(out_p)!r}")
    if out_p.suffix == ".nc" and sweep.mode != "grid":
        raise ValueError("out: NetCDF output needs mode='grid'; use .csv for lists")
    ck = checkpoint_path(out_p)
    spec = sweep.spec()
    if not resume:
        check_writable(out_p, force=force, name="out")
        if ck.exists() and not force:
            raise ValueError(f"out: checkpoint {str(ck)!r} exists from an earlier run; pass resume=True (--resume) "
                             "to continue it or force=True (--force) to start afresh")
    else:
        parent = out_p.parent if str(out_p.parent) else Path(".")
        if not parent.is_dir():
            raise ValueError(f"out: folder {str(parent)!r} does not exist")
    if workers is not None and (not isinstance(workers, int) or workers < 0):
        raise ValueError(f"workers must be an integer >= 0, got {workers!r}")
    done: dict[int, dict[str, Any]] = {}
    if resume and ck.exists():
        done = _read_checkpoint(ck, spec)
    elif resume and out_p.exists() and not ck.exists():
        meta = read_meta(out_p)
        if meta.get("spec") != spec:
            raise ValueError(f"resume: {str(out_p)!r} holds a different sweep; refusing to mix results")
        return out_p  # already complete
    else:
        atomic_write_text(ck, json.dumps(spec) + "\n", force=True, name="checkpoint")
    todo = [i for i in range(sweep.size) if i not in done]
    n_workers = (os.cpu_count() or 1) if workers is None else workers
    if batch_size is None:
        batch_size = max(1, min(256, math.ceil(len(todo) / max(1, 4 * max(1, n_workers)))))
    elif not isinstance(batch_size, int) or batch_size < 1:
        raise ValueError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    batches = _batches(todo, batch_size)
    it = _iter_dask(spec, batches, scheduler) if scheduler is not None else _iter_local(spec, batches, n_workers)
    bar = _bar(sweep.size, len(done), progress, sweep.quantity)
    n_new = 0
    try:
        with open(ck, "a") as fh:
            for rows in it:
                for r in rows:
                    fh.write(json.dumps(r) + "\n")
                    done[int(r["i"])] = r
                fh.flush()
                os.fsync(fh.fileno())
                n_new += len(rows)
                if bar is not None:
                    bar.update(len(rows))
                if _stop_after is not None and n_new >= _stop_after:
                    raise SweepInterrupted(f"stopped after {n_new} points (test hook)")
    finally:
        with contextlib.suppress(Exception):
            it.close()  # type: ignore[attr-defined]
        if bar is not None:
            bar.close()
    _write_output(sweep, done, out_p, force=True)
    ck.unlink()
    return out_p


def _bar(total: int, initial: int, progress: bool, desc: str) -> Any:
    if not progress:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, desc=f"sweep {desc}", unit="pt", dynamic_ncols=True)


def _columns(sweep: Sweep) -> list[str]:
    return [*sweep.axes, *QUANTITIES[sweep.quantity], "error"]


def _meta(sweep: Sweep) -> dict[str, Any]:
    return {"spec": sweep.spec(), "shape": list(sweep.shape), "columns": _columns(sweep),
            "order": "row-major over the axes in the order given (first axis slowest)" if sweep.mode == "grid"
            else "one row per list index", "rrbody_version": __version__}


def _write_output(sweep: Sweep, done: dict[int, dict[str, Any]], out: Path, *, force: bool) -> None:
    from rrbody.model.io import atomic_path, atomic_write_text

    missing = [i for i in range(sweep.size) if i not in done]
    if missing:
        raise ValueError(f"internal: {len(missing)} sweep points missing (first {missing[:5]})")
    meta = _meta(sweep)
    cols = _columns(sweep)
    rows = []
    for i in range(sweep.size):
        r = done[i]
        rows.append({**sweep.point(i), **{c: r.get(c) for c in cols if c not in sweep.axes}})
    if out.suffix == ".csv":
        with atomic_path(out, force=force, name="out") as tmp, open(tmp, "w", newline="") as fh:
            fh.write(_HEADER + json.dumps(meta) + "\n")
            w = csv.writer(fh)
            w.writerow(cols)
            for r in rows:
                w.writerow(["" if r[c] is None else (repr(float(r[c])) if isinstance(r[c], float) else r[c])
                            for c in cols])
    else:
        import xarray as xr

        coords = {n: np.asarray(v) for n, v in sweep.axes.items()}
        data: dict[str, Any] = {}
        for c in cols:
            if c in sweep.axes:
                continue
            vals = [r[c] for r in rows]
            if c in ("regime", "error"):
                arr = np.asarray(["" if v is None else str(v) for v in vals], dtype=object)
            elif c in ("reverse_rotation", "settled"):
                arr = np.asarray([-1 if v is None else int(bool(v)) for v in vals], dtype=np.int8)
            else:
                arr = np.asarray([np.nan if v is None else float(v) for v in vals], dtype=float)
            data[c] = (list(sweep.axes), arr.reshape(sweep.shape))
        ds = xr.Dataset(data, coords=coords, attrs={"rrbody_sweep": json.dumps(meta)})
        with atomic_path(out, force=force, name="out") as tmp:
            ds.to_netcdf(tmp, engine=_nc_engine())
    atomic_write_text(out.with_name(out.name + ".json"), json.dumps(meta, indent=1) + "\n", force=True,
                      name="sidecar")


def read_meta(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The metadata of a sweep output (from its sidecar, else its header)."""
    p = Path(path)
    side = p.with_name(p.name + ".json")
    if side.exists():
        return json.loads(side.read_text())
    if p.suffix == ".csv":
        first = p.read_text().split("\n", 1)[0]
        if first.startswith(_HEADER):
            return json.loads(first[len(_HEADER):])
    raise ValueError(f"{str(p)!r} is not an rrbody sweep output (no metadata)")


def load_sweep(path: str | os.PathLike[str]) -> Any:
    """Read a sweep output: a list of row dicts (CSV) or an ``xarray.Dataset`` (NetCDF)."""
    p = Path(path)
    if p.suffix == ".nc":
        import xarray as xr

        with xr.open_dataset(p, engine=_nc_engine()) as ds:
            return ds.load()
    with open(p, newline="") as fh:
        first = fh.readline()
        if not first.startswith(_HEADER):
            raise ValueError(f"{str(p)!r} is not an rrbody sweep CSV")
        return list(csv.DictReader(fh))


def _nc_engine() -> str:
    """h5netcdf (NetCDF4) when h5py is importable, else scipy's NetCDF3 writer (always available)."""
    try:
        import h5py  # noqa: F401
    except ImportError:
        return "scipy"
    return "h5netcdf"


def run_fresh_or_resume(sweep: Sweep, out: str | os.PathLike[str], *, workers: int | None = None,
                        progress: bool = False) -> Any:
    """For scene scripts: recompute ``out`` from scratch, unless an interrupted run left a
    checkpoint for the same sweep, which is then resumed. Returns :func:`load_sweep` of the result."""
    ck = checkpoint_path(out)
    path = run_sweep(sweep, out, resume=ck.exists(), force=not ck.exists(), workers=workers, progress=progress)
    return load_sweep(path)
