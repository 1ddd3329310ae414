"""The rerun recording of a :class:`~rrbody.render.recorder.Recorder`'s frames (rerun-sdk 0.41).

The same conventions as :mod:`rrbody.render.rerun`: one time line ``"time"`` (simulated seconds),
everything sent column-wise (one call per entity for the whole capture), and the plane a 3D view of
z = 0 seen from above with +y up (rerun's 2D views would mirror it). World frame, SI units.

Entities
--------
``world/static``                  the space's static shapes (closed line strips), static
``world/bodies/<label>``          one per body: its outline in its own frame (static line strips)
                                  and a ``Transform3D`` at every captured time (translation and the
                                  rotation about z); with ``color="spin"`` its colour at every time
``world/bodies/<label>/P``, ``.../link``  the driven point P of a body rrbody's builder drives and the
                                  rigid link from it to the centre of gravity (body frame)
``world/trails/<label>/bNNNN``    the centre of gravity's path in blocks (see rerun.py), for chosen bodies
``plots/speed/<label>``           |v| of the centre of gravity (m/s), for the ``plots`` bodies
``plots/spin/<label>``            the spin (rad/s)
``plots/friction_power/<label>``  F.v + tau spin (W, <= 0 while sliding), with a plane only
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.render.rerun import MAX_TRAIL_POINTS, TIMELINE, points_3d, stride, trail_blocks

__all__ = ["blueprint", "send", "entities"]


def _u8(rgba: np.ndarray) -> np.ndarray:
    return np.clip(np.round(np.asarray(rgba)[..., :3] * 255.0), 0, 255).astype(np.uint8)


def entities(rec: Any, *, trails: np.ndarray | None = None, plots: list[int] | None = None) -> set[str]:
    """The entity paths :func:`send` writes (trail blocks as their body's ``world/trails/<label>``)."""
    out = {f"world/bodies/{x}" for x in rec.labels}
    out |= {f"world/bodies/{rec.labels[k]}/{x}" for k in np.flatnonzero(~np.isnan(rec._anchor[:, 0])) for x in ("P",
                                                                                                                "link")}
    if rec._static:
        out.add("world/static")
    for k in plots or []:
        out |= {f"plots/speed/{rec.labels[k]}", f"plots/spin/{rec.labels[k]}"}
        if rec.plane is not None:
            out.add(f"plots/friction_power/{rec.labels[k]}")
    if trails is not None:
        out |= {f"world/trails/{rec.labels[k]}" for k in np.flatnonzero(trails)}
    return out


def blueprint(view: tuple[float, ...], plots: bool) -> Any:
    """The plane seen from above (y up) beside the speed, spin and friction power plots."""
    import rerun.blueprint as rrb

    x0, x1, y0, y1 = view
    cx, cy, half = 0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * max(x1 - x0, y1 - y0)
    eye = rrb.EyeControls3D(position=[cx, cy, 2.6 * half], look_target=[cx, cy, 0.0], eye_up=[0.0, 1.0, 0.0])
    plane = rrb.Spatial3DView(origin="/world", name="plane (m), y up, seen from above", eye_controls=eye,
                              line_grid=rrb.LineGrid3D(visible=True))
    if not plots:
        return rrb.Blueprint(plane, collapse_panels=False)
    series = [rrb.TimeSeriesView(origin="/plots/speed", name="speed of the centre of gravity (m/s)"),
              rrb.TimeSeriesView(origin="/plots/spin", name="spin (rad/s)"),
              rrb.TimeSeriesView(origin="/plots/friction_power", name="friction power (W)")]
    return rrb.Blueprint(rrb.Horizontal(plane, rrb.Vertical(*series), column_shares=[3, 2]), collapse_panels=False)


def send(stream: Any, rec: Any, *, color: Any, trails: np.ndarray, plots: list[int]) -> None:
    """Log the capture of ``rec`` (a Recorder) to the recording ``stream``."""
    import rerun as rr

    n = rec.n_frames
    t = rec._times[:n]
    d = rec._data[:n]
    times = rr.TimeColumn(TIMELINE, duration=t)
    stream.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    if rec._static:
        stream.log("world/static", rr.LineStrips3D([points_3d(np.vstack([o, o[:1]])) for o in rec._static],
                                                   colors=[(90, 90, 90)], radii=[-1.5]), static=True)
    fixed = rec.colours(color)
    sense = rec.marks(color) if fixed is None else None
    spin_rgb = {-1.0: (214, 39, 40), 1.0: (31, 119, 180), 0.0: (154, 154, 154)}
    half = 0.5 * d[:, :, 2]
    for k, label in enumerate(rec.labels):
        path = f"world/bodies/{label}"
        strips = [points_3d(np.vstack([o, o[:1]])) for o in rec._outlines[k]]
        colours = [tuple(int(v) for v in _u8(fixed[k]))] if fixed is not None else None
        stream.log(path, rr.LineStrips3D(strips, colors=colours, radii=[-1.5]), static=True)
        quat = np.column_stack([np.zeros(n), np.zeros(n), np.sin(half[:, k]), np.cos(half[:, k])])
        stream.send_columns(path, indexes=[times],
                            columns=rr.Transform3D.columns(translation=np.column_stack([d[:, k, 0], d[:, k, 1],
                                                                                        np.zeros(n)]),
                                                           quaternion=quat))
        if sense is not None:
            rgb = np.array([spin_rgb[float(s)] for s in sense[:, k]], dtype=np.uint8)
            stream.send_columns(path, indexes=[times], columns=rr.LineStrips3D.columns(colors=rgb))
        if not math.isnan(rec._anchor[k, 0]):
            stream.log(f"{path}/P", rr.Points3D([points_3d(rec._anchor[k:k + 1])[0]], colors=[(0, 0, 0)], radii=[-4.0],
                                                labels=["P"], show_labels=True), static=True)
            stream.log(f"{path}/link", rr.LineStrips3D([points_3d(np.vstack([rec._anchor[k], rec._cog[k]]))],
                                                       colors=[(0, 0, 0)], radii=[-1.0]), static=True)
    if trails.any():
        centres = rec.centres()
        keep = stride(n, MAX_TRAIL_POINTS)
        for k in np.flatnonzero(trails):
            for b, (tb, pb, _) in enumerate(trail_blocks(t[keep], centres[keep, k], None)):
                path = f"world/trails/{rec.labels[k]}/b{b:04d}"
                stream.log(path, rr.LineStrips3D.from_fields(colors=[(68, 68, 68)], radii=[-1.0]), static=True)
                if len(tb) < 2:
                    continue
                stream.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=tb[1:])],
                                    columns=rr.LineStrips3D.columns(strips=[points_3d(pb[: j + 1]) for j in range(1,
                                                                                                                  len(tb))]))
    for k in plots:
        label = rec.labels[k]
        speed = np.hypot(d[:, k, 3], d[:, k, 4])
        series = [("speed", speed), ("spin", d[:, k, 5])]
        if rec.plane is not None:
            series.append(("friction_power", d[:, k, 6] * d[:, k, 3] + d[:, k, 7] * d[:, k, 4] + d[:, k, 8] * d[:, k,
                                                                                                                5]))
        for what, vals in series:
            path = f"plots/{what}/{label}"
            stream.log(path, rr.SeriesLines(names=label), static=True)
            stream.send_columns(path, indexes=[times], columns=rr.Scalars.columns(scalars=vals))
