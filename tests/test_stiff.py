"""The stiff regime: large k at omega = 0.6, the impulsive start from phi0 = pi, the
automatic switch between DOP853 and the Rosenbrock method RODAS4, and bounded, explained runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody import flip_time, rod_mass_scene
from rrbody.integrate.ode import integrate_driven
from rrbody.model.bodies import Disk
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene
from rrbody.physics.bind import kernel_params
from rrbody.physics.dynamics import SYSTEM_DRIVEN, driven_rhs, jacobian, system_from_params

from .reference import quasi_static_tf_times_omega, scipy_stiff_flip_time

W = 0.6
KS = (1e2, 1e3, 1e4, 1e5, 1e6)


@pytest.mark.parametrize("H", [0.05, 0.1, 0.2])
@pytest.mark.parametrize("k", KS)
def test_stiff_flip_time_matches_implicit_reference(H: float, k: float) -> None:
    # the stiff-regime acceptance bound: the default flip-time (no flag) gives t_f to 1e-6 relative. The reference
    # is scipy's Radau IIA (implicit, order 5) at rtol 1e-12 with the analytic Jacobian written
    # independently in tests/reference.py, with a zero-speed dead band 1e4 times narrower than
    # rrbody's (so the band's effect is checked too). Measured agreement: <= 6e-13 on this grid.
    ours = flip_time(rod_mass_scene(H, k, W))
    assert ours.settled and ours.t_f is not None, ours.regime
    ref_tf, ref_phi = scipy_stiff_flip_time(H, k, W, ours.t_stop, method="Radau", rtol=1e-12, dead_band=1e-13)
    assert ours.t_f == pytest.approx(ref_tf, rel=1e-6)
    assert ours.phi_min == pytest.approx(ref_phi, rel=1e-6)


@pytest.mark.parametrize("H", [0.05, 0.1, 0.2])
def test_stiff_trend_to_exact_quasi_static_limit(H: float) -> None:
    # omega t_f -> C(H) (exact dragged-mass limit, tests/reference.py) with an inertial correction
    # c(H) omega^2 / k: the relative deviation times k must converge as k grows. Measured:
    # k dev = -0.60073 (k = 1e5) and -0.60073 (1e6) at H = 0.2; a 1 % bound on the change over the
    # last decade still fails for any error of t_f above ~1e-8 relative at k = 1e6.
    C = quasi_static_tf_times_omega(H) / W
    scaled = [k * (flip_time(rod_mass_scene(H, k, W)).t_f - C) / C for k in (1e4, 1e5, 1e6)]
    assert all(s < 0 for s in scaled)  # friction finite: the body lags the quasi-static limit
    assert abs(scaled[2] - scaled[1]) < 0.01 * abs(scaled[2])
    assert abs(scaled[2] - scaled[1]) < abs(scaled[1] - scaled[0])


def test_method_switches_only_where_stiff() -> None:
    # phixtpm (k / omega^2 = 0.14) is not stiff, not even at its impulsive start (CM at rest): there
    # h |lambda| at steps h ~ t is the same at every t, 0.02 here (ode._start_for), far inside
    # DOP853's stability limit STIFF_HLAMB, so DOP853 runs throughout; so it does from phi0 = pi/2.
    # At k = 100 (h |lambda| ~ 46 at the start) the run starts with the stiff method. The slow case
    # (k / omega^2 = 7.5e4) is stiff: the stiff method takes over, in a fraction of the 290k explicit
    # steps the old loop needed.
    for phi0 in (math.pi, math.pi / 2):
        sc = rod_mass_scene(0.2, 0.05, 0.6, phi0)
        p, S = kernel_params(sc)
        easy = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=math.inf, rtol=1e-13, stop="flip")
        assert easy.stats["n_stiff_steps"] == 0 and easy.stats["n_switches"] == 0
    sc = rod_mass_scene(0.2, 100.0, 0.6)
    p, S = kernel_params(sc)
    start = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=1e-3, rtol=1e-10)
    assert start.stats["n_stiff_steps"] == start.n_steps > 0
    sc = rod_mass_scene(0.25, 7.5, 0.01)
    p, S = kernel_params(sc)
    hard = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=math.inf, rtol=1e-13, stop="flip")
    assert hard.stats["n_stiff_steps"] > 0 and hard.n_steps < 100_000


@pytest.mark.parametrize("stepper", ["dop853", "rodas", "radau"])
def test_forced_methods_agree_with_auto(stepper: str) -> None:
    # Each method alone converges to the same flip (orders 8, 4 and 5): rtol 1e-13 runs agree to
    # 1e-9 (measured ~1e-12 between them).
    for H, k, w in [(0.2, 0.05, 0.6), (0.2, 100.0, 0.6)]:
        sc = rod_mass_scene(H, k, w)
        assert flip_time(sc, stepper=stepper).t_f == pytest.approx(flip_time(sc).t_f, rel=1e-9)


def test_rodas_is_fourth_order() -> None:
    # Forced RODAS4: each 16x tightening of rtol must cut the t_f error at least 4x (order >= 2 in
    # the step, with margin; the step scales with rtol^(1/4)).
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    ref = flip_time(sc, rtol=1e-14, stepper="dop853").t_f
    errs = [abs(flip_time(sc, rtol=r, stepper="rodas").t_f - ref) for r in (1.6e-7, 1e-8, 6.25e-10)]
    assert errs[1] < errs[0] / 4 and errs[2] < errs[1] / 4


@pytest.mark.parametrize("law", ["dry", "viscous"])
def test_analytic_jacobian_matches_finite_differences(law: str) -> None:
    sc = rod_mass_scene(0.2, 30.0, 0.6, friction=law)
    p, S = kernel_params(sc)
    rng = np.random.default_rng(1)
    for _ in range(20):
        t = float(rng.uniform(0, 10))
        y = np.array([rng.uniform(-10, 10), rng.uniform(-5, 5)])
        f0 = np.empty(2)
        driven_rhs(t, y, p, S, f0)
        J = np.empty((2, 2))
        fx = np.empty(2)
        jacobian(system_from_params(p, SYSTEM_DRIVEN), t, y, p, S, f0, J, fx)
        fd = np.empty((2, 2))
        fp = np.empty(2)
        fm = np.empty(2)
        for j in range(2):
            e = np.zeros(2)
            e[j] = 1e-6
            driven_rhs(t, y + e, p, S, fp)
            driven_rhs(t, y - e, p, S, fm)
            fd[:, j] = (fp - fm) / 2e-6
        driven_rhs(t + 1e-6, y, p, S, fp)
        driven_rhs(t - 1e-6, y, p, S, fm)
        # central differences: error O(1e-12 |f'''|) plus rounding ~1e-10 |f| / 1e-6
        assert np.allclose(J, fd, rtol=1e-6, atol=1e-6)
        assert np.allclose(fx, (fp - fm) / 2e-6, rtol=1e-6, atol=1e-6)


def test_l_zero_answers_at_once() -> None:
    sc = Scene(Disk(R=0.3, l=0.0), CircularDrive(omega=0.6, d=1.0), Friction("dry", 0.05))
    res = flip_time(sc)
    assert res.t_f is None and res.n_steps == 0 and "l = 0" in res.regime


def test_cap_says_which_cap_when_and_how_long() -> None:
    res = flip_time(rod_mass_scene(0.2, 0.05, 0.6), max_steps=100)
    assert res.t_f is None and not res.settled
    assert "max_steps=100" in res.regime and " at t=" in res.regime and "s of computing" in res.regime


def test_extended_body_stiff_rodas_with_finite_difference_jacobian() -> None:
    # A disk at k = 1000: RODAS4 with the finite-difference Jacobian (extended bodies) and DOP853
    # converge to the same flip; measured agreement 8e-13 at the default rtol, asserted at 1e-9.
    sc = Scene(Disk(R=0.1, l=0.2), CircularDrive(omega=0.6, d=1.0), Friction("dry", 1000.0))
    a = flip_time(sc, stepper="dop853")
    b = flip_time(sc, stepper="rodas")
    assert a.settled and b.settled and a.t_f is not None
    assert b.t_f == pytest.approx(a.t_f, rel=1e-9)


def test_radau_converges_without_order_reduction_in_the_dragged_phase() -> None:
    # The slow case (k / omega^2 = 7.5e4): Radau IIA (stage order 3) keeps its accuracy where
    # RODAS4's steps shrink 20x per 100x of rtol. Reference: scipy's Radau at rtol 1e-12 with the
    # analytic Jacobian (tests/reference.py). Measured t_f errors: 6.5e-9 (rtol 1e-6), 2.9e-11
    # (1e-8), 2.7e-14 (1e-10); asserted with 10x margins, and a 100x tightening must gain >= 10x.
    H, k, w = 0.25, 7.5, 0.01
    sc = rod_mass_scene(H, k, w)
    ref_tf, _ = scipy_stiff_flip_time(H, k, w, flip_time(sc).t_stop, method="Radau", rtol=1e-12)
    errs = [abs(flip_time(sc, rtol=r, stepper="radau").t_f - ref_tf) / ref_tf for r in (1e-6, 1e-8)]
    assert errs[0] < 1e-7 and errs[1] < 3e-10 and errs[1] < errs[0] / 10
