"""The recorder (rrbody.plugin.Recorder): what filming costs, for 1,000 bodies.

Capture overhead: 1,000 bodies (disks and boxes, half each) slide and spin on a plane with
PlaneFriction (mu = 0.01: they keep sliding through the measurement), in two scenes: on a grid 1 m
apart, so nothing touches (the cheapest ``pf.step`` there is: the target is judged on it), and
packed 0.45 m apart in a walled box, colliding. Blocks of ``BLOCK`` steps of ``pf.step`` alone
alternate, in one run, with blocks of ``pf.step`` followed by ``rec.capture()`` (every step
captured; velocities and friction included, and poses only), the best block of each kind giving the
per-step times and their ratio. These recorders reserve their frames (``Recorder(...,
reserve=...)``, as docs/plugin.md advises for a run of known length): the memory is claimed when
the recorder is made, so a block times the capture itself.

Growth: without ``reserve`` the store doubles as it fills and each fresh page of memory is mapped
by the operating system at its first write. Whole runs of ``GROW`` steps with and without a
capture at every step (bodies apart, a new recorder each run, best of 3, interleaved) give that
case's overhead, amortised over the run, and the time ``reserve`` itself takes for as many frames.

Render rate: the same 1,000 bodies captured every step for 10 s of simulated time, then a 10 s
movie at 30 frames/s at 1280x720 (300 frames: set-up, drawing, RGBA transfer and H.264 encoding,
ffmpeg running as a separate process), end to end, best of 3, once coloured by body and once by
spin with velocity arrows.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, write_csv

NAME = "recorder"
TITLE = "Recorder: capture overhead and render rate, 1,000 bodies"
N_BODIES, DT, BLOCK, GROW = 1000, 1.0 / 60.0, 50, 1500


def _scene(n: int, mu: float = 0.01, spacing: float = 1.0) -> tuple:
    """n bodies on a square grid ``spacing`` m apart; below 1 m, inside walls 0.5 m beyond the grid."""
    import pymunk

    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    side = int(math.ceil(math.sqrt(n)))
    if spacing < 1.0:
        lo, hi = -0.5, spacing * (side - 1) + 0.5
        corners = [(lo, lo), (hi, lo), (hi, hi), (lo, hi)]
        space.add(*[pymunk.Segment(space.static_body, a, b, 0.05) for a, b in zip(corners, corners[1:] + corners[:1])])
    for i in range(n):
        b = pymunk.Body()
        b.position = (spacing * (i % side), spacing * (i // side))
        s = pymunk.Circle(b, 0.2) if i % 2 else pymunk.Poly.create_box(b, (0.35, 0.25))
        s.density = 10.0
        space.add(b, s)
        b.velocity = (0.3 * math.cos(i), 0.3 * math.sin(i))  # < 0.5 m/s: 1 m apart, no contact for 1.5 s
        b.angular_velocity = 2.0 * math.sin(3.0 * i)
        pf.add(b, mu=mu)
    return space, pf


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("pymunk")
    if not ok:
        return StudyResult(NAME, TITLE, skipped=f"pymunk not importable ({why})")
    from rrbody.plugin import Recorder

    n = 200 if quick else N_BODIES
    costs: dict[str, tuple[float, float, float]] = {}  # case -> (pf.step, with capture, poses only), s
    for case, spacing in (("apart", 1.0), ("packed", 0.45)):
        space, pf = _scene(n, spacing=spacing)
        frames = 3 + (3 if quick else 9) * BLOCK + 1  # every capture below, reserved
        full = Recorder(space, pf, max_mb=8000.0, reserve=frames)
        poses = Recorder(space, pf, motion=False, max_mb=8000.0, reserve=frames)
        for _ in range(3):  # compiled step and capture, first allocations: not counted
            pf.step(DT)
            full.capture()
            poses.capture()
        best = [math.inf, math.inf, math.inf]
        for _ in range(3 if quick else 9):  # interleaved: a block of each, the best of each kind
            for kind, rec in ((0, None), (1, full), (2, poses)):
                w0 = time.perf_counter()
                for _ in range(BLOCK):
                    pf.step(DT)
                    if rec is not None:
                        rec.capture()
                best[kind] = min(best[kind], (time.perf_counter() - w0) / BLOCK)
        costs[case] = (best[0], best[1], best[2])
        print(f"[recorder] {case}: pf.step {best[0] * 1e3:.3f} ms, with capture {best[1] * 1e3:.3f} ms "
              f"(+{best[1] / best[0] - 1:.1%}), poses only {best[2] * 1e3:.3f} ms (+{best[2] / best[0] - 1:.1%})",
              flush=True)
    bare, filmed, _ = costs["apart"]
    overhead = filmed / bare - 1.0

    # growth: whole runs, a new recorder (no reserve) each, against runs without a capture
    steps = 300 if quick else GROW
    space, pf = _scene(n)
    for _ in range(3):
        pf.step(DT)
    runs = [math.inf, math.inf]
    claim = math.inf
    for _ in range(3):
        for kind in (0, 1):
            rec = Recorder(space, pf, max_mb=8000.0) if kind else None
            w0 = time.perf_counter()
            for _ in range(steps):
                pf.step(DT)
                if rec is not None:
                    rec.capture()
            runs[kind] = min(runs[kind], time.perf_counter() - w0)
            del rec
        w0 = time.perf_counter()
        Recorder(space, pf, max_mb=8000.0, reserve=steps)
        claim = min(claim, time.perf_counter() - w0)
    growth = runs[1] / runs[0] - 1.0
    print(f"[recorder] growth: {steps} steps {runs[0]:.3f} s, with capture (no reserve) {runs[1]:.3f} s "
          f"(+{growth:.1%}); reserve={steps} takes {claim:.3f} s", flush=True)

    # render: 10 s captured every step, a 10 s movie at 30 fps
    space, pf = _scene(n)
    rec = Recorder(space, pf, max_mb=4000.0)
    seconds = 2.0 if quick else 10.0
    for _ in range(int(round(seconds / DT))):
        pf.step(DT)
        rec.capture()
    walls: dict[str, float] = {}
    n_frames = int(round(seconds * 30))
    with tempfile.TemporaryDirectory(prefix="rrbody-bench-") as tmp:
        rec.movie(Path(tmp) / "warm.mp4", fps=30, t_end=rec.times[10], progress=False)  # fonts, ffmpeg: not counted
        for rep in range(1 if quick else 3):
            for look, kw in (("by body", {}), ("by spin, velocity arrows", {"color": "spin", "arrows": ("velocity",)})):
                path = Path(tmp) / f"m{rep}.mp4"
                w0 = time.perf_counter()
                rec.movie(path, fps=30, size=(1280, 720), force=True, progress=False, **kw)
                walls[look] = min(walls.get(look, math.inf), time.perf_counter() - w0)
                print(f"[recorder] movie {look}: {walls[look]:.2f} s for {n_frames} frames", flush=True)
    rows = []
    for case, (b0, b1, b2) in costs.items():
        rows += [{"what": f"{case}: pf.step alone (ms)", "value": b0 * 1e3},
                 {"what": f"{case}: pf.step + capture (ms)", "value": b1 * 1e3},
                 {"what": f"{case}: capture overhead (fraction of pf.step)", "value": b1 / b0 - 1.0},
                 {"what": f"{case}: capture overhead, poses only (motion=False)", "value": b2 / b0 - 1.0}]
    rows += [{"what": f"growth: {steps} steps, capture overhead without reserve (amortised)", "value": growth},
             {"what": f"growth: Recorder(reserve={steps}) takes (s)", "value": claim},
             {"what": f"growth: {steps} steps of pf.step alone (s)", "value": runs[0]}]
    rows.append({"what": "bytes per captured frame", "value": rec.bytes_per_frame})
    rows += [{"what": f"movie {look}: s for a {seconds:g} s movie at 30 fps", "value": w} for look, w in walls.items()]
    write_csv(out / "recorder.csv", rows)
    worst = max(walls.values())
    fps = n_frames / worst
    targets = [
        Target("capture overhead, every step, 1,000 bodies", "<= 10 %",
               f"{overhead:.1%} with reserved frames ({filmed * 1e3:.3f} vs {bare * 1e3:.3f} ms per step, bodies "
               f"apart; packed and colliding {costs['packed'][1] / costs['packed'][0] - 1:.1%}; poses only "
               f"{costs['apart'][2] / bare - 1:.1%}). Without reserve, over {steps} steps: {growth:.1%} "
               f"(fresh memory; reserving it takes {claim:.2f} s)", overhead <= 0.10),
        Target("render rate, 1,000 bodies at 1280x720", ">= 20 frames/s",
               f"{fps:.1f} frames/s ({worst:.1f} s for a {seconds:g} s movie at 30 fps, the slower look)", fps >= 20.0),
    ]
    if quick:
        targets = [Target(t.name, t.target, t.measured + " [quick: 200 bodies]", None) for t in targets]
    md = [f"## {TITLE}", "", __doc__.split("\n\n", 1)[1].strip(), "", machine_text(), "",
          md_table(["what", "value"], [(r["what"], fmt(r["value"])) for r in rows]), ""]
    return StudyResult(NAME, TITLE, targets=targets, markdown="\n".join(md), files=["recorder.csv"],
                       extra={"highlights": [f"capture adds {overhead:.1%} to pf.step (1,000 bodies); "
                                             f"movies render at {fps:.0f} frames/s at 720p"]})
