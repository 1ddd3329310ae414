"""Renderers: MP4 movies (frame count, size, codec, duration, atomic writes) and rerun recordings
(read back: entities, time range, values)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rrbody.analysis.simulate import simulate
from rrbody.model.bodies import Ellipse
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene, rod_mass_scene
from rrbody.model.trajectory import Trajectory

imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")


@pytest.fixture(scope="module")
def s1_short() -> Trajectory:
    """The Movie S1 scene (k = 0.003 s^-2, H = 0.6, omega = 0.6 rad/s, phi0 = pi) for 4 s."""
    return simulate(rod_mass_scene(0.6, 0.003, 0.6, math.pi), t_max=4.0, dt_out=0.05)


def _probe(path: Path) -> dict:
    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    gen.close()
    return meta


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# ---- MP4 ---------------------------------------------------------------------------------------
def test_frame_times_mapping() -> None:
    from rrbody.render.mp4 import frame_times

    # 4 simulated s at 2x speed and 10 fps: frames every 0.2 simulated s, 0 .. 4 inclusive -> 21
    t = frame_times(0.0, 4.0, fps=10, speed=2.0)
    assert len(t) == 21
    assert t[0] == 0.0 and t[-1] == pytest.approx(4.0, abs=1e-12)  # exact up to float rounding
    assert np.allclose(np.diff(t), 0.2, atol=1e-12)
    with pytest.raises(ValueError, match="speed"):
        frame_times(0.0, 4.0, fps=10, speed=0.0)


def test_short_movie_metadata(tmp_path: Path, s1_short: Trajectory) -> None:
    from rrbody.render.mp4 import render_movie

    out = render_movie(s1_short, tmp_path / "m.mp4", fps=10, size=(320, 180), speed=2.0)
    assert out == tmp_path / "m.mp4" and out.stat().st_size > 0
    meta = _probe(out)
    assert meta["codec"] == "h264"
    assert meta["size"] == (320, 180) and meta["source_size"] == (320, 180)
    assert meta["pix_fmt"].startswith("yuv420p")
    assert meta["fps"] == 10
    n, secs = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert n == 21  # frame_times(0, 4, fps=10, speed=2): 0, 0.2, ..., 4.0
    assert secs == pytest.approx(21 / 10, abs=1e-6)  # each frame shows for 1/fps s; ffmpeg reports 2 decimals
    assert _leftovers(tmp_path) == ["m.mp4"]  # no temporary file left


def test_existing_file_not_clobbered(tmp_path: Path, s1_short: Trajectory) -> None:
    from rrbody.render.mp4 import render_movie

    p = tmp_path / "m.mp4"
    p.write_bytes(b"old")
    with pytest.raises(ValueError, match="already exists"):
        render_movie(s1_short, p, fps=5, size=(128, 72), speed=4.0)
    assert p.read_bytes() == b"old"
    render_movie(s1_short, p, fps=5, size=(128, 72), speed=4.0, force=True)
    assert _probe(p)["codec"] == "h264"


@pytest.mark.parametrize("exc", [RuntimeError, KeyboardInterrupt])
def test_failed_render_leaves_nothing(tmp_path: Path, s1_short: Trajectory, monkeypatch: pytest.MonkeyPatch,
                                      exc: type[BaseException]) -> None:
    from rrbody.render import mp4

    real = mp4.MovieFigure.frame
    calls = {"n": 0}

    def failing(self: mp4.MovieFigure, tau: float, *, banner: bool = False) -> memoryview:
        calls["n"] += 1
        if calls["n"] == 4:  # a few frames already went to ffmpeg
            raise exc("boom")
        return real(self, tau, banner=banner)

    monkeypatch.setattr(mp4.MovieFigure, "frame", failing)
    keep = tmp_path / "keep.mp4"
    keep.write_bytes(b"previous movie")
    with pytest.raises(exc):
        mp4.render_movie(s1_short, tmp_path / "new.mp4", fps=10, size=(128, 72), speed=2.0)
    calls["n"] = 0
    with pytest.raises(exc):
        mp4.render_movie(s1_short, keep, fps=10, size=(128, 72), speed=2.0, force=True)
    assert _leftovers(tmp_path) == ["keep.mp4"]
    assert keep.read_bytes() == b"previous movie"


def test_bad_options(tmp_path: Path, s1_short: Trajectory) -> None:
    from rrbody.render.mp4 import render_movie

    with pytest.raises(ValueError, match="even"):
        render_movie(s1_short, tmp_path / "m.mp4", size=(321, 180))
    with pytest.raises(ValueError, match=r"\.mp4"):
        render_movie(s1_short, tmp_path / "m.avi")
    with pytest.raises(ValueError, match="fps"):
        render_movie(s1_short, tmp_path / "m.mp4", fps=-1)
    # the API applies the limits table's ranges, as the CLI does: fps in [1, 240], speed > 0
    with pytest.raises(ValueError, match=r"fps must be in \[1, 240\] frames/s, got 0\.5"):
        render_movie(s1_short, tmp_path / "m.mp4", fps=0.5)
    with pytest.raises(ValueError, match="speed"):
        render_movie(s1_short, tmp_path / "m.mp4", speed=0.0)
    assert _leftovers(tmp_path) == []


def test_red_blue_split_follows_t_f(s1_short: Trajectory) -> None:
    from rrbody.render.flip import FlipMark
    from rrbody.render.mp4 import MovieFigure

    fig = MovieFigure(s1_short, size=(320, 180), flip=FlipMark("flip", 2.0))
    fig.update(1.3)
    red_x, _ = fig.A["phi_red"].get_data()
    blue_x, _ = fig.A["phi_blue"].get_data()
    assert len(blue_x) == 0 and red_x[-1] == pytest.approx(1.3)  # drawn up to the current time only
    assert not fig.A["tf_line"].get_visible()
    fig.update(3.1)
    red_x, _ = fig.A["phi_red"].get_data()
    blue_x, blue_y = fig.A["phi_blue"].get_data()
    assert red_x[-1] == pytest.approx(2.0) and blue_x[0] == pytest.approx(2.0)  # both meet at t_f
    assert blue_x[-1] == pytest.approx(3.1)
    # the phi curve ends on phi(3.1), interpolated between samples 0.05 s apart (linear: error ~ phi'' dt^2/8)
    assert blue_y[-1] == pytest.approx(np.interp(3.1, s1_short.t, s1_short.phi), abs=1e-12)
    seg = fig.A["trail"].get_segments()
    assert seg[-1][-1][0] == pytest.approx(np.interp(3.1, s1_short.t, s1_short.x_cm), abs=1e-12)
    assert fig.A["tf_line"].get_visible()


def _synthetic_ellipse(driven: bool = True) -> Trajectory:
    """A made-up ellipse run (R_A = 0.3 m, R_B = 0.1 m): CM (0.2 t, -0.1 t), angle 0.3 + 0.5 t, P on the unit circle."""
    body = Ellipse(R0=0.2, delta=0.5, l=0.1)
    drive = CircularDrive(omega=1.0, d=1.0) if driven else None
    scene = Scene(body=body, drive=drive, friction=Friction("none"), phi0=math.pi)
    t = np.linspace(0.0, 1.0, 11)
    ang = 0.3 + 0.5 * t
    z = np.zeros_like(t)
    return Trajectory(t=t, phi=ang, phi_dot=z + 0.5, x_cm=0.2 * t, y_cm=-0.1 * t, vx_cm=z, vy_cm=z,
                      x_p=np.cos(t), y_p=np.sin(t), body_angle=ang, spin=z + 0.5,
                      meta={"scene": scene.describe()}, events={})


def test_ellipse_drawn_to_scale() -> None:
    """The outline has semi-axes R_A, R_B about the CM at the body angle; the rod joins CM and P."""
    from rrbody.render.flip import FlipMark
    from rrbody.render.mp4 import MovieFigure

    fig = MovieFigure(_synthetic_ellipse(), size=(320, 180), flip=FlipMark("none"))
    fig.update(0.6)  # a sample time: no interpolation error
    x, y = fig.A["outline"].get_data()
    cx, cy, a = 0.2 * 0.6, -0.1 * 0.6, 0.3 + 0.5 * 0.6
    # body-frame coordinates of the outline points
    u = np.cos(a) * (x - cx) + np.sin(a) * (y - cy)
    v = -np.sin(a) * (x - cx) + np.cos(a) * (y - cy)
    assert np.allclose((u / 0.3) ** 2 + (v / 0.1) ** 2, 1.0, atol=1e-12)  # exact ellipse, float rounding only
    # the 96-gon has vertices at body angles 0 and pi/2: the extremes are the semi-axes themselves
    assert u.max() == pytest.approx(0.3, abs=1e-12) and v.max() == pytest.approx(0.1, abs=1e-12)
    rx, ry = fig.A["rod"].get_data()
    assert (rx[0], ry[0]) == pytest.approx((cx, cy)) and (rx[1], ry[1]) == pytest.approx((math.cos(0.6),
                                                                                          math.sin(0.6)))


def test_poster(tmp_path: Path, s1_short: Trajectory) -> None:
    import imageio.v3 as iio

    from rrbody.render.mp4 import render_poster

    p = render_poster(s1_short, tmp_path / "poster.png", size=(320, 180))
    img = iio.imread(p)
    assert img.shape[:2] == (180, 320)
    with pytest.raises(ValueError, match="already exists"):
        render_poster(s1_short, p, size=(320, 180))


# ---- rerun -------------------------------------------------------------------------------------
def _read_rrd(path: Path) -> dict[str, dict]:
    """entity path -> {"times": seconds (float array), "values": list} of its time-indexed rows."""
    import pyarrow as pa
    from rerun.chunk import RrdReader

    out: dict[str, dict] = {}
    for ch in RrdReader(path).store().stream().to_chunks():
        ent = out.setdefault(ch.entity_path.lstrip("/"), {"times": [], "values": [], "static": False})
        if ch.is_static:
            ent["static"] = True
            continue
        rb = ch.to_record_batch()
        if "time" not in rb.schema.names:
            continue
        ns = rb.column("time").cast(pa.int64()).to_numpy()
        ent["times"].extend((ns * 1e-9).tolist())
        data = [n for n in rb.schema.names if n not in ("rerun.controls.RowId", "time", "log_time")]
        if "Scalars:scalars" in data:
            ent["values"].extend(v[0] for v in rb.column("Scalars:scalars").to_pylist())
        if "TextLog:text" in data:
            ent["values"].extend(v[0] for v in rb.column("TextLog:text").to_pylist())
    return out


def test_rerun_round_trip(tmp_path: Path, s1_short: Trajectory) -> None:
    from rrbody.render.rerun import expected_entities, record

    out = record(s1_short, tmp_path / "run.rrd", flip=2.5)
    assert out == tmp_path / "run.rrd"
    assert _leftovers(tmp_path) == ["run.rrd"]
    ents = _read_rrd(out)
    assert expected_entities(s1_short, 2.5) <= set(ents)
    assert "world/body/outline" not in ents  # a rod-mass body has no outline
    trail = [e for e in ents if e.startswith("world/cm_trail/")]
    assert len(trail) >= 2  # split at t_f into a red and a blue part
    t = s1_short.t
    # phi is split at t_f into a red and a blue series that share the sample where they meet
    red, blue = ents["plots/phi/reverse"], ents["plots/phi/normal"]
    assert max(red["times"]) >= 2.5 - 0.05 and min(blue["times"]) <= 2.5  # no gap at the flip
    assert max(red["times"]) <= 2.5 + 0.05 + 1e-9 and min(blue["times"]) >= 2.5 - 0.05 - 1e-9
    times = np.concatenate([red["times"], blue["times"]])
    vals = np.concatenate([red["values"], blue["values"]])
    _, first = np.unique(np.round(times, 6), return_index=True)
    # the time line is a duration in ns: seconds round-trip to 1 ns
    assert np.allclose(times[first], t, atol=1e-9)
    assert np.array_equal(vals[first], s1_short.phi)  # float64 stored exactly
    th = ents["plots/theta/normal"]
    k = np.searchsorted(t, th["times"][0] - 1e-9)
    assert np.array_equal(np.asarray(th["values"])[np.argsort(th["times"])], s1_short.theta[k:])
    flip = ents["plots/phi/flip"]
    assert flip["times"] == [pytest.approx(2.5, abs=1e-9)]
    all_times = [x for e in ents.values() for x in e["times"]]
    assert min(all_times) == pytest.approx(t[0], abs=1e-9) and max(all_times) == pytest.approx(t[-1], abs=1e-9)


def test_rerun_no_clobber_and_spawn_without_screen(tmp_path: Path, s1_short: Trajectory,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    from rrbody.render.rerun import record

    p = tmp_path / "run.rrd"
    p.write_bytes(b"old")
    with pytest.raises(ValueError, match="already exists"):
        record(s1_short, p)
    assert p.read_bytes() == b"old"
    with pytest.raises(ValueError, match=r"\.rrd"):
        record(s1_short, tmp_path / "run.txt")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(ValueError, match="screen"):
        record(s1_short, None, spawn=True)
    assert _leftovers(tmp_path) == ["run.rrd"]


def test_cli_movie_and_recording(tmp_path: Path, cli) -> None:  # type: ignore[no-untyped-def]
    movie, rrd = tmp_path / "c.mp4", tmp_path / "c.rrd"
    r = cli("simulate", "--H", "0.6", "--k", "0.003", "--omega", "0.6", "--t-max", "1", "--dt-out", "0.05",
            "--movie", str(movie), "--rerun", str(rrd))
    assert r.code == 0, r.err
    assert _probe(movie)["codec"] == "h264"
    n, _ = imageio_ffmpeg.count_frames_and_secs(str(movie))
    assert n == 31  # 1 s at the default 30 fps, real time: frames at 0, 1/30, ..., 1
    assert "plots/phi/reverse" in _read_rrd(rrd)  # t_f = 42.14 s comes later: reverse rotation throughout
    r = cli("simulate", "--H", "0.6", "--k", "0.003", "--omega", "0.6", "--t-max", "1", "--movie", str(movie))
    assert r.code == 2 and "already exists" in r.err


@pytest.mark.parametrize("driven", [True, False])
def test_extended_and_free_bodies_render(tmp_path: Path, driven: bool) -> None:
    from rrbody.render.mp4 import render_movie
    from rrbody.render.rerun import expected_entities, record

    traj = _synthetic_ellipse(driven)
    m = render_movie(traj, tmp_path / "e.mp4", fps=10, size=(128, 72))
    assert imageio_ffmpeg.count_frames_and_secs(str(m))[0] == 11  # 1 s at 10 fps, real time: 0, 0.1, ..., 1
    ents = _read_rrd(record(traj, tmp_path / "e.rrd"))
    assert "world/body/outline" in expected_entities(traj)
    assert expected_entities(traj) <= set(ents)
    assert ("world/drive_circle" in ents) == driven
    assert len(ents["world/body/outline"]["times"]) == len(traj)


# ---- truthful flips: the whole run's flip time, not the lowest phi of the span -------------------------
# H 0.2, k 0.033 s^-2, omega 0.6 rad/s, phi0 = pi: flip_time gives t_f = 23.40 s. A 20 s span ends during
# reverse rotation (its lowest phi, at 18.58 s, is not the flip); a 60 s span contains the settled flip.
PHIXTPM = dict(H=0.2, k=0.033, omega=0.6)


@pytest.fixture(scope="module")
def phixtpm_flip() -> float:
    from rrbody.analysis.flip import flip_time

    t_f = flip_time(rod_mass_scene(**PHIXTPM)).t_f
    assert t_f == pytest.approx(23.40, abs=0.005)  # the number, to the 2 decimals pictures show
    return t_f


@pytest.mark.parametrize("t_max", [20.0, 60.0])
def test_movie_flip_is_the_whole_runs(tmp_path: Path, t_max: float, phixtpm_flip: float) -> None:
    from rrbody.render.flip import flip_mark
    from rrbody.render.mp4 import MovieFigure, render_movie

    traj = simulate(rod_mass_scene(**PHIXTPM), t_max=t_max, dt_out=0.1)
    assert traj.events["t_phi_min"] < 20.0 if t_max == 20.0 else True  # the span's own minimum would lie
    mark = flip_mark(traj)  # default: computed, as render_movie does
    assert mark.t_f == pytest.approx(phixtpm_flip, abs=1e-9)  # from the run or flip_time: same minimum
    fig = MovieFigure(traj, flip=mark, size=(320, 180))
    caption = " ".join(t.get_text() for t in fig.fig.texts)
    fig.update(t_max, banner=False)
    if t_max == 20.0:
        assert "no flip within this span" in caption and "23.40" in caption
        assert not fig.A["tf_line"].get_visible() and len(fig.A["phi_blue"].get_data()[0]) == 0  # red throughout
    else:
        assert "flip at $t_f$ = 23.40 s" in caption
        assert fig.A["tf_line"].get_visible() and fig.A["tf_line"].get_xdata()[0] == pytest.approx(phixtpm_flip)
        assert fig.A["phi_red"].get_data()[0][-1] == pytest.approx(phixtpm_flip)
    # the movie holds the flip frame for 1.5 s of playback (15 frames at 10 fps) only when the flip is shown
    m = render_movie(traj, tmp_path / "m.mp4", fps=10, size=(160, 90), speed=10.0)
    n, _ = imageio_ffmpeg.count_frames_and_secs(str(m))
    assert n == int(t_max) + 1 + (15 if t_max == 60.0 else 0)


@pytest.mark.parametrize("t_max", [20.0, 60.0])
def test_recording_flip_is_the_whole_runs(tmp_path: Path, t_max: float, phixtpm_flip: float) -> None:
    from rrbody.render.rerun import record

    traj = simulate(rod_mass_scene(**PHIXTPM), t_max=t_max, dt_out=0.1)
    ents = _read_rrd(record(traj, tmp_path / "r.rrd"))
    log = " | ".join(ents["events"]["values"])
    if t_max == 20.0:
        assert "plots/phi/flip" not in ents and "plots/phi/normal" not in ents
        assert "no flip within this span: t_f = 23.40 s comes later" in log and "FLIP" not in log
    else:
        assert ents["plots/phi/flip"]["times"] == [pytest.approx(phixtpm_flip, abs=1e-9)]  # ns time line
        assert "FLIP: t_f = 23.4024" in log
        assert max(ents["plots/phi/reverse"]["times"]) < min(ents["plots/phi/normal"]["times"]) + 0.1 + 1e-9


def test_recording_energy_and_power_from_the_friction_kernel(tmp_path: Path) -> None:
    """Dry friction on a point mass: |F| = mu g = k d while it moves, so the friction power is -k d |v|."""
    from rrbody.render.rerun import record

    traj = simulate(rod_mass_scene(**PHIXTPM), t_max=5.0, dt_out=0.1)
    ents = _read_rrd(record(traj, tmp_path / "r.rrd"))
    power = np.asarray(ents["plots/power/friction"]["values"])[np.argsort(ents["plots/power/friction"]["times"])]
    speed = np.hypot(traj.vx_cm, traj.vy_cm)
    assert np.allclose(power[1:], -0.033 * speed[1:], rtol=1e-12)  # exact law; t = 0 is the CM at rest
    kin = np.asarray(ents["plots/energy/kinetic"]["values"])[np.argsort(ents["plots/energy/kinetic"]["times"])]
    assert np.allclose(kin, 0.5 * speed**2, rtol=1e-12)  # point mass: no spin energy


@pytest.mark.parametrize("t_max,in_span", [("20", False), ("60", True)])
def test_cli_pictures_use_the_whole_runs_flip(tmp_path: Path, cli, t_max: str, in_span: bool,  # type: ignore[no-untyped-def]
                                              phixtpm_flip: float) -> None:
    import json

    r = cli("simulate", "--H", "0.2", "--k", "0.033", "--omega", "0.6", "--t-max", t_max, "--dt-out", "0.2",
            "--rerun", str(tmp_path / "c.rrd"), "--json")
    assert r.code == 0, r.err
    flip = json.loads(r.out)["flip"]
    assert flip["in_span"] is in_span and flip["t_f"] == pytest.approx(phixtpm_flip, abs=1e-9)
    log = " | ".join(_read_rrd(tmp_path / "c.rrd")["events"]["values"])
    assert ("FLIP" in log) is in_span


def test_movie_bytes_reproducible(tmp_path: Path, s1_short: Trajectory) -> None:
    """Same run, same options: the same MP4 bytes (no creation time, no random ids)."""
    from rrbody.render.mp4 import render_movie

    a = render_movie(s1_short, tmp_path / "a.mp4", fps=5, size=(160, 90), speed=4.0, arrows=True)
    b = render_movie(s1_short, tmp_path / "b.mp4", fps=5, size=(160, 90), speed=4.0, arrows=True)
    assert a.read_bytes() == b.read_bytes()


@pytest.mark.parametrize("fmt", ["svg", "png"])
def test_figure_bytes_reproducible(tmp_path: Path, fmt: str) -> None:
    """A figure saved twice (fresh figures, so fresh matplotlib ids) gives identical bytes, with no date."""
    from matplotlib.figure import Figure

    from rrbody.render.figures import savefig_reproducible

    def draw(path: Path) -> bytes:
        fig = Figure(figsize=(2, 1.5))
        ax = fig.add_subplot()
        ax.plot([0, 1, 2], [0, 1, 0], label="x")
        ax.fill_between([0, 1], [0, 1], alpha=0.3)  # clip paths get ids
        ax.set_title(r"$\phi(t)$")  # mathtext glyphs get ids
        savefig_reproducible(fig, path, fmt=fmt)
        return path.read_bytes()

    a, b = draw(tmp_path / f"a.{fmt}"), draw(tmp_path / f"b.{fmt}")
    assert a == b
    if fmt == "svg":
        assert b"<dc:date>" not in a
    else:
        assert b"Software" not in a and b"matplotlib" not in a.lower()
