"""Exact references without friction: the rotating-frame pendulum (docs/physics.md).

With k = 0, theta = phi - w t + pi obeys H theta'' = -w^2 sin(theta). From phi0 = pi the pendulum
starts at the bottom with theta' = -w (1 + 1/H), so one backward revolution takes
T_1 = 4 H K(m) / (w (H + 1)), m = 4 H / (H + 1)^2, and RR exists iff w T_1 < 2 pi, i.e.
2 H K(m) < pi (H + 1). These closed forms are derived here again, independently of rrbody.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

from rrbody import critical_h, rod_mass_scene, simulate
from rrbody.analysis.flip import flip_time, reverse_rotation_exists
from rrbody.integrate.ode import integrate_driven
from rrbody.physics.bind import kernel_params


def exact_Hc0() -> float:
    return brentq(lambda H: 2 * H * ellipk(4 * H / (H + 1) ** 2) - math.pi * (H + 1), 0.3, 0.99, xtol=1e-15)


def test_exact_Hc0_value() -> None:
    # the paper quotes 0.793; the exact root is 0.7927...
    assert abs(exact_Hc0() - 0.7927) < 1e-4


def test_critical_h_frictionless_matches_elliptic_integral() -> None:
    # bisection tolerance 1e-10 plus the RR-test's integration error (rtol 1e-13 on T_1, whose
    # sensitivity dT_1/dH is O(1)): 1e-8 leaves two orders of margin and still checks 8 digits.
    Hc = critical_h(0.0, 0.3, tol=1e-10)
    assert abs(Hc - exact_Hc0()) < 1e-8


@pytest.mark.parametrize("H", [0.1, 0.3, 0.6, 0.78])
def test_T1_matches_elliptic_integral(H: float) -> None:
    w = 0.7
    sc = rod_mass_scene(H, 0.0, w, math.pi, friction="none")
    p, S = kernel_params(sc)
    res = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=2 * 2 * math.pi / w, rtol=1e-13, stop="rr")
    exact = 4 * H * ellipk(4 * H / (H + 1) ** 2) / (w * (H + 1))
    # rtol = 1e-13 on an 8th-order method: the event time is accurate to ~1e-12 relative; 1e-10
    # allows for the Newton event refinement's floating-point floor.
    assert res.T1 == pytest.approx(exact, rel=1e-10)


def test_rr_predicate_on_both_sides_of_Hc0() -> None:
    Hc = exact_Hc0()
    assert reverse_rotation_exists(rod_mass_scene(Hc - 1e-6, 0.0, 0.3, friction="none"))
    assert not reverse_rotation_exists(rod_mass_scene(Hc + 1e-6, 0.0, 0.3, friction="none"))


@pytest.mark.parametrize("H", [0.8, 1.0 + 1e-9, 2.0, 10.0, 1e3])
def test_no_reverse_rotation_anywhere_above_Hc0(H: float) -> None:
    # 2 H K(m) - pi (H + 1) > 0 for every H > H_c(0) (it tends to 0+ as H -> inf): H_c(0) is the only
    # RR boundary without friction, and the ODE test agrees (at H = 1 + 1e-9 the revolution takes
    # ~20 driving periods: K diverges logarithmically at m = 1).
    m = 4 * H / (H + 1) ** 2
    assert 2 * H * ellipk(m) - math.pi * (H + 1) > 0
    assert not reverse_rotation_exists(rod_mass_scene(H, 0.0, 0.3, friction="none"))


def test_pendulum_energy_conserved() -> None:
    # E = H theta'^2 / 2 - w^2 cos(theta) is the exact first integral of the frictionless motion.
    H, w = 0.4, 1.1
    tr = simulate(rod_mass_scene(H, 0.0, w, 2.0, friction="none"), t_max=40.0, dt_out=0.05, rtol=1e-13)
    theta = tr.phi - w * tr.t + math.pi
    thetad = tr.phi_dot - w
    E = 0.5 * H * thetad**2 - w**2 * np.cos(theta)
    # rtol 1e-13 over ~40 periods: the drift is bounded by the global error, ~1e-11 of the energy scale w^2
    assert np.max(np.abs(E - E[0])) < 1e-9 * w**2


def test_no_friction_flip_time_says_no_flip() -> None:
    res = flip_time(rod_mass_scene(0.2, 0.0, 0.6, friction="none"))
    assert res.t_f is None and res.reverse_rotation
    assert "perennial" in res.regime
