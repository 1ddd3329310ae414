"""Movie of a chaotic orbit, its reverse-rotation stretches marked from the run's own spin.

The chaotic orbit of ``rrbody scene chaos`` (H = 0.5, omega = 2 rad/s, a plane tilted by 0.5 rad,
no friction; maximal Lyapunov exponent 0.385 1/s): its first T_END s at SPEED x real time (about
16 s of playback at 30 fps, 1280 x 720, H.264). The phi(t) curve and the CM trail are red where the
body spins against its orbit (phi' omega < 0, from the run's samples), blue elsewhere; a red
"reverse rotation" label is up exactly while the state shown is in reverse rotation
(:mod:`rrbody.render.chaos_movie`). Outputs: movies/chaos.mp4, and in ``out_dir`` a poster of the last
frame (chaos_poster.png), the trajectory (chaos_trajectory.csv) and summary.json (the RR stretches).
"""

from __future__ import annotations

import sys
from pathlib import Path

#: the chaotic orbit of scenes/chaos.py
H, OMEGA, TILT = 0.5, 2.0, 0.5
#: simulated span (s), playback speed (simulated s per s), frames per second, output sampling (s)
T_END, SPEED, FPS, DT_OUT = 40.0, 2.5, 30, 0.01


def main(out_dir: Path, *, force: bool = True) -> None:
    import numpy as np

    from rrbody.analysis.report import write_summary
    from rrbody.analysis.simulate import simulate
    from rrbody.model.scene import scene_from_params
    from rrbody.render.chaos_movie import ChaosMovieFigure, render_chaos_movie, rr_mask, rr_stretches

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    movies = out_dir.parent.parent / "movies"  # movies/ is the sibling of results/ (the runner's layout)
    movies.mkdir(parents=True, exist_ok=True)
    scene = scene_from_params(H=H, k=None, omega=OMEGA, friction="none", tilt=TILT)
    traj = simulate(scene, t_max=T_END, dt_out=DT_OUT)
    traj.save(out_dir / "chaos_trajectory.csv", force=force)
    stretches = rr_stretches(traj.t, traj.phi_dot, OMEGA)
    mask = rr_mask(traj.t, traj.phi_dot, OMEGA)
    title = f"A chaotic orbit: rod-mass H = {H:g}, omega = {OMEGA:g} rad/s, plane tilted by {TILT:g} rad, no friction"
    path = render_chaos_movie(traj, movies / "chaos.mp4", force=force, progress=sys.stderr.isatty(), fps=FPS,
                              speed=SPEED, title=title)
    ChaosMovieFigure(traj, title=title).save(out_dir / "chaos_poster.png", float(traj.t[-1]), force=force)
    write_summary(out_dir, {"H": H, "omega": OMEGA, "tilt_rad": TILT, "friction": "none", "t_end": T_END,
                            "dt_out": DT_OUT, "speed": SPEED, "fps": FPS,
                            "rr_fraction_of_samples": float(np.mean(mask)), "rr_stretches": len(stretches),
                            "rr_stretches_s": [[round(a, 4), round(b, 4)] for a, b in stretches]}, force=force)
    print(f"chaos movie: {len(stretches)} reverse-rotation stretches over {T_END:g} s -> {path} "
          f"({path.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "movie-chaos")
