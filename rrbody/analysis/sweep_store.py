"""Sweep storage: the append-only checkpoint and the final table (CSV or NetCDF) with its metadata.

``sweep`` arguments are :class:`rrbody.analysis.sweep.Sweep` objects (typed ``Any`` here: this
module sits below the sweep engine and does not import it).

Every file is written atomically (:mod:`rrbody.model.io`); the checkpoint is appended to, flushed
and fsync'ed per batch (its format: :mod:`rrbody.analysis.sweep`).

Output
------
``.csv``: one row per point (axis values, then results); the first line is
``# rrbody-sweep: {json}`` with the specification, the axes (the grid metadata) and the rrbody
version. ``.nc``: a NetCDF file (xarray, h5netcdf engine) with one dimension per grid axis and the
same metadata in the attribute ``rrbody_sweep`` (NetCDF4 via h5netcdf when h5py is installed, else
NetCDF3 via scipy). A ``<out>.json`` sidecar repeats the metadata.

One output, three files (the table, its checkpoint, its sidecar): :func:`output_files` lists them,
for the locks that keep a second writer away and for :func:`check_outputs`, which validates them
all before a sweep computes or writes anything.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from rrbody._version import __version__

__all__ = ["checkpoint_path", "read_checkpoint", "write_output", "read_meta", "load_sweep", "columns", "HEADER",
           "count_rows", "output_files", "check_outputs", "stream_checkpoint"]

HEADER = "# rrbody-sweep: "


def checkpoint_path(out: str | os.PathLike[str]) -> Path:
    """The checkpoint beside ``out``: ``<out>.checkpoint.jsonl``."""
    p = Path(out)
    return p.with_name(p.name + ".checkpoint.jsonl")


def output_files(out: str | os.PathLike[str]) -> list[tuple[str, Path]]:
    """Every file a sweep to ``out`` writes, as ``(name, path)``: the table, its checkpoint, its sidecar."""
    p = Path(out)
    return [("out", p), ("checkpoint", checkpoint_path(p)), ("sidecar", p.with_name(p.name + ".json"))]


def check_outputs(out: str | os.PathLike[str], *, grid: bool, resume: bool, force: bool, existing: bool = True,
                  name: str = "out") -> None:
    """Validate a sweep's outputs before any work: the suffix (``.nc`` needs a grid), its writer
    installed (``.nc``: xarray, else :class:`~rrbody.model.extras.MissingExtraError` naming the
    ``data`` extra), every file a regular file or absent in a writable folder; an existing table or
    sidecar (the table's own file too: nothing of the user's is replaced) needs ``force``, or
    ``resume`` with a sweep to resume (its checkpoint or its table there), and an existing checkpoint
    needs ``resume`` or ``force``. ValueError naming ``out``.

    ``name``: the output as the caller calls it, in the message of a missing writer (``--out``).
    ``existing=False`` checks only what another writer cannot change (suffix, names, folder, kinds):
    the check before the output lock is taken; the full check follows under the lock."""
    from rrbody.model.io import check_writable
    from rrbody.model.outputs import require_writer, writer_of

    p = Path(out)
    if p.suffix not in (".csv", ".nc"):
        raise ValueError(f"out must end in .csv or .nc, got {str(p)!r}")
    if p.suffix == ".nc" and not grid:
        raise ValueError("out: NetCDF output needs mode='grid'; use .csv for lists")
    if resume and force:
        raise ValueError("resume and force contradict each other: resume continues the checkpoint, force discards "
                         "it and starts afresh; give one of them")
    ck = checkpoint_path(p)
    # resume replaces the table and its sidecar only when there is a sweep to resume: else it is a first run
    replace = force or (resume and (ck.exists() or p.exists())) or not existing
    for kind, f in output_files(p):
        check_writable(f, force=replace or kind == "checkpoint", name="out" if kind == "out" else f"out: {kind}")
    # the table's writer is installed: a missing one found after the work would leave a checkpoint that
    # blocks the same command (without --resume) once the extra is installed
    writer = writer_of(p)
    if writer is not None:
        require_writer(writer, name=name)
    if existing and not (resume or force) and ck.exists():
        raise ValueError(f"out: checkpoint {str(ck)!r} exists from an earlier run; pass resume=True (--resume) to "
                         "continue it or force=True (--force) to start afresh")


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


def stream_checkpoint(path: Path, spec: dict[str, Any], results: Iterable[list[dict[str, Any]]],
                      done: dict[int, dict[str, Any]]) -> Iterator[int]:
    """Append every batch of rows of ``results`` to the checkpoint ``path`` (created, atomically, with
    the header ``spec`` if absent), flushed and fsync'ed per batch; ``done`` gains the rows; yields
    each batch's size once it is on disk. An OSError of a write names ``path`` (its ``filename``)."""
    from rrbody.model.io import atomic_write_text

    if not path.exists():
        atomic_write_text(path, json.dumps(spec) + "\n", force=True, name="checkpoint")
    try:  # unbuffered: one write per batch, nothing left to flush (and fail) at close
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CLOEXEC)
    except OSError as e:
        raise _named(e, path) from None
    try:
        for rows in results:
            data = "".join(json.dumps(r) + "\n" for r in rows).encode()
            try:
                while data:
                    data = data[os.write(fd, data):]
                os.fsync(fd)
            except OSError as e:
                raise _named(e, path) from None
            done.update((int(r["i"]), r) for r in rows)
            yield len(rows)
    finally:
        os.close(fd)


def _named(e: OSError, path: Path) -> OSError:
    """``e`` with ``path`` as its file name (a write on an open file does not name it)."""
    return e if e.filename else type(e)(e.errno, e.strerror, str(path))


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
            if c in ("regime", "error", "method"):
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
    """h5netcdf (NetCDF4) when both h5netcdf and h5py are importable, else scipy's NetCDF3 writer (a core
    package: always available once xarray is)."""
    try:
        import h5netcdf  # noqa: F401
        import h5py  # noqa: F401
    except ImportError:  # h5py alone is not enough: xarray's engine "h5netcdf" is the h5netcdf package
        return "scipy"
    return "h5netcdf"


def count_rows(path: Path) -> int:
    """Finished points in a checkpoint (for the message after an interruption or a fault): complete
    lines only, since a write cut short (a kill, a full disk) leaves a last line without its newline."""
    try:
        with open(path, "rb") as fh:
            return max(0, sum(1 for ln in fh if ln.endswith(b"\n") and ln.strip()) - 1)
    except OSError:
        return 0
