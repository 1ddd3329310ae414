"""Off-screen MP4 movies of a run: matplotlib (Agg, no display) -> imageio-ffmpeg's bundled ffmpeg.

Layout (the paper's Fig. ``SSs`` / Movie S1): the left panel draws phi(t) as time advances, red
before the flip time t_f and blue after; the right panel shows the driving circle (radius d), the
driven point P, the body drawn to scale at its current orientation (a point mass on its massless
rod, or a disk / ellipse outline plus the massless rod from the CM to P), and the CM history as a
trail coloured the same way. The simulated time is shown in the corner.

Speed: the static parts (axes, labels, circle, legend) are drawn once and cached as a bitmap
(``canvas.copy_from_bbox``); each frame restores that bitmap and draws only the artists that change
(``set_data`` + ``draw_artist``), then hands the RGBA buffer straight to ffmpeg's stdin. Output:
H.264 (libx264), yuv420p, MP4 container, written to a temporary sibling and renamed into place
(:func:`rrbody.io.atomic_path`), so an interrupted render leaves nothing behind.

Units: simulated time t in s; movie time in s of playback; ``speed`` = simulated seconds per
second of playback; positions in m (world frame); angles in rad.
"""

from __future__ import annotations

import math
from collections.abc import Generator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.checks import check_int, check_positive, check_real
from rrbody.model.io import atomic_path, check_writable
from rrbody.model.trajectory import Trajectory

__all__ = ["render_movie", "render_poster", "frame_times", "MovieFigure", "RED", "BLUE"]

#: colours of the two regimes (before / after t_f), matplotlib's tab:red and tab:blue
RED = "#d62728"
BLUE = "#1f77b4"
#: the CM marker (the paper draws the CM position as a green point)
GREEN = "#2ca02c"

CODEC = "libx264"
PIX_FMT = "yuv420p"


# ---- validation and time mapping --------------------------------------------------------------
def _check_size(size: Sequence[int]) -> tuple[int, int]:
    """(width, height) in pixels: even integers (yuv420p halves both chroma axes) in [64, 7680]."""
    if not isinstance(size, (tuple, list)) or len(size) != 2:
        raise ValueError(f"size must be a pair (width, height) of pixels, got {size!r}")
    w = check_int("size[0]", size[0], 64, 7680)
    h = check_int("size[1]", size[1], 64, 4320)
    if w % 2 or h % 2:
        raise ValueError(f"size must have even width and height (yuv420p), got {w}x{h}")
    return w, h


def frame_times(t_start: float, t_end: float, *, fps: float, speed: float) -> np.ndarray:
    """Simulated time (s) of each movie frame: t_start + speed * k / fps for k = 0, 1, ... up to t_end.

    The movie lasts ``len(result) / fps`` s of playback (ffmpeg shows each frame for 1/fps s).
    """
    fps = check_positive("fps", fps, unit="frames/s")
    speed = check_positive("speed", speed)
    if not t_end > t_start:
        raise ValueError(f"t_end must be > t_start={t_start:g} s, got {t_end!r}")
    # the small slack keeps the last frame when (t_end - t_start) * fps / speed is an integer up to rounding
    n = int(math.floor((t_end - t_start) * fps / speed * (1.0 + 1e-12) + 1e-9)) + 1
    return t_start + speed * np.arange(n) / fps


def _resolve_tf(traj: Trajectory, t_f: float | None) -> float | None:
    """The red/blue split time: given, else ``traj.events['t_phi_min']`` (None: no split)."""
    if t_f is None:
        t_f = traj.events.get("t_phi_min")
        if t_f is None:
            return None
    return check_real("t_f", t_f)


# ---- growing polylines -------------------------------------------------------------------------
class _Growing:
    """A polyline through samples ``(t_i, xy_i)`` revealed up to a time, ending on the exact
    (linearly interpolated) point at that time, so consecutive frames join without gaps."""

    def __init__(self, t: np.ndarray, xy: np.ndarray) -> None:
        self.t = t
        self.xy = xy

    def upto(self, tau: float) -> np.ndarray:
        t, xy = self.t, self.xy
        if len(t) == 0 or tau < t[0]:
            return xy[:0]
        i = int(np.searchsorted(t, tau, side="right"))
        if i >= len(t):
            return xy
        out = np.empty((i + 1, xy.shape[1]))
        out[:i] = xy[:i]
        w = (tau - t[i - 1]) / (t[i] - t[i - 1])
        out[i] = (1.0 - w) * xy[i - 1] + w * xy[i]
        return out


def _split(t: np.ndarray, xy: np.ndarray, t_f: float | None) -> tuple[_Growing, _Growing]:
    """Split samples at t_f into (before, after), both containing the exact point at t_f."""
    if t_f is None or t_f <= t[0]:
        return _Growing(t[:0], xy[:0]), _Growing(t, xy)
    if t_f >= t[-1]:
        return _Growing(t, xy), _Growing(t[:0], xy[:0])
    at = np.array([np.interp(t_f, t, xy[:, j]) for j in range(xy.shape[1])])
    i = int(np.searchsorted(t, t_f, side="right"))
    before_t = np.append(t[:i], t_f)
    before = np.vstack([xy[:i], at])
    after_t = np.insert(t[i:], 0, t_f)
    after = np.vstack([at, xy[i:]])
    return _Growing(before_t, before), _Growing(after_t, after)


# ---- the figure --------------------------------------------------------------------------------
def _scene_info(traj: Trajectory) -> dict[str, Any]:
    """Body and drive geometry from ``traj.meta['scene']`` (a :meth:`Scene.describe` dict); a
    trajectory without it is drawn as a point mass on a rod of the sampled CM-P distance."""
    sc = dict(traj.meta.get("scene") or {})
    if "body" not in sc:
        sc["body"] = "rod"
        sc["l"] = float(math.hypot(traj.x_p[0] - traj.x_cm[0], traj.y_p[0] - traj.y_cm[0]))
        sc["R_A"] = sc["R_B"] = 0.0
    return sc


def _title(sc: dict[str, Any]) -> str:
    kind = sc.get("body", "rod")
    parts = []
    if sc.get("H") is not None:
        parts.append(f"H = {sc['H']:.4g}")
    if sc.get("k") is not None:
        law = (sc.get("friction") or {}).get("law", "dry")
        unit = "s$^{-1}$" if law == "viscous" else "s$^{-2}$"
        parts.append(f"k = {sc['k']:.4g} {unit}" + ("" if law == "dry" else f" ({law})"))
    drive = sc.get("drive")
    if drive:
        parts.append(rf"$\omega$ = {drive['omega']:.4g} rad/s")
    if sc.get("phi0") is not None:
        phi0 = float(sc["phi0"])
        frac = phi0 / math.pi
        txt = (r"$\pi$" if abs(frac - 1) < 1e-12 else r"$\pi/2$" if abs(frac - 0.5) < 1e-12
               else f"{phi0:.4g}")
        parts.append(rf"$\phi_0$ = {txt}")
    name = {"rod": "rod-mass body", "disk": "disk", "ellipse": "ellipse"}.get(kind, kind)
    if kind != "rod" and sc.get("R_A"):
        name += f" (R$_A$ = {sc['R_A']:.3g} m, R$_B$ = {sc['R_B']:.3g} m, l = {sc.get('l', 0):.3g} m)"
    return name + ": " + ", ".join(parts)


class MovieFigure:
    """The two-panel figure, drawn off-screen; :meth:`frame` returns the RGBA buffer at time t.

    ``window`` = (t_start, t_end) in s restricts axes limits and data to the rendered span.
    """

    def __init__(self, traj: Trajectory, *, size: tuple[int, int] = (1280, 720), t_f: float | None = None,
                 trail: bool = True, window: tuple[float, float] | None = None, speed: float | None = None,
                 title: str | None = None) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.lines import Line2D

        if len(traj) < 2:
            raise ValueError(f"traj must have at least 2 samples to animate, got {len(traj)}")
        w, h = _check_size(size)
        t = np.asarray(traj.t, dtype=float)
        t0, t1 = window if window is not None else (float(t[0]), float(t[-1]))
        keep = (t >= t0 - 1e-12) & (t <= t1 + 1e-12)
        # keep one sample either side of the window so interpolation at its ends is exact
        idx = np.flatnonzero(keep)
        lo, hi = max(int(idx[0]) - 1, 0), min(int(idx[-1]) + 2, len(t))
        sl = slice(lo, hi)
        self.t = t[sl]
        self.t0, self.t1 = float(t0), float(t1)
        self.t_f = t_f
        self.trail = trail
        sc = _scene_info(traj)
        self.sc = sc
        ra, rb = float(sc.get("R_A") or 0.0), float(sc.get("R_B") or 0.0)
        self.extended = ra > 0.0
        s = np.linspace(0.0, 2.0 * math.pi, 97)
        self._outline = np.column_stack([ra * np.cos(s), rb * np.sin(s)])  # body frame, closed

        phi = np.asarray(traj.phi, dtype=float)[sl]
        cm = np.column_stack([traj.x_cm, traj.y_cm])[sl].astype(float)
        pp = np.column_stack([traj.x_p, traj.y_p])[sl].astype(float)
        ang = np.asarray(traj.body_angle, dtype=float)[sl]
        # one array for "the state at time tau" interpolation: cm, P, body angle, phi
        self._state = np.column_stack([cm, pp, ang, phi])
        self._phi_red, self._phi_blue = _split(self.t, np.column_stack([self.t, phi]), t_f)
        self._cm_red, self._cm_blue = _split(self.t, cm, t_f)

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
        fig.suptitle(title if title is not None else _title(sc), fontsize=13)

        # ---- left panel: phi(t)
        axl = fig.add_axes((0.065, 0.11, 0.40, 0.76))
        inwin = (self.t >= self.t0 - 1e-12) & (self.t <= self.t1 + 1e-12)
        pmin, pmax = float(phi[inwin].min()), float(phi[inwin].max())
        pad = 0.05 * max(pmax - pmin, 1e-6)
        axl.set_xlim(self.t0, self.t1 + 0.015 * (self.t1 - self.t0))  # room for the "now" marker
        axl.set_ylim(pmin - pad, pmax + pad)
        axl.set_xlabel("t (s)")
        axl.set_ylabel(r"$\phi$ (rad)")
        axl.grid(alpha=0.3)
        handles = []
        if t_f is not None and t_f > self.t0:
            handles.append(Line2D([], [], color=RED, lw=2, label=rf"$t < t_f$ = {t_f:.4g} s"))
        handles.append(Line2D([], [], color=BLUE, lw=2,
                              label=r"$t > t_f$" if handles else "no flip: normal rotation throughout"))
        axl.legend(handles=handles, loc="upper left", fontsize=10, framealpha=0.9)

        # ---- right panel: the plane, to scale
        axr = fig.add_axes((0.52, 0.05, 0.46, 0.84))
        axr.set_aspect("equal", adjustable="box")
        reach = max(ra, rb)
        xs = np.concatenate([cm[:, 0], pp[:, 0]])
        ys = np.concatenate([cm[:, 1], pp[:, 1]])
        drive = sc.get("drive")
        d = float(drive["d"]) if drive else 0.0
        xlo, xhi = min(xs.min() - reach, -d), max(xs.max() + reach, d)
        ylo, yhi = min(ys.min() - reach, -d), max(ys.max() + reach, d)
        span = max(xhi - xlo, yhi - ylo, 1e-6)
        # equal aspect: centre the data box and give both axes the same span (the axes box is ~1.2:1)
        cx, cy = 0.5 * (xlo + xhi), 0.5 * (ylo + yhi)
        half = 0.54 * span
        axr.set_xlim(cx - half * 1.15, cx + half * 1.15)
        axr.set_ylim(cy - half, cy + half)
        axr.set_xlabel("x (m)")
        axr.set_ylabel("y (m)")
        axr.grid(alpha=0.2)
        if drive:
            s2 = np.linspace(0.0, 2.0 * math.pi, 361)
            axr.plot(d * np.cos(s2), d * np.sin(s2), ls=":", color="k", lw=1.2, label="path of P")
            axr.plot([0], [0], "+", color="k", ms=8)
        sp = "" if speed is None else (r"  ($\times$" + f"{speed:.3g} real time)" if speed != 1.0
                                        else "  (real time)")
        note = ("red before the flip time $t_f$, blue after" if t_f is not None and t_f > self.t0
                else "no flip in this span (blue throughout)") + ("; CM history and the path of P (dotted)" if drive else "; CM history")
        fig.text(0.5, 0.915, note + sp, ha="center", va="center", fontsize=10, color="0.35")

        # ---- the animated artists (excluded from the cached background)
        lw = 2.0 * h / 720.0
        A: dict[str, Any] = {}
        A["phi_red"], = axl.plot([], [], color=RED, lw=lw, animated=True)
        A["phi_blue"], = axl.plot([], [], color=BLUE, lw=lw, animated=True)
        A["phi_now"], = axl.plot([], [], "o", color="k", ms=5, animated=True)
        A["tf_line"] = axl.axvline(t_f if t_f is not None else 0.0, color="0.4", ls="--", lw=1.0, animated=True)
        A["trail_red"], = axr.plot([], [], color=RED, lw=0.9 * lw, alpha=0.85, animated=True)
        A["trail_blue"], = axr.plot([], [], color=BLUE, lw=0.9 * lw, alpha=0.85, animated=True)
        A["arm"], = axr.plot([], [], color="0.6", lw=1.0, animated=True)  # centre -> P: the drive's crank
        A["rod"], = axr.plot([], [], color="0.15", lw=1.6 * lw, solid_capstyle="round", animated=True)
        if self.extended:
            A["outline"], = axr.plot([], [], color="0.15", lw=1.3 * lw, animated=True)
            A["cm"], = axr.plot([], [], "o", color=GREEN, ms=6, mec="k", mew=0.8, animated=True)
        else:
            A["cm"], = axr.plot([], [], "o", color=GREEN, ms=14 * h / 720, mec="k", mew=1.0, animated=True)
        A["p"], = axr.plot([], [], "o", color="k", ms=7 * h / 720, animated=True)
        A["time"] = axr.text(0.02, 0.97, "", transform=axr.transAxes, ha="left", va="top", fontsize=15,
                             family="monospace", animated=True)
        self.axl, self.axr, self.A = axl, axr, A
        canvas.draw()
        self._bg = canvas.copy_from_bbox(fig.bbox)

    # ------------------------------------------------------------------------------------------
    def update(self, tau: float) -> None:
        """Set every animated artist to its state at simulated time ``tau`` (s)."""
        A = self.A
        st = _Growing(self.t, self._state).upto(tau)[-1]
        cx, cy, px, py, ang = st[0], st[1], st[2], st[3], st[4]
        red = self._phi_red.upto(tau)
        blue = self._phi_blue.upto(tau)
        A["phi_red"].set_data(red[:, 0], red[:, 1])
        A["phi_blue"].set_data(blue[:, 0], blue[:, 1])
        A["phi_now"].set_data([tau], [st[5]])
        after = self.t_f is not None and tau >= self.t_f
        A["tf_line"].set_visible(bool(after and self.t_f is not None and self.t_f > self.t0))
        if self.trail:
            r = self._cm_red.upto(tau)
            b = self._cm_blue.upto(tau)
            A["trail_red"].set_data(r[:, 0], r[:, 1])
            A["trail_blue"].set_data(b[:, 0], b[:, 1])
        if self.sc.get("drive"):
            A["arm"].set_data([0.0, px], [0.0, py])
        A["rod"].set_data([cx, px], [cy, py])
        if self.extended:
            c, s = math.cos(ang), math.sin(ang)
            o = self._outline
            A["outline"].set_data(cx + c * o[:, 0] - s * o[:, 1], cy + s * o[:, 0] + c * o[:, 1])
        A["cm"].set_data([cx], [cy])
        A["p"].set_data([px], [py])
        A["time"].set_text(f"t = {tau:7.2f} s")
        A["time"].set_color(BLUE if (self.t_f is None or tau >= self.t_f) else RED)

    def frame(self, tau: float) -> memoryview:
        """RGBA pixels (height x width x 4, row-major) of the frame at simulated time ``tau`` (s).

        The returned buffer is reused by the next call: copy it to keep it.
        """
        self.update(tau)
        self.canvas.restore_region(self._bg)
        for a in self.A.values():
            if a.get_visible():
                a.axes.draw_artist(a)
        return self.canvas.buffer_rgba()

    def rgb(self, tau: float) -> np.ndarray:
        """A copy of the frame at ``tau`` as an (h, w, 3) uint8 array."""
        return np.asarray(self.frame(tau))[:, :, :3].copy()

    def save(self, path: str | Path, tau: float, *, force: bool = False) -> Path:
        """Write the full figure at time ``tau`` as PNG or SVG (by suffix), atomically."""
        fmt = Path(path).suffix.lower().lstrip(".")
        if fmt not in ("png", "svg"):
            raise ValueError(f"path must end in .png or .svg, got {str(path)!r}")
        self.update(tau)
        with atomic_path(path, force=force, name="poster") as tmp:
            self.fig.savefig(tmp, format=fmt, dpi=self.fig.dpi)  # savefig draws animated artists too
        return Path(path)


# ---- writing -----------------------------------------------------------------------------------
def _open_writer(path: Path, size: tuple[int, int], fps: float) -> Generator[None, Any, None]:
    """A started imageio-ffmpeg writer taking RGBA frames: H.264 in MP4, yuv420p (any player)."""
    import imageio_ffmpeg

    gen = imageio_ffmpeg.write_frames(
        str(path), size, pix_fmt_in="rgba", pix_fmt_out=PIX_FMT, fps=fps, codec=CODEC,
        quality=None, macro_block_size=2,  # size is checked even; no rescaling
        # crf 26 / preset fast: plain line art compresses to < 1 MB a minute at 1280x720 (medium: same size,
        # ~40% slower encoding, measured with `python -m rrbody.render.mp4`);
        # faststart puts the index first so browsers can play while downloading
        output_params=["-crf", "26", "-preset", "fast", "-movflags", "+faststart", "-f", "mp4"],
    )
    gen.send(None)
    return gen


def render_movie(traj: Trajectory, path: str | Path, *, force: bool = False, progress: bool = False,
                 fps: float = 30, size: tuple[int, int] = (1280, 720), speed: float = 1.0,
                 t_f: float | None = None, trail: bool = True, t_start: float | None = None,
                 t_end: float | None = None, title: str | None = None) -> Path:
    """Render ``traj`` to an MP4 at ``path`` and return the path.

    Parameters
    ----------
    traj : Trajectory
        Any run (driven or free); the body is drawn from ``traj.meta['scene']``.
    fps : float
        Frames per second of playback.
    size : (int, int)
        Width and height in pixels (even numbers).
    speed : float
        Simulated seconds per second of playback (1: real time; 2.5: 2.5x faster).
    t_f : float or None
        Red/blue split time in s; default ``traj.events['t_phi_min']`` (the flip time of the run).
    trail : bool
        Draw the CM history.
    t_start, t_end : float or None
        Simulated time span to render (default: the whole run).
    force : bool
        Overwrite an existing file. Without it an existing ``path`` is an error (checked before
        any frame is drawn).
    """
    final = check_writable(path, force=force, name="movie")
    if final.suffix.lower() != ".mp4":
        raise ValueError(f"movie path must end in .mp4, got {str(path)!r}")
    fps = check_positive("fps", fps, unit="frames/s")
    if fps > 240:
        raise ValueError(f"fps must lie in (0, 240], got {fps!r}")
    speed = check_positive("speed", speed)
    size = _check_size(size)
    tf = _resolve_tf(traj, t_f)
    a = float(traj.t[0]) if t_start is None else check_real("t_start", t_start)
    b = float(traj.t[-1]) if t_end is None else check_real("t_end", t_end)
    if not (traj.t[0] - 1e-9 <= a < b <= traj.t[-1] + 1e-9):
        raise ValueError(f"t_start, t_end must satisfy {traj.t[0]:g} <= t_start < t_end <= {traj.t[-1]:g} s, "
                         f"got {a!r}, {b!r}")
    times = frame_times(a, b, fps=fps, speed=speed)
    fig = MovieFigure(traj, size=size, t_f=tf, trail=trail, window=(a, b), speed=speed, title=title)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(times), unit="frame", desc=f"movie {final.name}", leave=False)
    try:
        with atomic_path(final, force=force, name="movie") as tmp:
            writer = _open_writer(tmp, size, fps)
            try:
                for tau in times:
                    writer.send(fig.frame(float(tau)))
                    if bar is not None:
                        bar.update(1)
            finally:
                writer.close()  # waits for ffmpeg to finish (or to exit after an error)
    finally:
        if bar is not None:
            bar.close()
    return final


def render_poster(traj: Trajectory, path: str | Path, *, tau: float | None = None, force: bool = False,
                  size: tuple[int, int] = (1280, 720), t_f: float | None = None, trail: bool = True,
                  title: str | None = None) -> Path:
    """One still of the movie layout at simulated time ``tau`` (default: the last sample), PNG or SVG."""
    check_writable(path, force=force, name="poster")
    tf = _resolve_tf(traj, t_f)
    fig = MovieFigure(traj, size=size, t_f=tf, trail=trail, title=title)
    when = float(traj.t[-1]) if tau is None else check_real("tau", tau)
    return fig.save(path, when, force=force)


# ---- cost measurement: python -m rrbody.render.mp4 [seconds_of_movie] ------------------------------
