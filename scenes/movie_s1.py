"""Movie S1 (paper Fig. SSs): phi(t) and the CM history, red before t_f, blue after; petal-shaped RR paths.

Parameters of the paper's Fig. SSs: rod-mass body, k = mu g / d = 0.003 s^-2, H = 0.6,
omega = 0.6 rad/s, phi0 = pi. Reverse rotation (petal-shaped CM paths with cusps) lasts until
the flip time t_f ~ 42 s; the movie runs on to t_f + 60 s so that the rounded paths of normal
rotation follow. Time is sped up 2.5x (about 42 s of playback at 30 fps, 1280x720, H.264), with a
1.5 s pause and a banner at the flip. O, P and the CM are labelled; a dial shows the orbit's and the
spin's sense; green and purple arrows are the CM velocity and the friction force.

Outputs: movies/movie_s1.mp4 (beside results/), and in ``out_dir`` a poster of the last frame
(movie_s1_poster.png) and the trajectory that was rendered (movie_s1_trajectory.csv).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

#: the scene (paper Fig. SSs)
K, H, OMEGA, PHI0 = 0.003, 0.6, 0.6, math.pi
#: simulated seconds shown after the flip; playback speed (simulated s per s); frames per second
AFTER_FLIP, SPEED, FPS = 60.0, 2.5, 30
#: playback seconds the movie pauses on the flip
HOLD = 1.5
#: output sampling (s): fine enough that the drawn polylines look smooth (~300 points per period)
DT_OUT = 0.02


def main(out_dir: Path, *, force: bool = True) -> None:
    from rrbody.analysis.flip import flip_time
    from rrbody.analysis.simulate import simulate
    from rrbody.model.scene import rod_mass_scene
    from rrbody.render.mp4 import render_movie, render_poster

    out_dir.mkdir(parents=True, exist_ok=True)
    movies = out_dir.parent.parent / "movies"  # movies/ is the sibling of results/ (the runner's layout)
    movies.mkdir(parents=True, exist_ok=True)
    # 1. the scene and its flip time (the red/blue split); each long step says what it does on stderr
    # (stdout keeps the one result line)
    print("Movie S1: computing the flip time and the run ...", file=sys.stderr, flush=True)
    scene = rod_mass_scene(H, K, OMEGA, PHI0)
    flip = flip_time(scene)
    if flip.t_f is None:
        raise RuntimeError(f"Movie S1 expects a flip, got regime: {flip.regime}")
    t_end = math.ceil(flip.t_f + AFTER_FLIP)
    # 2. the run, sampled finely for smooth curves
    traj = simulate(scene, t_max=float(t_end), dt_out=DT_OUT)
    traj.save(out_dir / "movie_s1_trajectory.csv", force=force)
    # 3. the movie and a poster of its last frame
    # (the flip is held for HOLD s of playback under a banner; the trail fades over 4 driving periods)
    # progress on a terminal and in a log alike (a bar, or a line per tenth of the frames)
    print(f"Movie S1: t_f = {flip.t_f:.4f} s; rendering 0..{t_end} s at x{SPEED}, {FPS} fps, 1280x720 ...",
          file=sys.stderr, flush=True)
    path = render_movie(traj, movies / "movie_s1.mp4", force=force, progress=True, fps=FPS,
                        speed=SPEED, flip=flip, hold=HOLD, arrows=True)
    render_poster(traj, out_dir / "movie_s1_poster.png", force=force, flip=flip)
    print(f"Movie S1: t_f = {flip.t_f:.4f} s, 0..{t_end} s at x{SPEED} -> {path} "
          f"({path.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "movie-s1")
