"""rerun recordings (.rrd) of a run, for the rerun viewer of the pinned rerun-sdk (0.41.0).

Everything is sent with the columnar API (``send_columns``: one call per entity for the whole run),
on a single time line ``"time"`` (a duration, in simulated seconds). World frame, metres, radians.

Entities
--------
``world/drive_circle``   static: the circle of radius d followed by P
``world/P``              Points2D: the driven point
``world/cm``             Points2D: the centre of mass (green, like the paper)
``world/body/rod``       LineStrips2D: the massless rod CM -> P
``world/body/outline``   LineStrips2D: disk / ellipse outline at its current orientation (extended bodies)
``world/cm_trail/bNNNN`` LineStrips2D: the CM history, in blocks (see below), red before t_f, blue after
``plots/phi/phi``        Scalars: phi(t) (rad)
``plots/phi/flip``       Scalars, one row at t = t_f: the flip-time marker (value phi_min)
``plots/phi_dot``        Scalars: phi'(t) (rad/s)
``plots/theta``          Scalars: theta = phi - omega t + pi (rad, driven runs)
``events``               TextLog: the flip, at t = t_f
``meta/scene``           static TextDocument: the scene description (JSON)

The CM trail: rerun shows each entity's latest value at the time cursor, so a growing history is
stored as consecutive blocks of ``TRAIL_BLOCK`` trail points. Block ``b`` holds, at the time of
each of its points, the polyline from its first point up to that point; earlier blocks keep their
final (complete) polyline. The viewer therefore draws exactly the history up to the cursor, at a
storage cost of about ``TRAIL_BLOCK / 2`` points per trail sample instead of a quadratic one.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
import uuid
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.io import atomic_path, check_writable
from rrbody.model.trajectory import Trajectory, _jsonable

__all__ = ["record", "TIMELINE", "TRAIL_BLOCK", "MAX_WORLD_ROWS", "MAX_TRAIL_POINTS", "expected_entities"]

TIMELINE = "time"
#: trail points per block (storage ~ TRAIL_BLOCK / 2 points per trail sample)
TRAIL_BLOCK = 64
#: caps that keep long runs light: the world entities and the trail are decimated to at most this
#: many rows/points (the time series always keep every sample)
MAX_WORLD_ROWS = 50_000
MAX_TRAIL_POINTS = 8_000

_RED = (214, 39, 40)
_BLUE = (31, 119, 180)
_GREEN = (44, 160, 44)


def _stride(n: int, cap: int) -> np.ndarray:
    """Indices 0..n-1 thinned to at most ``cap`` (the last sample always kept)."""
    if n <= cap:
        return np.arange(n)
    idx = np.arange(0, n, int(math.ceil(n / cap)))
    return idx if idx[-1] == n - 1 else np.append(idx, n - 1)


def _has_screen() -> bool:
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def _trail_blocks(t: np.ndarray, xy: np.ndarray, t_f: float | None) -> list[tuple[np.ndarray, np.ndarray, bool]]:
    """Split the (decimated) trail into blocks (times, points, before_flip); consecutive blocks
    share their boundary point so the polyline is continuous; no block straddles t_f."""
    if t_f is not None and t[0] < t_f < t[-1]:
        i = int(np.searchsorted(t, t_f, side="right"))
        at = np.array([np.interp(t_f, t, xy[:, 0]), np.interp(t_f, t, xy[:, 1])])
        t = np.insert(t, i, t_f)
        xy = np.insert(xy, i, at, axis=0)
        parts = [(t[: i + 1], xy[: i + 1], True), (t[i:], xy[i:], False)]
    else:
        before = t_f is not None and t[-1] <= t_f
        parts = [(t, xy, before)]
    blocks = []
    for tt, pp, red in parts:
        n = len(tt)
        start = 0
        while start < n - 1 or (n == 1 and start == 0):
            stop = min(start + TRAIL_BLOCK, n - 1)
            blocks.append((tt[start: stop + 1], pp[start: stop + 1], red))
            if n == 1:
                break
            start = stop
    return blocks


def expected_entities(traj: Trajectory) -> set[str]:
    """The entity paths :func:`record` writes for ``traj`` (trail blocks excluded)."""
    sc = traj.meta.get("scene") or {}
    ents = {"world/P", "world/cm", "world/body/rod", "plots/phi/phi", "plots/phi_dot", "meta/scene"}
    if sc.get("drive"):
        ents |= {"world/drive_circle", "plots/theta"}
    if float(sc.get("R_A") or 0.0) > 0.0:
        ents.add("world/body/outline")
    return ents


def _blueprint(driven: bool) -> Any:
    import rerun.blueprint as rrb

    plots = [rrb.TimeSeriesView(origin="/plots/phi", name="phi (rad)"),
             rrb.TimeSeriesView(origin="/plots/phi_dot", name="phi' (rad/s)")]
    if driven:
        plots.append(rrb.TimeSeriesView(origin="/plots/theta", name="theta = phi - omega t + pi (rad)"))
    return rrb.Blueprint(
        rrb.Horizontal(rrb.Spatial2DView(origin="/world", name="plane (m)"), rrb.Vertical(*plots),
                       column_shares=[3, 2]),
        collapse_panels=False,
    )


def _log_run(rec: Any, traj: Trajectory, t_f: float | None) -> None:
    """Send the whole run to ``rec`` (static parts with ``log``, time-varying parts with ``send_columns``)."""
    import rerun as rr

    sc = traj.meta.get("scene") or {}
    drive = sc.get("drive")
    t = np.asarray(traj.t, dtype=float)
    n = len(t)

    # static: the scene (JSON) and the drive circle
    rec.log("meta/scene", rr.TextDocument("```json\n" + json.dumps(_jsonable(traj.meta), indent=1) + "\n```",
                                          media_type=rr.MediaType.MARKDOWN), static=True)
    if drive:
        s = np.linspace(0.0, 2.0 * math.pi, 257)
        d = float(drive["d"])
        rec.log("world/drive_circle", rr.LineStrips2D([np.column_stack([d * np.cos(s), d * np.sin(s)])],
                                                      colors=[(0, 0, 0)], radii=[-1.0]), static=True)

    # time series: every sample
    times = rr.TimeColumn(TIMELINE, duration=t)
    rec.log("plots/phi/phi", rr.SeriesLines(names="phi", colors=[(60, 60, 60)]), static=True)
    rec.send_columns("plots/phi/phi", indexes=[times], columns=rr.Scalars.columns(scalars=traj.phi))
    rec.log("plots/phi_dot", rr.SeriesLines(names="phi'"), static=True)
    rec.send_columns("plots/phi_dot", indexes=[times], columns=rr.Scalars.columns(scalars=traj.phi_dot))
    if drive:
        rec.log("plots/theta", rr.SeriesLines(names="theta"), static=True)
        rec.send_columns("plots/theta", indexes=[times], columns=rr.Scalars.columns(scalars=traj.theta))

    # the flip-time marker
    if t_f is not None and t[0] <= t_f <= t[-1]:
        phi_f = float(np.interp(t_f, t, traj.phi))
        rec.log("plots/phi/flip", rr.SeriesPoints(names="flip t_f", colors=[_RED], markers="diamond",
                                                  marker_sizes=[6.0]), static=True)
        rec.set_time(TIMELINE, duration=float(t_f))
        rec.log("plots/phi/flip", rr.Scalars(phi_f))
        rec.log("events", rr.TextLog(f"flip: t_f = {t_f:.6g} s, phi = {phi_f:.6g} rad", level="INFO"))
        rec.reset_time()

    # the plane: P, CM, rod, outline (decimated for very long runs)
    w = _stride(n, MAX_WORLD_ROWS)
    tw = rr.TimeColumn(TIMELINE, duration=t[w])
    cm = np.column_stack([traj.x_cm, traj.y_cm])[w]
    pp = np.column_stack([traj.x_p, traj.y_p])[w]
    ra, rb = float(sc.get("R_A") or 0.0), float(sc.get("R_B") or 0.0)
    # marker sizes in UI points (negative radii), so they read the same at any zoom
    rec.log("world/P", rr.Points2D.from_fields(colors=[(0, 0, 0)], radii=[-4.0]), static=True)
    rec.send_columns("world/P", indexes=[tw], columns=rr.Points2D.columns(positions=pp))
    rec.log("world/cm", rr.Points2D.from_fields(colors=[_GREEN], radii=[-7.0 if ra == 0.0 else -3.0]), static=True)
    rec.send_columns("world/cm", indexes=[tw], columns=rr.Points2D.columns(positions=cm))
    rods = np.stack([cm, pp], axis=1)  # (rows, 2 points, xy)
    rec.log("world/body/rod", rr.LineStrips2D.from_fields(colors=[(40, 40, 40)], radii=[-2.0]), static=True)
    rec.send_columns("world/body/rod", indexes=[tw], columns=rr.LineStrips2D.columns(strips=list(rods)))
    if ra > 0.0:
        s = np.linspace(0.0, 2.0 * math.pi, 65)
        ox, oy = ra * np.cos(s), rb * np.sin(s)
        ang = np.asarray(traj.body_angle, dtype=float)[w][:, None]
        c, sn = np.cos(ang), np.sin(ang)
        outl = np.stack([cm[:, :1] + c * ox - sn * oy, cm[:, 1:] + sn * ox + c * oy], axis=2)
        rec.log("world/body/outline", rr.LineStrips2D.from_fields(colors=[(40, 40, 40)], radii=[-2.0]),
                static=True)
        rec.send_columns("world/body/outline", indexes=[tw], columns=rr.LineStrips2D.columns(strips=list(outl)))

    # the CM trail in blocks (see the module docstring)
    k = _stride(n, MAX_TRAIL_POINTS)
    blocks = _trail_blocks(t[k], np.column_stack([traj.x_cm, traj.y_cm])[k], t_f)
    for b, (tb, pb, red) in enumerate(blocks):
        path = f"world/cm_trail/b{b:04d}"
        rec.log(path, rr.LineStrips2D.from_fields(colors=[_RED if red else _BLUE], radii=[-1.5]), static=True)
        m = len(tb)
        if m < 2:
            continue
        strips = [pb[: j + 1] for j in range(1, m)]
        rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=tb[1:])],
                         columns=rr.LineStrips2D.columns(strips=strips))


def record(traj: Trajectory, path: str | Path | None, *, spawn: bool = False, force: bool = False,
           t_f: float | None = None) -> Path | None:
    """Write a rerun recording of ``traj`` to ``path`` (.rrd) and/or open the viewer (``spawn``).

    ``t_f`` (s): the flip time for the marker and the red/blue trail; default
    ``traj.events['t_phi_min']`` (None or 0: no marker, all blue). The file is written to a
    temporary sibling and renamed into place, so an interrupted run leaves nothing behind; an
    existing file is kept unless ``force``. ``spawn`` needs a screen: without one, a file is still
    written (with a note on stderr), and with no ``path`` it is an error. Returns ``path``.
    """
    import rerun as rr

    if path is None and not spawn:
        raise ValueError("rerun path must be given (a .rrd file) unless spawn=True")
    if path is not None:
        final = check_writable(path, force=force, name="rerun")
        if final.suffix.lower() != ".rrd":
            raise ValueError(f"rerun path must end in .rrd, got {str(path)!r}")
    if len(traj) < 1:
        raise ValueError("traj must have at least 1 sample, got 0")
    if t_f is None:
        t_f = traj.events.get("t_phi_min")
    tf = None if t_f is None or not math.isfinite(float(t_f)) or float(t_f) <= float(traj.t[0]) else float(t_f)
    driven = bool((traj.meta.get("scene") or {}).get("drive"))
    bp = _blueprint(driven)
    viewer = spawn and _has_screen()
    if spawn and not viewer:
        msg = "rerun_spawn: no screen here (DISPLAY / WAYLAND_DISPLAY unset), so no viewer was opened"
        if path is None:
            raise ValueError(msg + "; write a file with --rerun PATH.rrd and open it with `rerun PATH.rrd`")
        print(f"rrbody: {msg}; the recording is in {path}", file=sys.stderr)

    rec = rr.RecordingStream("rrbody", recording_id=uuid.uuid4())
    exe = shutil.which("rerun") or str(Path(sys.executable).with_name("rerun"))
    if viewer:
        from rerun.sinks import spawn as spawn_viewer

        spawn_viewer(connect=False, executable_path=exe, recording=rec)
    if path is None:
        rec.connect_grpc(default_blueprint=bp)
        _log_run(rec, traj, tf)
        rec.flush()
        rec.disconnect()
        return None
    with atomic_path(path, force=force, name="rerun") as tmp:
        if viewer:
            rec.set_sinks(rr.GrpcSink(), rr.FileSink(str(tmp)), default_blueprint=bp)
        else:
            rec.save(tmp, default_blueprint=bp)
        try:
            _log_run(rec, traj, tf)
            rec.flush()
        finally:
            rec.disconnect()  # closes the file (writes its footer) before the rename
    return Path(path)
