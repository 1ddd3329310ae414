"""A movie of a chaotic orbit with its reverse-rotation stretches marked where the run shows them.

Reverse rotation (RR) is the paper's: the body spins against its orbit, phi' omega < 0. Nothing is
drawn by hand: the marks come from the trajectory's own phi' (:func:`rr_mask`, :func:`rr_stretches`)
and the drive's omega, the same sign the movie's spin dial shows. On top of the movie layout
(:class:`~rrbody.render.movie_figure.MovieFigure`: phi(t) on the left, the plane on the right):

- the phi(t) curve and the CM trail are red on the samples in RR, blue elsewhere (a segment takes
  the colour of the state at its midpoint, phi' interpolated linearly between samples);
- while the state shown is in RR, a red "reverse rotation" label under the clock.

The state at a frame's time tau is the linear interpolation of the samples (as every other drawn
quantity), so a frame is marked exactly when phi'(tau) omega < 0 for the interpolated phi'
(:meth:`ChaosMovieFigure.marked`; ``tests/test_chaos_movie.py`` checks it frame by frame).
Units: t in s, phi in rad, phi' in rad/s.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.trajectory import Trajectory
from rrbody.render.flip import BLUE, RED, FlipMark
from rrbody.render.movie_figure import MovieFigure, check_movie, check_span

__all__ = ["rr_mask", "rr_stretches", "ChaosMovieFigure", "render_chaos_movie"]


def _omega(traj: Trajectory) -> float:
    drive = (traj.meta.get("scene") or {}).get("drive")
    if not drive:
        raise ValueError("traj must be a driven run (its scene has a drive): reverse rotation is against the orbit")
    return float(drive["omega"])


def rr_mask(t: np.ndarray, phi_dot: np.ndarray, omega: float) -> np.ndarray:
    """True where the spin is against the orbit, phi' omega < 0 (the samples ``t``, ``phi_dot``)."""
    del t  # the times only label the samples; the sign is the state's own
    return np.asarray(phi_dot, dtype=float) * float(omega) < 0.0


def rr_stretches(t: np.ndarray, phi_dot: np.ndarray, omega: float) -> list[tuple[float, float]]:
    """The RR stretches (s) of a sampled run: each [start, end] with phi' omega < 0 between, the ends
    where phi' crosses zero, located by linear interpolation between the samples around the change
    (a stretch cut by the run's start or end begins or ends there)."""
    t = np.asarray(t, dtype=float)
    pd = np.asarray(phi_dot, dtype=float)
    m = rr_mask(t, pd, omega)
    out: list[tuple[float, float]] = []
    change = np.flatnonzero(m[1:] != m[:-1])

    def cross(i: int) -> float:
        a, b = pd[i], pd[i + 1]
        return float(t[i] + (t[i + 1] - t[i]) * a / (a - b)) if a != b else float(t[i])

    start = float(t[0]) if m[0] else None
    for i in change:
        if m[i + 1]:
            start = cross(int(i))
        elif start is not None:
            out.append((start, cross(int(i))))
            start = None
    if start is not None:
        out.append((start, float(t[-1])))
    return out


class ChaosMovieFigure(MovieFigure):
    """The movie figure with the RR stretches of ``traj`` marked (see the module docstring)."""

    def __init__(self, traj: Trajectory, **kw: Any) -> None:
        self.omega = _omega(traj)
        kw.setdefault("flip", FlipMark("none", reason="no friction; red where the spin is against the orbit "
                                                      "(reverse rotation, from the run's own phi')"))
        super().__init__(traj, **kw)
        from matplotlib.colors import to_rgba
        from matplotlib.lines import Line2D

        self._pd = np.asarray(traj.phi_dot, dtype=float)
        self._tall = np.asarray(traj.t, dtype=float)
        self._rgba = (np.array(to_rgba(RED)), np.array(to_rgba(BLUE)))  # trail: reverse rotation, not
        lw = 2.0 * self.size[1] / 720.0
        self.A["phi_red"].set_linewidth(lw)
        self.A["rr_text"] = self.axr.text(0.02, 0.89, "reverse rotation", transform=self.axr.transAxes, ha="left",
                                          va="top", fontsize=14, color=RED, weight="bold", animated=True,
                                          visible=False)
        self.axl.legend(handles=[Line2D([], [], color=RED, lw=2, label=r"reverse rotation ($\phi'\omega < 0$)"),
                                 Line2D([], [], color=BLUE, lw=2, label=r"normal rotation")],
                        loc="upper left", fontsize=9, framealpha=0.9)
        self.canvas.draw()  # the legend is static: into the cached background
        self._bg = self.canvas.copy_from_bbox(self.fig.bbox)

    def spin_at(self, tau: float) -> float:
        """phi'(tau) (rad/s), linearly interpolated between the samples, as every drawn state."""
        return float(np.interp(tau, self._tall, self._pd))

    def marked(self, tau: float) -> bool:
        """True when the frame at ``tau`` shows reverse rotation: phi'(tau) omega < 0."""
        return self.spin_at(tau) * self.omega < 0.0

    def _trail_first(self, mid: np.ndarray) -> np.ndarray:
        """Trail segments in red: those whose mid time (s) is in reverse rotation, phi' omega < 0."""
        return np.interp(mid, self._tall, self._pd) * self.omega < 0.0

    def update(self, tau: float, *, banner: bool = False) -> None:
        super().update(tau, banner=banner)
        tt, ph = self._phi.upto(tau)
        ph = ph[:, 1]
        # each sample coloured by its own state; a segment between two samples of different states is
        # drawn in both colours (blue on top), so the curve has no gap
        rr = np.interp(tt, self._tall, self._pd) * self.omega < 0.0
        red = np.where(rr | np.r_[False, rr[:-1]] | np.r_[rr[1:], False], ph, np.nan) if len(tt) else ph
        blue = np.where(~rr | np.r_[False, ~rr[:-1]] | np.r_[~rr[1:], False], ph, np.nan) if len(tt) else ph
        self.A["phi_red"].set_data(tt, red)
        self.A["phi_blue"].set_data(tt, blue)
        now = self.marked(tau)
        self.A["rr_text"].set_visible(now)
        self.A["time"].set_color(RED if now else BLUE)


def render_chaos_movie(traj: Trajectory, path: str | Path, *, force: bool = False, progress: bool = False,
                       fps: float = 30, size: tuple[int, int] = (1280, 720), speed: float = 1.0,
                       t_start: float | None = None, t_end: float | None = None, title: str | None = None,
                       trail_fade: float | None = None) -> Path:
    """Render the driven run ``traj`` to the MP4 ``path`` with its RR stretches marked; returns the path.
    Options as :func:`rrbody.render.mp4.render_movie` (there is no flip to hold)."""
    from rrbody.model.checks import check_positive
    from rrbody.render.mp4 import frame_times, write_frames

    final, fps, speed, size = check_movie(path, force=force, fps=fps, speed=speed, size=size)
    a, b = check_span(traj, t_start, t_end)
    omega = _omega(traj)
    fade = 4.0 * 2.0 * math.pi / abs(omega) if trail_fade is None else check_positive("trail_fade", trail_fade,
                                                                                       unit="s")
    times = frame_times(a, b, fps=fps, speed=speed)
    fig = ChaosMovieFigure(traj, size=size, window=(a, b), speed=speed, title=title, trail_fade=fade)
    return write_frames(final, (fig.frame(float(tau)) for tau in times), len(times), size=size, fps=fps, force=force,
                        progress=progress)
