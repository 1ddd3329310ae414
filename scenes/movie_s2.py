"""Movie S2 (paper Fig. NormalAndPhasePortrait a): normal rotation from t = 0, with the CM history to t = 80 s.

Same parameters as Movie S1 except the initial angle: rod-mass body, k = mu g / d = 0.003 s^-2,
H = 0.6, omega = 0.6 rad/s, phi0 = pi/2. Reverse rotation is not allowed here: phi never falls
below phi0, there is no flip time, and phi(t) and the CM history are drawn in blue throughout
(the paper's solid blue line). 0..80 s sped up 2x (40 s of playback at 30 fps, 1280x720, H.264).

Outputs: movies/movie_s2.mp4 (beside results/), and in ``out_dir`` a poster of the last frame
(movie_s2_poster.png) and the trajectory that was rendered (movie_s2_trajectory.csv).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

#: the scene (paper Fig. NormalAndPhasePortrait a, inset: CM history from t = 0 to 80 s)
K, H, OMEGA, PHI0 = 0.003, 0.6, 0.6, 0.5 * math.pi
T_END, SPEED, FPS = 80.0, 2.0, 30
#: output sampling (s): fine enough that the drawn polylines look smooth (~500 points per period)
DT_OUT = 0.02


def main(out_dir: Path, *, force: bool = True) -> None:
    from rrbody.analysis.flip import flip_time
    from rrbody.analysis.simulate import simulate
    from rrbody.model.scene import rod_mass_scene
    from rrbody.render.mp4 import render_movie, render_poster

    out_dir.mkdir(parents=True, exist_ok=True)
    movies = out_dir.parent.parent / "movies"  # movies/ is the sibling of results/ (the runner's layout)
    movies.mkdir(parents=True, exist_ok=True)
    # 1. the scene; check the paper's claim that there is no reverse rotation (so no red part)
    scene = rod_mass_scene(H, K, OMEGA, PHI0)
    flip = flip_time(scene)
    if flip.t_f is not None:
        raise RuntimeError(f"Movie S2 expects normal rotation from t = 0, got regime: {flip.regime}")
    # 2. the run to t = 80 s
    traj = simulate(scene, t_max=T_END, dt_out=DT_OUT)
    traj.save(out_dir / "movie_s2_trajectory.csv", force=force)
    # 3. the movie (no flip: blue throughout, said in the caption) and a poster of its last frame
    path = render_movie(traj, movies / "movie_s2.mp4", force=force, progress=sys.stderr.isatty(), fps=FPS,
                        speed=SPEED, flip=flip, arrows=True)
    render_poster(traj, out_dir / "movie_s2_poster.png", force=force, flip=flip)
    print(f"Movie S2: {flip.regime}; 0..{T_END:g} s at x{SPEED} -> {path} ({path.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "movie-s2")
