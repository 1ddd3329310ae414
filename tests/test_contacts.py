"""Real contacts: pressure distributions on both paths, against exact results.

Exact references: the spin torque of a disk under uniform pressure (2/3 mu N R), a ring (mu N R) and
Hertz's pressure (3 pi mu N a / 16); the stop ratio v / (R Omega) of a sliding and spinning hoop
(1), a uniform disk (0.653, Farkas et al. 2003) and washers in between; feet as an exact finite sum
of point contacts; the ODE path's contact method and the plugin computing the same numbers."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from scipy.optimize import brentq

from rrbody import pressure as rp
from rrbody.engine import PlaneFriction
from rrbody.model.bodies import Disk, Ellipse
from rrbody.model.scene import Scene, scene_from_params
from rrbody.physics import contact as C
from rrbody.physics.bind import kernel_params
from rrbody.physics.footprint import apply_pressure, body_parts, ellipse_part
from rrbody.physics.wrench import body_wrench

G = 9.81


def _disk(R: float, *, mu: float = 0.5, pressure: object = "uniform", moment: float | None = None,
          v: tuple[float, float] = (0.0, 0.0), w: float = 0.0) -> tuple[pymunk.Space, PlaneFriction, pymunk.Body]:
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    body = pymunk.Body()
    shape = pymunk.Circle(body, R)
    shape.density = 3.0
    space.add(body, shape)
    if moment is not None:
        body.moment = moment * body.mass  # I / m given (m^2): a hoop, a washer
    body.velocity, body.angular_velocity = v, w
    pf.add(body, mu=mu, pressure=pressure)
    return space, pf, body


@pytest.mark.parametrize(("pressure", "lever"), [
    ("uniform", 2.0 / 3.0),                 # (2/3) R: the mean distance of a disk's points
    (rp.ring(0.1), 1.0),                    # every point at R
    (rp.hertz(0.1), 3.0 * math.pi / 16.0),  # Hertz: 3 pi a / 16 (Johnson, Contact Mechanics)
    (rp.annulus(0.05, 0.1), (2.0 / 3.0) * (1 - 0.5 ** 3) / (1 - 0.5 ** 2)),  # (2/3)(Ro^3 - Ri^3)/(Ro^2 - Ri^2)
])
def test_pure_spin_torque_is_exact_for_each_profile(pressure: object, lever: float) -> None:
    """Spinning in place about the centre: torque mu N R times the profile's mean lever, no force.
    Tolerances: the ring and Hertz kernels are closed forms (rounding, 1e-13); the uniform disk and
    the annulus go through the instantaneous-centre quadrature (24 nodes: ~5e-12 against the closed form)."""
    R, mu, w0 = 0.1, 0.5, 7.0
    for w in (w0, -w0):
        space, pf, b = _disk(R, mu=mu, pressure=pressure, w=w)
        fx, fy, tq = pf.wrench(b)
        assert tq == pytest.approx(-math.copysign(1.0, w) * mu * b.mass * G * R * lever, rel=1e-11)
        assert abs(fx) + abs(fy) < 1e-11 * mu * b.mass * G


@pytest.mark.parametrize(("pressure", "lever", "moment"), [
    (rp.ring(0.1), 1.0, 0.01),                  # a hoop (I = m R^2) on its rim: mu g / R
    (rp.hertz(0.1), 3.0 * math.pi / 16.0, 0.005),  # a disk on a Hertz patch of radius R
])
def test_spin_down_is_at_the_exact_rate(pressure: object, lever: float, moment: float) -> None:
    """Pure spin decelerates at mu g lever / (I/m): the staggered scheme is exact for a constant
    deceleration (the angle to rounding, measured ~1e-14 rad) until the step the body stops in."""
    R, mu, w0, dt = 0.1, 0.4, 12.0, 1e-3
    alpha = mu * G * R * lever / moment
    space, pf, b = _disk(R, mu=mu, pressure=pressure, moment=moment, w=w0)
    worst = 0.0
    while not (b.angular_velocity == 0.0 and b.velocity == (0.0, 0.0)):
        pf.step(dt)
        if pf.t < w0 / alpha - 2 * dt:
            worst = max(worst, abs(b.angle - (w0 * pf.t - 0.5 * alpha * pf.t ** 2)))
    assert worst < 1e-11
    assert abs(pf.stop_time(b) - w0 / alpha) <= dt
    assert b.position == (0.0, 0.0)


def _ratio_fixed_point(rin: float, rout: float, kappa: float) -> float:
    """eps* = v / (R Omega) where sliding and spin stop together: F(eps) = eps T(eps) / kappa, from
    the footprint kernel (F per unit load and mu g, T in units of R; kappa = I / (m R^2))."""
    pr = rp.ring(rout) if rin == rout else rp.annulus(rin, rout)
    shapes, geo, *_ = apply_pressure([ellipse_part(0.0, 0.0, rout, rout)], pr)

    def f(eps: float) -> float:
        fx, fy, tq = C.footprint_wrench(shapes, geo, 0, shapes.shape[0], eps * rout, 0.0, 1.0, 0.0)
        return math.hypot(fx, fy) - eps * abs(tq) / rout / kappa

    return brentq(f, 0.05, 5.0, xtol=1e-14)


def test_stop_ratio_rises_from_the_disk_to_the_ring() -> None:
    """Washers of inner radius Ri (uniform pressure on their area, I = m (Ri^2 + Ro^2) / 2): the
    ratio at which slide and spin stop together rises monotonically from 0.653 (a disk, the Farkas
    ratio) to exactly 1 (a hoop on its rim: F = T = 2/pi at eps = 1)."""
    R = 0.1
    ratios = [_ratio_fixed_point(f * R, R, 0.5 * (1 + f * f)) for f in (0.0, 0.25, 0.5, 0.75, 0.9)]
    hoop = _ratio_fixed_point(R, R, 1.0)
    assert ratios[0] == pytest.approx(0.653, abs=5e-4)  # Farkas et al. (2003), 3 figures
    assert hoop == pytest.approx(1.0, abs=1e-12)  # exact: the elliptic closed form at x = 1
    assert np.all(np.diff([*ratios, hoop]) > 0)


@pytest.mark.parametrize(("rin", "kappa"), [(0.1, 1.0), (0.05, 0.625)])
def test_a_sliding_spinning_washer_approaches_its_ratio(rin: float, kappa: float) -> None:
    """Launched above and below eps*, v/(R Omega) moves monotonically toward it while both slow down
    (as for the disk: test_plugin)."""
    R, w0, dt = 0.1, 20.0, 2.5e-4
    pr = rp.ring(R) if rin == R else rp.annulus(rin, R)
    eps_star = _ratio_fixed_point(rin, R, kappa)
    for e0 in (0.4, 2.0):
        space, pf, b = _disk(R, pressure=pr, moment=kappa * R * R, v=(e0 * R * w0, 0.0), w=w0)
        eps = []
        while not (b.angular_velocity == 0.0 and b.velocity == (0.0, 0.0)):
            pf.step(dt)
            vx, vy, w = pf.velocity(b)
            if w > 0.0 and math.hypot(vx, vy) > 0.0:
                eps.append(math.hypot(vx, vy) / (R * w))
        e = np.array(eps[:-3])  # the last steps are the limiter's and the rest rule's
        # the hoop reaches eps* = 1 before it stops (its instantaneous centre then rides the rim) and
        # stays there to ~1e-6 (the step's rounding of v / (R Omega) near the stop): monotone until then
        near = np.flatnonzero(np.abs(e - eps_star) < 1e-5)
        d = np.diff(e[:near[0] if near.size else e.size])
        assert np.all(d > 0) if e0 < eps_star else np.all(d < 0)
        assert abs(e[-1] - eps_star) < 0.25 * abs(e0 - eps_star)


def test_three_feet_are_exactly_three_point_contacts() -> None:
    """A body on three feet: the wrench is the finite sum over the feet of -mu g share v_i / |v_i|,
    to rounding, at any motion (shares normalised from loads)."""
    feet = [(0.05, 0.0, 2.0), (-0.04, 0.03, 1.0), (-0.04, -0.03, 1.0)]
    mu = 0.3
    for v, w, ang in [((0.3, -0.1), 2.0, 0.4), ((0.0, 0.0), 5.0, 0.0), ((1.0, 0.5), -0.2, 2.0)]:
        space, pf, b = _disk(0.1, mu=mu, pressure=rp.points(feet), v=v, w=w)
        b.angle = ang
        fx, fy, tq = pf.wrench(b)
        ex = ey = et = 0.0
        c, s = math.cos(ang), math.sin(ang)
        for x, y, load in feet:
            share = load / 4.0
            rx, ry = c * x - s * y, s * x + c * y  # the foot in the world frame, from the CG
            ux, uy = v[0] - w * ry, v[1] + w * rx
            sp = math.hypot(ux, uy)
            gx, gy = -mu * b.mass * G * share * ux / sp, -mu * b.mass * G * share * uy / sp
            ex, ey, et = ex + gx, ey + gy, et + rx * gy - ry * gx
        scale = mu * b.mass * G * 0.1
        assert abs(fx - ex) < 1e-13 * scale * 10 and abs(fy - ey) < 1e-13 * scale * 10
        assert abs(tq - et) < 1e-13 * scale


@pytest.mark.parametrize("pressure", ["ring:0.25", "annulus:0.1,0.3", "hertz:0.2", "points:0.1,0,1;-0.1,0,1"])
def test_the_ode_path_uses_the_plugins_kernel(pressure: str) -> None:
    """One description, both paths: a scene with a pressure binds to the contact method, whose wrench
    (per unit mass) equals the plugin's (per kg) for the same body and motion, bit for bit up to the
    rotations (1e-14)."""
    scene = scene_from_params(body="disk", R0=0.3, k=1.0, no_drive=True, v0=(1.0, 0.0), spin0=2.0,
                              pressure=pressure)
    p, S = kernel_params(scene)
    space, pf, b = _disk(0.3, mu=scene.friction.coeff / G, pressure=pressure)
    for v, w, ang in [((0.4, 0.1), 3.0, 0.2), ((1.0, -2.0), 0.5, -1.0), ((0.0, 0.0), 1.0, 0.0)]:
        b.angle = ang
        got = body_wrench(p, S, ang, v[0], v[1], w)
        want = pf.wrench(b, velocity=(*v, w))
        assert got[0] == pytest.approx(want[0] / b.mass, abs=1e-14)
        assert got[1] == pytest.approx(want[1] / b.mass, abs=1e-14)
        assert got[2] == pytest.approx(want[2] / b.mass, abs=1e-14)


def test_uniform_through_the_contact_method_equals_the_quadrature() -> None:
    """friction_method='contact' with uniform pressure is the ellipse quadrature itself: the free
    ellipse's whole trajectory is the same as with 'icr' (same kernel, rounding only)."""
    from rrbody.analysis.simulate import simulate

    base = dict(body="ellipse", R0=0.2, delta=0.4, k=2.0, no_drive=True, v0=(0.5, 0.2), spin0=4.0, t_max=0.3)
    a = simulate(scene_from_params(**base, friction_method="icr"))
    b = simulate(scene_from_params(**base, friction_method="contact"))
    assert np.allclose(a.body_angle, b.body_angle, rtol=0, atol=1e-13)
    assert np.allclose(a.x_cm, b.x_cm, rtol=0, atol=1e-13)


def test_a_disk_on_its_rim_spins_down_on_the_ode_path() -> None:
    """The ODE path with ring pressure: pure spin decelerates at mu g R / (R^2 / 2) = 2 mu g / R exactly
    (the integrator's tolerance, 1e-13 default: asked 1e-10)."""
    from rrbody.analysis.simulate import simulate

    R, mu, w0 = 0.2, 0.3, 6.0
    scene = scene_from_params(body="disk", R0=R, mu=mu, g=G, no_drive=True, spin0=w0, pressure=f"ring:{R}",
                              t_max=0.5 * w0 * R / (2 * mu * G))
    traj = simulate(scene)
    alpha = 2 * mu * G / R
    t = traj.t
    assert np.allclose(traj.body_angle, w0 * t - 0.5 * alpha * t ** 2, rtol=0, atol=1e-10)


@pytest.mark.parametrize(("make", "match"), [
    (lambda: rp.ring(-0.1), r"ring radius must be in \[1e-9, 1e6\] m, got -0.1"),
    (lambda: rp.annulus(0.2, 0.1), r"annulus inner radius must be in \[0, 0.1\) m"),
    (lambda: rp.hertz(float("nan")), r"hertz radius a must be in"),
    (lambda: rp.points([(0.0, 0.0, -1.0)]), r"feet\[0\] share must be in \(0, inf\)"),
    (lambda: rp.points([]), r"feet must hold at least one"),
    (lambda: rp.parse_pressure("ring"), r"pressure must be one of uniform, ring:R"),
    (lambda: rp.parse_pressure("ring:x"), r"pressure must be one of"),
    (lambda: rp.parse_pressure("ring:-2"), r"pressure 'ring:-2': ring radius must be"),
])
def test_bad_pressures_name_the_parameter(make: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        make()  # type: ignore[operator]


def test_loads_off_the_body_are_refused() -> None:
    """A ring wider than the body, a foot off it, a field that is negative or integrates to zero."""
    parts = body_parts(Disk(R=0.1))
    with pytest.raises(ValueError, match=r"ring must lie on the body's footprint .* got radius 0.2 m"):
        apply_pressure(parts, rp.ring(0.2))
    with pytest.raises(ValueError, match=r"hertz patch must lie on the body's footprint"):
        apply_pressure(parts, rp.hertz(0.05, centre=(0.08, 0.0)))
    with pytest.raises(ValueError, match=r"feet\[1\] must lie on the body's footprint .* got \(0.2, 0\) m"):
        apply_pressure(parts, rp.points([(0.0, 0.0, 1.0), (0.2, 0.0, 1.0)]))
    with pytest.raises(ValueError, match=r"pressure density must be finite and >= 0 on the footprint, got -1.0"):
        apply_pressure(parts, rp.field(lambda x, y: -np.ones_like(x)))
    with pytest.raises(ValueError, match=r"pressure density must integrate to a positive load"):
        apply_pressure(parts, rp.field(lambda x, y: np.zeros_like(x)))
    with pytest.raises(ValueError, match=r"pressure density p\(x, y\) failed on arrays of points"):
        apply_pressure(parts, rp.field(lambda x, y: 1 / 0))
    with pytest.raises(ValueError, match=r"pressure 'ring' needs an extended body"):
        Scene(body=__import__("rrbody").RodMass(l=0.2), drive=None, pressure=rp.ring(0.1))
    # an ellipse: the ring must fit inside the smaller semi-axis
    with pytest.raises(ValueError, match=r"ring must lie on the body's footprint"):
        apply_pressure(body_parts(Ellipse(R0=0.1, delta=0.5)), rp.ring(0.1))
    apply_pressure(body_parts(Ellipse(R0=0.1, delta=0.5)), rp.ring(0.05))


def test_a_field_pressure_converges_to_the_exact_profile() -> None:
    """field(p) samples p on a Gauss rule: p = const gives the uniform disk, p = sqrt(1 - r^2/R^2) the
    Hertz patch; the error falls as the samples grow (dry friction's kink at the instantaneous
    centre limits it to an algebraic rate), and at 16384 samples it is below 1e-3 (measured)."""
    R = 0.1
    parts = body_parts(Disk(R=R))
    motion = (0.3, 0.1, 2.0)  # the instantaneous centre inside the disk
    cases = [(lambda x, y: np.ones_like(x), "uniform"),
             (lambda x, y: np.sqrt(np.maximum(0.0, 1 - (x * x + y * y) / R ** 2)), rp.hertz(R))]
    for density, exact in cases:
        want = np.array(C.footprint_wrench(*apply_pressure(parts, rp.as_pressure(exact))[:2], 0, 1, *motion, 0.0))
        errs = []
        for n in (1024, 4096, 16384):
            shapes, geo, *_ = apply_pressure(parts, rp.field(density, samples=n))
            got = np.array(C.footprint_wrench(shapes, geo, 0, shapes.shape[0], *motion, 0.0))
            errs.append(float(np.max(np.abs(got - want) / np.array([1, 1, R]))))
        assert errs[-1] < errs[0] and errs[-1] < 1e-3, errs


def test_cli_pressure_runs_and_bad_values_are_one_line(tmp_path: object) -> None:
    from tests.clirun import run_many

    ok, bad, rod = run_many([
        ["simulate", "--body", "disk", "--R0", "0.2", "--no-drive", "--spin0", "3", "--k", "1", "--pressure",
         "ring:0.2", "--t-max", "0.2", "--json"],
        ["simulate", "--body", "disk", "--R0", "0.2", "--no-drive", "--spin0", "3", "--k", "1", "--pressure",
         "ring:0.3", "--t-max", "0.2", "--json"],
        ["simulate", "--H", "0.2", "--omega", "1", "--k", "1", "--pressure", "hertz:0.1", "--t-max", "0.2", "--json"],
    ])
    assert ok.code == 0, ok.err
    assert bad.code == 2 and bad.err.count("\n") == 1 and "ring must lie on the body's footprint" in bad.err
    assert rod.code == 2 and "needs an extended body" in rod.err and "Traceback" not in rod.err


def test_feet_run_on_both_paths_from_the_command_line() -> None:
    """A disk on two feet from the command line: the engine path and the ODE path both run it to rest,
    and the ODE path reports the pivot on a foot it followed (rrbody.integrate.pivot; the two paths
    agree at the plugin's order in tests/test_feet_ode.py)."""
    import json

    from tests.clirun import run_many

    base = ["simulate", "--body", "disk", "--R0", "0.2", "--no-drive", "--v0", "1,0", "--spin0", "5", "--k", "2",
            "--pressure", "points:0.1,0,1;-0.1,0,1", "--t-max", "1", "--json"]
    engine, ode = run_many([[base[0], "--method", "engine", *base[1:]], base])
    assert engine.code == 0, engine.err
    assert ode.code == 0, ode.err
    out = json.loads(ode.out)
    assert out["t_stop"] is not None and [p["ended_by"] for p in out["pivots"]] == ["stop"]
    eng = json.loads(engine.out)
    # the engine path stops on its step grid and follows a pivot at first order in dt: two of its steps
    assert abs(out["t_stop"] - eng["t_stop"]) < 2.0 * eng["meta"]["dt"]
