"""Free bodies sliding and spinning to rest: exact stop times, a clean stop, energy never gained."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rrbody.analysis.simulate import simulate
from rrbody.model.bodies import Disk, Ellipse, RodMass
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene
from rrbody.model.trajectory import Trajectory
from rrbody.physics import area


def _free(body, v0=(0.0, 0.0), spin0: float = 0.0, mu_g: float = 0.5, law: str = "dry", t_max: float = 10.0,
          dt: float = 0.01, **kw) -> Trajectory:
    sc = Scene(body=body, drive=None, friction=Friction(law, mu_g), v0=v0, spin0=spin0, **kw)
    return simulate(sc, t_max=t_max, dt_out=dt, rtol=1e-11)


def _clean_stop(tr: Trajectory, icm: float) -> None:
    """Invariants of a clean stop: kinetic energy never rises, no velocity or spin sign flips,
    exact rest (and no drift) after t_stop."""
    K = 0.5 * (tr.vx_cm ** 2 + tr.vy_cm ** 2 + icm * tr.spin ** 2)
    assert np.all(np.diff(K) <= 1e-15 * K[0])  # rounding of K only
    # no reversal between samples: the CM velocity turns (a non-circular body's path curves) but
    # never flips, and the spin keeps its sign (dry friction opposes it at every element)
    assert np.all(tr.vx_cm[:-1] * tr.vx_cm[1:] + tr.vy_cm[:-1] * tr.vy_cm[1:] >= 0.0)
    w = tr.spin[np.abs(tr.spin) > 1e-12 * np.max(np.abs(tr.spin))] if np.any(tr.spin) else np.zeros(0)
    assert np.all(np.sign(w) == np.sign(w[0])) if len(w) else True
    ts = tr.events["t_stop"]
    assert ts is not None
    after = tr.t > ts
    assert after.any()
    for col in (tr.vx_cm, tr.vy_cm, tr.spin):
        assert np.all(col[after] == 0.0)
    for col in (tr.x_cm, tr.y_cm, tr.body_angle):
        assert np.all(col[after] == col[after][0])


@pytest.mark.parametrize("v0", [(1.0, 0.5), (-0.3, 0.0), (0.0, 2.0)])
def test_point_mass_stops_at_elementary_time_and_distance(v0) -> None:
    mu_g = 0.5
    tr = _free(RodMass(l=0.1), v0=v0, mu_g=mu_g)
    v = math.hypot(*v0)
    # t = v0/(mu g), distance v0^2 / (2 mu g), along v0: the motion is exactly linear in t, so the
    # integrator and the analytic final stretch are exact up to rounding
    assert tr.events["t_stop"] == pytest.approx(v / mu_g, rel=1e-13)
    assert tr.events["distance"] == pytest.approx(v * v / (2 * mu_g), rel=1e-13)
    x, y = tr.events["stop_position"]
    assert x * v0[1] - y * v0[0] == pytest.approx(0.0, abs=1e-14)
    _clean_stop(tr, 0.0)


def _eps_star() -> float:
    # self-similar approach to rest of a disk: v'/v = Omega'/Omega with v' = -mu g f(eps) and
    # Omega' = -mu g R t(eps) / (R^2/2): f(eps) = 2 eps t(eps), from the closed form
    return brentq(lambda e: area.disk_closed_form_ratio(e)[0] - 2 * e * area.disk_closed_form_ratio(e)[1],
                  0.1, 5.0, xtol=1e-15)


def test_sliding_spinning_disk_stops_with_both_velocities_together() -> None:
    R = 0.5
    tr = _free(Disk(R=R), v0=(1.0, 0.0), spin0=3.0, dt=0.001)
    _clean_stop(tr, R * R / 2)
    ts = tr.events["t_stop"]
    before = (tr.t < ts) & (tr.t > ts - 0.05)
    v = np.hypot(tr.vx_cm, tr.vy_cm)[before]
    w = tr.spin[before]
    # both still nonzero just before the stop, and their ratio at the self-similar fixed point
    # (Farkas et al. 2003: 0.653); the fixed point is attracting, ratio settles to ~1e-4 in 0.05 s
    assert np.all(v > 0) and np.all(w > 0)
    assert v[-1] / (w[-1] * R) == pytest.approx(_eps_star(), rel=1e-3)
    assert _eps_star() == pytest.approx(0.653, abs=5e-4)
    # a disk slides straight: the force is along -v by symmetry
    assert np.max(np.abs(tr.y_cm)) < 1e-14


def test_pure_spin_and_pure_slide_of_a_disk() -> None:
    R, mu_g = 0.4, 0.5
    # pure spin: tau = (2/3) mu g R, Omega' = -(4/3) mu g / R: stops at 3 R Omega0 / (4 mu g), CM still
    tr = _free(Disk(R=R), spin0=2.0, mu_g=mu_g)
    assert tr.events["t_stop"] == pytest.approx(3 * R * 2.0 / (4 * mu_g), rel=1e-12)
    assert np.all(tr.x_cm == 0.0) and np.all(tr.y_cm == 0.0)
    _clean_stop(tr, R * R / 2)
    # pure slide: no spin appears; stops like a point mass
    tr = _free(Disk(R=R), v0=(0.6, 0.8), mu_g=mu_g)
    assert np.all(tr.spin == 0.0)
    assert tr.events["t_stop"] == pytest.approx(1.0 / mu_g, rel=1e-12)
    assert tr.events["distance"] == pytest.approx(1.0 / (2 * mu_g), rel=1e-12)


@pytest.mark.parametrize("delta", [0.5, -0.9])
def test_ellipse_stops_cleanly_and_friction_never_does_positive_work(delta: float) -> None:
    body = Ellipse(R0=0.3, delta=delta)
    tr = _free(body, v0=(0.4, -0.2), spin0=-6.0)
    _clean_stop(tr, body.inertia_per_mass)
    # friction power P = -(F.v + tau Omega) >= 0 at every sample (evaluated by the ICR rule)
    for i in range(0, len(tr), 7):
        fx, fy, tau = area.icr_wrench(body, tr.body_angle[i], tr.vx_cm[i], tr.vy_cm[i], tr.spin[i], coeff=0.5)
        assert -(fx * tr.vx_cm[i] + fy * tr.vy_cm[i] + tau * tr.spin[i]) >= 0.0


def test_sampled_path_agrees_on_the_stop() -> None:
    body = Ellipse(R0=0.3, delta=0.5)
    a = _free(body, v0=(0.4, -0.2), spin0=-6.0)
    b = _free(body, v0=(0.4, -0.2), spin0=-6.0, friction_method="sampled", samples=12_288)
    _clean_stop(b, body.inertia_per_mass)
    # sampled wrench error ~1/N ~ 1e-4 (tests/test_area.py) -> stop time and place to ~1e-3
    assert b.events["t_stop"] == pytest.approx(a.events["t_stop"], rel=1e-3)
    assert b.events["distance"] == pytest.approx(a.events["distance"], rel=1e-3)


def test_viscous_free_body_decays_exponentially() -> None:
    # F = -gamma v and tau = -gamma I_cm Omega: v and Omega both decay as exp(-gamma t), never stop
    gamma = 0.7
    body = Ellipse(R0=0.3, delta=0.4)
    tr = _free(body, v0=(1.0, 0.3), spin0=2.0, mu_g=gamma, law="viscous", t_max=5.0, dt=0.05)
    assert tr.events["t_stop"] is None
    decay = np.exp(-gamma * tr.t)
    assert np.max(np.abs(tr.vx_cm - decay)) < 1e-9  # rtol 1e-11 on a unit-size exponential
    assert np.max(np.abs(tr.spin - 2.0 * decay)) < 2e-9
    assert tr.x_cm[-1] == pytest.approx((1 - decay[-1]) / gamma, rel=1e-9)


def test_at_rest_from_the_start_and_frictionless() -> None:
    tr = _free(Disk(R=0.2), t_max=1.0, dt=0.1)
    assert tr.events["t_stop"] == 0.0 and np.all(tr.x_cm == 0.0)
    tr = _free(Disk(R=0.2), v0=(1.0, 0.0), spin0=1.0, law="none", t_max=1.0, dt=0.1)
    assert tr.events["t_stop"] is None
    assert tr.x_cm[-1] == pytest.approx(1.0, rel=1e-12) and tr.body_angle[-1] == pytest.approx(1.0, rel=1e-12)


def test_free_simulation_refuses_a_driven_scene() -> None:
    from rrbody.integrate.free import simulate_free
    from rrbody.model.drive import CircularDrive

    sc = Scene(body=Disk(R=0.2, l=0.1), drive=CircularDrive(omega=1.0, d=1.0), friction=Friction("dry", 0.5))
    with pytest.raises(ValueError, match="free scene"):
        simulate_free(sc, t_max=1.0, dt_out=0.1)


def test_an_off_centre_load_turns_the_spin_through_zero_and_stops() -> None:
    """A disk pressing on a ring off its centre (rrbody.pressure.ring(0.03, centre=(0.05, 0))): the
    load's offset turns friction's torque against a small spin, which passes through zero while the
    disk slides on (it stopped the ODE path with a step size underflow when a step could not reverse
    the spin). It comes to rest, at the engine path's stop within two of its steps (its order at a
    stop, docs/engine.md)."""
    from rrbody import pressure as rp
    from rrbody.model.scene import scene_from_params

    sc = scene_from_params(body="disk", R0=0.1, no_drive=True, v0=(0.0, 1.0), spin0=0.5, mu=0.3,
                           pressure=rp.ring(0.03, centre=(0.05, 0.0)))
    tr = simulate(sc, t_max=1.0)
    assert tr.meta["status"] == "came to rest" and tr.events["t_stop"] is not None
    assert (np.diff(np.sign(tr.phi_dot)) != 0).any()  # the spin did turn through zero
    eng = simulate(sc, t_max=1.0, method="engine")
    assert abs(eng.events["t_stop"] - tr.events["t_stop"]) < 2.0 * eng.meta["dt"]
