"""The sweep quantity ``chaos`` (maps of the maximal Lyapunov exponent and the reverse-rotation
fraction over two parameters): each point is the direct computation, a sweep resumes to the same
table, the RR fraction is the trajectory's own, and bad options are refused before any work."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rrbody.analysis.chaos import auto_method, lyapunov
from rrbody.analysis.chaos_map import CHAOS_COLUMNS, chaos_point
from rrbody.analysis.sweep import SweepInterrupted, load_sweep, run_sweep
from rrbody.analysis.sweep_spec import Sweep
from rrbody.model.scene import scene_from_params

OPTS = {"periods": 12, "transient": 3, "rr_samples": 16}
BASE = {"H": 0.5, "k": None, "friction": "none"}
AXES = {"tilt": (0.0, 0.5), "omega": (1.0, 2.0)}


def _sweep() -> Sweep:
    return Sweep(base=BASE, axes=AXES, quantity="chaos", options=OPTS)


def _num(v: str) -> float:
    return float(v) if v != "" else math.nan


def test_points_are_the_direct_computation(tmp_path: Path) -> None:
    table = load_sweep(run_sweep(_sweep(), tmp_path / "m.csv", workers=0, progress=False))
    assert len(table) == 4
    for row in table:
        sc = scene_from_params(H=0.5, k=None, friction="none", tilt=float(row["tilt"]), omega=float(row["omega"]))
        period = 2 * math.pi / sc.omega
        res = lyapunov(sc, t_max=12 * period, transient=3 * period, rr_samples=16, method=auto_method(sc))
        # the same deterministic computation: bit for bit (the CSV writes repr of each float)
        assert float(row["lambda_max"]) == res.exponents[0]
        assert float(row["lambda_2"]) == res.exponents[1]
        assert float(row["rr_fraction"]) == res.meta["rr_fraction"]
        assert row["method"] == "tangent" and row["error"] == ""
        assert float(row["t_measured"]) == 12 * period
        assert float(row["lambda_floor"]) == math.log(12 * period) / (12 * period)
        half = res.running[len(res.times) // 2:, 0]
        assert float(row["lambda_spread"]) == half.max() - half.min()
    # frictionless: the tangent exponents sum to the divergence 0 (Liouville), to the integrator's error
    for row in table:
        assert abs(float(row["lambda_max"]) + float(row["lambda_2"])) < 1e-8


def test_span_in_seconds() -> None:
    """``t_max``: the same span in seconds at every point, as ``rrbody lyapunov --t-max``."""
    sc = scene_from_params(H=0.5, k=None, omega=2.0, friction="none", tilt=0.5)
    r = chaos_point(sc, t_max=20.0, transient=1.5, rr_samples=8)
    ref = lyapunov(sc, t_max=20.0, transient=1.5 * math.pi, rr_samples=8)
    assert r["lambda_max"] == ref.exponents[0] and r["t_measured"] == 20.0
    assert r["lambda_floor"] == math.log(20.0) / 20.0
    assert chaos_point(sc, t_max=5.0)["lambda_spread"] is None  # 2 periods: no last half to compare


def test_dry_friction_takes_two_trajectories() -> None:
    sc = scene_from_params(H=0.5, k=0.1, omega=2.0, friction="dry", tilt=0.3)
    r = chaos_point(sc, periods=6, transient=1, rr_samples=8)
    assert r["method"] == "two" and r["lambda_2"] is None
    period = math.pi
    ref = lyapunov(sc, t_max=6 * period, transient=period, method="two", rr_samples=8)
    assert r["lambda_max"] == ref.exponents[0]


def test_resume_gives_the_uninterrupted_table(tmp_path: Path) -> None:
    whole = run_sweep(_sweep(), tmp_path / "a.csv", workers=0, progress=False)
    with pytest.raises(SweepInterrupted):
        run_sweep(_sweep(), tmp_path / "b.csv", workers=0, batch_size=1, progress=False, _stop_after=2)
    assert not (tmp_path / "b.csv").exists()
    resumed = run_sweep(_sweep(), tmp_path / "b.csv", workers=0, batch_size=1, progress=False, resume=True)
    assert resumed.read_text() == whole.read_text()


def test_rr_fraction_is_the_trajectorys_own() -> None:
    """The fraction of samples with phi' omega < 0 from an independent run (simulate, rtol 1e-13, the
    same sample times): the two agree to within the bound the quantity reports (a sample may only
    flip sign where phi' is within the integrators' difference of zero)."""
    from rrbody.analysis.simulate import simulate

    sc = scene_from_params(H=0.5, k=None, omega=2.0, friction="none", tilt=0.5)
    period = math.pi
    r = chaos_point(sc, periods=10, transient=0, rr_samples=16)
    tr = simulate(sc, t_max=10 * period, dt_out=period / 16)
    t, pd = np.asarray(tr.t), np.asarray(tr.phi_dot)
    keep = t < 10 * period - 1e-9
    frac = float(np.mean(pd[keep] * sc.omega < 0))
    assert 0.05 < r["rr_fraction"] < 0.95  # the chaotic orbit turns both ways
    assert abs(frac - r["rr_fraction"]) <= 1.0 / keep.sum() + 1e-15  # at most one sample of 160 differs
    # the bound the column states holds for a finer sampling of the same span
    fine = chaos_point(sc, periods=10, transient=0, rr_samples=256)
    assert abs(fine["rr_fraction"] - r["rr_fraction"]) <= r["rr_bound"]


def test_transient_keeps_the_divergence() -> None:
    """Viscous friction: the exponents sum to -k exactly (Liouville) whatever the transient."""
    sc = scene_from_params(H=0.2, k=0.05, omega=0.6, friction="viscous", tilt=0.2)
    period = 2 * math.pi / 0.6
    res = lyapunov(sc, t_max=20 * period, transient=5 * period)
    assert abs(res.exponents.sum() + 0.05) < 1e-9  # the integrator's error (tests/test_chaos.py: 1e-9)
    assert res.times[0] == pytest.approx(6 * period) and res.meta["transient"] == 5 * period


@pytest.mark.parametrize(("options", "word"), [
    ({"periods": 1}, "periods"), ({"periods": 2.5}, "periods"), ({"transient": -1}, "transient"),
    ({"t_max": 0.0}, "t_max"), ({"t_max": 100.0, "periods": 50}, "t_max and periods"),
    ({"rr_samples": 0}, "rr_samples"), ({"estimate": "qr"}, "estimate"), ({"rtol": 0.0}, "rtol"),
    ({"d0": 1.0}, "d0"), ({"tol": 1e-6}, "tol"), ({"accuracy": "draft"}, "accuracy"),
])
def test_bad_options_rejected(options: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        Sweep(base=BASE, axes=AXES, quantity="chaos", options=options)


def test_tangent_under_dry_friction_refused_before_work() -> None:
    with pytest.raises(ValueError, match="estimate 'tangent'"):
        Sweep(base={"H": 0.5, "k": 0.1, "friction": "dry"}, axes=AXES, quantity="chaos",
              options={"estimate": "tangent"})


def test_map_figure_is_reproducible(tmp_path: Path) -> None:
    from rrbody.render.chaos_map import chaos_map_arrays, plot_chaos_map

    table = run_sweep(_sweep(), tmp_path / "m.nc", workers=0, progress=False)
    a = chaos_map_arrays(table)
    b = chaos_map_arrays(run_sweep(_sweep(), tmp_path / "m.csv", workers=0, progress=False))
    assert np.array_equal(a["lambda_max"], b["lambda_max"]) and a["lambda_max"].shape == (2, 2)
    p1 = plot_chaos_map(table, tmp_path / "one.png")
    p2 = plot_chaos_map(table, tmp_path / "two.png")
    assert p1.read_bytes() == p2.read_bytes()
    flip = run_sweep(Sweep(base={"H": 0.2, "k": 0.05}, axes={"omega": (0.6,)}, quantity="rr"), tmp_path / "r.csv",
                     workers=0, progress=False)
    with pytest.raises(ValueError, match="chaos sweep"):
        plot_chaos_map(flip, tmp_path / "three.png")
    assert set(CHAOS_COLUMNS) <= set(load_sweep(tmp_path / "m.csv")[0])


def test_long_renormalisation_interval() -> None:
    """A renorm of many driving periods: the tangent vectors are re-orthonormalised once a period
    inside it (without that the loop's absolute error scale for them collapsed the step size on a
    chaotic orbit: a hang). The logarithms add up, so a regular orbit's exponents do not change."""
    sc = scene_from_params(H=0.2, k=0.05, omega=0.6, friction="viscous")
    period = 2 * math.pi / 0.6
    a = lyapunov(sc, t_max=50 * period)
    b = lyapunov(sc, t_max=50 * period, renorm=10 * period)
    assert len(b.times) == 5
    assert np.max(np.abs(a.exponents - b.exponents)) < 1e-12  # measured 5e-16: rounding of the sums
    chaotic = scene_from_params(H=0.5, k=None, omega=2.0, friction="none", tilt=0.5)
    c = lyapunov(chaotic, t_max=40 * math.pi, renorm=20 * math.pi)  # e^(0.4 x 63) growth per interval
    assert c.exponents[0] > 0.1 and abs(c.exponents.sum()) < 1e-8  # frictionless: the sum is 0 (Liouville)
