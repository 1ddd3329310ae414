"""The movie's two-panel figure, drawn off-screen: phi(t) on the left, the plane on the right.

Left: phi(t) as time advances, red before the flip time t_f, blue after (grey when the flip is not
known), with a dashed line at t_f once it has passed. Right, to scale: the drive circle (radius d)
about O, the driven point P, the body at its current orientation (a point mass on its massless rod,
or a disk / ellipse outline plus the rod from the CM to P), the labels O, P and CM, a fading CM
trail, and optionally the CM velocity and the friction force as arrows. A dial in the corner shows
the orbit's sense (counter-clockwise) beside the body's spin sense: red while the body
spins against the orbit, blue when with it. Friction is written as the paper's mu g/d.

Speed: the static parts are drawn once and cached as a bitmap; each frame restores it and draws only
the artists that change (``draw_artist``). Units: t in s, positions in m (world frame), angles in rad.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.checks import check_int
from rrbody.model.io import atomic_path
from rrbody.model.trajectory import Trajectory
from rrbody.render.flip import BLUE, GREY, RED, FlipMark
from rrbody.render.quantities import mechanics
from rrbody.render.scene_text import scene_info, title_text

__all__ = ["MovieFigure", "GREEN", "check_size"]

#: the CM marker (the paper draws the CM position as a green point)
GREEN = "#2ca02c"
#: trail opacity floor: history older than the fade time stays faintly visible
TRAIL_FLOOR = 0.10


def check_size(size: Sequence[int]) -> tuple[int, int]:
    """(width, height) in pixels: even integers (yuv420p halves both chroma axes) in [64, 7680]."""
    if not isinstance(size, (tuple, list)) or len(size) != 2:
        raise ValueError(f"size must be a pair (width, height) of pixels, got {size!r}")
    w = check_int("size[0]", size[0], 64, 7680)
    h = check_int("size[1]", size[1], 64, 4320)
    if w % 2 or h % 2:
        raise ValueError(f"size must have even width and height (yuv420p), got {w}x{h}")
    return w, h


def check_movie(path: str | Path, *, force: bool, fps: float, speed: float,
                size: Sequence[int]) -> tuple[Path, float, float, tuple[int, int]]:
    """A movie's output and playback, checked before any frame is drawn: (the final path, fps, speed
    in simulated s per s of playback, (width, height) in pixels). ValueError for a path that exists
    without ``force`` or does not end in .mp4, and for values outside the limits table's ranges."""
    from rrbody.model.checks import check
    from rrbody.model.io import check_writable

    final = check_writable(path, force=force, name="movie")
    if final.suffix.lower() != ".mp4":
        raise ValueError(f"movie path must end in .mp4, got {str(path)!r}")
    return final, check("fps", fps), check("movie_speed", speed, label="speed"), check_size(size)


def check_span(traj: Trajectory, t_start: float | None, t_end: float | None) -> tuple[float, float]:
    """The simulated span (s) a movie of ``traj`` renders: the whole run by default."""
    from rrbody.model.checks import check_real

    a = float(traj.t[0]) if t_start is None else check_real("t_start", t_start)
    b = float(traj.t[-1]) if t_end is None else check_real("t_end", t_end)
    if not (traj.t[0] - 1e-9 <= a < b <= traj.t[-1] + 1e-9):
        raise ValueError(f"t_start, t_end must satisfy {traj.t[0]:g} <= t_start < t_end <= {traj.t[-1]:g} s, "
                         f"got {a!r}, {b!r}")
    return a, b


class _Growing:
    """Samples ``(t_i, xy_i)`` revealed up to a time, ending on the exact (linearly interpolated)
    point at that time, so consecutive frames join without gaps."""

    def __init__(self, t: np.ndarray, xy: np.ndarray) -> None:
        self.t, self.xy = t, xy

    def upto(self, tau: float) -> tuple[np.ndarray, np.ndarray]:
        """(times, points) of the samples up to ``tau`` plus the interpolated point at ``tau``."""
        t, xy = self.t, self.xy
        if len(t) == 0 or tau < t[0]:
            return t[:0], xy[:0]
        i = int(np.searchsorted(t, tau, side="right"))
        if i >= len(t):
            return t, xy
        w = (tau - t[i - 1]) / (t[i] - t[i - 1])
        return np.append(t[:i], tau), np.vstack([xy[:i], (1.0 - w) * xy[i - 1] + w * xy[i]])


def _arc(cx: float, cy: float, r: float, a0: float, a1: float, n: int = 40) -> tuple[np.ndarray, np.ndarray]:
    s = np.linspace(a0, a1, n)
    return cx + r * np.cos(s), cy + r * np.sin(s)


class MovieFigure:
    """The figure; :meth:`frame` returns the RGBA buffer at time t.

    ``flip``: the :class:`~rrbody.render.flip.FlipMark` of the whole run (see :func:`flip_mark`).
    ``window`` = (t_start, t_end) in s restricts axes limits and data to the rendered span.
    ``trail_fade`` (s): the trail's opacity falls linearly from 1 (now) to a faint floor over this
    age; None keeps the whole history fully drawn (posters). ``arrows``: draw the CM velocity and the
    friction force (each scaled to its largest value in the span).
    """

    def __init__(self, traj: Trajectory, *, flip: FlipMark, size: tuple[int, int] = (1280, 720),
                 trail: bool = True, window: tuple[float, float] | None = None, speed: float | None = None,
                 title: str | None = None, trail_fade: float | None = None, arrows: bool = False) -> None:
        from rrbody.model.extras import require

        require("matplotlib", purpose="a movie")
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection
        from matplotlib.colors import to_rgba
        from matplotlib.figure import Figure
        from matplotlib.lines import Line2D

        if len(traj) < 2:
            raise ValueError(f"traj must have at least 2 samples to animate, got {len(traj)}")
        w, h = check_size(size)
        t = np.asarray(traj.t, dtype=float)
        t0, t1 = window if window is not None else (float(t[0]), float(t[-1]))
        idx = np.flatnonzero((t >= t0 - 1e-12) & (t <= t1 + 1e-12))
        sl = slice(max(int(idx[0]) - 1, 0), min(int(idx[-1]) + 2, len(t)))  # one sample either side
        self.t = t[sl]
        self.t0, self.t1 = float(t0), float(t1)
        self.flip, self.trail, self.trail_fade = flip, trail, trail_fade
        self.sc = sc = scene_info(traj)
        self.driven = bool(sc.get("drive"))
        ra, rb = float(sc.get("R_A") or 0.0), float(sc.get("R_B") or 0.0)
        self.extended = ra > 0.0
        s = np.linspace(0.0, 2.0 * math.pi, 97)
        self._outline = np.column_stack([ra * np.cos(s), rb * np.sin(s)])  # body frame, closed
        phi = np.asarray(traj.phi, dtype=float)[sl]
        cm = np.column_stack([traj.x_cm, traj.y_cm])[sl].astype(float)
        pp = np.column_stack([traj.x_p, traj.y_p])[sl].astype(float)
        cols = [cm, pp, np.asarray(traj.body_angle, float)[sl, None], phi[:, None],
                np.asarray(traj.spin, float)[sl, None], np.column_stack([traj.vx_cm, traj.vy_cm])[sl]]
        self.arrows = arrows
        if arrows:
            mech = mechanics(traj)
            f = np.zeros((len(t), 2)) if mech is None else np.column_stack([mech.fx, mech.fy])
            cols.append(f[sl])
        # one array for "the state at time tau": cm(0:2) P(2:4) angle(4) phi(5) spin(6) v(7:9) [F(9:11)]
        self._state = _Growing(self.t, np.column_stack(cols))
        self._phi = _Growing(self.t, np.column_stack([self.t, phi]))
        self._cm = _Growing(self.t, cm)
        if flip.status == "flip" and flip.t_f is not None:
            self._rgba = (np.array(to_rgba(RED)), np.array(to_rgba(BLUE)))
        else:
            c = np.array(to_rgba(GREY if flip.status == "unknown" else BLUE))
            self._rgba = (c, c)

        # ---- figure: pixel-exact size; fonts scale with the height (sized for 720 px)
        dpi = 100.0 * h / 720.0
        fig = Figure(figsize=(w / dpi, h / dpi), dpi=dpi)
        canvas = FigureCanvasAgg(fig)
        if canvas.get_width_height() != (w, h):  # float rounding of w/dpi*dpi: nudge up by a hair
            fig.set_size_inches((w + 1e-3) / dpi, (h + 1e-3) / dpi)
        if canvas.get_width_height() != (w, h):
            raise ValueError(f"size {w}x{h} cannot be rendered pixel-exactly (got {canvas.get_width_height()})")
        self.fig, self.canvas, self.size = fig, canvas, (w, h)
        fig.patch.set_facecolor("white")
        fig.suptitle(title if title is not None else title_text(sc), fontsize=13)
        sp = "" if speed is None else (r"  ($\times$" + f"{speed:.3g} real time)" if speed != 1.0 else "  (real time)")
        key = ("red: reverse rotation, before $t_f$; blue: after" if flip.status == "flip" else
               "grey: flip not known" if flip.status == "unknown" else "blue: normal rotation")
        cap = flip.caption(self.t0, self.t1).replace("t_f", "$t_f$")
        fig.text(0.5, 0.915, f"{cap}.  {key}{sp}", ha="center", va="center",
                 fontsize=10, color="0.3")

        # ---- left panel: phi(t)
        axl = fig.add_axes((0.065, 0.11, 0.40, 0.76))
        inwin = (self.t >= self.t0 - 1e-12) & (self.t <= self.t1 + 1e-12)
        pmin, pmax = float(phi[inwin].min()), float(phi[inwin].max())
        pad = 0.05 * max(pmax - pmin, 1e-6)
        axl.set_xlim(self.t0, self.t1 + 0.015 * (self.t1 - self.t0))
        axl.set_ylim(pmin - pad, pmax + pad)
        axl.set_xlabel("t (s)")
        axl.set_ylabel(r"$\phi$ (rad), angle of CM $\to$ P")
        axl.grid(alpha=0.3)
        if flip.status == "flip":
            handles = [Line2D([], [], color=RED, lw=2, label=r"$t < t_f$ (reverse rotation)"),
                       Line2D([], [], color=BLUE, lw=2, label=r"$t > t_f$ (normal rotation)")]
            axl.legend(handles=handles, loc="upper left", fontsize=9, framealpha=0.9)

        # ---- right panel: the plane, to scale
        axr = fig.add_axes((0.52, 0.05, 0.46, 0.84))
        axr.set_aspect("equal", adjustable="box")
        reach = max(ra, rb)
        d = float(sc["drive"]["d"]) if self.driven else 0.0
        xs, ys = np.concatenate([cm[:, 0], pp[:, 0]]), np.concatenate([cm[:, 1], pp[:, 1]])
        xlo, xhi = min(xs.min() - reach, -d), max(xs.max() + reach, d)
        ylo, yhi = min(ys.min() - reach, -d), max(ys.max() + reach, d)
        span = max(xhi - xlo, yhi - ylo, 1e-6)
        cx, cy, half = 0.5 * (xlo + xhi), 0.5 * (ylo + yhi), 0.56 * span
        axr.set_xlim(cx - half * 1.15, cx + half * 1.15)
        axr.set_ylim(cy - half, cy + half)
        axr.set_xlabel("x (m)")
        axr.set_ylabel("y (m)")
        axr.grid(alpha=0.2)
        self.span = span
        if self.driven:
            axr.plot(*_arc(0.0, 0.0, d, 0.0, 2.0 * math.pi, 361), ls=":", color="k", lw=1.2)
            axr.plot([0], [0], "+", color="k", ms=9)
            axr.annotate("O", (0.0, 0.0), xytext=(-6, -6), textcoords="offset points", ha="right", va="top",
                         fontsize=12)
        self._dial(fig, axr)

        # ---- animated artists (excluded from the cached background)
        lw = 2.0 * h / 720.0
        A: dict[str, Any] = {}
        A["phi_red"], = axl.plot([], [], color=RED, lw=lw, animated=True)
        A["phi_blue"], = axl.plot([], [], color=self._rgba[1], lw=lw, animated=True)
        A["phi_now"], = axl.plot([], [], "o", color="k", ms=5, animated=True)
        A["tf_line"] = axl.axvline(flip.t_f if flip.t_f is not None else 0.0, color="0.4", ls="--", lw=1.0,
                                   animated=True, visible=False)
        A["trail"] = LineCollection([], linewidths=0.9 * lw, animated=True)
        axr.add_collection(A["trail"])
        if self.driven:
            A["arm"], = axr.plot([], [], color="0.6", lw=1.0, animated=True)  # O -> P: the drive's crank
        A["rod"], = axr.plot([], [], color="0.15", lw=1.6 * lw, solid_capstyle="round", animated=True)
        if self.extended:
            A["outline"], = axr.plot([], [], color="0.15", lw=1.3 * lw, animated=True)
        A["cm"], = axr.plot([], [], "o", color=GREEN, ms=(6 if self.extended else 14) * h / 720, mec="k", mew=0.8,
                            animated=True)
        A["p"], = axr.plot([], [], "o", color="k", ms=7 * h / 720, animated=True)
        A["lab_p"] = axr.annotate("P", (0, 0), xytext=(7, 7), textcoords="offset points", fontsize=12,
                                  animated=True)
        A["lab_cm"] = axr.annotate("CM", (0, 0), xytext=(8, -14), textcoords="offset points", fontsize=11,
                                   color="#1a6e1a", animated=True)
        if arrows:
            st = self._state.xy
            self._vscale = 0.22 * span / max(float(np.hypot(st[:, 7], st[:, 8]).max()), 1e-300)
            self._fscale = 0.22 * span / max(float(np.hypot(st[:, 9], st[:, 10]).max()), 1e-300)
            A["v"] = axr.quiver([0.0], [0.0], [0.0], [0.0], color=GREEN, angles="xy", scale_units="xy", scale=1.0,
                                width=0.006, animated=True, zorder=5)
            A["f"] = axr.quiver([0.0], [0.0], [0.0], [0.0], color="#9467bd", angles="xy", scale_units="xy",
                                scale=1.0, width=0.006, animated=True, zorder=5)
            axr.legend(handles=[Line2D([], [], color=GREEN, lw=2, label="CM velocity"),
                                Line2D([], [], color="#9467bd", lw=2, label="friction force")],
                       loc="lower left", fontsize=9, framealpha=0.85)
        A["time"] = axr.text(0.02, 0.97, "", transform=axr.transAxes, ha="left", va="top", fontsize=15,
                             family="monospace", animated=True)
        # the banner sits mid-height in the phi panel, clear of its key and of the curve at the flip (its minimum)
        A["banner"] = fig.text(0.30, 0.60, "", ha="center", va="center", fontsize=17, color="white", weight="bold",
                               animated=True, visible=False,
                               bbox={"boxstyle": "round,pad=0.5", "fc": BLUE, "ec": "none", "alpha": 0.9})
        self.axl, self.axr, self.A = axl, axr, A
        canvas.draw()
        self._bg = canvas.copy_from_bbox(fig.bbox)

    def _dial(self, fig: Any, axr: Any) -> None:
        """Orbit- and spin-sense indicator in the plane panel's top-right corner (its own axes)."""
        from matplotlib.lines import Line2D

        box = axr.get_position()
        ax = fig.add_axes((box.x1 - 0.145, box.y1 - 0.2, 0.14, 0.19))
        ax.set_xlim(-1.2, 1.2)
        ax.set_ylim(-1.05, 1.25)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.patch.set_alpha(0.85)
        for side in ax.spines.values():
            side.set_color("0.7")
        if self.driven:  # the orbit turns counter-clockwise (omega > 0)
            x, y = _arc(-0.58, 0.15, 0.4, -0.6 * math.pi, 0.9 * math.pi)
            ax.plot(x, y, color="k", lw=1.6)
            ax.plot([x[-1]], [y[-1]], marker=(3, 0, math.degrees(0.9 * math.pi)), color="k", ms=9)
            ax.text(-0.58, 0.95, "orbit", ha="center", fontsize=9)
        self._spin_x = 0.58 if self.driven else 0.0
        self._spin_line = Line2D([], [], lw=1.6, animated=True)
        self._spin_head = Line2D([], [], lw=0, ms=9, animated=True)
        self._spin_text = ax.text(self._spin_x, 0.95, "spin", ha="center", fontsize=9, animated=True)
        self._regime_text = ax.text(0.0, -0.82, "", ha="center", fontsize=9, weight="bold", animated=True)
        for a in (self._spin_line, self._spin_head):
            ax.add_line(a)
        self.dial = ax

    # ------------------------------------------------------------------------------------------
    def _trail_first(self, mid: np.ndarray) -> np.ndarray:
        """Which trail segments (their mid times, s) take the first of the two trail colours: those
        before the flip."""
        if self.flip.status == "flip" and self.flip.t_f is not None:
            return mid < self.flip.t_f
        return np.zeros(len(mid), bool)

    def _trail_segments(self, tau: float) -> tuple[np.ndarray, np.ndarray]:
        tt, xy = self._cm.upto(tau)
        if len(tt) < 2:
            return np.zeros((0, 2, 2)), np.zeros((0, 4))
        seg = np.stack([xy[:-1], xy[1:]], axis=1)
        mid = 0.5 * (tt[:-1] + tt[1:])
        rgba = np.where(self._trail_first(mid)[:, None], self._rgba[0], self._rgba[1]).copy()
        if self.trail_fade is not None:
            rgba[:, 3] = np.clip(1.0 - (tau - mid) / self.trail_fade, TRAIL_FLOOR, 1.0)
        return seg, rgba

    def update(self, tau: float, *, banner: bool = False) -> None:
        """Set every animated artist to its state at simulated time ``tau`` (s); ``banner`` shows the flip banner."""
        A, flip = self.A, self.flip
        st = self._state.upto(tau)[1][-1]
        cx, cy, px, py, ang, spin = st[0], st[1], st[2], st[3], st[4], st[6]
        tt, ph = self._phi.upto(tau)
        ph = ph[:, 1]
        if flip.status == "flip" and flip.t_f is not None:
            k = int(np.searchsorted(tt, flip.t_f, side="right"))
            at = float(np.interp(flip.t_f, tt, ph)) if 0 < k < len(tt) else None
            red_t, red_p = (np.append(tt[:k], flip.t_f), np.append(ph[:k], at)) if at is not None else (tt[:k], ph[:k])
            blue_t, blue_p = (np.insert(tt[k:], 0, flip.t_f), np.insert(ph[k:], 0, at)) if at is not None else (
                tt[k:], ph[k:])
        else:
            red_t, red_p, blue_t, blue_p = tt[:0], ph[:0], tt, ph
        A["phi_red"].set_data(red_t, red_p)
        A["phi_blue"].set_data(blue_t, blue_p)
        A["phi_now"].set_data([tau], [st[5]])
        A["tf_line"].set_visible(flip.in_span(self.t0, self.t1) and not flip.before(tau))
        if self.trail:
            seg, rgba = self._trail_segments(tau)
            A["trail"].set_segments(seg)
            A["trail"].set_color(rgba)
        if self.driven:
            A["arm"].set_data([0.0, px], [0.0, py])
        A["rod"].set_data([cx, px], [cy, py])
        if self.extended:
            c, s = math.cos(ang), math.sin(ang)
            o = self._outline
            A["outline"].set_data(cx + c * o[:, 0] - s * o[:, 1], cy + s * o[:, 0] + c * o[:, 1])
        A["cm"].set_data([cx], [cy])
        A["p"].set_data([px], [py])
        # labels sit beyond each point along the rod (CM) and the crank (P), so no line crosses them
        ux, uy, r = cx - px, cy - py, math.hypot(cx - px, cy - py)
        ux, uy = (ux / r, uy / r) if r > 0 else (0.0, -1.0)
        A["lab_cm"].xy = (cx, cy)
        A["lab_cm"].xyann = (14.0 * ux - 8.0, 14.0 * uy - 5.0)
        r = math.hypot(px, py)
        vx, vy = (px / r, py / r) if r > 0 else (-ux, -uy)
        A["lab_p"].xy = (px, py)
        A["lab_p"].xyann = (11.0 * vx - 4.0, 11.0 * vy - 5.0)
        if self.arrows:
            A["v"].set_offsets([[cx, cy]])
            A["v"].set_UVC([st[7] * self._vscale], [st[8] * self._vscale])
            A["f"].set_offsets([[cx, cy]])
            A["f"].set_UVC([st[9] * self._fscale], [st[10] * self._fscale])
        colour = flip.colour(tau)
        A["time"].set_text(f"t = {tau:7.2f} s")
        A["time"].set_color(colour)
        # spin dial: the arrow turns with the body's spin; red while against the orbit
        ccw = spin >= 0.0
        x, y = _arc(self._spin_x, 0.15, 0.4, -0.6 * math.pi, 0.9 * math.pi)
        if not ccw:
            x, y = x[::-1], y[::-1]
        reverse = self.driven and spin < 0.0
        c = RED if reverse else BLUE
        self._spin_line.set_data(x, y)
        self._spin_line.set_color(c)
        head = math.degrees(0.9 * math.pi if ccw else -0.6 * math.pi + math.pi)
        self._spin_head.set_data([x[-1]], [y[-1]])
        self._spin_head.set_marker((3, 0, head))
        self._spin_head.set_color(c)
        self._regime_text.set_text(("spin against orbit" if reverse else "spin with orbit") if self.driven else
                                   ("spin counter-clockwise" if ccw else "spin clockwise"))
        self._regime_text.set_color(c)
        A["banner"].set_visible(banner and flip.t_f is not None)
        if banner and flip.t_f is not None:
            A["banner"].set_text(f"FLIP at t$_f$ = {flip.t_f:.2f} s\nreverse rotation ends")

    def frame(self, tau: float, *, banner: bool = False) -> memoryview:
        """RGBA pixels (height x width x 4, row-major) at simulated time ``tau`` (s); the buffer is reused."""
        self.update(tau, banner=banner)
        self.canvas.restore_region(self._bg)
        for a in [*self.A.values(), self._spin_line, self._spin_head, self._spin_text, self._regime_text]:
            if a.get_visible():
                (a.axes if a.axes is not None else self.fig).draw_artist(a)
        return self.canvas.buffer_rgba()

    def rgb(self, tau: float, *, banner: bool = False) -> np.ndarray:
        """A copy of the frame at ``tau`` as an (h, w, 3) uint8 array."""
        return np.asarray(self.frame(tau, banner=banner))[:, :, :3].copy()

    def save(self, path: str | Path, tau: float, *, force: bool = False) -> Path:
        """Write the full figure at time ``tau`` as PNG or SVG (by suffix), atomically and byte-reproducibly."""
        from rrbody.render.figures import savefig_reproducible

        fmt = Path(path).suffix.lower().lstrip(".")
        if fmt not in ("png", "svg"):
            raise ValueError(f"path must end in .png or .svg, got {str(path)!r}")
        self.update(tau)
        with atomic_path(path, force=force, name="poster") as tmp:
            savefig_reproducible(self.fig, tmp, fmt=fmt, dpi=self.fig.dpi)  # draws animated artists too
        return Path(path)
