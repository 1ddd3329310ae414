"""Off-screen MP4 movies of a run: matplotlib (Agg, no display) -> imageio-ffmpeg's bundled ffmpeg.

The figure (:class:`~rrbody.render.movie_figure.MovieFigure`): phi(t) on the left, red before the
flip time t_f and blue after; the plane on the right with O, P and the CM labelled, the body to scale,
a fading CM trail, an orbit/spin dial that shows reverse rotation at a glance and optional velocity and
friction arrows. The flip is the whole run's (:func:`rrbody.render.flip.flip_mark`), never the lowest
phi of the rendered span; when it falls inside the span the movie holds the flip frame for
``hold`` seconds of playback under a banner, and the banner stays up for as long again.

Each frame restores a cached background and draws only the artists that change, then hands the RGBA
buffer straight to ffmpeg's stdin. Output: H.264 (libx264), yuv420p, MP4, written to a temporary
sibling and renamed into place (:func:`rrbody.io.atomic_path`). ffmpeg is told to write no creation
time and no encoder string, so the same run and options give the same bytes.

Units: simulated time t in s; movie time in s of playback; ``speed`` = simulated seconds per
second of playback; positions in m (world frame); angles in rad.
"""

from __future__ import annotations

import math
from collections.abc import Generator, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.model.checks import check, check_positive, check_range, check_real
from rrbody.model.io import atomic_path, check_writable
from rrbody.model.trajectory import Trajectory
from rrbody.render.flip import BLUE, RED, FlipMark, flip_mark
from rrbody.render.movie_figure import GREEN, MovieFigure, check_movie, check_span

__all__ = ["render_movie", "render_poster", "write_frames", "frame_times", "frame_schedule", "MovieFigure", "RED",
           "BLUE", "GREEN"]

CODEC = "libx264"
PIX_FMT = "yuv420p"


# ---- time mapping -------------------------------------------------------------------------------
def frame_times(t_start: float, t_end: float, *, fps: float, speed: float) -> np.ndarray:
    """Simulated time (s) of each movie frame: t_start + speed * k / fps for k = 0, 1, ... up to t_end.

    The movie lasts ``len(result) / fps`` s of playback (ffmpeg shows each frame for 1/fps s).
    """
    fps = check("fps", fps)
    speed = check("movie_speed", speed, label="speed")
    if not t_end > t_start:
        raise ValueError(f"t_end must be > t_start={t_start:g} s, got {t_end!r}")
    # the small slack keeps the last frame when (t_end - t_start) * fps / speed is an integer up to rounding
    n = int(math.floor((t_end - t_start) * fps / speed * (1.0 + 1e-12) + 1e-9)) + 1
    return t_start + speed * np.arange(n) / fps


def frame_schedule(times: np.ndarray, flip: FlipMark, *, fps: float, hold: float) -> list[tuple[float, bool]]:
    """(simulated time, banner shown) per frame: ``times``, plus ``hold`` s of playback frozen at t_f when
    the flip lies inside the span; the banner is up while frozen and for ``hold`` s of playback after."""
    out = [(float(x), False) for x in times]
    if hold <= 0.0 or not flip.in_span(float(times[0]), float(times[-1])) or flip.t_f is None:
        return out
    n_hold = max(int(round(hold * fps)), 1)
    k = int(np.searchsorted(times, flip.t_f, side="left"))
    frozen = [(float(flip.t_f), True)] * n_hold
    after = [(tau, i < n_hold) for i, (tau, _) in enumerate(out[k:])]
    return out[:k] + frozen + after


# ---- writing -----------------------------------------------------------------------------------
def _open_writer(path: Path, size: tuple[int, int], fps: float) -> Generator[None, Any, None]:
    """A started imageio-ffmpeg writer taking RGBA frames: H.264 in MP4, yuv420p (any player)."""
    from rrbody.model.extras import require

    imageio_ffmpeg = require("imageio_ffmpeg", purpose="a movie")
    gen = imageio_ffmpeg.write_frames(
        str(path), size, pix_fmt_in="rgba", pix_fmt_out=PIX_FMT, fps=fps, codec=CODEC,
        quality=None, macro_block_size=2,  # size is checked even; no rescaling
        # crf 28 / preset fast: line art with a fading trail and arrows stays < 1 MB a minute at 1280x720
        # (medium: the same size, encoded more slowly, measured with `python -m rrbody.render.mp4`);
        # faststart puts the index first so browsers can play while downloading
        # no creation_time and no encoder/version strings in the container: identical runs, identical bytes
        output_params=["-crf", "28", "-preset", "fast", "-movflags", "+faststart", "-map_metadata", "-1",
                       "-fflags", "+bitexact", "-flags:v", "+bitexact", "-f", "mp4"],
    )
    gen.send(None)
    return gen


def render_movie(traj: Trajectory, path: str | Path, *, force: bool = False, progress: bool = False,
                 fps: float = 30, size: tuple[int, int] = (1280, 720), speed: float = 1.0, flip: Any = None,
                 trail: bool = True, t_start: float | None = None, t_end: float | None = None,
                 title: str | None = None, hold: float = 1.5, trail_fade: float | None = None,
                 arrows: bool = False) -> Path:
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
    flip : FlipResult, FlipMark, float or None
        The whole run's flip (see :func:`rrbody.render.flip.flip_mark`); default: computed from the
        run's scene with ``flip_time``, so a span that ends before t_f says "no flip within this span".
    trail : bool
        Draw the CM history.
    t_start, t_end : float or None
        Simulated time span to render (default: the whole run).
    hold : float
        Seconds of playback the movie stays on the flip frame (with a banner); 0: no pause.
    trail_fade : float or None
        Age (s, simulated) over which the trail fades to a faint floor; default 4 driving periods
        (10 s for a free body).
    arrows : bool
        Draw the CM velocity and the friction force (from the scene's friction kernel).
    force : bool
        Overwrite an existing file. Without it an existing ``path`` is an error (checked before
        any frame is drawn).
    """
    # the limits table's ranges, the same the CLI applies
    final, fps, speed, size = check_movie(path, force=force, fps=fps, speed=speed, size=size)
    hold = check_range("hold", hold, 0.0, 60.0)
    a, b = check_span(traj, t_start, t_end)
    mark = flip_mark(traj, flip)
    fade = _default_fade(traj) if trail_fade is None else check_positive("trail_fade", trail_fade, unit="s")
    schedule = frame_schedule(frame_times(a, b, fps=fps, speed=speed), mark, fps=fps, hold=hold)
    fig = MovieFigure(traj, flip=mark, size=size, trail=trail, window=(a, b), speed=speed, title=title,
                      trail_fade=fade, arrows=arrows)
    return write_frames(final, (fig.frame(tau, banner=banner) for tau, banner in schedule), len(schedule),
                        size=size, fps=fps, force=force, progress=progress)


def write_frames(final: Path, frames: Iterable[Any], n: int, *, size: tuple[int, int], fps: float, force: bool,
                 progress: bool, name: str = "movie") -> Path:
    """Encode ``n`` RGBA frames (``size`` pixels, each a buffer of height x width x 4 bytes) to the MP4
    ``final`` (already checked by ``check_writable``) at ``fps``: written to a temporary sibling and
    renamed into place, with progress on stderr if ``progress`` (a bar on a terminal, a line per tenth
    of the frames elsewhere: :class:`~rrbody.render.movie_progress.FrameProgress`). Returns ``final``."""
    from rrbody.render.movie_progress import FrameProgress

    bar = FrameProgress(n, f"{name} {final.name}") if progress else None
    try:
        with atomic_path(final, force=force, name=name) as tmp:
            writer = _open_writer(tmp, size, fps)
            try:
                for frame in frames:
                    writer.send(frame)
                    if bar is not None:
                        bar.update(1)
            finally:
                writer.close()  # waits for ffmpeg to finish (or to exit after an error)
    finally:
        if bar is not None:
            bar.close()
    return final


def _default_fade(traj: Trajectory) -> float:
    """Four driving periods (s): long enough to see the last petals, short enough not to clutter."""
    drive = (traj.meta.get("scene") or {}).get("drive")
    return 4.0 * 2.0 * math.pi / float(drive["omega"]) if drive else 10.0


def render_poster(traj: Trajectory, path: str | Path, *, tau: float | None = None, force: bool = False,
                  size: tuple[int, int] = (1280, 720), flip: Any = None, trail: bool = True,
                  title: str | None = None, arrows: bool = False) -> Path:
    """One still of the movie layout at simulated time ``tau`` (default: the last sample), PNG or SVG.

    The whole CM history is drawn at full strength (no fading), like the paper's Fig. SSs.
    """
    check_writable(path, force=force, name="poster")
    fig = MovieFigure(traj, flip=flip_mark(traj, flip), size=size, trail=trail, title=title, arrows=arrows)
    when = float(traj.t[-1]) if tau is None else check_real("tau", tau)
    return fig.save(path, when, force=force)
