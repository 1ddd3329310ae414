"""Rendering: milliseconds per 1280x720 movie frame.

The phixtpm run (rod-mass, H = 0.2, k = 0.05, w = 0.6, 45 s) rendered with
:func:`rrbody.render.mp4.render_movie` (matplotlib Agg + ffmpeg libx264, 30 fps) to a temporary
file: end-to-end time per frame (drawing, RGBA transfer and encoding; ffmpeg runs as a separate
process, so on 2 cores encoding overlaps drawing). Also the drawing alone
(:meth:`MovieFigure.frame`) and the figure set-up (once per movie).
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, write_csv

NAME = "render"
TITLE = "Rendering: ms per 1280x720 movie frame"


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("rrbody.render.mp4")
    if not ok:
        print(f"[render] skipped: rrbody.render.mp4 not importable ({why})", flush=True)
        return StudyResult(NAME, TITLE, skipped=f"rrbody.render.mp4 not importable ({why})")
    from rrbody.analysis.simulate import simulate
    from rrbody.model.scene import rod_mass_scene
    from rrbody.render.flip import flip_mark
    from rrbody.render.mp4 import MovieFigure, frame_times, render_movie

    t0 = time.perf_counter()
    traj = simulate(rod_mass_scene(0.2, 0.05, 0.6), t_max=45.0)
    fps = 30.0
    counts = (30, 90) if quick else (60, 300)
    walls = {}
    size_mb = math.nan
    with tempfile.TemporaryDirectory(prefix="rrbody-bench-") as tmp:
        # warm-up (font cache, ffmpeg binary in the page cache), not counted
        render_movie(traj, Path(tmp) / "warm.mp4", fps=fps, size=(1280, 720), speed=45.0, force=True)
        for n_frames in counts:
            speed = 45.0 / (n_frames / fps)   # the whole run in n_frames frames
            best = math.inf
            for rep in range(1 if quick else 2):
                path = Path(tmp) / f"m{n_frames}_{rep}.mp4"
                w0 = time.perf_counter()
                render_movie(traj, path, fps=fps, size=(1280, 720), speed=speed, force=True)
                best = min(best, time.perf_counter() - w0)
                size_mb = path.stat().st_size / 1e6
            walls[n_frames] = (best, len(frame_times(0.0, 45.0, fps=fps, speed=speed)))
            print(f"[render] {walls[n_frames][1]} frames: {best:.2f} s", flush=True)
    (wa, na), (wb, nb) = walls[counts[0]], walls[counts[1]]
    times = frame_times(0.0, 45.0, fps=fps, speed=45.0 / (counts[1] / fps))
    rows = [{"what": "render_movie end to end (set-up, draw, encode)", "frames": nb, "ms_per_frame": wb / nb * 1e3},
            {"what": f"render_movie marginal cost per frame ({na} -> {nb} frames)", "frames": nb - na,
             "ms_per_frame": (wb - wa) / (nb - na) * 1e3}]
    w0 = time.perf_counter()
    fig = MovieFigure(traj, size=(1280, 720), flip=flip_mark(traj))
    setup = time.perf_counter() - w0
    w0 = time.perf_counter()
    for tau in times:
        fig.frame(float(tau))
    draw = (time.perf_counter() - w0) / len(times)
    rows.append({"what": "MovieFigure.frame (drawing only)", "frames": len(times), "ms_per_frame": draw * 1e3})
    rows.append({"what": "MovieFigure set-up (once per movie)", "frames": 1, "ms_per_frame": setup * 1e3})
    files = [str(write_csv(out / "render.csv", rows))]
    e2e = rows[0]["ms_per_frame"]
    marg = rows[1]["ms_per_frame"]
    targets = [Target("movie frame 1280x720", "<= 40 ms",
                      f"{e2e:.1f} ms end to end over {nb} frames; marginal {marg:.1f} ms; drawing {draw * 1e3:.1f} ms",
                      e2e <= 40.0, "ffmpeg (libx264) runs in its own process: on a loaded 2-core machine it competes")]
    md = [f"## {TITLE}", "", machine_text(), "",
          f"phixtpm run (45 s) at 1280x720, 30 fps, libx264 crf 26 ({fmt(size_mb)} MB for {nb} frames); "
          "best of the repeats. The marginal cost is the slope between the two movie lengths (no set-up, no "
          "ffmpeg start-up).", "",
          md_table(["what", "frames", "ms per frame"], [(r["what"], r["frames"], r["ms_per_frame"]) for r in rows]),
          "", "Data: `render.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    return res
