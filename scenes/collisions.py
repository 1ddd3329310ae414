"""Collisions (the paper's outlook): a dozen driven and free bodies on one rough plane; which collisions restart RR?

Six driven bodies (disks and ellipses, rrbody's builder with collisions on) ride concentric drive
circles d = 1.0 ... 3.85 m at alternating rates (0.6 and 0.45 rad/s, so neighbours keep meeting); they
form a binary mixture: three have P far from the CM (H 0.11-0.34, below H_c: alone they reverse-rotate)
and three have P near the CM (H 1.46-3.41, above H_c(0) = 0.79: alone they cannot). Six free bodies,
boxes and L-shapes (two boxes on one pymunk body), lie in the swept rings and are knocked about
(mu g = 0.3 m/s^2). Nothing touches at t = 0.
All twelve feel area-integrated dry friction from rrbody's PlaneFriction (k = mu g / d = 0.02 s^-2
for the driven ones). A reverse-rotation episode of a driven body is a stretch with phi' < 0 during
which phi falls by more than pi; it "starts at a collision" if the body began a contact within
COLLISION_WINDOW s before. Outputs: results/collisions/ (summary.json with the episodes per body,
collisions.png) and movies/collisions.mp4 (a short movie of the first T_MOVIE s).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

DT, T_END, T_MOVIE, SAMPLE = 2e-3, 80.0, 40.0, 10  # s, s, s, steps between samples
K, COLLISION_WINDOW = 0.02, 1.0  # s^-2; s
#: drive radii (m): a body with P far from its CM (sweeping d +- 0.45 m) between two with P at the CM
RADII = (1.0, 1.65, 2.1, 2.75, 3.2, 3.85)


def _build() -> tuple[Any, Any, list[tuple[str, Any, Any]], list[tuple[str, Any]]]:
    """(space, plane, driven [(name, scene, handle)], free [(name, body)])."""
    import pymunk

    from rrbody.engine import EngineSettings, attach, plane_for
    from rrbody.model.bodies import Disk, Ellipse
    from rrbody.model.drive import CircularDrive
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene

    space = pymunk.Space()  # top-down: no gravity
    pf = plane_for(space)
    settings = EngineSettings(dt=DT, collide=True)
    driven = []
    for i, d in enumerate(RADII):
        rr_capable = i % 2 == 0
        l = 0.3 if rr_capable else 0.002  # P almost at the CM: H = I/(m d l) + l/d > 0.8
        body = Disk(R=0.15, l=l) if i % 4 < 2 else Ellipse(R0=0.15, delta=0.4, l=l)
        sc = Scene(body=body, drive=CircularDrive(0.6 if i % 2 == 0 else 0.45, d=d),
                   friction=Friction.from_k("dry", K, d), phi0=math.pi)
        driven.append((f"driven {i} ({body.kind}, H={sc.H:.2f})", sc, attach(space, sc, settings=settings)))
    free = []
    rng = np.random.default_rng(11)
    for i in range(6):
        b = pymunk.Body()
        if i % 2 == 0:
            shapes = [pymunk.Poly.create_box(b, (0.3, 0.3))]
        else:  # an L: two boxes on one body
            shapes = [pymunk.Poly(b, [(0, 0), (0.4, 0), (0.4, 0.15), (0, 0.15)]),
                      pymunk.Poly(b, [(0, 0.15), (0.15, 0.15), (0.15, 0.4), (0, 0.4)])]
        for s in shapes:
            s.density = 12.0
        r, a = (1.3, 2.4, 3.5)[i % 3], 1.0 + 0.85 * i  # in the rings, away from the bodies at angle 0
        b.position = (r * math.cos(a), r * math.sin(a))
        b.angle = rng.uniform(0, 2 * math.pi)
        space.add(b, *shapes)
        pf.add(b, mu=0.3 / 9.81)  # mu g = 0.3 m/s^2
        free.append((f"free {i} ({'box' if i % 2 == 0 else 'L'})", b))
    return space, pf, driven, free


def _episodes(t: np.ndarray, phi: np.ndarray, phid: np.ndarray, hits: list[float]) -> list[dict]:
    """Reverse-rotation episodes of a driven body (orbit counter-clockwise): runs of phi' < 0 in which phi
    falls by more than pi (:func:`rrbody.analysis.episodes.reverse_episodes`)."""
    from rrbody.analysis.episodes import reverse_episodes

    return reverse_episodes(t, phi, phid, hits=hits, window=COLLISION_WINDOW)


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.analysis.flip import flip_time
    from rrbody.analysis.report import write_summary
    from rrbody.engine.memory.compat import on_begin
    from rrbody.render.figures import save_figure
    from rrbody.render.recorder import shape_outlines

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    space, pf, driven, free = _build()
    names = [n for n, _, _ in driven] + [n for n, _ in free]
    bodies = [h.body for _, _, h in driven] + [b for _, b in free]
    index = {b: k for k, b in enumerate(bodies)}
    hits: list[list[float]] = [[] for _ in bodies]

    def begin(arbiter: Any, space_: Any, data: Any) -> None:
        """pymunk's collision callback: note the time for both bodies that began touching."""
        for b in arbiter.bodies:
            if b in index:
                hits[index[b]].append(pf.t)

    on_begin(space, None, None, begin)  # any two shapes (pymunk 6 and 7 alike)
    from rrbody.plugin import Recorder

    n = round(T_END / DT)
    rec = Recorder(space, pf, bodies=bodies, every=SAMPLE)  # x, y, angle of every body, every SAMPLE steps
    phi = np.zeros((n // SAMPLE + 1, len(driven), 2))  # phi, phi'
    for i in range(n + 1):
        if i:
            pf.step(DT)
        if rec.capture():
            phi[rec.n_frames - 1] = [(h.phi, h.phi_dot) for _, _, h in driven]
    t, pose = rec.times, rec.frames[:, :, :3]
    # episodes per driven body, and whether each body reverse-rotates alone (ODE path, no collisions)
    summary = {"dt": DT, "t_end": T_END, "k": K, "collision_window_s": COLLISION_WINDOW, "bodies": {}}
    for j, (name, sc, _) in enumerate(driven):
        eps = _episodes(t, phi[:, j, 0], phi[:, j, 1], hits[j])
        summary["bodies"][name] = {"H": sc.H, "omega": sc.omega, "d": sc.d,
                                   "reverse_rotation_alone": flip_time(sc).reverse_rotation,
                                   "collisions": len(hits[j]), "rr_episodes": len(eps),
                                   "rr_episodes_starting_at_collision": sum(e["starts_at_collision"] for e in eps),
                                   "episodes": eps}
    for j, (name, b) in enumerate(free, start=len(driven)):
        summary["bodies"][name] = {"collisions": len(hits[j]), "at_rest_since_s": pf.stop_time(b)}
    write_summary(out_dir, summary, force=force)
    # figure: phi(t) of each driven body in its own row, its episodes shaded there only; every body's path
    fig = plt.figure(figsize=(13, 7.5), constrained_layout=True)
    grid = fig.add_gridspec(len(driven), 2, width_ratios=(1.25, 1.0))
    rows = [fig.add_subplot(grid[j, 0]) for j in range(len(driven))]
    for j, (name, _, _) in enumerate(driven):
        a, info = rows[j], summary["bodies"][name]
        line, = a.plot(t, phi[:, j, 0] / (2 * math.pi), lw=0.9, color=f"C{j}")  # its path's colour on the right
        for e in info["episodes"]:
            a.axvspan(e["t_start"], e["t_end"], color=line.get_color(),
                      alpha=0.35 if e["starts_at_collision"] else 0.12,
                      lw=0)
        a.plot(hits[j], np.interp(hits[j], t, phi[:, j, 0] / (2 * math.pi)), "k|", ms=7)
        alone = "reverse-rotates alone" if info["reverse_rotation_alone"] else "cannot reverse-rotate alone"
        a.set_title(f"{name}: {alone}; {info['rr_episodes']} RR episodes, "
                    f"{info['rr_episodes_starting_at_collision']} started at a collision", fontsize=8, loc="left")
        a.set_ylabel(r"$\phi/2\pi$", fontsize=8)
        a.tick_params(labelsize=7)
        if j < len(driven) - 1:
            a.tick_params(labelbottom=False)
    rows[-1].set_xlabel("t (s)")
    rows[0].text(1.0, 1.35, "shaded: reverse-rotation episodes (dark: started at a collision); |: collisions",
                 transform=rows[0].transAxes, ha="right", fontsize=8)
    b = fig.add_subplot(grid[:, 1])
    for j in range(len(names)):
        b.plot(pose[:, j, 0], pose[:, j, 1], lw=0.6, color=f"C{j}" if j < len(driven) else "0.55")  # free: grey
        for o in shape_outlines(bodies[j]):
            o = np.vstack([o, o[:1]])
            x, y, ang = pose[-1, j]
            c, s = math.cos(ang), math.sin(ang)
            b.plot(x + c * o[:, 0] - s * o[:, 1], y + s * o[:, 0] + c * o[:, 1], "k-", lw=0.8)
    b.set(xlabel="x (m)", ylabel="y (m)", aspect="equal",
          title=f"paths over {T_END:g} s (driven: the colour of their row; free: grey), final poses")
    save_figure(fig, out_dir, "collisions", force=force)
    plt.close(fig)
    movies = out_dir.parent.parent / "movies"  # movies/ is the sibling of results/ (the runner's layout)
    movies.mkdir(parents=True, exist_ok=True)
    # the first T_MOVIE s at 20 frames per s of playback, 4 simulated s per s
    colours = ["tab:red" if j % 2 == 0 else "tab:blue" for j in range(len(driven))] + ["0.5"] * len(free)
    rec.movie(movies / "collisions.mp4", fps=20, speed=4.0, size=(640, 640), t_end=T_MOVIE, color=colours,
              box=(-4.6, 4.6, -4.6, 4.6), title="red: H < H_c, blue: H > H_c, grey: free", force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "collisions")
