"""The chaos movie (movies/chaos.mp4, scenes/movie_chaos.py): reverse rotation is marked on exactly
the frames and samples where the run's own spin is against the orbit (phi' omega < 0)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rrbody.model.scene import scene_from_params
from rrbody.render.chaos_movie import ChaosMovieFigure, render_chaos_movie, rr_mask, rr_stretches

OMEGA = 2.0


@pytest.fixture(scope="module")
def chaotic():  # type: ignore[no-untyped-def]
    from rrbody.analysis.simulate import simulate

    # the chaotic orbit of the chaos scene, its first 12 s (four RR stretches)
    return simulate(scene_from_params(H=0.5, k=None, omega=OMEGA, friction="none", tilt=0.5), t_max=12.0, dt_out=0.02)


def test_stretches_are_the_runs_own(chaotic) -> None:  # type: ignore[no-untyped-def]
    t, pd = np.asarray(chaotic.t), np.asarray(chaotic.phi_dot)
    st = rr_stretches(t, pd, OMEGA)
    assert len(st) >= 3
    inside = np.zeros(len(t), bool)
    for a, b in st:
        inside |= (t >= a) & (t <= b)
    # every sample inside a stretch spins against the orbit and every sample outside with it
    assert np.array_equal(inside, pd * OMEGA < 0.0)
    assert np.array_equal(rr_mask(t, pd, OMEGA), pd * OMEGA < 0.0)
    # the ends inside the run are the zeros of the samples' linear interpolant (rounding: 1e-12)
    for a, b in st:
        for end in (a, b):
            if 0.0 < end < t[-1]:
                assert abs(np.interp(end, t, pd)) < 1e-12
    # a reversed drive reverses the meaning of the same spin
    assert np.array_equal(rr_mask(t, pd, -OMEGA), pd * OMEGA > 0.0)


def test_frames_marked_exactly_where_the_spin_is_against_the_orbit(chaotic) -> None:  # type: ignore[no-untyped-def]
    from rrbody.render.mp4 import frame_times

    t, pd = np.asarray(chaotic.t), np.asarray(chaotic.phi_dot)
    fig = ChaosMovieFigure(chaotic, size=(320, 180))
    taus = frame_times(0.0, 12.0, fps=10, speed=1.0)
    marks = []
    for tau in taus:
        fig.frame(float(tau))
        shown = fig.A["rr_text"].get_visible()
        assert shown == (np.interp(tau, t, pd) * OMEGA < 0.0), tau
        marks.append(shown)
        # the phi curve: every sample so far in RR is on the red line, every other on the blue one
        tt, red = fig.A["phi_red"].get_data()
        _, blue = fig.A["phi_blue"].get_data()
        rr = np.interp(tt, t, pd) * OMEGA < 0.0
        assert np.all(np.isfinite(np.asarray(red)[rr])) and np.all(np.isfinite(np.asarray(blue)[~rr]))
        # and no sample is red unless it or a neighbour is in RR (the join of two stretches)
        near = rr | np.r_[False, rr[:-1]] | np.r_[rr[1:], False]
        assert not np.any(np.isfinite(np.asarray(red)[~near]))
    assert any(marks) and not all(marks)  # the span holds both regimes


def test_short_movie(tmp_path: Path, chaotic) -> None:  # type: ignore[no-untyped-def]
    import imageio_ffmpeg

    from rrbody.render.mp4 import frame_times

    out = render_chaos_movie(chaotic, tmp_path / "c.mp4", fps=10, size=(160, 90), speed=4.0)
    n, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert n == len(frame_times(0.0, 12.0, fps=10, speed=4.0))
    with pytest.raises(ValueError, match="already exists"):
        render_chaos_movie(chaotic, out, fps=10, size=(160, 90), speed=4.0)
    with pytest.raises(ValueError, match="mp4"):
        render_chaos_movie(chaotic, tmp_path / "c.avi")
    with pytest.raises(ValueError, match="size"):
        render_chaos_movie(chaotic, tmp_path / "d.mp4", size=(161, 90))


def test_free_body_refused(tmp_path: Path) -> None:
    from rrbody.analysis.simulate import simulate

    free = simulate(scene_from_params(body="disk", R0=0.1, k=2.0, no_drive=True, v0=(1.0, 0.0)), t_max=0.5,
                    dt_out=0.1)
    with pytest.raises(ValueError, match="driven"):
        render_chaos_movie(free, tmp_path / "f.mp4")
    assert not (tmp_path / "f.mp4").exists()
