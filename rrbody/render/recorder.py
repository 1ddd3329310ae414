"""Film your own bodies: a recorder for any pymunk space with rrbody's plane friction.

::

    rec = Recorder(space, pf)                    # every body of the space that can move and has shapes
    for _ in range(n):
        pf.step(dt)
        rec.capture()                            # poses (and velocities, friction) of this instant
    rec.movie("run.mp4")                         # or rec.rerun("run.rrd"), rec.poster("run.png")

A capture stores numbers, not pictures: per captured frame and body its pose (x, y, angle: the
pymunk body's origin in m, world frame, and its angle in rad) and, with ``motion=True`` (the
default), the velocity of its centre of gravity and its spin at the same instant (m/s, rad/s: for
bodies of the plugin the second-order reading
:meth:`rrbody.engine.plugin.plane.PlaneFriction.velocity` gives, since pymunk's own velocity after a step
belongs to half a step later) and the friction the plane applied in the last step (N and N m,
:meth:`rrbody.engine.plugin.plane.PlaneFriction.friction`). Memory: bodies x frames x 3 numbers (poses
only) or x 9 (with motion), 8 bytes each; a capture that would pass ``max_mb`` stops with a
``ValueError`` and keeps the frames it has.

Pictures are drawn from those numbers only: every shape of every filmed body at its captured pose
(circles with a radius line, so a spinning disk shows its spin; convex polygons, rounded ones and
thick segments by their true outline), the space's static shapes, the captured time, and on request
arrows, arcs and trails. Nothing is interpolated: a movie frame shows the last captured frame at or
before its time, under that frame's own time label.

Colour by spin (``color="spin"``) answers the paper's question for any body: red where the body
turns against its orbit, blue where it turns with it, grey where either is zero. The orbit's sense
is the drive's for a body driven at P by rrbody's builder, and for any other body the sense in which
its centre of gravity's path turns (the sign of v x dv/dt, from the captured velocities by central
differences); a body sliding straight or at rest has none.

The numbers live on the recorder's tape (:class:`rrbody.engine.recording.tape.Tape`, ``rec.tape``: the pymunk
side, which reads the bodies and the plugin); this module draws from them and reads nothing of pymunk
but the shapes' outlines and the static shapes.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Sequence
from operator import attrgetter
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.engine.recording.tape import Tape
from rrbody.model.checks import check_int, check_real
from rrbody.model.io import atomic_path, check_writable
from rrbody.render.movie_figure import check_movie, check_size
from rrbody.render.recorder_picture import (
    CIRCLE_POINTS,
    NEUTRAL,
    REVERSE,
    VW,
    VX,
    VY,
    WITH,
    Picture,
    body_colours,
    check_color,
    fit_view,
    shape_outlines,
    to_world,
)

__all__ = ["Recorder", "shape_outlines", "CIRCLE_POINTS", "REVERSE", "WITH", "NEUTRAL"]

#: relative size under which the orbit's turning (v x a) counts as none (rounding of a straight path)
_STRAIGHT = 1e-9


def _from_tape(name: str, doc: str) -> Any:
    """A read-only property of the recorder: its tape's attribute ``name`` (:class:`rrbody.engine.recording.tape.Tape`;
    the recorder keeps no copy of what the tape holds)."""
    return property(attrgetter(f"tape.{name}"), doc=doc)


class Recorder:
    """Captures the bodies of a pymunk space step by step; films them as MP4, rerun recording or poster.

    The captured numbers are on ``rec.tape`` (:class:`rrbody.engine.recording.tape.Tape`, which reads pymunk and
    the plugin); the recorder draws from them.

    Parameters
    ----------
    space : pymunk.Space
        The space to film. Its static shapes (walls, obstacles) are drawn as they are when filmed.
    plane : rrbody.engine.plugin.plane.PlaneFriction or None
        The space's plane friction: its clock gives each frame's time, and it gives its bodies'
        velocities at that time and the friction it applied. Without it, give ``capture(t=...)``.
    bodies : sequence of pymunk.Body or None
        The bodies to film (dynamic or kinematic, in the space, with shapes). Default: the plane's
        bodies, then every other body of the space that can move and has shapes.
    labels : sequence of str or None
        A name per body (the rerun entity and plot names; default ``b0000``, ``b0001``, ...).
    every : int
        Store one frame per ``every`` calls of :meth:`capture` (>= 1; default 1: every call).
    motion : bool
        Also store velocities, spins and the plane's friction (9 numbers per body and frame, not 3):
        needed for ``color="spin"``, arrows and the rerun plots.
    max_mb : float
        The captured frames' memory cap in MB (10^6 bytes; default 1000).
    reserve : int or None
        Room for this many stored frames, claimed now (>= 1, within ``max_mb``; default None: the
        store starts small and doubles as it fills). The memory is written once here, so that no
        capture in the loop waits for the operating system to map a fresh page (on this project's
        machines the first write of fresh memory costs several times the capture itself). More
        frames than this can still be captured: the store then doubles.
    """

    def __init__(self, space: Any, plane: Any = None, *, bodies: Sequence[Any] | None = None,
                 labels: Sequence[str] | None = None, every: int = 1, motion: bool = True,
                 max_mb: float = 1000.0, reserve: int | None = None) -> None:
        import pymunk

        self.tape = Tape(space, plane, bodies=bodies, labels=labels, every=every, motion=motion, max_mb=max_mb,
                         reserve=reserve)
        # geometry, read now (like the plugin's add): outlines in body coordinates, their reach from the
        # centre of gravity (m), and the static shapes in the world frame as they are now
        self._outlines = [shape_outlines(b) for b in self.bodies]
        self._reach = np.array([max(float(np.hypot(*(o - c).T).max()) for o in outs)
                                for outs, c in zip(self._outlines, self._cog)])
        self._static = [o for b in [space.static_body, *[x for x in space.bodies if x.body_type == pymunk.Body.STATIC]]
                        for o in [to_world(p, b.position.x, b.position.y, b.angle) for p in shape_outlines(b)]]

    # ---- the tape's (rrbody.engine.recording.tape): what was filmed and the frames, read-only ---------------
    space = _from_tape("space", "The filmed pymunk space.")
    plane = _from_tape("plane", "The space's PlaneFriction, or None.")
    bodies = _from_tape("bodies", "The filmed bodies (a tuple), in the order of the frames' rows.")
    labels = _from_tape("labels", "A name per filmed body (a tuple of str).")
    every = _from_tape("every", "One frame is stored per ``every`` calls of :meth:`capture`.")
    motion = _from_tape("motion", "Whether velocities, spins and friction are stored (9 numbers per body and "
                                  "frame, else 3).")
    max_mb = _from_tape("max_mb", "The captured frames' memory cap (MB, 10^6 bytes).")
    _cog = _from_tape("cog", "Each body's centre of gravity in its own frame (bodies, 2), m.")
    _anchor = _from_tape("anchor", "The driven point P of each body rrbody's builder drives (body frame, m; NaN "
                                   "for the others).")
    bytes_per_frame = _from_tape("bytes_per_frame", "Memory one captured frame takes: bodies x (3 or 9) numbers "
                                                    "x 8 bytes.")
    n_frames = _from_tape("n_frames", "How many frames were captured.")
    _data = _from_tape("data", "The frame store, not a copy (its first ``n_frames`` rows are the frames).")
    _times = _from_tape("stamps", "The frames' times (s; the first ``n_frames``), not a copy.")

    @property
    def times(self) -> np.ndarray:
        """The captured frames' times (s), a copy."""
        return self._times[:self.n_frames].copy()

    @property
    def frames(self) -> np.ndarray:
        """The captured numbers, a copy: (frames, bodies, 3 or 9): x, y, angle of the body's origin (m,
        rad, world frame), then with motion the centre of gravity's velocity and the spin (m/s,
        rad/s) and the plane's friction force and torque in the last step (N, N m)."""
        return self._data[:self.n_frames].copy()

    def capture(self, t: float | None = None) -> bool:
        """Store this instant (one call in ``every``; returns whether it stored a frame). ``t``: the time
        (s); default the plane's clock. Raises ValueError, storing nothing, if a filmed body has left the
        space or the frame would pass ``max_mb``; the frames already captured stay."""
        return self.tape.capture(t)

    # ---- derived quantities ----------------------------------------------------------------------
    def _need_frames(self) -> None:
        if self.n_frames == 0:
            raise ValueError("nothing to film: 0 frames captured (call rec.capture() after each step)")

    def _need_motion(self, what: str) -> None:
        if not self.motion:
            raise ValueError(f"{what} needs velocities: create the Recorder with motion=True")

    def centres(self) -> np.ndarray:
        """Centres of gravity (frames, bodies, 2), m, world frame."""
        return self.tape.centres()

    def senses(self) -> np.ndarray:
        """(frames, bodies): -1 where a body turns against its orbit (reverse rotation), +1 with it,
        0 where its spin or its orbit's sense is zero (see the module docstring for the orbit's sense)."""
        self._need_motion('color="spin"')
        d = self._data[:self.n_frames]
        t = self._times[:self.n_frames]
        v = d[:, :, VX:VY + 1]
        if self.n_frames >= 2:
            a = np.gradient(v, t, axis=0)
        else:
            a = np.zeros_like(v)
        cross = v[:, :, 0] * a[:, :, 1] - v[:, :, 1] * a[:, :, 0]
        size = np.hypot(v[:, :, 0], v[:, :, 1]) * np.hypot(a[:, :, 0], a[:, :, 1])
        orbit = np.where(np.abs(cross) > _STRAIGHT * size, np.sign(cross), 0.0)
        sense = self.tape.drive_sense  # a driven body's orbit turns as its drive does
        driven = sense != 0.0
        orbit[:, driven] = sense[driven]
        return np.sign(d[:, :, VW]) * orbit

    def marks(self, color: Any) -> np.ndarray:
        """(frames, bodies) of -1 (red), +1 (blue), 0 (grey): ``color`` itself if it is such an array of
        marks (e.g. only the reverse-rotation episodes an analysis established:
        :func:`rrbody.analysis.episodes.episode_marks`), else :meth:`senses` (``color="spin"``)."""
        return color if isinstance(color, np.ndarray) else self.senses()

    def _frame_at(self, tau: float) -> int:
        """The last captured frame at or before simulated time ``tau`` (the first one before it all)."""
        t = self._times[:self.n_frames]
        return int(max(np.searchsorted(t, tau * (1 + 1e-12) + 1e-12, side="right") - 1, 0))

    # ---- pictures --------------------------------------------------------------------------------
    def _view(self, box: Sequence[float] | None, aspect: float, frames: np.ndarray | None = None) -> tuple[float, ...]:
        """(xmin, xmax, ymin, ymax) in m: ``box`` as given (checked here), or fitted to every filmed
        body's whole outline over the frames with a margin (:func:`fit_view`), widened to ``aspect``."""
        if box is not None:
            try:
                x0, x1, y0, y1 = (float(v) for v in box)
            except (TypeError, ValueError):
                x0 = math.nan
            if not all(math.isfinite(v) for v in (x0, x1, y0, y1)) or not (x0 < x1 and y0 < y1):
                raise ValueError(f"box must be (xmin, xmax, ymin, ymax) in m, finite with xmin < xmax and "
                                 f"ymin < ymax, got {box!r}")
            return fit_view(np.empty((0, 0, 2)), np.empty(0), aspect, (x0, x1, y0, y1))
        return fit_view(self.centres() if frames is None else self.centres()[frames], self._reach, aspect)

    def _check_look(self, color: Any, arrows: Iterable[str], trails: Any) -> tuple[Any, tuple[str, ...], np.ndarray]:
        arrows = tuple(arrows)
        bad = [a for a in arrows if a not in ("velocity", "friction", "torque")]
        if bad:
            raise ValueError(f"arrows must be some of 'velocity', 'friction', 'torque', got {bad[0]!r}")
        if arrows:
            self._need_motion("arrows")
        color = check_color(color, self.n_frames, len(self.bodies))
        if isinstance(color, str) and color == "spin":
            self._need_motion('color="spin"')
        if trails is True:
            mask = np.ones(len(self.bodies), bool)
        elif trails is False or trails is None:
            mask = np.zeros(len(self.bodies), bool)
        else:
            mask = np.zeros(len(self.bodies), bool)
            mask[self._indices(trails, "trails must be True, False or filmed bodies")] = True
        return color, arrows, mask

    def _indices(self, bodies: Iterable[Any], what: str) -> list[int]:
        """The filmed bodies' indices of ``bodies``; ValueError starting with ``what`` for one not filmed."""
        index = {b: k for k, b in enumerate(self.bodies)}
        out = []
        for b in bodies:
            if b not in index:
                raise ValueError(f"{what}, got {b!r} (not filmed)")
            out.append(index[b])
        return out

    def image(self, t: float | None = None, *, size: tuple[int, int] = (1280, 720), box: Sequence[float] | None = None,
              color: Any = "body", arrows: Iterable[str] = (), trails: Any = False, title: str | None = None
              ) -> np.ndarray:
        """The picture (height x width x 3, uint8) of the last frame captured at or before ``t`` (s;
        default the last frame), as a movie frame shows it."""
        self._need_frames()
        size = check_size(size)
        color, arrows, mask = self._check_look(color, arrows, trails)
        k = self.n_frames - 1 if t is None else self._frame_at(check_real("t", t))
        art = Picture(self, size=size, box=self._view(box, size[0] / size[1]), color=color, arrows=arrows,
                       trails=mask, title=title)
        art.update(k)
        return np.asarray(art.frame())[:, :, :3].copy()

    def movie(self, path: str | Path, *, fps: float = 30, speed: float = 1.0, size: tuple[int, int] = (1280, 720),
              box: Sequence[float] | None = None, color: Any = "body", arrows: Iterable[str] = (),
              trails: Any = False, title: str | None = None, t_start: float | None = None,
              t_end: float | None = None, force: bool = False, progress: bool | None = None) -> Path:
        """An MP4 of the captured frames at ``fps`` frames per s of playback, ``speed`` simulated s per s
        (each frame: the last capture at or before its time). ``color``: "body" (one colour each),
        "spin" (red against the orbit, blue with it, grey neither), a colour, one per body, or marks
        (an array (frames, bodies) of -1 red, +1 blue, 0 grey: :meth:`marks`);
        ``arrows``: any of "velocity" (of the centre of gravity), "friction" (the plane's force on
        it) and "torque" (an arc, the friction torque's sense and size); ``trails``: True or the
        bodies whose centre of gravity's path to draw; ``box``: (xmin, xmax, ymin, ymax) in m
        (default: fitted to what moved). An existing file needs ``force``. Returns the path."""
        from rrbody.model.extras import require
        from rrbody.render.mp4 import frame_times, write_frames

        require("imageio_ffmpeg", purpose="a movie")
        final, fps, speed, size = check_movie(path, force=force, fps=fps, speed=speed, size=size)
        self._need_frames()
        color, arrows, mask = self._check_look(color, arrows, trails)
        t = self._times[:self.n_frames]
        a = float(t[0]) if t_start is None else check_real("t_start", t_start)
        b = float(t[-1]) if t_end is None else check_real("t_end", t_end)
        if not (t[0] - 1e-9 <= a <= b <= t[-1] + 1e-9):
            raise ValueError(f"t_start, t_end must satisfy {t[0]:g} <= t_start <= t_end <= {t[-1]:g} s, got {a!r}, "
                             f"{b!r}")
        taus = frame_times(a, b, fps=fps, speed=speed) if b > a else np.array([a])
        ks = [self._frame_at(float(x)) for x in taus]
        span = np.arange(ks[0], ks[-1] + 1)
        art = Picture(self, size=size, box=self._view(box, size[0] / size[1], span), color=color, arrows=arrows,
                       trails=mask, title=title, arrow_frames=span)

        def frames() -> Iterable[Any]:
            for k in ks:
                art.update(k)
                yield art.frame()

        show = sys.stderr.isatty() if progress is None else bool(progress)
        try:
            return write_frames(final, frames(), len(ks), size=size, fps=fps, force=force, progress=show)
        finally:
            art.close()

    def poster(self, path: str | Path, *, times: Sequence[float] | None = None, panels: int = 4,
               size: tuple[int, int] | None = None, box: Sequence[float] | None = None, color: Any = "body",
               arrows: Iterable[str] = (), trails: Any = False, title: str | None = None, force: bool = False) -> Path:
        """One PNG of chosen instants side by side: the frames captured last at or before each of
        ``times`` (s; default ``panels`` instants evenly spread over the capture), each under its time,
        all on one box (fitted to the whole capture unless given). Size default 480 px a panel x 480."""
        final = check_writable(path, force=force, name="poster")
        if final.suffix.lower() != ".png":
            raise ValueError(f"poster path must end in .png, got {str(path)!r}")
        self._need_frames()
        t = self._times[:self.n_frames]
        if times is None:
            panels = check_int("panels", panels, 1, 12)
            times = np.linspace(t[0], t[-1], panels)
        times = [check_real("times", x) for x in times]
        if not 1 <= len(times) <= 12:
            raise ValueError(f"times must give 1 to 12 instants, got {len(times)}")
        size = check_size((480 * len(times), 480) if size is None else size)
        color, arrows, mask = self._check_look(color, arrows, trails)
        ks = [self._frame_at(x) for x in times]
        w = size[0] // len(times)
        view = self._view(box, w / size[1])
        import matplotlib.figure as mfig
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        fig = mfig.Figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
        FigureCanvasAgg(fig)
        for i, k in enumerate(ks):
            art = Picture(self, size=(w, size[1]), box=view, color=color, arrows=arrows, trails=mask,
                           title=title, fig=fig, rect=(i / len(ks), 0.0, 1.0 / len(ks), 1.0))
            art.update(k)
        from rrbody.render.figures import savefig_reproducible

        with atomic_path(final, force=force, name="poster") as tmp:
            savefig_reproducible(fig, tmp, fmt="png", dpi=100)  # no date or version: the same poster, the same bytes
        return final

    def rerun(self, path: str | Path | None, *, spawn: bool = False, plots: Sequence[Any] | None = None,
              color: Any = "body", trails: Any = False, force: bool = False) -> Path | None:
        """A rerun recording (.rrd at ``path`` and/or a spawned viewer): one entity per body,
        ``world/bodies/<label>`` (its outline in its own frame, moved by a transform at every captured
        time), the static shapes, P of driven bodies, optional trails, and for ``plots`` (bodies;
        default every body when there are at most 8) the speed of the centre of gravity (m/s), the
        spin (rad/s) and the friction power F.v + tau spin (W) under ``plots/<quantity>/<label>``."""
        from rrbody.render import rerun as rerun_io

        rerun_io.check_output(path, spawn=spawn, force=force)
        self._need_frames()
        color, _, mask = self._check_look(color, (), trails)
        if plots is None:
            chosen = list(range(len(self.bodies))) if len(self.bodies) <= 8 else []
        else:
            chosen = self._indices(plots, "plots must list filmed bodies")
        if chosen:
            self._need_motion("plots")
        from rrbody.render.recorder_rerun import blueprint, send

        view = self._view(None, 1.0)
        return rerun_io.write_recording(path, spawn=spawn, force=force, blueprint=blueprint(view, bool(chosen)),
                                        send=lambda rec: send(rec, self, color=color, trails=mask, plots=chosen))

    def colours(self, color: Any) -> Any:
        """Per-body RGBA (bodies x 4) for a fixed colouring, or None for "spin" or marks (per frame: :meth:`marks`)."""
        return body_colours(color, len(self.bodies))
