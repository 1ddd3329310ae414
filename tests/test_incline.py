"""A tilted plane and static friction: exact results on both paths.

On a plane tilted at alpha with mu = tan(alpha), a sliding point mass keeps v (1 + cos theta)
constant (theta from the downhill direction) and tends to v0 (1 + cos theta0) / 2; slid downhill a
body accelerates at g (sin alpha - mu cos alpha); with mu < tan(alpha) < mu_static a body released
at rest stays exactly at rest; a box breaks away when a slowly growing push reaches mu_static m g,
or a torque the static torque limit mu_static m g <|r|> (uniform pressure: the mean distance of its
points from the centre)."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from rrbody import pressure as rp
from rrbody.analysis.simulate import simulate
from rrbody.engine import PlaneFriction
from rrbody.model.scene import scene_from_params
from rrbody.physics.polygon import box_spin_torque

G = 9.81
ALPHA = math.atan(0.4)


def _plane(*, tilt: float = ALPHA, downhill: float = 0.0, mu: float = 0.4, mu_static: float | None = None,
           v: tuple[float, float] = (0.0, 0.0), pressure: object = "uniform", box: float = 0.2):
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G, tilt=tilt, downhill=downhill)
    b = pymunk.Body()
    s = pymunk.Poly.create_box(b, (box, box))
    s.density = 2.0
    space.add(b, s)
    b.velocity = v
    pf.add(b, mu=mu, mu_static=mu_static, pressure=pressure)
    return space, pf, b


def _invariant(vx: np.ndarray, vy: np.ndarray, downhill: float) -> np.ndarray:
    v = np.hypot(vx, vy)
    return v + vx * math.cos(downhill) + vy * math.sin(downhill)  # v (1 + cos theta)


def test_ode_point_mass_keeps_the_invariant_at_mu_equal_tan_alpha() -> None:
    """The ODE path: v (1 + cos theta) stays at its start to 1e-8 (the integrator's rtol 1e-13 asked;
    measured ~5e-14) over a long run, and v tends to v0 (1 + cos theta0) / 2."""
    dh = 0.7
    for theta0 in (0.5 * math.pi, 2.0, 1.0):
        v0 = (math.cos(dh + theta0), math.sin(dh + theta0))
        scene = scene_from_params(body="rod", H=0.2, no_drive=True, v0=v0, mu=0.4, g=G, tilt=ALPHA, downhill=dh,
                                  t_max=20.0)
        tr = simulate(scene)
        inv = _invariant(tr.vx_cm, tr.vy_cm, dh)
        assert np.max(np.abs(inv - (1 + math.cos(theta0)))) < 1e-8
        # once theta is small it decays at the rate g sin(alpha) / v (>= 4.7 /s here): after 20 s the
        # limit is reached to the integrator's tolerance
        assert math.hypot(tr.vx_cm[-1], tr.vy_cm[-1]) == pytest.approx((1 + math.cos(theta0)) / 2, abs=1e-9)


def test_plugin_point_contact_keeps_the_invariant_to_second_order() -> None:
    """The plugin, with all the load on one foot at the centre of gravity (a point contact): the
    invariant's drift falls 4x per halving of dt (the staggered scheme's second order)."""
    dh = 0.3
    errs = []
    for dt in (2e-3, 1e-3, 5e-4):
        v0 = (math.cos(dh + 2.0), math.sin(dh + 2.0))
        space, pf, b = _plane(downhill=dh, v=v0, pressure=rp.points([(0.0, 0.0, 1.0)]))
        worst = 0.0
        while pf.t < 3.0:
            pf.step(dt)
            vx, vy, _ = pf.velocity(b)
            worst = max(worst, abs(_invariant(np.array(vx), np.array(vy), dh) - (1 + math.cos(2.0))))
        errs.append(worst)
    rates = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    assert all(1.8 < r < 2.3 for r in rates), (errs, rates)


def test_slid_downhill_it_accelerates_at_the_exact_rate() -> None:
    """g (sin alpha - mu cos alpha): the ODE path to its tolerance, the plugin to rounding (a
    constant acceleration is exact in the staggered scheme)."""
    mu = 0.3
    a = G * (math.sin(ALPHA) - mu * math.cos(ALPHA))
    tr = simulate(scene_from_params(body="disk", R0=0.1, no_drive=True, v0=(1.0, 0.0), mu=mu, g=G, tilt=ALPHA,
                                    t_max=2.0))
    assert np.allclose(tr.vx_cm, 1.0 + a * tr.t, rtol=0, atol=1e-11)
    space, pf, b = _plane(mu=mu, v=(1.0, 0.0))
    for _ in range(2000):
        pf.step(1e-3)
        vx, vy, w = pf.velocity(b)
        assert vx == pytest.approx(1.0 + a * pf.t, abs=1e-12) and vy == 0.0 and w == 0.0


def test_held_by_static_friction_for_a_million_steps() -> None:
    """mu < tan(alpha) < mu_static: released at rest, the box stays bit-identically at rest."""
    space, pf, b = _plane(mu=0.3, mu_static=0.5, downhill=1.1)
    b.angle = 0.4
    for _ in range(1_000_000):
        pf.step(1e-3)
    assert b.position == (0.0, 0.0) and b.angle == 0.4
    assert b.velocity == (0.0, 0.0) and b.angular_velocity == 0.0


def test_ode_path_holds_or_releases_a_body_at_rest() -> None:
    """The ODE path: held where mu_static >= tan(alpha); released otherwise, it slides from rest at
    g (sin alpha - mu cos alpha) (its start along the break-away acceleration, then the integrator)."""
    held = simulate(scene_from_params(body="disk", R0=0.1, no_drive=True, mu=0.3, mu_static=0.5, g=G, tilt=ALPHA,
                                      t_max=1.0))
    assert np.all(held.x_cm == 0.0) and np.all(held.y_cm == 0.0) and held.meta["status"] == "came to rest"
    go = simulate(scene_from_params(body="disk", R0=0.1, no_drive=True, mu=0.3, mu_static=0.35, g=G, tilt=ALPHA,
                                    downhill=0.5, t_max=1.0))
    a = G * (math.sin(ALPHA) - 0.3 * math.cos(ALPHA))
    # the start at 1e-6 of the run from the constant-acceleration motion: exact to rounding here
    assert np.allclose(np.hypot(go.x_cm, go.y_cm), 0.5 * a * go.t ** 2, rtol=0, atol=1e-10)
    assert np.allclose(np.arctan2(go.y_cm[1:], go.x_cm[1:]), 0.5, atol=1e-9)


def test_ode_path_goes_up_stops_and_slides_back() -> None:
    """Launched uphill on a plane steeper than mu_static: it stops after v0 / (g (sin + mu cos)),
    cannot be held, and slides back from the stop at g (sin - mu cos) (the run restarts there along
    the break-away acceleration; the samples before the stop are the uphill motion's, exactly)."""
    mu = 0.3
    up = G * (math.sin(ALPHA) + mu * math.cos(ALPHA))
    down = G * (math.sin(ALPHA) - mu * math.cos(ALPHA))
    tr = simulate(scene_from_params(body="disk", R0=0.1, no_drive=True, v0=(-1.0, 0.0), mu=mu, g=G, tilt=ALPHA,
                                    t_max=1.0))
    stop = 1.0 / up
    assert tr.events["break_aways"] == 1 and tr.events["t_stop"] is None
    before, after = tr.t <= stop, tr.t > stop + 1e-6
    # uphill: v = -1 + up t; back down from the stop: v = down (t - stop) (the ODE path's tolerance; the
    # restart's seed is exact to O(tau^2) with tau = 1e-6 s)
    assert np.allclose(tr.vx_cm[before], -1.0 + up * tr.t[before], rtol=0, atol=1e-9)
    assert np.allclose(tr.vx_cm[after], down * (tr.t[after] - stop), rtol=0, atol=1e-9)
    assert np.all(tr.vy_cm == 0.0)


def test_plugin_goes_up_stops_and_slides_back() -> None:
    """Uphill at v0 on a plane steeper than mu_static: it stops after v0 / (g (sin + mu cos)) (within a
    step) and then slides down at g (sin - mu cos) from rest."""
    mu, dt = 0.3, 1e-3
    space, pf, b = _plane(mu=mu, mu_static=0.35, v=(-1.0, 0.0))
    up = G * (math.sin(ALPHA) + mu * math.cos(ALPHA))
    down = G * (math.sin(ALPHA) - mu * math.cos(ALPHA))
    while pf.t < 1.0:
        pf.step(dt)
    vx, _, _ = pf.velocity(b)
    assert vx == pytest.approx(down * (1.0 - 1.0 / up), abs=2 * up * dt)


def test_a_growing_push_breaks_the_box_away_at_mu_static_m_g() -> None:
    """A push at the centre of gravity growing by 1e-4 mu_s m g per step on a level plane: the box
    holds exactly (not a nanometre of creep) until the push reaches mu_s m g, and moves in that step."""
    mu, mu_s, dt = 0.3, 0.5, 1e-3
    space, pf, b = _plane(tilt=0.0, mu=mu, mu_static=mu_s)
    limit = mu_s * b.mass * G
    k = 0
    while b.velocity == (0.0, 0.0):
        k += 1
        b.force = (1e-4 * k * limit, 0.0)
        pf.step(dt)
        assert k < 20000
    assert 1e-4 * (k - 1) * limit <= limit <= 1e-4 * k * limit * (1 + 1e-12)
    assert b.velocity.y == 0.0 and b.angular_velocity == 0.0  # it slides along the push


def test_a_growing_torque_breaks_the_box_away_at_its_static_torque_limit() -> None:
    """A torque growing by 1e-4 of the limit per step: the box turns first in the step the torque
    passes mu_s m g a (sqrt 2 + ln(1 + sqrt 2)) / 6, the mean distance of a square's points from its
    centre (uniform pressure), and turns in place."""
    mu, mu_s, dt, a = 0.3, 0.5, 1e-3, 0.2
    space, pf, b = _plane(tilt=0.0, mu=mu, mu_static=mu_s, box=a)
    limit = mu_s * b.mass * G * box_spin_torque(a)
    k = 0
    while b.angular_velocity == 0.0:
        k += 1
        b.torque = 1e-4 * k * limit
        pf.step(dt)
        assert k < 20000
    assert 1e-4 * (k - 1) * limit <= limit * (1 + 1e-9) and limit <= 1e-4 * k * limit * (1 + 1e-9)
    assert abs(b.velocity.x) + abs(b.velocity.y) < 1e-12


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"tilt": 2.0}, r"tilt must be in \[0, 1.5708\) rad, got 2.0"),
    ({"tilt": -0.1}, r"tilt must be in \[0, 1.5708\) rad"),
    ({"downhill": float("nan")}, r"downhill must be in"),
])
def test_bad_tilts_name_the_parameter(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        PlaneFriction(pymunk.Space(), **kwargs)
    with pytest.raises(ValueError, match=match):
        scene_from_params(body="disk", R0=0.1, no_drive=True, mu=0.3, **kwargs)


def test_mu_static_below_mu_is_refused_everywhere() -> None:
    space, pf, b = _plane(tilt=0.0)
    with pytest.raises(ValueError,
                       match=r"mu_static must be >= mu \(0.4: static friction is never below kinetic\), got 0.3"):
        pf.add(b, mu=0.4, mu_static=0.3)
    with pytest.raises(ValueError, match=r"mu_static must be >= mu \(0.4"):
        scene_from_params(body="disk", R0=0.1, no_drive=True, mu=0.4, g=G, mu_static=0.3)
    from tests.clirun import run_many

    (r,) = run_many([["simulate", "--body", "disk", "--R0", "0.1", "--no-drive", "--mu", "0.4", "--mu-static", "0.3",
                      "--tilt", "10deg", "--t-max", "1", "--json"]])
    assert r.code == 2 and r.err.count("\n") == 1 and "--mu-static must be >= mu (0.4" in r.err


def test_driven_rod_mass_on_a_tilt_is_the_forced_double_pendulum() -> None:
    """Frictionless, the driven rod-mass body on a tilt obeys l^2 phi'' = omega^2 l d sin(phi - omega t)
    + l (sin phi g_x - cos phi g_y) (I_cm = 0): rrbody's phi(t) against scipy's DOP853 at rtol 1e-12
    on that equation (agreement to 1e-8 asked over 20 s; both integrators' tolerances are far below)."""
    from scipy.integrate import solve_ivp

    H, w, tilt, dh = 0.5, 1.3, 0.3, 0.4
    scene = scene_from_params(H=H, omega=w, friction="none", tilt=tilt, downhill=dh, phi0=2.0, phi_dot0=0.5, t_max=20.0)
    tr = simulate(scene)
    l, d = H, 1.0
    gx, gy = G * math.sin(tilt) * math.cos(dh), G * math.sin(tilt) * math.sin(dh)

    def f(t: float, y: np.ndarray) -> list[float]:
        return [y[1],
                (w * w * l * d * math.sin(y[0] - w * t) + l * (math.sin(y[0]) * gx - math.cos(y[0]) * gy)) / l ** 2]

    ref = solve_ivp(f, (0.0, 20.0), [2.0, 0.5], method="DOP853", rtol=1e-12, atol=1e-12, t_eval=tr.t,
                    dense_output=False)
    assert np.max(np.abs(ref.y[0] - tr.phi)) < 1e-8


def test_plugin_and_ode_agree_on_a_tilt_at_second_order() -> None:
    """A disk on its rim (ring pressure) launched across a slope with spin, on both paths: the plugin's
    end state approaches the ODE path's 4x closer per halving of dt."""
    R, mu, tilt, dh, v0, w0, T = 0.1, 0.2, 0.15, 0.0, (0.0, 1.0), 8.0, 0.6
    ode = simulate(scene_from_params(body="disk", R0=R, no_drive=True, v0=v0, spin0=w0, mu=mu, g=G, tilt=tilt,
                                     downhill=dh, pressure=f"ring:{R}", t_max=T))
    want = np.array([ode.x_cm[-1], ode.y_cm[-1], ode.body_angle[-1]])
    from tests.plugin_orders import plugin_errors

    errs, rates = plugin_errors(lambda b: pymunk.Circle(b, R), want, v0=v0, w0=w0, T=T, dts=(4e-3, 2e-3, 1e-3),
                                plane={"g": G, "tilt": tilt, "downhill": dh}, add={"mu": mu, "pressure": rp.ring(R)})
    assert all(1.7 < r < 2.3 for r in rates), (errs, rates)


def test_rrbody_scenes_on_the_engine_path_take_the_tilt() -> None:
    """A driven disk (P off the centre) on a tilted plane through --method engine: phi approaches the
    ODE path's at second order in dt (the scene's tilt builds the space's plane); a second scene with
    another tilt in the same space is refused (one space, one plane)."""
    sc = scene_from_params(body="disk", R0=0.1, l=0.05, omega=1.0, k=0.05, tilt=0.2, downhill=0.5, t_max=20.0)
    ode = simulate(sc).phi[-1]
    errs = [abs(simulate(sc, method="engine", dt=dt).phi[-1] - ode) for dt in (2e-3, 1e-3)]
    assert 3.0 < errs[0] / errs[1] < 5.0, errs
    from rrbody.engine import EngineSettings, attach

    space = pymunk.Space()
    attach(space, sc, settings=EngineSettings(dt=1e-3))
    with pytest.raises(ValueError, match=r"scene tilt must match the space's plane"):
        attach(space, sc.with_(tilt=0.1), settings=EngineSettings(dt=1e-3))


def test_a_load_static_friction_cannot_hold_is_refused_without_the_limit_set_test() -> None:
    """The kernel skips the limit-set test (and its deferral to the second loop) for a load whose force
    is above mu_s g per unit mass (``_may_hold`` False); the skip is sound only if the test itself then
    says "not held" (:func:`rrbody.contact.rest.held`). Loads within 1e-13 .. 1e-6 (relative) of
    the bound on either side, in every direction and at every angle, with torques up to the static
    torque limit: wherever ``_may_hold`` refuses, ``_held`` refuses too, and it refuses loads above
    1 + 1e-9 (the margin, 1e-12 on the square, covers the rotation's rounding, a few ulps)."""
    from rrbody.contact import kernel as K

    space, pf, b = _plane(tilt=0.0, mu=0.3, mu_static=0.5)
    j = 0
    B = pf._bodies
    m, mus = B[j, K.MASS], B[j, K.STATIC_COEFF]
    rng = np.random.default_rng(5)
    out = np.zeros((1, 3))
    refused = 0
    for _ in range(4000):
        rel = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-13, -6)
        phi, alpha = rng.uniform(0, 2 * math.pi, 2)
        f = m * mus * (1.0 + rel)
        out[0] = f * math.cos(phi), f * math.sin(phi), m * mus * 0.2 * rng.uniform(-1, 1)
        B[j, K.HELD] = -1.0  # no remembered answer: the test runs
        may = K.R.may_hold(j, B, out[0, 0], out[0, 1])
        if not may:
            refused += 1
            assert not K.R.held(0, j, alpha, B, pf._k_shapes, pf._k_geo, out)
        if rel > 1e-9:
            assert not may
    assert refused > 1000  # (about half the loads are above the bound: the check is not vacuous)


def test_an_active_body_pushing_a_wall_beyond_static_friction_is_never_tested() -> None:
    """An active box whose propulsion (1.5 mu_s m g) pushes it into a wall: it comes to rest against
    the wall, the rest rule wants to stop it every step, and static friction could never hold its
    load; the limit-set test never runs (its remembered load stays unset), and the box stays pressed
    to the wall. (It starts moving: a body at rest is tested, to see whether it breaks away.)"""
    from rrbody.contact import kernel as K
    from rrbody.plugin import Active

    space, pf, b = _plane(tilt=0.0, mu=0.3, mu_static=0.4, v=(0.05, 0.0))
    space.add(pymunk.Segment(space.static_body, (0.3, -1.0), (0.3, 1.0), 0.01))
    pf.activate(b, Active(force=1.5 * 0.4 * G * b.mass))
    for _ in range(600):
        pf.step(1e-3)
    assert pf._bodies[0, K.HELD] == -1.0
    assert abs(b.position.x - (0.3 - 0.01 - 0.1)) < 1e-2 and b.velocity.length < 1e-2
