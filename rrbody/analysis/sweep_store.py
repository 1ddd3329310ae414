"""Sweep storage: the append-only checkpoint and the final table (CSV or NetCDF) with its metadata.

``sweep`` arguments are :class:`rrbody.analysis.sweep.Sweep` objects (typed ``Any`` here: this
module sits below the sweep engine and does not import it).

See :mod:`rrbody.analysis.sweep` for the formats. Every file is written atomically
(:mod:`rrbody.model.io`); the checkpoint is appended to, flushed and fsync'ed per batch.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from rrbody._version import __version__

__all__ = ["checkpoint_path", "read_checkpoint", "write_output", "read_meta", "load_sweep", "columns", "HEADER",
           "count_rows"]

HEADER = "# rrbody-sweep: "


def checkpoint_path(out: str | os.PathLike[str]) -> Path:
    """The checkpoint beside ``out``: ``<out>.checkpoint.jsonl``."""
    p = Path(out)
    return p.with_name(p.name + ".checkpoint.jsonl")


def read_checkpoint(path: Path, spec: dict[str, Any]) -> dict[int, dict[str, Any]]:
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


def columns(sweep: Any) -> list[str]:
    return [*sweep.axes, *sweep.columns, "error"]


def _meta(sweep: Any) -> dict[str, Any]:
    return {"spec": sweep.spec(), "shape": list(sweep.shape), "columns": columns(sweep),
            "order": "row-major over the axes in the order given (first axis slowest)" if sweep.mode == "grid"
            else "one row per list index", "rrbody_version": __version__}


def write_output(sweep: Any, done: dict[int, dict[str, Any]], out: Path, *, force: bool) -> None:
    from rrbody.model.io import atomic_path, atomic_write_text

    missing = [i for i in range(sweep.size) if i not in done]
    if missing:
        raise ValueError(f"internal: {len(missing)} sweep points missing (first {missing[:5]})")
    meta = _meta(sweep)
    cols = columns(sweep)
    rows = []
    for i in range(sweep.size):
        r = done[i]
        rows.append({**sweep.point(i), **{c: r.get(c) for c in cols if c not in sweep.axes}})
    if out.suffix == ".csv":
        with atomic_path(out, force=force, name="out") as tmp, open(tmp, "w", newline="") as fh:
            fh.write(HEADER + json.dumps(meta) + "\n")
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
        if first.startswith(HEADER):
            return json.loads(first[len(HEADER):])
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
        if not first.startswith(HEADER):
            raise ValueError(f"{str(p)!r} is not an rrbody sweep CSV")
        return list(csv.DictReader(fh))


def _nc_engine() -> str:
    """h5netcdf (NetCDF4) when h5py is importable, else scipy's NetCDF3 writer (always available)."""
    try:
        import h5py  # noqa: F401
    except ImportError:
        return "scipy"
    return "h5netcdf"


def count_rows(path: Path) -> int:
    """Finished points in a checkpoint (for the message after an interruption)."""
    try:
        with open(path) as fh:
            return max(0, sum(1 for ln in fh if ln.strip()) - 1)
    except OSError:
        return 0
