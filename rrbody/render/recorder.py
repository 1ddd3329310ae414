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
bodies of the plugin the second-order reading :meth:`PlaneFriction.velocity` gives, since pymunk's
own velocity after a step belongs to half a step later) and the friction the plane applied in the
last step (N and N m, :meth:`PlaneFriction.friction`). Memory: bodies x frames x 3 numbers (poses
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

from rrbody.engine import kernel as K
from rrbody.engine.batchio import BatchIO, body_uid
from rrbody.engine.rows import Rows
from rrbody.model.checks import check, check_int, check_positive, check_real
from rrbody.model.io import atomic_path, check_writable
from rrbody.render.movie_figure import check_size

__all__ = ["Recorder", "shape_outlines", "CIRCLE_POINTS", "REVERSE", "WITH", "NEUTRAL"]

#: points on a circle's rim in its outline (a regular polygon: its centroid is the circle's centre)
CIRCLE_POINTS = 48
#: colour by spin: turning against the orbit (reverse rotation), with it, neither
REVERSE, WITH, NEUTRAL = "#d62728", "#1f77b4", "#9a9a9a"
_WIDTH_POSE, _WIDTH_MOTION = 3, 9  # numbers per body and frame
_PX, _PY, _PA, _VX, _VY, _VW, _FX, _FY, _FT = range(9)
#: relative size under which the orbit's turning (v x a) counts as none (rounding of a straight path)
_STRAIGHT = 1e-9
#: the plugin's arrays when there is no plane (capture_rows reads none of it then)
_NO_ROWS = np.zeros((0, K.N_BODY))


# ---- outlines ------------------------------------------------------------------------------------
def _capsule(a: np.ndarray, b: np.ndarray, r: float) -> np.ndarray:
    """The outline of the set within r of the segment a-b (a stadium), counter-clockwise."""
    d = b - a
    ang = math.atan2(d[1], d[0]) if np.any(d) else 0.0
    half = CIRCLE_POINTS // 2
    s1 = ang - math.pi / 2 + np.linspace(0.0, math.pi, half + 1)
    s0 = ang + math.pi / 2 + np.linspace(0.0, math.pi, half + 1)
    return np.vstack([b + r * np.column_stack([np.cos(s1), np.sin(s1)]),
                      a + r * np.column_stack([np.cos(s0), np.sin(s0)])])


def _rounded(v: np.ndarray, r: float) -> np.ndarray:
    """A convex polygon ``v`` grown by r (pymunk's rounded polygon): its vertices' circles' convex hull."""
    from scipy.spatial import ConvexHull

    s = np.linspace(0.0, 2.0 * math.pi, CIRCLE_POINTS, endpoint=False)
    ring = r * np.column_stack([np.cos(s), np.sin(s)])
    pts = (v[:, None, :] + ring[None, :, :]).reshape(-1, 2)
    return pts[ConvexHull(pts).vertices]


def shape_outlines(body: Any) -> list[np.ndarray]:
    """Outlines of ``body``'s shapes in its own frame (pymunk's body coordinates, m): one closed
    polygon (k x 2, not repeating its first point) per shape. A circle starts at its centre and runs
    round its rim from the body's x axis, so its edge draws the radius a pymunk debug view draws; a
    segment is the stadium within its radius (a line when the radius is 0)."""
    import pymunk

    out = []
    for s in body.shapes:
        if isinstance(s, pymunk.Circle):
            c = np.array(tuple(s.offset))
            a = np.linspace(0.0, 2.0 * math.pi, CIRCLE_POINTS + 1)
            out.append(np.vstack([c, c + s.radius * np.column_stack([np.cos(a), np.sin(a)])]))
        elif isinstance(s, pymunk.Poly):
            v = np.array([tuple(p) for p in s.get_vertices()], dtype=float)
            out.append(_rounded(v, s.radius) if s.radius > 0.0 else v)
        elif isinstance(s, pymunk.Segment):
            a, b = np.array(tuple(s.a)), np.array(tuple(s.b))
            out.append(_capsule(a, b, s.radius) if s.radius > 0.0 else np.vstack([a, b]))
    return out


def _to_world(o: np.ndarray, x: float, y: float, ang: float) -> np.ndarray:
    c, s = math.cos(ang), math.sin(ang)
    return np.column_stack([x + c * o[:, 0] - s * o[:, 1], y + s * o[:, 0] + c * o[:, 1]])


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
    plane : PlaneFriction or None
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
    """

    def __init__(self, space: Any, plane: Any = None, *, bodies: Sequence[Any] | None = None,
                 labels: Sequence[str] | None = None, every: int = 1, motion: bool = True,
                 max_mb: float = 1000.0) -> None:
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
                        for o in [_to_world(p, b.position.x, b.position.y, b.angle) for p in shape_outlines(b)]]
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
        self._width = _WIDTH_MOTION if self.motion else _WIDTH_POSE
        self._frame_bytes = len(self.bodies) * self._width * 8
        self._kernel: Any = None  # capture_rows' compiled entry point, found on the first capture
        self._store = Rows((len(self.bodies), self._width))  # the frames, and their times (s)
        self._clock = Rows(None)
        self.n_frames = 0
        self._calls = 0
        self._rows = np.full(len(self.bodies), -1, dtype=np.int64)  # their rows in the space's bulk read
        self._prow: tuple[int, np.ndarray] | None = None  # (plane.members, their rows in the plane's arrays)
        self._no_plane = np.full(len(self.bodies), -1, dtype=np.int64)
        self._io = BatchIO(space, poses=True)

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
        n = self.n_frames
        if (n + 1) * self._frame_bytes > self.max_mb * 1e6:
            raise ValueError(f"max_mb: frame {n} would take the capture past max_mb={self.max_mb:g} MB "
                             f"({len(self.bodies)} bodies x {self._width} numbers x 8 bytes a frame); "
                             f"the {n} frames captured are kept: film them, raise max_mb, or capture less "
                             f"often (every=...)")
        got, ids, _ = self._io.read()
        self._store.ensure(n + 1)
        self._clock.ensure(n + 1)
        prow = self._plane_rows()
        bodies = self.plane._bodies if self.plane is not None else _NO_ROWS
        args = (got, ids, self._ids, self._rows, bodies, prow, self._data[n])
        if self._kernel is None:
            self._kernel, ok = K.fast_entry(K.capture_rows, *args)
        else:
            ok = self._kernel(*args)
        if not ok:
            # the space's order changed (bodies added or removed): find the filmed bodies again
            order = np.argsort(ids)
            rows = _rows_of(ids[order], order, self._ids)
            if (rows < 0).any():
                k = int(np.flatnonzero(rows < 0)[0])
                raise ValueError(f"bodies[{k}] ({self.labels[k]}) is no longer in the space (frame {n}): a filmed "
                                 f"body must stay in the space; the {n} frames captured are kept")
            self._rows = rows
            K.capture_rows(got, ids, self._ids, self._rows, bodies, prow, self._data[n])
        self._times[n] = t
        self.n_frames = self._store.n = self._clock.n = n + 1
        return True

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
        c, s = np.cos(d[:, :, _PA]), np.sin(d[:, :, _PA])
        gx, gy = self._cog[:, 0], self._cog[:, 1]
        return np.stack([d[:, :, _PX] + c * gx - s * gy, d[:, :, _PY] + s * gx + c * gy], axis=2)

    def senses(self) -> np.ndarray:
        """(frames, bodies): -1 where a body turns against its orbit (reverse rotation), +1 with it,
        0 where its spin or its orbit's sense is zero (see the module docstring for the orbit's sense)."""
        self._need_motion('color="spin"')
        d = self._data[:self.n_frames]
        t = self._times[:self.n_frames]
        v = d[:, :, _VX:_VY + 1]
        if self.n_frames >= 2:
            a = np.gradient(v, t, axis=0)
        else:
            a = np.zeros_like(v)
        cross = v[:, :, 0] * a[:, :, 1] - v[:, :, 1] * a[:, :, 0]
        size = np.hypot(v[:, :, 0], v[:, :, 1]) * np.hypot(a[:, :, 0], a[:, :, 1])
        orbit = np.where(np.abs(cross) > _STRAIGHT * size, np.sign(cross), 0.0)
        driven = self._drive_sense != 0.0
        orbit[:, driven] = self._drive_sense[driven]
        return np.sign(d[:, :, _VW]) * orbit

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
        """(xmin, xmax, ymin, ymax) in m: ``box`` as given, or fitted to every filmed body over the
        frames (its centre of gravity +- its reach) and padded 4 %; either widened about its centre
        to the picture's aspect (``aspect`` = width / height), so that a metre is as long across as up."""
        if box is not None:
            try:
                x0, x1, y0, y1 = (float(v) for v in box)
            except (TypeError, ValueError):
                x0 = math.nan
            if not all(math.isfinite(v) for v in (x0, x1, y0, y1)) or not (x0 < x1 and y0 < y1):
                raise ValueError(f"box must be (xmin, xmax, ymin, ymax) in m, finite with xmin < xmax and "
                                 f"ymin < ymax, got {box!r}")
            w, h = x1 - x0, y1 - y0
        else:
            c = self.centres() if frames is None else self.centres()[frames]
            r = self._reach[None, :]
            x0, x1 = float((c[:, :, 0] - r).min()), float((c[:, :, 0] + r).max())
            y0, y1 = float((c[:, :, 1] - r).min()), float((c[:, :, 1] + r).max())
            w, h = 1.04 * max(x1 - x0, 1e-9), 1.04 * max(y1 - y0, 1e-9)
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        w, h = max(w, h * aspect), max(h, w / aspect)
        return cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2

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
        art = _Picture(self, size=size, box=self._view(box, size[0] / size[1]), color=color, arrows=arrows,
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
        final = check_writable(path, force=force, name="movie")
        if final.suffix.lower() != ".mp4":
            raise ValueError(f"movie path must end in .mp4, got {str(path)!r}")
        fps = check("fps", fps)
        speed = check("movie_speed", speed, label="speed")
        size = check_size(size)
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
        art = _Picture(self, size=size, box=self._view(box, size[0] / size[1], span), color=color, arrows=arrows,
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
            art = _Picture(self, size=(w, size[1]), box=view, color=color, arrows=arrows, trails=mask,
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


class _Picture:
    """The artists of one picture of a Recorder's frames, updated in place frame by frame (matplotlib,
    Agg): the static shapes and scale bar in a cached background; the bodies (one compound path per
    colour), P and its link, arrows (quivers), torque arcs and trails (LineCollections) and the time
    label drawn each frame."""

    def __init__(self, rec: Recorder, *, size: tuple[int, int], box: tuple[float, ...], color: Any,
                 arrows: tuple[str, ...], trails: np.ndarray, title: str | None, fig: Any = None,
                 rect: tuple[float, float, float, float] = (0.0, 0.0, 1.0, 1.0),
                 arrow_frames: np.ndarray | None = None) -> None:
        import matplotlib.figure as mfig
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection, PolyCollection

        self.rec = rec
        own = fig is None
        if own:
            fig = mfig.Figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
            FigureCanvasAgg(fig)
        self.fig, self.own = fig, own
        ax = fig.add_axes(rect)
        ax.set_xlim(box[0], box[1])
        ax.set_ylim(box[2], box[3])
        ax.set_aspect("auto")  # the box already has the picture's aspect: 1 m is as wide as it is tall
        ax.set_axis_off()
        self.ax = ax
        ax.add_patch(_frame_patch(ax))
        if rec._static:
            ax.add_collection(PolyCollection(rec._static, closed=True, facecolors="#cfcfcf", edgecolors="#555555",
                                             linewidths=1.0))
        _scale_bar(ax, box)
        # the bodies' outlines, all in one array, each polygon closed by a repeat of its first vertex:
        # vertex -> body, vertex -> polygon; drawn as one compound path per colour (a PathCollection of
        # a few paths renders 1,000 bodies several times faster than 1,000 separate polygons)
        from matplotlib.collections import PathCollection
        from matplotlib.path import Path as MPath

        polys = [(k, np.vstack([o, o[:1]])) for k, outs in enumerate(rec._outlines) for o in outs]
        self._vb = np.concatenate([np.full(len(o), k) for k, o in polys])
        self._v = np.concatenate([o for _, o in polys])
        codes = [np.full(len(o), MPath.LINETO, dtype=MPath.code_type) for _, o in polys]
        for c in codes:
            c[0], c[-1] = MPath.MOVETO, MPath.CLOSEPOLY
        self._codes = np.concatenate(codes)
        self._pbody = np.array([k for k, _ in polys])
        self.fixed = rec.colours(color)
        self.spin = rec.marks(color) if self.fixed is None else None
        if self.fixed is not None:
            faces = _faded(self.fixed)
            palette, which = np.unique(faces, axis=0, return_inverse=True)
            self._palette, self._group = palette, np.asarray(which).ravel()  # body -> its colour's index
        else:
            self._palette = np.array([_RGBA_REVERSE, _RGBA_WITH, _RGBA_NEUTRAL])
            self._group = np.zeros(len(rec.bodies), dtype=np.intp)
        self.bodies = PathCollection([], edgecolors="#222222", linewidths=0.8, animated=True)
        ax.add_collection(self.bodies)
        self.trails = trails
        self.trail = LineCollection([], linewidths=0.8, colors="#444444", animated=True) if trails.any() else None
        if self.trail is not None:
            ax.add_collection(self.trail)
        self.centres = rec.centres()
        self.driven = np.flatnonzero(~np.isnan(rec._anchor[:, 0]))
        self.p = ax.scatter([], [], s=14, c="k", zorder=5, animated=True) if len(self.driven) else None
        # the rigid link from P to the centre of gravity (P may lie outside the body, as for a rod-mass)
        self.link = LineCollection([], colors="k", linewidths=0.8, zorder=5, animated=True) if len(self.driven) else None
        if self.link is not None:
            ax.add_collection(self.link)
        # arrows: one scale per kind over the frames filmed, its largest value a tenth of the box's width
        self.arrows: dict[str, Any] = {}
        span = slice(None) if arrow_frames is None else arrow_frames
        d = rec._data[:rec.n_frames][span]
        width = box[1] - box[0]
        legend = []
        for kind, cols, colour, unit in (("velocity", (_VX, _VY), "#2ca02c", "m/s"), ("friction", (_FX, _FY), "#9467bd", "N")):
            if kind in arrows:
                big = float(np.hypot(d[:, :, cols[0]], d[:, :, cols[1]]).max()) if d.size else 0.0
                scale = 0.1 * width / big if big > 0.0 else 0.0
                q = ax.quiver(np.zeros(len(rec.bodies)), np.zeros(len(rec.bodies)), np.zeros(len(rec.bodies)),
                              np.zeros(len(rec.bodies)), angles="xy", scale_units="xy", scale=1.0, color=colour,
                              width=0.003, zorder=6, animated=True)
                self.arrows[kind] = (q, cols, scale)
                if scale > 0.0:
                    legend.append(f"{kind}: 1 {unit} = {scale:.3g} m")
        if "torque" in arrows:
            big = float(np.abs(d[:, :, _FT]).max()) if d.size else 0.0
            self.torque = (LineCollection([], colors="#9467bd", linewidths=1.4, animated=True, zorder=6),
                           1.5 * math.pi / big if big > 0.0 else 0.0)
            ax.add_collection(self.torque[0])
            if big > 0.0:
                legend.append(f"torque arc: {big:.3g} N m = 270 deg")
        else:
            self.torque = None
        if self.spin is not None and not isinstance(color, np.ndarray):  # (marks: the caller's title says what they are)
            legend.insert(0, "red: turns against its orbit, blue: with it, grey: neither")
        style = dict(transform=ax.transAxes, fontsize=max(7, min(12, size[1] // 50)),
                     bbox=dict(facecolor="white", alpha=0.8, edgecolor="none", pad=2))
        if legend:
            ax.text(0.01, 0.01, "\n".join(legend), ha="left", va="bottom", **style)
        self.label = ax.text(0.01, 0.99, "", ha="left", va="top", animated=True, **style)
        self.title = title
        step = np.diff(rec._times[:rec.n_frames])
        dt = float(step[step > 0].min()) if (step > 0).any() else 1.0
        self.decimals = int(min(max(-math.floor(math.log10(dt)), 0), 6))
        self.bg = None
        if own:  # a movie's background: everything that does not move, drawn once
            self.fig.canvas.draw()
            self.bg = self.fig.canvas.copy_from_bbox(ax.bbox)

    def update(self, k: int) -> None:
        """Put the artists at captured frame ``k``."""
        rec = self.rec
        d = rec._data[k]
        x, y, a = d[:, _PX], d[:, _PY], d[:, _PA]
        c, s = np.cos(a)[self._vb], np.sin(a)[self._vb]
        vx, vy = self._v[:, 0], self._v[:, 1]
        world = np.column_stack([x[self._vb] + c * vx - s * vy, y[self._vb] + s * vx + c * vy])
        group = self._group
        if self.spin is not None:  # 0 against the orbit, 1 with it, 2 neither
            sense = self.spin[k]
            group = np.where(sense < 0, 0, np.where(sense > 0, 1, 2))
        vgroup = group[self._vb]
        from matplotlib.path import Path as MPath

        paths, faces = [], []
        for g in np.unique(vgroup):
            sel = vgroup == g
            paths.append(MPath(world[sel], self._codes[sel]))
            faces.append(self._palette[g])
        self.bodies.set_paths(paths)
        self.bodies.set_facecolor(faces)
        cen = self.centres[k]
        if self.trail is not None:
            idx = np.flatnonzero(self.trails)
            self.trail.set_segments([self.centres[:k + 1, b] for b in idx])
        if self.p is not None:
            anc = rec._anchor[self.driven]
            ca, sa = np.cos(a[self.driven]), np.sin(a[self.driven])
            at = np.column_stack([x[self.driven] + ca * anc[:, 0] - sa * anc[:, 1],
                                  y[self.driven] + sa * anc[:, 0] + ca * anc[:, 1]])
            self.p.set_offsets(at)
            self.link.set_segments(np.stack([at, cen[self.driven]], axis=1))
        for q, cols, scale in self.arrows.values():
            q.set_offsets(cen)
            q.set_UVC(scale * d[:, cols[0]], scale * d[:, cols[1]])
        if self.torque is not None:
            lc, scale = self.torque
            arcs = []
            for b in np.flatnonzero(d[:, _FT] != 0.0):
                sweep = scale * d[b, _FT]
                r = 0.75 * rec._reach[b]
                s_ = a[b] + np.linspace(0.0, sweep, 16)
                arcs.append(np.column_stack([cen[b, 0] + r * np.cos(s_), cen[b, 1] + r * np.sin(s_)]))
            lc.set_segments(arcs)
        when = f"t = {rec._times[k]:.{self.decimals}f} s"
        self.label.set_text(when if not self.title else f"{self.title}    {when}")
        if not self.own:  # a poster panel: drawn with the figure
            for art in self._animated():
                art.set_animated(False)

    def _animated(self) -> list[Any]:
        arts = [self.bodies, self.label]
        arts += [x for x in (self.trail, self.link, self.p) if x is not None]
        arts += [q for q, _, _ in self.arrows.values()]
        if self.torque is not None:
            arts.append(self.torque[0])
        return arts

    def frame(self) -> memoryview:
        """The RGBA buffer of the current frame (the background restored, the moving artists drawn)."""
        canvas = self.fig.canvas
        canvas.restore_region(self.bg)
        for art in self._animated():
            self.ax.draw_artist(art)
        return canvas.buffer_rgba()

    def close(self) -> None:
        self.fig.clear()


def _faded(rgba: np.ndarray) -> np.ndarray:
    out = np.array(rgba, dtype=float)
    out[:, 3] = 0.85
    return out


_RGBA_REVERSE, _RGBA_WITH, _RGBA_NEUTRAL = (np.array([int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)] + [0.85])
                                            for h in (REVERSE, WITH, NEUTRAL))


def _frame_patch(ax: Any) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle((0, 0), 1, 1, transform=ax.transAxes, facecolor="white", edgecolor="#888888", lw=1.0,
                     zorder=-10)


def _scale_bar(ax: Any, box: tuple[float, ...]) -> None:
    """A bar of a round length (1, 2 or 5 x 10^n m) near a fifth of the box's width, bottom right."""
    width = box[1] - box[0]
    raw = width / 5.0
    base = 10.0 ** math.floor(math.log10(raw))
    length = max(m * base for m in (1.0, 2.0, 5.0) if m * base <= raw)
    x1 = box[1] - 0.03 * width
    y = box[2] + 0.05 * (box[3] - box[2])
    ax.plot([x1 - length, x1], [y, y], color="k", lw=2.0, solid_capstyle="butt")
    ax.text(x1 - length / 2, y + 0.01 * (box[3] - box[2]), f"{length:g} m", ha="center", va="bottom", fontsize=9)
