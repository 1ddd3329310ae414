"""Flip time (docs/physics.md, "Definitions rrbody fixes"): agreement with an independent scipy solution,
convergence as the tolerance tightens, the stopping rule, the phi0 = pi start and the regimes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody import flip_time, rod_mass_scene
from rrbody.physics.bind import kernel_params
from rrbody.physics.dynamics import driven_rhs

from .reference import quasi_static_tf_times_omega, scipy_flip_time

PHIXTPM = (0.2, 0.05, 0.6)


@pytest.mark.parametrize("friction", ["dry", "viscous"])
def test_phixtpm_agrees_with_tight_scipy(friction: str) -> None:
    H, k, w = PHIXTPM
    ours = flip_time(rod_mass_scene(H, k, w, friction=friction))
    assert ours.settled and ours.t_f is not None
    ref_tf, ref_phi = scipy_flip_time(H, k, w, math.pi, ours.t_stop, viscous=(friction == "viscous"))
    # the flip-time acceptance bound: <= 1e-6 relative against a tight (rtol=atol=1e-13) scipy solution
    assert ours.t_f == pytest.approx(ref_tf, rel=1e-6)
    assert ours.phi_min == pytest.approx(ref_phi, rel=1e-6)


@pytest.mark.parametrize("friction", ["dry", "viscous"])
def test_flip_time_converges_as_tolerance_tightens(friction: str) -> None:
    sc = rod_mass_scene(*PHIXTPM, friction=friction)
    ref = flip_time(sc, rtol=1e-14).t_f
    errs = [abs(flip_time(sc, rtol=r).t_f - ref) for r in (1e-6, 1e-8, 1e-10)]
    # 8th-order local error control: each 100x tightening must cut the error clearly (at least 10x)
    assert errs[1] < errs[0] / 10 and errs[2] < max(errs[1] / 10, 1e-12 * ref)


@pytest.mark.parametrize("H,k,w", [(0.2, 0.05, 0.6), (0.6, 0.003, 0.6), (0.2, 0.0015, 0.6), (0.25, 7.5, 0.1),
                                   (0.8, 0.003, 2.0), (0.2, 0.1, 0.6)])
def test_stopping_rule_certain_against_ten_times_the_settle_margin(H: float, k: float, w: float) -> None:
    sc = rod_mass_scene(H, k, w)
    short = flip_time(sc)
    long = flip_time(sc, settle_turns=20, settle_periods=30)
    # the long run met its own rule: 10x the rise (20 turns) and 10x the wait (30 periods)
    assert long.settled and short.settled and long.t_stop > short.t_stop
    # the same minimum, to the last bits (the two runs share every step up to short.t_stop)
    assert long.t_phi_min == short.t_phi_min and long.phi_min == short.phi_min


def test_phi0_pi_start_is_finite_and_zero_torque() -> None:
    # At phi0 = pi the CM starts at rest: the dry term is 0/0; its self-consistent limit is 0.
    for friction in ("dry", "viscous"):
        sc = rod_mass_scene(0.3, 0.5, 0.9, math.pi, friction=friction)
        p, S = kernel_params(sc)
        out = np.empty(2)
        driven_rhs(0.0, np.array([sc.phi0, sc.initial_phi_dot]), p, S, out)
        assert np.all(np.isfinite(out))
        # phi''(0) = (w^2/H) sin(pi) + friction limit 0: zero up to the rounding of sin(pi) ~ 1e-16
        assert abs(out[1]) < 1e-12


def test_phi0_pi_flip_time_is_continuous_in_phi0() -> None:
    # The 0/0 start must not make t_f(phi0) jump: nearby starts give nearby flip times.
    sc = rod_mass_scene(0.2, 0.05, 0.6, math.pi)
    t0 = flip_time(sc).t_f
    t_eps = [flip_time(sc.with_(phi0=math.pi + e)).t_f for e in (-1e-7, 1e-7)]
    # dt_f/dphi0 = 0 at pi (symmetric optimum of the RR interval, paper Fig. seco1), so 1e-7 in
    # phi0 moves t_f by far less than 1e-5 s; a spurious torque at t = 0 would show as O(k h).
    assert all(abs(t - t0) < 1e-5 for t in t_eps)


def test_no_reverse_rotation_reported_plainly() -> None:
    res = flip_time(rod_mass_scene(0.6, 0.003, 0.6, math.pi / 2))
    assert res.t_f is None and not res.reverse_rotation and "no reverse rotation" in res.regime


def test_quasi_static_limit_is_approached_at_rate_omega2_over_k() -> None:
    # omega t_f -> C(H) as omega -> 0 (exact dragged-mass limit, tests/reference.py); the deviation
    # is an inertial correction, so it must shrink in proportion to omega^2 / k.
    H, k = 0.25, 7.5
    C = quasi_static_tf_times_omega(H)
    devs = []
    for w in (0.1, 0.03):
        tf = flip_time(rod_mass_scene(H, k, w)).t_f
        devs.append(abs(w * tf - C) / C)
    ratio = (0.1 / 0.03) ** 2
    assert devs[0] / devs[1] == pytest.approx(ratio, rel=0.2)  # slope 2 in omega within 20 %
    assert devs[1] < 1e-3


def test_paper_estimate_is_only_leading_order() -> None:
    # The paper's 2 sqrt(2) / (2 + 1/H) for omega t_f misses the exact limit by ~11 % at H = 0.25.
    H = 0.25
    paper = 2 * math.sqrt(2) / (2 + 1 / H)
    assert abs(paper - quasi_static_tf_times_omega(H)) / quasi_static_tf_times_omega(H) > 0.1
