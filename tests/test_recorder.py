"""The recorder (rrbody.plugin.Recorder): pictures drawn where the bodies are, captures that hold the
plugin's own numbers, rerun recordings with one entity per body, and the usual answer to bad input.

Tolerances: a picture is checked to 1 px for positions and 2 degrees for angles (the recorder's stated bound:
rasterising at 200 px/m puts a pixel at 5 mm; a disk's radius line and antialiased edges move its
pixel centroid by well under a pixel); captured numbers are compared exactly with what the plugin
reports, since the capture reads the same values.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pymunk = pytest.importorskip("pymunk")

from rrbody.plugin import PlaneFriction, Recorder  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BOX, SIZE = (0.0, 3.2, 0.0, 1.8), (640, 360)  # 200 px per m, the box's aspect is the picture's
PX_PER_M = 200.0


def _body(space: pymunk.Space, shape: str, pos: tuple[float, float], angle: float) -> pymunk.Body:
    b = pymunk.Body()
    s = pymunk.Circle(b, 0.2) if shape == "disk" else pymunk.Poly.create_box(b, (0.4, 0.4))
    s.density = 1.0
    b.position, b.angle = pos, angle
    space.add(b, s)
    return b


def _pixels(img: np.ndarray, rgb: tuple[int, int, int]) -> np.ndarray:
    """World coordinates (m; x right, y up) of the pixel centres whose colour is within 40 of ``rgb``."""
    near = np.abs(img.astype(int) - np.array(rgb)).max(axis=2) < 40
    rows, cols = np.nonzero(near)
    return np.column_stack([BOX[0] + (cols + 0.5) / PX_PER_M, BOX[3] - (rows + 0.5) / PX_PER_M])


def _blend(hex_rgb: tuple[float, float, float]) -> tuple[int, int, int]:
    """A face colour drawn at the recorder's alpha 0.85 over white."""
    return tuple(int(round(255 * (0.85 * c + 0.15))) for c in hex_rgb)


def test_a_thick_segment_and_a_two_shape_body_are_drawn_as_their_union() -> None:
    """A capsule (a segment of radius 0.1 from (-0.3, 0) to (0.3, 0)) and an L of two boxes, each at a
    known pose: in the body's own frame, the pixels of its face span the shape's exact extent to 2 px
    (the outline, 1.1 px wide, covers the face's outermost pixel; antialiasing one more), and their
    centroid lies within 1 px of the shape's area centroid."""
    space = pymunk.Space()
    cap = pymunk.Body()
    cap.position, cap.angle = (0.9, 0.9), 0.4
    el = pymunk.Body()
    el.position, el.angle = (2.2, 0.8), -0.5
    ls = [pymunk.Poly(el, [(0, 0), (0.4, 0), (0.4, 0.15), (0, 0.15)]),
          pymunk.Poly(el, [(0, 0.15), (0.15, 0.15), (0.15, 0.4), (0, 0.4)])]
    space.add(cap, pymunk.Segment(cap, (-0.3, 0.0), (0.3, 0.0), 0.1), el, *ls)
    for sh in [*cap.shapes, *el.shapes]:
        sh.density = 1.0
    rec = Recorder(space, bodies=[cap, el])
    rec.capture(t=0.0)
    img = rec.image(size=SIZE, box=BOX, color=[(1.0, 0.0, 0.0), (0.0, 0.0, 1.0)])
    # the L's area centroid in its own frame: the two boxes' centroids weighted by their areas
    a1, a2 = 0.4 * 0.15, 0.15 * 0.25
    el_centre = (a1 * np.array([0.2, 0.075]) + a2 * np.array([0.075, 0.275])) / (a1 + a2)
    for body, rgb, lo, hi, centre in ((cap, (1.0, 0.0, 0.0), (-0.4, -0.1), (0.4, 0.1), (0.0, 0.0)),
                                      (el, (0.0, 0.0, 1.0), (0.0, 0.0), (0.4, 0.4), el_centre)):
        world = _pixels(img, _blend(rgb)) - np.array(tuple(body.position))
        c, s = math.cos(body.angle), math.sin(body.angle)
        local = np.column_stack([c * world[:, 0] + s * world[:, 1], -s * world[:, 0] + c * world[:, 1]])
        assert np.all(np.abs(local.min(axis=0) - lo) * PX_PER_M < 2.0), (local.min(axis=0), lo)
        assert np.all(np.abs(local.max(axis=0) - hi) * PX_PER_M < 2.0), (local.max(axis=0), hi)
        assert np.hypot(*(local.mean(axis=0) - centre)) * PX_PER_M < 1.0


def test_known_poses_are_drawn_where_they_are() -> None:
    """A disk at (1.0, 0.6), turned 0.7 rad, and a square at (2.2, 1.1), turned 0.3 rad: pixel centroids
    within 1 px of the centres; the disk's angle from its radius line, the square's from its edges
    (the rectangle of least area around its pixels), each within 2 degrees."""
    space = pymunk.Space()
    disk = _body(space, "disk", (1.0, 0.6), 0.7)
    square = _body(space, "square", (2.2, 1.1), 0.3)
    rec = Recorder(space, bodies=[disk, square])
    rec.capture(t=0.0)
    img = rec.image(size=SIZE, box=BOX, color=[(1.0, 0.0, 0.0), (0.0, 0.0, 1.0)])
    assert img.shape == (360, 640, 3)
    for body, rgb in ((disk, (1.0, 0.0, 0.0)), (square, (0.0, 0.0, 1.0))):
        pts = _pixels(img, _blend(rgb))
        centre = pts.mean(axis=0)
        assert np.hypot(*(centre - np.array(tuple(body.position)))) * PX_PER_M < 1.0, (centre, body.position)
    # the disk's radius line: dark pixels well inside the rim, from the centre along the body's x axis
    dark = _pixels(img, (34, 34, 34)) - np.array(tuple(disk.position))
    r = np.hypot(dark[:, 0], dark[:, 1])
    inner = dark[(r > 0.03) & (r < 0.16)]
    line = math.atan2(inner[:, 1].mean(), inner[:, 0].mean())
    assert abs(math.degrees(line - 0.7)) < 2.0
    # the square: the rotation (mod 90 degrees) at which its pixels' bounding rectangle is smallest
    pts = _pixels(img, _blend((0.0, 0.0, 1.0))) - np.array(tuple(square.position))
    grid = np.radians(np.arange(0.0, 90.0, 0.1))
    areas = [np.ptp(pts @ [math.cos(a), math.sin(a)]) * np.ptp(pts @ [-math.sin(a), math.cos(a)]) for a in grid]
    found = math.degrees(grid[int(np.argmin(areas))])
    assert abs((found - math.degrees(0.3) + 45.0) % 90.0 - 45.0) < 2.0


def _sliding(n: int = 3) -> tuple[pymunk.Space, PlaneFriction, list[pymunk.Body]]:
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    bodies = []
    for i in range(n):
        b = _body(space, "disk" if i % 2 else "square", (1.5 * i, 0.0), 0.1 * i)
        b.velocity, b.angular_velocity = (1.0, 0.3 * i), 4.0 - 3.0 * i
        pf.add(b, mu=0.3)
        bodies.append(b)
    return space, pf, bodies


def test_a_capture_holds_the_plugins_own_numbers() -> None:
    """Poses as pymunk has them, velocities as pf.velocity reads them at pf.t, friction as pf.friction
    reports it: the same numbers, exactly; ``every`` keeps one call in three; memory as documented."""
    space, pf, bodies = _sliding()
    rec = Recorder(space, pf, every=3)
    assert rec.bodies == tuple(bodies) and rec.bytes_per_frame == 3 * 9 * 8
    stored = []
    for _ in range(9):
        pf.step(1e-3)
        stored.append(rec.capture())
    assert stored == [True, False, False] * 3 and rec.n_frames == 3
    assert np.allclose(rec.times, [1e-3, 4e-3, 7e-3], rtol=1e-12, atol=0.0)
    rec.capture()  # the 10th call: stored, at pf.t
    last = rec.frames[-1]
    for k, b in enumerate(bodies):
        assert tuple(last[k, :3]) == (b.position.x, b.position.y, b.angle)
        assert tuple(last[k, 3:6]) == pf.velocity(b)
        assert tuple(last[k, 6:9]) == pf.friction(b)
    assert rec.times[-1] == pf.t


def test_the_friction_the_plugin_reports_is_what_it_applied() -> None:
    """pf.friction after a step: the velocity change it causes is dt F / m (no other force acts), and
    for a sliding disk it opposes the motion with mu m g."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    disk = _body(space, "disk", (0.0, 0.0), 0.0)
    disk.velocity = (1.0, 0.0)
    pf.add(disk, mu=0.3)
    pf.step(1e-3)
    v0 = disk.velocity.x
    pf.step(1e-3)
    fx, fy, tq = pf.friction(disk)
    assert math.isclose(disk.velocity.x - v0, 1e-3 * fx / disk.mass, rel_tol=1e-12)
    assert math.isclose(fx, -0.3 * 9.81 * disk.mass, rel_tol=1e-12) and fy == 0.0 and tq == 0.0


def test_spin_senses_follow_the_drive_and_the_path() -> None:
    """A driven body (rrbody's builder) turns against its orbit exactly while phi' < 0 (the drive turns
    counter-clockwise); a disk sliding straight has no orbit; a body at rest has no spin."""
    from rrbody.engine import EngineSettings, attach, plane_for
    from rrbody.model.scene import rod_mass_scene

    space = pymunk.Space()
    pf = plane_for(space)
    h = attach(space, rod_mass_scene(0.2, 0.05, 0.6), settings=EngineSettings(dt=1e-2))
    straight = _body(space, "disk", (5.0, 5.0), 0.0)
    straight.velocity, straight.angular_velocity = (0.5, 0.0), 3.0  # uniform disk: friction along -v
    pf.add(straight, mu=0.01)
    rest = _body(space, "square", (-5.0, 5.0), 0.0)
    pf.add(rest, mu=0.3)
    rec = Recorder(space, pf)
    assert rec.bodies == (h.body, straight, rest)
    phid = []
    for _ in range(4500):  # t_f = 42.14 s (docs: the phixtpm run): reverse rotation, then normal
        pf.step(1e-2)
        rec.capture()
        phid.append(h.phi_dot)
    sense = rec.senses()
    phid = np.array(phid)
    moving = np.abs(phid) > 1e-9
    assert (sense[moving, 0] == np.sign(phid[moving])).all() and (sense[:, 0] < 0).any() and (sense[:, 0] > 0).any()
    assert (sense[:, 1] == 0).all() and (sense[:, 2] == 0).all()
    assert np.isfinite(rec._anchor[0]).all() and np.isnan(rec._anchor[1:]).all()  # P drawn for the driven body only


def test_movie_poster_and_image_write_what_was_captured(tmp_path: Path) -> None:
    """The movie has one frame per 1/fps s of playback over the span at ``speed`` (read back), the
    poster one panel per instant, and nothing else is left in the folder."""
    import imageio.v3 as iio

    from rrbody.render.mp4 import frame_times

    space, pf, bodies = _sliding()
    space.add(pymunk.Segment(space.static_body, (-1.0, -1.0), (4.0, -1.0), 0.05))  # a wall
    rec = Recorder(space, pf)
    for _ in range(100):
        pf.step(1e-2)
        rec.capture()
    movie = rec.movie(tmp_path / "run.mp4", fps=20, speed=0.5, size=(320, 180), color="spin",
                      arrows=("velocity", "friction", "torque"), trails=bodies[:1], progress=False)
    frames = np.stack(list(iio.imiter(movie)))
    assert frames.shape[1:3] == (180, 320)
    assert len(frames) == len(frame_times(rec.times[0], rec.times[-1], fps=20, speed=0.5))
    poster = rec.poster(tmp_path / "run.png", times=[0.1, 0.5, 1.0], size=(600, 200), trails=True)
    assert iio.imread(poster).shape[:2] == (200, 600)
    first = poster.read_bytes()
    rec.poster(poster, times=[0.1, 0.5, 1.0], size=(600, 200), trails=True, force=True)
    assert poster.read_bytes() == first  # no date or version in the file: the same poster, the same bytes
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.mp4", "run.png"]
    with pytest.raises(ValueError, match="already exists"):
        rec.movie(tmp_path / "run.mp4", size=(320, 180))


def _read_rrd(path: Path) -> dict[str, list[float]]:
    """entity path -> the times (s) of its time-indexed rows (rerun's own reader)."""
    import pyarrow as pa
    from rerun.chunk import RrdReader

    out: dict[str, list[float]] = {}
    for ch in RrdReader(path).store().stream().to_chunks():
        ent = out.setdefault(ch.entity_path.lstrip("/"), [])
        if ch.is_static:
            continue
        rb = ch.to_record_batch()
        if "time" in rb.schema.names:
            ent.extend((rb.column("time").cast(pa.int64()).to_numpy() * 1e-9).tolist())
    return out


def test_rerun_has_one_entity_per_body_with_every_captured_time(tmp_path: Path) -> None:
    from rrbody.render.recorder_rerun import entities

    space, pf, bodies = _sliding()
    rec = Recorder(space, pf, labels=["box", "puck", "box2"])
    for _ in range(50):
        pf.step(1e-2)
        rec.capture()
    path = rec.rerun(tmp_path / "run.rrd", color="spin", trails=bodies[:1])
    ents = _read_rrd(path)
    for label in rec.labels:
        times = sorted(set(ents[f"world/bodies/{label}"]))
        assert len(times) == rec.n_frames and np.allclose(times, rec.times, atol=1e-9)
        assert len(ents[f"plots/speed/{label}"]) == rec.n_frames
    want = entities(rec, trails=np.array([True, False, False]), plots=[0, 1, 2])
    got = {e if not e.startswith("world/trails/") else e.rsplit("/", 1)[0] for e in ents if e.count("/") >= 1}
    assert want <= got
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrd"]


@pytest.mark.parametrize("case, message", [
    ("no bodies", "bodies: nothing to film"),
    ("missing folder", "folder"),
    ("fps", "fps"),
    ("size", "size"),
    ("suffix", r"\.mp4"),
    ("removed", "no longer in the space"),
    ("removed, bulk read", "no longer in the space"),
    ("cap", "max_mb"),
    ("reserve", "reserve must be an integer in \\[1, 3\\] frames"),
    ("reserve 0", "reserve must be"),
    ("reserve bool", "reserve must be"),
    ("no motion", "motion=True"),
    ("no frames", "0 frames captured"),
])
def test_bad_input_is_refused_naming_it_and_writes_nothing(tmp_path: Path, case: str, message: str,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    space, pf, bodies = _sliding()
    if case == "removed, bulk read":  # the route taken where the bodies' struct layout is unknown
        monkeypatch.setattr("rrbody.engine.recording.tape.layout", lambda: None)
    rec = Recorder(space, pf)
    if case != "no frames":
        for _ in range(3):
            pf.step(1e-2)
            rec.capture()
    out = tmp_path / "m.mp4"
    with pytest.raises(ValueError, match=message):
        if case == "no bodies":
            Recorder(pymunk.Space())
        elif case == "missing folder":
            rec.movie(tmp_path / "nowhere" / "m.mp4")
        elif case == "fps":
            rec.movie(out, fps=0)
        elif case == "size":
            rec.movie(out, size=(321, 180))
        elif case == "suffix":
            rec.movie(tmp_path / "m.avi")
        elif case.startswith("removed"):
            pf.remove(bodies[1])
            space.remove(bodies[1], *bodies[1].shapes)
            pf.step(1e-2)
            rec.capture()
        elif case == "cap":
            small = Recorder(space, pf, max_mb=3 * 3 * 9 * 8 / 1e6)  # room for 3 frames
            for _ in range(4):
                small.capture()
        elif case == "reserve":
            Recorder(space, pf, max_mb=3 * 3 * 9 * 8 / 1e6, reserve=4)  # room for 3 frames
        elif case == "reserve 0":
            Recorder(space, pf, reserve=0)
        elif case == "reserve bool":
            Recorder(space, pf, reserve=True)
        elif case == "no motion":
            still = Recorder(space, pf, motion=False)
            still.capture()
            still.movie(out, color="spin")
        elif case == "no frames":
            rec.movie(out)
    assert list(tmp_path.iterdir()) == []
    if case.startswith("removed") or case == "cap":
        assert rec.n_frames == 3 or case == "cap"  # the frames captured before stay


def test_the_plugin_guides_film_it_program_runs(tmp_path: Path) -> None:
    """docs/plugin.md's "Film it" program, as a reader copies it, in an empty folder."""
    text = (ROOT / "docs" / "plugin.md").read_text()
    section = text[text.index("## Film it"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    assert sorted(x.name for x in tmp_path.iterdir()) == ["pucks.mp4", "pucks.png", "pucks.rrd"]


def test_rerun_draws_p_and_its_link_for_a_driven_body(tmp_path: Path) -> None:
    from rrbody.engine import EngineSettings, attach, plane_for
    from rrbody.model.scene import rod_mass_scene
    from rrbody.render.recorder_rerun import entities

    space = pymunk.Space()
    pf = plane_for(space)
    attach(space, rod_mass_scene(0.2, 0.05, 0.6), settings=EngineSettings(dt=1e-2))
    rec = Recorder(space, pf)
    for _ in range(20):
        pf.step(1e-2)
        rec.capture()
    ents = _read_rrd(rec.rerun(tmp_path / "d.rrd"))
    assert {"world/bodies/b0000/P", "world/bodies/b0000/link"} <= set(ents)
    assert entities(rec, plots=[0]) <= set(ents)


@pytest.mark.private
def test_both_read_routes_capture_the_same_frames(monkeypatch: pytest.MonkeyPatch) -> None:
    """The capture reads the filmed bodies from their structs (rrbody.engine.recording.capture) where pymunk's
    layout of them is known, as on the pymunk this suite runs (asserted: else the fast route would go
    untested), and from the space's bulk read otherwise: both give the same numbers, bit for bit,
    through collisions, a kinematic body, a body outside the plugin, bodies added to and removed from
    the space (its bulk read's order changes) and ``reserve`` (more frames than reserved: the store
    grows)."""
    from rrbody.engine.recording.capture import layout

    assert layout() is not None
    space, pf, bodies = _sliding()
    free = _body(space, "box", (0.3, 0.05), 0.3)  # overlaps the first square: they collide; not in the plugin
    free.velocity = (-0.5, 0.2)
    kin = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    kin.position, kin.velocity, kin.angular_velocity = (0.2, 0.8), (0.1, 0.0), 1.5
    space.add(kin, pymunk.Circle(kin, 0.05))
    fast = Recorder(space, pf, reserve=40)
    assert fast.tape._store.buf.shape[0] == 40
    monkeypatch.setattr("rrbody.engine.recording.tape.layout", lambda: None)
    bulk = Recorder(space, pf)
    assert fast.tape._io is None and bulk.tape._io is not None
    extra = []
    for i in range(50):
        pf.step(1e-2)
        if i == 4:  # another body enters and the first extra leaves: the space's order changes
            extra.append(_body(space, "disk", (2.5, 0.3), 0.0))
        if i == 8:
            space.remove(extra[0], *extra[0].shapes)
        assert fast.capture() and bulk.capture()
    assert fast.n_frames == bulk.n_frames == 50 and fast.tape._store.reallocs == 2  # reserved 40, then doubled
    assert np.array_equal(fast.frames, bulk.frames) and np.array_equal(fast.times, bulk.times)
    assert np.abs(fast.frames[:, :, 3:6]).max() > 0.0  # they moved
