"""rerun recordings (.rrd) of a run, for the rerun viewer of the pinned rerun-sdk (0.41.0).

Everything is sent with the columnar API (``send_columns``: one call per entity for the whole run),
on a single time line ``"time"`` (a duration, in simulated seconds). World frame, metres, radians;
energies and powers per unit mass (J/kg, W/kg).

The plane is y-up: rerun's 2D views draw +y downwards (rerun issue #1387: they ignore
``ViewCoordinates``), which would mirror the counter-clockwise drive into a clockwise one, exactly the
sense reverse rotation is about. So the plane is a 3D view of the z = 0 plane (``ViewCoordinates``
right-handed, z up) whose eye looks straight down with +y up on screen. The data are the true
coordinates (hovering shows them); only the camera is placed.

The flip is the whole run's (:func:`rrbody.render.flip.flip_mark`), never the lowest phi of the
recorded span; a span that ends before t_f says "no flip within this span" in the event log.

Entities
--------
``world/O``, ``world/drive_circle``  static: the centre O (labelled) and the circle of radius d followed by P
``world/P``, ``world/cm``            Points3D, labelled "P" and "CM" (green, like the paper)
``world/body/rod``, ``world/body/outline``  the massless rod CM -> P; a disk / ellipse outline
``world/arrows/velocity``, ``world/arrows/friction``  Arrows3D at the CM (scales in the scene text)
``world/cm_trail/bNNNN``             the CM history in blocks (see below), red before t_f, blue after
``plots/phi/{reverse,normal,unknown}``, ``plots/theta/...``  phi(t) and theta = phi - omega t + pi, split at t_f
``plots/phi/flip``                   one row at t = t_f: the flip marker (value phi_min)
``plots/phi_dot``                    phi'(t) (rad/s)
``plots/energy/{kinetic,dissipated}``  1/2 v_cm^2 + 1/2 (I_cm/m) spin^2 and the energy friction removed
``plots/power/friction``             friction power F . v_cm + tau_cm spin (<= 0), from the friction kernel
``events``                           TextLog: the span, T_1, the flip (or "no flip within this span")
``meta/scene``                       static TextDocument: the scene in words and as JSON

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
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.io import atomic_path, check_writable
from rrbody.model.trajectory import Trajectory, jsonable
from rrbody.render.flip import FlipMark, flip_mark
from rrbody.render.quantities import mechanics

__all__ = ["record", "check_output", "write_recording", "TIMELINE", "TRAIL_BLOCK", "MAX_WORLD_ROWS", "MAX_TRAIL_POINTS",
           "expected_entities", "stride", "trail_blocks", "points_3d"]

TIMELINE = "time"
#: trail points per block (storage ~ TRAIL_BLOCK / 2 points per trail sample)
TRAIL_BLOCK = 64
#: caps that keep long runs light: the world entities and the trail are decimated to at most this
#: many rows/points (the time series always keep every sample)
MAX_WORLD_ROWS = 50_000
MAX_TRAIL_POINTS = 8_000

_RED = (214, 39, 40)
_BLUE = (31, 119, 180)
_GREY = (127, 127, 127)
_GREEN = (44, 160, 44)
_PURPLE = (148, 103, 189)


def stride(n: int, cap: int) -> np.ndarray:
    """Indices 0..n-1 thinned to at most ``cap`` (the last sample always kept)."""
    if n <= cap:
        return np.arange(n)
    idx = np.arange(0, n, int(math.ceil(n / cap)))
    return idx if idx[-1] == n - 1 else np.append(idx, n - 1)


def _has_screen() -> bool:
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def trail_blocks(t: np.ndarray, xy: np.ndarray, t_f: float | None) -> list[tuple[np.ndarray, np.ndarray, bool]]:
    """Split the (decimated) trail, times ``t`` (s) and points ``xy`` (n, 2; m), into blocks (times,
    points, before_flip); consecutive blocks share their boundary point so the polyline is continuous;
    no block straddles the flip time ``t_f`` (s; None: no flip)."""
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


def _segments(flip: FlipMark, t: np.ndarray) -> list[tuple[str, np.ndarray, tuple[int, int, int]]]:
    """(name, sample indices, colour) of the series parts: before t_f (reverse), after (normal), or unknown.

    Both parts of a split share the sample nearest t_f, so the plotted curve has no gap."""
    n = len(t)
    if flip.status == "unknown":
        return [("unknown", np.arange(n), _GREY)]
    if flip.status == "none" or flip.t_f is None or flip.t_f <= t[0]:
        return [("normal", np.arange(n), _BLUE)]
    if flip.t_f >= t[-1]:
        return [("reverse", np.arange(n), _RED)]
    k = int(np.searchsorted(t, flip.t_f, side="right"))
    return [("reverse", np.arange(0, min(k + 1, n)), _RED), ("normal", np.arange(k - 1 if k > 0 else 0, n), _BLUE)]


def expected_entities(traj: Trajectory, flip: Any = None) -> set[str]:
    """The entity paths :func:`record` writes for ``traj`` (trail blocks excluded)."""
    sc = traj.meta.get("scene") or {}
    mark = flip_mark(traj, flip)
    parts = [name for name, _, _ in _segments(mark, np.asarray(traj.t, float))]
    ents = {"world/P", "world/cm", "world/body/rod", "plots/phi_dot", "meta/scene", "events",
            "world/arrows/velocity"} | {f"plots/phi/{p}" for p in parts}
    if "body" in sc:
        ents |= {"plots/energy/kinetic", "plots/energy/dissipated", "plots/power/friction", "world/arrows/friction"}
    if sc.get("drive"):
        ents |= {"world/O", "world/drive_circle"} | {f"plots/theta/{p}" for p in parts}
    if float(sc.get("R_A") or 0.0) > 0.0:
        ents.add("world/body/outline")
    return ents


def _blueprint(driven: bool, view: tuple[float, float, float]) -> Any:
    """Plane (3D view looking down, y up) | phi, theta, energy, power | event log and scene text."""
    import rerun.blueprint as rrb

    cx, cy, half = view
    eye = rrb.EyeControls3D(position=[cx, cy, 2.6 * half], look_target=[cx, cy, 0.0], eye_up=[0.0, 1.0, 0.0])
    plane = rrb.Spatial3DView(origin="/world", name="plane (m), y up, seen from above", eye_controls=eye,
                              line_grid=rrb.LineGrid3D(visible=True))
    plots = [rrb.TimeSeriesView(origin="/plots/phi", name="phi (rad): red before t_f, blue after"),
             rrb.TimeSeriesView(origin="/plots/phi_dot", name="phi' (rad/s)")]
    if driven:
        plots.append(rrb.TimeSeriesView(origin="/plots/theta", name="theta = phi - omega t + pi (rad)"))
    plots += [rrb.TimeSeriesView(origin="/plots/energy", name="energy per unit mass (J/kg)"),
              rrb.TimeSeriesView(origin="/plots/power", name="friction power per unit mass (W/kg)")]
    text = rrb.Tabs(rrb.TextLogView(origin="/events", name="events"),
                    rrb.TextDocumentView(origin="/meta/scene", name="scene"))
    return rrb.Blueprint(
        rrb.Horizontal(rrb.Vertical(plane, text, row_shares=[3, 1]), rrb.Vertical(*plots), column_shares=[3, 2]),
        collapse_panels=False,
    )


def _view_box(traj: Trajectory) -> tuple[float, float, float]:
    """(centre x, centre y, half-extent) in m of everything drawn on the plane."""
    sc = traj.meta.get("scene") or {}
    d = float(sc["drive"]["d"]) if sc.get("drive") else 0.0
    reach = max(float(sc.get("R_A") or 0.0), float(sc.get("R_B") or 0.0))
    xs = np.concatenate([traj.x_cm, traj.x_p, [-d, d]])
    ys = np.concatenate([traj.y_cm, traj.y_p, [-d, d]])
    lo_x, hi_x, lo_y, hi_y = xs.min() - reach, xs.max() + reach, ys.min() - reach, ys.max() + reach
    return 0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y), max(0.5 * max(hi_x - lo_x, hi_y - lo_y), 1e-6)


def points_3d(xy: np.ndarray) -> np.ndarray:
    """Points of the plane, (n, 2), as 3D points at z = 0, (n, 3), in the same units."""
    return np.column_stack([xy, np.zeros(len(xy))])


def _scene_text(traj: Trajectory, mark: FlipMark, scales: list[str]) -> str:
    from rrbody.render.scene_text import scene_info, title_text

    t0, t1 = float(traj.t[0]), float(traj.t[-1])
    plain = title_text(scene_info(traj)).replace("$", "").replace("\\", "").replace("^{-", "^-").replace("}", "")
    lines = [f"# {plain}", "", f"**Flip:** {mark.caption(t0, t1)}.", "",
             f"Recorded span: {t0:g} s to {t1:g} s. Plane: metres, seen from above, x right, y up; the drive "
             "turns counter-clockwise. Red: reverse rotation, before t_f; blue: after (normal rotation).", ""]
    if scales:
        lines.append("Arrows at the CM (green: CM velocity, purple: friction force): " + "; ".join(scales) + ".")
        lines.append("")
    lines += ["```json", json.dumps(jsonable({k: v for k, v in traj.meta.items() if k != "wall_s"}), indent=1), "```"]
    return "\n".join(lines)


def _log_series(rec: Any, base: str, t: np.ndarray, values: np.ndarray, mark: FlipMark, label: str) -> None:
    import rerun as rr

    for name, idx, colour in _segments(mark, t):
        path = f"{base}/{name}"
        rec.log(path, rr.SeriesLines(names=f"{label} ({name})", colors=[colour]), static=True)
        rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=t[idx])],
                         columns=rr.Scalars.columns(scalars=values[idx]))


def _log_run(rec: Any, traj: Trajectory, mark: FlipMark) -> None:
    """Send the whole run to ``rec`` (static parts with ``log``, time-varying parts with ``send_columns``)."""
    import rerun as rr

    sc = traj.meta.get("scene") or {}
    drive = sc.get("drive")
    t = np.asarray(traj.t, dtype=float)
    n = len(t)
    t0, t1 = float(t[0]), float(t[-1])
    rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    if drive:
        s = np.linspace(0.0, 2.0 * math.pi, 257)
        d = float(drive["d"])
        rec.log("world/drive_circle", rr.LineStrips3D([points_3d(np.column_stack([d * np.cos(s), d * np.sin(s)]))],
                                                      colors=[(0, 0, 0)], radii=[-1.0]), static=True)
        rec.log("world/O", rr.Points3D([[0.0, 0.0, 0.0]], colors=[(0, 0, 0)], radii=[-3.0], labels=["O"],
                                       show_labels=True), static=True)

    # time series: every sample; phi and theta split at the whole run's flip
    _log_series(rec, "plots/phi", t, np.asarray(traj.phi, float), mark, "phi")
    if drive:
        _log_series(rec, "plots/theta", t, np.asarray(traj.theta, float), mark, "theta")
    times = rr.TimeColumn(TIMELINE, duration=t)
    rec.log("plots/phi_dot", rr.SeriesLines(names="phi'"), static=True)
    rec.send_columns("plots/phi_dot", indexes=[times], columns=rr.Scalars.columns(scalars=traj.phi_dot))
    mech = mechanics(traj)
    if mech is not None:
        for path, name, vals in (("plots/energy/kinetic", "kinetic energy", mech.kinetic),
                                 ("plots/energy/dissipated", "removed by friction", mech.dissipated),
                                 ("plots/power/friction", "friction power", mech.friction_power)):
            rec.log(path, rr.SeriesLines(names=name), static=True)
            rec.send_columns(path, indexes=[times], columns=rr.Scalars.columns(scalars=vals))

    # the event log: the span, T1, the flip or its absence
    rec.set_time(TIMELINE, duration=t0)
    rec.log("events", rr.TextLog(f"recorded span {t0:g} s to {t1:g} s; {mark.caption(t0, t1)}", level="INFO"))
    T1 = traj.events.get("T1")
    if T1 is not None and t0 <= float(T1) <= t1:
        rec.set_time(TIMELINE, duration=float(T1))
        rec.log("events", rr.TextLog(f"T1 = {float(T1):.6g} s: theta has made its first full backward turn",
                                     level="INFO"))
    if mark.in_span(t0, t1) and mark.t_f is not None:
        phi_f = float(np.interp(mark.t_f, t, traj.phi))
        rec.log("plots/phi/flip", rr.SeriesPoints(names="flip t_f", colors=[_RED], markers="diamond",
                                                  marker_sizes=[6.0]), static=True)
        rec.set_time(TIMELINE, duration=float(mark.t_f))
        rec.log("plots/phi/flip", rr.Scalars(phi_f))
        rec.log("events", rr.TextLog(f"FLIP: t_f = {mark.t_f:.6g} s, phi = {phi_f:.6g} rad: reverse rotation ends",
                                     level="WARN"))
    rec.reset_time()

    # the plane: O, P, CM, rod, outline, arrows (decimated for very long runs)
    w = stride(n, MAX_WORLD_ROWS)
    tw = rr.TimeColumn(TIMELINE, duration=t[w])
    cm = np.column_stack([traj.x_cm, traj.y_cm])[w]
    pp = np.column_stack([traj.x_p, traj.y_p])[w]
    ra, rb = float(sc.get("R_A") or 0.0), float(sc.get("R_B") or 0.0)
    # marker sizes in UI points (negative radii), so they read the same at any zoom
    rec.log("world/P", rr.Points3D.from_fields(colors=[(0, 0, 0)], radii=[-4.0], labels=["P"], show_labels=True),
            static=True)
    rec.send_columns("world/P", indexes=[tw], columns=rr.Points3D.columns(positions=points_3d(pp)))
    rec.log("world/cm", rr.Points3D.from_fields(colors=[_GREEN], radii=[-7.0 if ra == 0.0 else -3.0], labels=["CM"],
                                                show_labels=True), static=True)
    rec.send_columns("world/cm", indexes=[tw], columns=rr.Points3D.columns(positions=points_3d(cm)))
    rods = np.stack([points_3d(cm), points_3d(pp)], axis=1)  # (rows, 2 points, xyz)
    rec.log("world/body/rod", rr.LineStrips3D.from_fields(colors=[(40, 40, 40)], radii=[-2.0]), static=True)
    rec.send_columns("world/body/rod", indexes=[tw], columns=rr.LineStrips3D.columns(strips=list(rods)))
    if ra > 0.0:
        s = np.linspace(0.0, 2.0 * math.pi, 65)
        ox, oy = ra * np.cos(s), rb * np.sin(s)
        ang = np.asarray(traj.body_angle, dtype=float)[w][:, None]
        c, sn = np.cos(ang), np.sin(ang)
        outl = np.stack([cm[:, :1] + c * ox - sn * oy, cm[:, 1:] + sn * ox + c * oy, 0.0 * ox + 0.0 * ang], axis=2)
        rec.log("world/body/outline", rr.LineStrips3D.from_fields(colors=[(40, 40, 40)], radii=[-2.0]),
                static=True)
        rec.send_columns("world/body/outline", indexes=[tw], columns=rr.LineStrips3D.columns(strips=list(outl)))
    # arrows at the CM, each scaled so its largest value spans a quarter of the view
    half = _view_box(traj)[2]
    scales: dict[str, float] = {}
    v = np.column_stack([traj.vx_cm, traj.vy_cm])[w]
    arrows = [("velocity", v, _GREEN, "m per m/s")]
    if mech is not None:
        arrows.append(("friction", np.column_stack([mech.fx, mech.fy])[w], _PURPLE, "m per m/s^2"))
    for name, vec, colour, unit in arrows:
        scale = 0.5 * half / max(float(np.hypot(vec[:, 0], vec[:, 1]).max()), 1e-300)
        scales[f"{name} drawn at {scale:.3g} {unit}"] = scale
        path = f"world/arrows/{name}"
        rec.log(path, rr.Arrows3D.from_fields(colors=[colour], radii=[-1.5]), static=True)
        rec.send_columns(path, indexes=[tw], columns=rr.Arrows3D.columns(origins=points_3d(cm),
                                                                         vectors=points_3d(vec * scale)))
    rec.log("meta/scene", rr.TextDocument(_scene_text(traj, mark, list(scales)), media_type=rr.MediaType.MARKDOWN),
            static=True)

    # the CM trail in blocks (see the module docstring)
    k = stride(n, MAX_TRAIL_POINTS)
    tf = mark.t_f if mark.status == "flip" else None
    blocks = trail_blocks(t[k], np.column_stack([traj.x_cm, traj.y_cm])[k], tf if tf is not None else None)
    base = _GREY if mark.status == "unknown" else _BLUE
    for b, (tb, pb, red) in enumerate(blocks):
        path = f"world/cm_trail/b{b:04d}"
        colour = _RED if (red and tf is not None) else base
        rec.log(path, rr.LineStrips3D.from_fields(colors=[colour], radii=[-1.5]), static=True)
        m = len(tb)
        if m < 2:
            continue
        strips = [points_3d(pb[: j + 1]) for j in range(1, m)]
        rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=tb[1:])],
                         columns=rr.LineStrips3D.columns(strips=strips))


def record(traj: Trajectory, path: str | Path | None, *, spawn: bool = False, force: bool = False,
           flip: Any = None) -> Path | None:
    """Write a rerun recording of ``traj`` to ``path`` (.rrd) and/or open the viewer (``spawn``).

    ``flip``: the whole run's flip (a ``FlipResult`` from ``flip_time``, a ``FlipMark``, a time in s,
    or None to compute it from the run's scene; see :func:`rrbody.render.flip.flip_mark`). The file
    is written to a temporary sibling and renamed into place, so an interrupted run leaves nothing
    behind; an existing file is kept unless ``force``. ``spawn`` needs a screen: without one, a file
    is still written (with a note on stderr), and with no ``path`` it is an error. Returns ``path``.
    """
    check_output(path, spawn=spawn, force=force)
    if len(traj) < 1:
        raise ValueError("traj must have at least 1 sample, got 0")
    mark = flip_mark(traj, flip)
    driven = bool((traj.meta.get("scene") or {}).get("drive"))
    return write_recording(path, spawn=spawn, force=force, blueprint=_blueprint(driven, _view_box(traj)),
                           send=lambda rec: _log_run(rec, traj, mark))


def check_output(path: str | Path | None, *, spawn: bool, force: bool) -> None:
    """Refuse, before any work, a recording with nowhere to go, a path that is not a writable ``.rrd``
    (or an existing one without ``force``), and a missing rerun extra."""
    from rrbody.model.extras import require

    require("rerun", purpose="a rerun recording")
    if path is None and not spawn:
        raise ValueError("rerun path must be given (a .rrd file) unless spawn=True")
    if path is not None:
        final = check_writable(path, force=force, name="rerun")
        if final.suffix.lower() != ".rrd":
            raise ValueError(f"rerun path must end in .rrd, got {str(path)!r}")


def write_recording(path: str | Path | None, *, spawn: bool, force: bool, blueprint: Any,
                    send: Callable[[Any], None]) -> Path | None:
    """Open a recording stream (to ``path``, written to a temporary sibling and renamed into place, and/or
    to a spawned viewer), let ``send(rec)`` log everything, and close it. Returns ``path``."""
    import rerun as rr

    bp = blueprint
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
        send(rec)
        rec.flush()
        rec.disconnect()
        return None
    with atomic_path(path, force=force, name="rerun") as tmp:
        if viewer:
            rec.set_sinks(rr.GrpcSink(), rr.FileSink(str(tmp)), default_blueprint=bp)
        else:
            rec.save(tmp, default_blueprint=bp)
        try:
            send(rec)
            rec.flush()
        finally:
            rec.disconnect()  # closes the file (writes its footer) before the rename
    return Path(path)
