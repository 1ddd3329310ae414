"""The recorder's pictures (:class:`rrbody.render.recorder.Recorder`): every pymunk shape's exact
outline in its body's frame, and the matplotlib artists of one picture, updated frame by frame.
Units: m and rad, world frame for what is drawn; the frame store's columns are the tape's
(:mod:`rrbody.engine.recording.tape`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

# the frames' columns
from rrbody.engine.recording.tape import FT, FX, FY, PA, PX, PY, VW, VX, VY, WIDTH_MOTION, WIDTH_POSE

__all__ = ["shape_outlines", "fit_view", "MARGIN", "CIRCLE_POINTS", "REVERSE", "WITH", "NEUTRAL", "Picture", "to_world",
           "check_color", "body_colours", "WIDTH_POSE", "WIDTH_MOTION", "PX", "PY", "PA", "VX", "VY", "VW", "FX", "FY",
           "FT"]

#: points on a circle's rim in its outline (a regular polygon: its centroid is the circle's centre)
CIRCLE_POINTS = 48
#: colour by spin: turning against the orbit (reverse rotation), with it, neither
REVERSE, WITH, NEUTRAL = "#d62728", "#1f77b4", "#9a9a9a"
#: the blank border a fitted view keeps round the bodies' whole paths, on each side, as a fraction of
#: the paths' larger extent: clear of the panel's frame line, and of most of the time label and scale bar
MARGIN = 0.08

# ---- colours -------------------------------------------------------------------------------------
def check_color(color: Any, n_frames: int, n_bodies: int) -> Any:
    """A picture's ``color`` checked (ValueError otherwise): marks (an array (frames, bodies) of -1, 0,
    +1) or "spin" or "body" as given, a colour or one per body as a list of colours."""
    if isinstance(color, np.ndarray) and color.ndim == 2:  # marks per frame and body (-1, 0, +1)
        if color.shape != (n_frames, n_bodies) or not np.isin(color, (-1.0, 0.0, 1.0)).all():
            raise ValueError(f"color as marks must be an array (frames, bodies) = ({n_frames}, "
                             f"{n_bodies}) of -1, 0 and +1, got shape {color.shape}")
        return color
    if isinstance(color, str) and color in ("spin", "body"):
        return color
    from matplotlib.colors import is_color_like

    cols = [color] if isinstance(color, str) or (isinstance(color, tuple) and len(color) in (3, 4)
                                                  and all(isinstance(v, (int, float)) for v in color)) \
        else list(color)
    if len(cols) not in (1, n_bodies) or not all(is_color_like(c) for c in cols):
        raise ValueError(f"color must be 'body', 'spin', a colour or one colour per body ({n_bodies}), "
                         f"got {color!r}")
    return cols


def body_colours(color: Any, n_bodies: int) -> Any:
    """Per-body RGBA (bodies x 4) for a fixed colouring (checked by :func:`check_color`), or None for
    "spin" or marks (their colours change per frame)."""
    from matplotlib import colormaps
    from matplotlib.colors import to_rgba_array

    if (isinstance(color, str) and color == "spin") or isinstance(color, np.ndarray) and color.ndim == 2:
        return None
    if isinstance(color, str) and color == "body":
        cmap = colormaps["tab10"]
        return np.array([cmap(k % 10) for k in range(n_bodies)])
    rgba = to_rgba_array(color)
    return np.repeat(rgba, n_bodies, axis=0) if len(rgba) == 1 else rgba


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


def fit_view(centres: np.ndarray, reach: np.ndarray, aspect: float,
             box: tuple[float, float, float, float] | None = None) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) in m of a picture ``aspect`` (width / height) wide per unit of height.

    ``box`` given: that box (checked by the caller). Otherwise fitted to the bodies' whole motion:
    every body's centre of gravity ``centres`` (frames, bodies, 2; m, world frame) plus or minus its
    ``reach`` (bodies; m, the farthest point of its outline from its centre of gravity), so each
    outline lies inside at every frame and every angle, then :data:`MARGIN` of the larger extent
    added on each side. Either way the box is widened about its centre to the picture's aspect, so
    that a metre is as long across as up.
    """
    if box is not None:
        x0, x1, y0, y1 = box
        w, h = x1 - x0, y1 - y0
    else:
        r = np.asarray(reach, dtype=float)[None, :]
        x0, x1 = float((centres[:, :, 0] - r).min()), float((centres[:, :, 0] + r).max())
        y0, y1 = float((centres[:, :, 1] - r).min()), float((centres[:, :, 1] + r).max())
        # a body at rest in one place still gets a picture its own size, not a point
        pad = MARGIN * max(x1 - x0, y1 - y0, 1e-9)
        w, h = x1 - x0 + 2.0 * pad, y1 - y0 + 2.0 * pad
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    w, h = max(w, h * aspect), max(h, w / aspect)
    return cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2


def to_world(o: np.ndarray, x: float, y: float, ang: float) -> np.ndarray:
    c, s = math.cos(ang), math.sin(ang)
    return np.column_stack([x + c * o[:, 0] - s * o[:, 1], y + s * o[:, 0] + c * o[:, 1]])


class Picture:
    """The artists of one picture of a Recorder's frames, updated in place frame by frame (matplotlib,
    Agg): the static shapes and scale bar in a cached background; the bodies (one compound path per
    colour), P and its link, arrows (quivers), torque arcs and trails (LineCollections) and the time
    label drawn each frame."""

    def __init__(self, rec: Any, *, size: tuple[int, int], box: tuple[float, ...], color: Any,
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
        # a few paths: matplotlib's cost grows with the paths it draws, not with their vertices)
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
        self.link = LineCollection([], colors="k", linewidths=0.8, zorder=5,
                                   animated=True) if len(self.driven) else None
        if self.link is not None:
            ax.add_collection(self.link)
        # arrows: one scale per kind over the frames filmed, its largest value a tenth of the box's width
        self.arrows: dict[str, Any] = {}
        span = slice(None) if arrow_frames is None else arrow_frames
        d = rec._data[:rec.n_frames][span]
        width = box[1] - box[0]
        legend = []
        for kind, cols, colour, unit in (("velocity", (VX, VY), "#2ca02c", "m/s"), ("friction", (FX, FY), "#9467bd",
                                                                                    "N")):
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
            big = float(np.abs(d[:, :, FT]).max()) if d.size else 0.0
            self.torque = (LineCollection([], colors="#9467bd", linewidths=1.4, animated=True, zorder=6),
                           1.5 * math.pi / big if big > 0.0 else 0.0)
            ax.add_collection(self.torque[0])
            if big > 0.0:
                legend.append(f"torque arc: {big:.3g} N m = 270 deg")
        else:
            self.torque = None
        if self.spin is not None and not isinstance(color,
                                                    np.ndarray):  # (marks: the caller's title says what they are)
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
        x, y, a = d[:, PX], d[:, PY], d[:, PA]
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
            for b in np.flatnonzero(d[:, FT] != 0.0):
                sweep = scale * d[b, FT]
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
