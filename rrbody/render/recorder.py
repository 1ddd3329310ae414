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
:meth:`rrbody.engine.plugin.PlaneFriction.velocity` gives, since pymunk's own velocity after a step
belongs to half a step later) and the friction the plane applied in the last step (N and N m,
:meth:`rrbody.engine.plugin.PlaneFriction.friction`). Memory: bodies x frames x 3 numbers (poses
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
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.engine.batchio import BatchIO, body_uid
from rrbody.engine.bodymem import address, addresses
from rrbody.engine.capture import capture_direct, capture_rows, layout
from rrbody.contact.lean import fast_entry
from rrbody.contact.rows import Rows
from rrbody.model.checks import check_int, check_positive, check_real
from rrbody.model.io import atomic_path, check_writable
from rrbody.render.movie_figure import check_movie, check_size
from rrbody.render.recorder_picture import (CIRCLE_POINTS, NEUTRAL, PA, PX, PY, REVERSE, VW, VX, VY, WIDTH_MOTION,
                                            WIDTH_POSE, WITH, Picture, fit_view, shape_outlines, to_world)

__all__ = ["Recorder", "shape_outlines", "CIRCLE_POINTS", "REVERSE", "WITH", "NEUTRAL"]

#: relative size under which the orbit's turning (v x a) counts as none (rounding of a straight path)
_STRAIGHT = 1e-9
#: the plugin's arrays when there is no plane (capture_rows reads none of it then)
_NO_ROWS = np.zeros((0, K.N_BODY))


def _rows_of(keys: np.ndarray, rows: np.ndarray, want: np.ndarray) -> np.ndarray:
    """The row of each id of ``want`` in a table of ids ``keys`` (sorted) and their ``rows``; -1 where
    it is absent."""
    out = np.full(len(want), -1, dtype=np.int64)
    if len(keys):
        pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
        hit = keys[pos] == want
        out[hit] = rows[pos[hit]]
    return out


class Recorder:
    """Captures the bodies of a pymunk space step by step; films them as MP4, rerun recording or poster.

    Parameters
    ----------
    space : pymunk.Space
        The space to film. Its static shapes (walls, obstacles) are drawn as they are when filmed.
    plane : rrbody.engine.plugin.PlaneFriction or None
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

        if not isinstance(space, pymunk.Space):
            raise ValueError(f"space must be a pymunk.Space, got {space!r}")
        if plane is not None and getattr(plane, "space", None) is not space:
            raise ValueError(f"plane must be the PlaneFriction of this space (or None), got {plane!r}")
        self.space, self.plane = space, plane
        self.every = check_int("every", every, 1, 10**9)
        self.max_mb = check_positive("max_mb", max_mb, unit="MB")
        self.motion = bool(motion)
        if bodies is None:
            first = list(plane.bodies) if plane is not None else []
            seen = set(first)
            bodies = first + [b for b in space.bodies if b not in seen and b.shapes
                              and b.body_type != pymunk.Body.STATIC]
        self.bodies: tuple[Any, ...] = tuple(bodies)
        if not self.bodies:
            raise ValueError("bodies: nothing to film, got 0 bodies (the space has no dynamic or kinematic body "
                             "with shapes): add bodies to the space before creating the Recorder")
        for k, b in enumerate(self.bodies):
            if not isinstance(b, pymunk.Body) or b.space is not space or b.body_type == pymunk.Body.STATIC \
                    or not b.shapes:
                raise ValueError(f"bodies[{k}] must be a dynamic or kinematic pymunk.Body with shapes, in this "
                                 f"space, got {b!r}")
        if len(set(self.bodies)) != len(self.bodies):
            raise ValueError("bodies must not repeat a body")
        if labels is None:
            labels = [f"b{k:04d}" for k in range(len(self.bodies))]
        self.labels = tuple(str(x) for x in labels)
        if len(self.labels) != len(self.bodies) or len(set(self.labels)) != len(self.labels):
            raise ValueError(f"labels must give {len(self.bodies)} distinct names (one per body), got "
                             f"{len(self.labels)} ({len(set(self.labels))} distinct)")
        # geometry, read now (like the plugin's add): outlines in body coordinates, the centre of gravity
        self._outlines = [shape_outlines(b) for b in self.bodies]
        self._cog = np.array([tuple(b.center_of_gravity) for b in self.bodies], dtype=float)
        self._reach = np.array([max(float(np.hypot(*(o - c).T).max()) for o in outs)
                                for outs, c in zip(self._outlines, self._cog)])
        self._static = [o for b in [space.static_body, *[x for x in space.bodies if x.body_type == pymunk.Body.STATIC]]
                        for o in [to_world(p, b.position.x, b.position.y, b.angle) for p in shape_outlines(b)]]
        ids = np.array([body_uid(b) for b in self.bodies], dtype=np.int64)
        self._ids = ids
        # the driven point P (body coordinates) and the drive's sense, for bodies rrbody's builder drives
        self._anchor = np.full((len(self.bodies), 2), np.nan)
        self._drive_sense = np.zeros(len(self.bodies))
        if plane is not None:
            for k, b in enumerate(self.bodies):
                j = plane._slots.get(b)
                if j is not None and plane._bodies[j, K.DRV] > 0.0:
                    self._anchor[k] = plane._bodies[j, [K.ANX, K.ANY]]
                    self._drive_sense[k] = math.copysign(1.0, plane._bodies[j, K.OMG])
        self._width = WIDTH_MOTION if self.motion else WIDTH_POSE
        self._frame_bytes = len(self.bodies) * self._width * 8
        #: the most frames max_mb allows
        self._max_frames = int(self.max_mb * 1e6 // self._frame_bytes)
        self._kernel: Any = None  # the capture kernel's compiled entry point (capture_direct or capture_rows), found on the first capture
        self._store = Rows((len(self.bodies), self._width))  # the frames, and their times (s)
        self._clock = Rows(None)
        if reserve is not None:
            if self._max_frames < 1:
                raise ValueError(f"reserve: max_mb={self.max_mb:g} MB holds no frame of {self._frame_bytes} bytes; "
                                 f"raise max_mb")
            reserve = check_int("reserve", reserve, 1, self._max_frames,
                                unit=f"frames (what max_mb={self.max_mb:g} MB holds)")
            self._store.ensure(reserve, touch=True)
            self._clock.ensure(reserve, touch=True)
        self._calls = 0
        self._rows = np.full(len(self.bodies), -1, dtype=np.int64)  # their rows in the space's bulk read
        self._prow: tuple[int, np.ndarray] | None = None  # (plane.members, their rows in the plane's arrays)
        self._no_plane = np.full(len(self.bodies), -1, dtype=np.int64)
        # the bodies' state is read from their structs where pymunk's layout of them is known (about
        # 2 us per 1,000 bodies), else from the space's bulk read (about 14 us: rrbody.engine.capture)
        self._offs = layout()
        self._io = BatchIO(space, poses=True) if self._offs is None else None
        if self._offs is not None:
            self._addr = addresses(self.bodies)
            self._space_addr = address(space._space)

    # ---- capture ---------------------------------------------------------------------------------
    @property
    def bytes_per_frame(self) -> int:
        """Memory one captured frame takes: bodies x (3 or 9) numbers x 8 bytes."""
        return self._frame_bytes

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
        self._calls += 1
        if (self._calls - 1) % self.every:
            return False
        if t is None:
            if self.plane is None:
                raise ValueError("t must be given (the frame's time, s) when the Recorder has no plane")
            t = float(self.plane.t)
        else:
            t = check_real("t", t)
        n = self._store.n
        if n >= self._store.buf.shape[0] or n >= self._max_frames:
            self._make_room(n)
        prow = self._plane_rows()
        bodies = _NO_ROWS if self.plane is None else self.plane._bodies
        store = self._store.buf
        if self._io is None:
            kernel, args = capture_direct, (self._addr, self._offs, self._space_addr, bodies, prow, store, n)
        else:
            got, ids, _ = self._io.read()
            kernel, args = capture_rows, (got, ids, self._ids, self._rows, bodies, prow, store, n)
        if self._kernel is None:
            self._kernel, result = fast_entry(kernel, *args)
        else:
            result = self._kernel(*args)
        if self._io is None:
            if result >= 0:  # the index of a filmed body no longer in the space
                self._gone(result, n)
        elif not result:
            # the space's order changed (bodies added or removed): find the filmed bodies again
            order = np.argsort(ids)
            rows = _rows_of(ids[order], order, self._ids)
            if (rows < 0).any():
                self._gone(int(np.flatnonzero(rows < 0)[0]), n)
            self._rows = rows
            capture_rows(got, ids, self._ids, self._rows, bodies, prow, store, n)
        self._clock.buf[n] = t
        self._store.n = self._clock.n = n + 1
        return True

    def _gone(self, k: int, n: int) -> None:
        """The ValueError for filmed body ``k`` having left the space at frame ``n`` (nothing is stored)."""
        raise ValueError(f"bodies[{k}] ({self.labels[k]}) is no longer in the space (frame {n}): a filmed "
                         f"body must stay in the space; the {n} frames captured are kept")

    def _make_room(self, n: int) -> None:
        """Room for frame ``n`` (the store doubles), or the ValueError of ``max_mb`` (nothing changes)."""
        if n + 1 > self._max_frames:
            raise ValueError(f"max_mb: frame {n} would take the capture past max_mb={self.max_mb:g} MB "
                             f"({len(self.bodies)} bodies x {self._width} numbers x 8 bytes a frame); "
                             f"the {n} frames captured are kept: film them, raise max_mb, or capture less "
                             f"often (every=...)")
        self._store.ensure(n + 1)
        self._clock.ensure(n + 1)  # the same capacity as the store's: both grow by the same rule

    @property
    def n_frames(self) -> int:
        """How many frames were captured."""
        return self._store.n

    @property
    def _data(self) -> np.ndarray:
        """The frame store (its first ``n_frames`` rows are the frames)."""
        return self._store.buf

    @property
    def _times(self) -> np.ndarray:
        """The frames' times (s; the first ``n_frames``)."""
        return self._clock.buf

    def _plane_rows(self) -> np.ndarray:
        """Each filmed body's row in the plane's arrays, or -1 (cached until the plane's membership changes)."""
        pf = self.plane
        if pf is None:
            return self._no_plane
        if self._prow is None or self._prow[0] != pf.members:
            if pf._dirty:
                pf._relink()
            look = pf._k_lookup
            self._prow = (pf.members, _rows_of(look[0], look[1], self._ids))
        return self._prow[1]

    # ---- derived quantities ----------------------------------------------------------------------
    def _need_frames(self) -> None:
        if self.n_frames == 0:
            raise ValueError("nothing to film: 0 frames captured (call rec.capture() after each step)")

    def _need_motion(self, what: str) -> None:
        if not self.motion:
            raise ValueError(f"{what} needs velocities: create the Recorder with motion=True")

    def centres(self) -> np.ndarray:
        """Centres of gravity (frames, bodies, 2), m, world frame."""
        d = self._data[:self.n_frames]
        c, s = np.cos(d[:, :, PA]), np.sin(d[:, :, PA])
        gx, gy = self._cog[:, 0], self._cog[:, 1]
        return np.stack([d[:, :, PX] + c * gx - s * gy, d[:, :, PY] + s * gx + c * gy], axis=2)

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
        driven = self._drive_sense != 0.0
        orbit[:, driven] = self._drive_sense[driven]
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
        if isinstance(color, np.ndarray) and color.ndim == 2:  # marks per frame and body (-1, 0, +1)
            if color.shape != (self.n_frames, len(self.bodies)) or not np.isin(color, (-1.0, 0.0, 1.0)).all():
                raise ValueError(f"color as marks must be an array (frames, bodies) = ({self.n_frames}, "
                                 f"{len(self.bodies)}) of -1, 0 and +1, got shape {color.shape}")
        elif isinstance(color, str) and color == "spin":
            self._need_motion('color="spin"')
        elif not (isinstance(color, str) and color == "body"):
            from matplotlib.colors import is_color_like

            cols = [color] if isinstance(color, str) or (isinstance(color, tuple) and len(color) in (3, 4)
                                                          and all(isinstance(v, (int, float)) for v in color)) \
                else list(color)
            if len(cols) not in (1, len(self.bodies)) or not all(is_color_like(c) for c in cols):
                raise ValueError(f"color must be 'body', 'spin', a colour or one colour per body "
                                 f"({len(self.bodies)}), got {color!r}")
            color = cols
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
            raise ValueError(f"t_start, t_end must satisfy {t[0]:g} <= t_start <= t_end <= {t[-1]:g} s, got {a!r}, {b!r}")
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
        from rrbody.render import rerun as R

        R.check_output(path, spawn=spawn, force=force)
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
        return R.write_recording(path, spawn=spawn, force=force, blueprint=blueprint(view, bool(chosen)),
                                 send=lambda rec: send(rec, self, color=color, trails=mask, plots=chosen))

    def colours(self, color: Any) -> Any:
        """Per-body RGBA (bodies x 4) for a fixed colouring, or None for "spin" or marks (per frame: :meth:`marks`)."""
        from matplotlib import colormaps
        from matplotlib.colors import to_rgba_array

        if (isinstance(color, str) and color == "spin") or isinstance(color, np.ndarray) and color.ndim == 2:
            return None
        if isinstance(color, str) and color == "body":
            cmap = colormaps["tab10"]
            return np.array([cmap(k % 10) for k in range(len(self.bodies))])
        rgba = to_rgba_array(color)
        return np.repeat(rgba, len(self.bodies), axis=0) if len(rgba) == 1 else rgba


