"""Active bodies in the pymunk plugin (PlaneFriction.activate): exact references (docs/active.md).

- Propulsion F through the centre of gravity, no friction, a spin W: the body turns at W and the
  force with it; the centre of gravity runs on a circle of radius F / (m W^2), period 2 pi / W.
- Propulsion off the centre of gravity, no friction: the spin grows linearly (torque p x F), the path
  is a Cornu-type spiral; reference: its velocity and position as one-dimensional integrals (quad).
- Propulsion off the centre of gravity with linear drag (the medium's, or viscous plane friction: the
  same for a uniform body): the terminal spin W = tau / (I gamma_r) and the circle of radius
  F / (m W sqrt(gamma_t^2 + W^2)), period 2 pi / W.
- Rotational noise with rotational drag only: the spin is an Ornstein-Uhlenbeck process; from w = 0
  the angle's increment is Gaussian with variance V(t) = 2 D_r [t - 2 (1 - e^{-g t})/g + (1 - e^{-2 g t})/(2 g)],
  so <cos(alpha(t) - alpha(0))> = exp(-V/2) -> exp(-D_r t) up to a constant factor for g t >> 1.
- Friction off, no propulsion: collisions conserve the total momentum; dry friction alone never
  raises the kinetic energy; the same seed gives bit-identical runs.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from scipy.integrate import quad

from rrbody.contact import kernel as K
from rrbody.engine.memory.compat import on_begin
from rrbody.engine.plugin.shapes import body_footprint
from rrbody.model.pressure import uniform
from rrbody.plugin import Active, PlaneFriction

M, R = 0.2, 0.05  # kg, m: the test disk


def _disk(space: pymunk.Space, pf: PlaneFriction, *, mu: float = 0.0, pos: tuple[float, float] = (0.0, 0.0),
          r: float = R) -> pymunk.Body:
    b = pymunk.Body()
    s = pymunk.Circle(b, r)
    s.mass = M
    b.position = pos
    space.add(b, s)
    pf.add(b, mu=mu)
    return b


def _l_shape(space: pymunk.Space, pf: PlaneFriction, *, mu: float, pos: tuple[float, float],
             a: float = 0.1) -> pymunk.Body:
    """An L of two boxes (legs 2a x a and a x 2a) on one body, density 20 kg/m^2."""
    b = pymunk.Body()
    shapes = [pymunk.Poly(b, [(0, 0), (2 * a, 0), (2 * a, a), (0, a)]),
              pymunk.Poly(b, [(0, a), (a, a), (a, 3 * a), (0, 3 * a)])]
    for s in shapes:
        s.density = 20.0
    b.position = pos
    space.add(b, *shapes)
    pf.add(b, mu=mu)
    return b


def _order(dts: list[float], errs: list[float]) -> float:
    return float(np.polyfit(np.log(dts), np.log(errs), 1)[0])


# ---- deterministic closed forms ---------------------------------------------------------------
def _circle_through_cm(dt: float) -> tuple[float, float]:
    """(max relative radius error, relative period error) over one period."""
    F, W, a0 = 0.02, 3.0, 0.3
    space = pymunk.Space()
    pf = PlaneFriction(space)
    b = _disk(space, pf)
    rad = F / (M * W * W)
    b.angle, b.angular_velocity = a0, W
    b.velocity = (F / (M * W) * math.sin(a0), -F / (M * W) * math.cos(a0))  # no drift: the circle's centre is fixed
    c = np.array([rad * math.cos(a0), rad * math.sin(a0)])
    pf.activate(b, Active(force=F))
    period = 2 * math.pi / W
    n = int(round(period / dt))
    pts = np.empty((n, 2))
    for k in range(n):
        pf.step(dt)
        pts[k] = tuple(b.position)
    x = pts - c
    th = np.unwrap(np.arctan2(x[:, 1], x[:, 0]))
    slope = np.polyfit(dt * np.arange(1, n + 1), th, 1)[0]  # the orbit's rate, from the positions
    return float(np.max(np.abs(np.hypot(x[:, 0], x[:, 1]) - rad)) / rad), abs(2 * math.pi / slope - period) / period


def test_force_through_the_centre_runs_on_its_circle_to_1e6_second_order() -> None:
    dts = [1 / 800, 1 / 1600, 1 / 3200]
    got = [_circle_through_cm(dt) for dt in dts]
    rad_err = [g[0] for g in got]
    per_err = [g[1] for g in got]
    # the scheme is second order (leapfrog, docs/active.md): slopes of a clean power law, +-0.1
    assert abs(_order(dts, rad_err) - 2.0) < 0.1, rad_err
    assert abs(_order(dts, per_err) - 2.0) < 0.1, per_err
    assert rad_err[-1] < 1e-6 and per_err[-1] < 1e-6, got


def _spiral(dt: float, T: float = 1.0) -> float:
    """Position error at T (m) of an off-centre propulsion without friction, against the integrals."""
    F, ang, p, w0, a0 = 0.02, 0.4, (0.03, -0.01), 1.0, 0.2
    space = pymunk.Space()
    pf = PlaneFriction(space)
    b = _disk(space, pf)
    b.angle, b.angular_velocity, b.velocity = a0, w0, (0.1, -0.05)
    act = Active(force=F, angle=ang, point=p)
    pf.activate(b, act)
    for _ in range(int(round(T / dt))):
        pf.step(dt)
    beta = act.torque / b.moment  # constant angular acceleration, rad/s^2

    def e(s: float, k: int) -> float:
        th = a0 + ang + w0 * s + 0.5 * beta * s * s
        return (T - s) * (math.cos(th) if k == 0 else math.sin(th))

    ref = [v * T + F / M * quad(e, 0.0, T, args=(k,), epsabs=1e-14, epsrel=1e-13)[0] for k, v in enumerate((0.1,
                                                                                                            -0.05))]
    return math.hypot(b.position.x - ref[0], b.position.y - ref[1])


def test_off_centre_force_without_friction_follows_the_spiral_second_order() -> None:
    dts = [1 / 200, 1 / 400, 1 / 800]
    errs = [_spiral(dt) for dt in dts]
    assert abs(_order(dts, errs) - 2.0) < 0.1, errs
    assert errs[-1] < 1e-6, errs  # m, over a path of ~0.15 m


def _terminal_circle(dt: float, plane: bool) -> tuple[float, float]:
    """(relative radius error, relative period error) of the terminal circle under linear drag g."""
    F, g = 0.02, 4.0
    space = pymunk.Space()
    pf = PlaneFriction(space)
    b = pymunk.Body()
    s = pymunk.Circle(b, R)
    s.mass = M
    space.add(b, s)
    if plane:  # viscous plane friction (the builder's law): for a uniform disk gamma_t = gamma_r = g
        pf.add_footprint(b, law=K.LAW_VISCOUS, coeff=g, footprint=body_footprint(b, uniform()), snap=False,
                         history=None)
        act = Active(force=F, angle=math.pi / 2, point=(0.02, 0.0))
    else:
        pf.add(b, mu=0.0)
        act = Active(force=F, angle=math.pi / 2, point=(0.02, 0.0), drag=g, rot_drag=g)
    pf.activate(b, act)
    W = act.torque / (b.moment * g)
    rad = F / (M * W * math.hypot(g, W))
    period = 2 * math.pi / W
    for _ in range(int(round(40 / g / dt))):  # transients decay as exp(-g t): e^-40 left
        pf.step(dt)
    n = int(round(period / dt))
    pts = np.empty((n, 2))
    for k in range(n):
        pf.step(dt)
        pts[k] = tuple(b.position)
    A = np.c_[2 * pts, np.ones(n)]  # the circle's centre: algebraic least-squares fit
    cx, cy, _ = np.linalg.lstsq(A, (pts**2).sum(1), rcond=None)[0]
    th = np.unwrap(np.arctan2(pts[:, 1] - cy, pts[:, 0] - cx))
    slope = np.polyfit(dt * np.arange(n), th, 1)[0]
    return abs(float(np.hypot(pts[:, 0] - cx,
                              pts[:, 1] - cy).mean()) - rad) / rad, abs(2 * math.pi / slope - period) / period


@pytest.mark.parametrize("plane", [False, True], ids=["medium-drag", "viscous-plane"])
def test_terminal_circle_under_linear_drag(plane: bool) -> None:
    dts = [1 / 200, 1 / 400, 1 / 800]
    got = [_terminal_circle(dt, plane) for dt in dts]
    rad_err = [g[0] for g in got]
    assert abs(_order(dts, rad_err) - 2.0) < 0.1, rad_err
    assert rad_err[-1] < 1e-6, rad_err
    # the terminal spin is the scheme's exact fixed point: the period to rounding (1e-12 of a
    # least-squares slope over ~3000 angles)
    assert max(g[1] for g in got) < 1e-11, got


# ---- noise ---------------------------------------------------------------------------------------
def test_rotational_noise_decorrelates_the_orientation_as_exp_minus_dr_t() -> None:
    N, D, G, dt, T = 1000, 0.5, 20.0, 1e-3, 2.0
    space = pymunk.Space()
    pf = PlaneFriction(space)
    pf.seed(7)
    bodies = [_disk(space, pf, pos=(k % 40, k // 40)) for k in range(N)]  # 1 m apart: never touch
    for b in bodies:
        pf.activate(b, Active(force=0.0, rot_drag=G, rot_diffusion=D))
    a0 = np.array([b.angle for b in bodies])
    checks = {500: None, 1000: None, 2000: None}  # steps -> cos(alpha - alpha0) per body
    w2 = []
    for k in range(1, int(round(T / dt)) + 1):
        pf.step(dt)
        if k in checks:
            checks[k] = np.cos(np.array([b.angle for b in bodies]) - a0)
            w2.append(np.mean([b.angular_velocity**2 for b in bodies]))
    for k, c in checks.items():
        t = k * dt
        V = 2 * D * (t - 2 * (1 - math.exp(-G * t)) / G + (1 - math.exp(-2 * G * t)) / (2 * G))
        se = c.std(ddof=1) / math.sqrt(N)  # the statistical error of the mean over N independent bodies
        assert abs(c.mean() - math.exp(-V / 2)) < 4 * se, (t, c.mean(), math.exp(-V / 2), se)
    # the decay rate between t = 0.5 s and 2 s (g t >= 10: the exp(-D_r t) regime): D_r to 4 sigma,
    # sigma from the two means' standard errors (their positive correlation makes this conservative)
    c1, c2 = checks[500], checks[2000]
    d_est = -(math.log(c2.mean()) - math.log(c1.mean())) / 1.5
    sd = math.hypot(c1.std(ddof=1) / c1.mean(), c2.std(ddof=1) / c2.mean()) / math.sqrt(N) / 1.5
    assert abs(d_est - D) < 4 * sd, (d_est, D, sd)
    # the spin's variance D_r g (the stationary OU value; Euler-Maruyama's bias g dt / 2 = 1 %, plus 3 % statistics)
    assert abs(w2[-1] / (D * G) - 1) < 0.05, w2


def test_translational_noise_gives_the_ornstein_uhlenbeck_spread() -> None:
    """Translational noise with drag g only, from rest: each velocity component is an OU process, and
    each displacement component is Gaussian with variance V(t) (the formula of the rotational test, D_t
    in place of D_r), so the mean squared displacement is 2 V(t) -> 4 D_t t."""
    N, D, G, dt = 1000, 1e-4, 20.0, 1e-3
    space = pymunk.Space()
    pf = PlaneFriction(space)
    pf.seed(11)
    bodies = [_disk(space, pf, pos=(k % 40, k // 40)) for k in range(N)]  # 1 m apart, ~0.03 m of spread
    for b in bodies:
        pf.activate(b, Active(force=0.0, drag=G, diffusion=D))
    x0 = np.array([tuple(b.position) for b in bodies])
    for k in range(1, 2001):
        pf.step(dt)
        if k in (500, 2000):
            t = k * dt
            d2 = ((np.array([tuple(b.position) for b in bodies]) - x0) ** 2).sum(1)
            V = 2 * D * (t - 2 * (1 - math.exp(-G * t)) / G + (1 - math.exp(-2 * G * t)) / (2 * G))
            se = d2.std(ddof=1) / math.sqrt(N)  # the statistical error of the mean over N independent bodies
            assert abs(d2.mean() - 2 * V) < 4 * se, (t, d2.mean(), 2 * V, se)
    v2 = np.mean([b.velocity.dot(b.velocity) for b in bodies])
    # stationary OU: <v^2> = 2 D_t g (two components); Euler-Maruyama's bias g dt / 2 = 1 %, statistics ~4.5 %
    assert abs(v2 / (2 * D * G) - 1) < 0.15, v2
    assert all(b.angular_velocity == 0.0 for b in bodies)  # no torque: no spin


def _noisy_run(seed: int, steps: int = 200) -> np.ndarray:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    pf.seed(seed)
    bodies = []
    for k in range(12):
        b = _disk(space, pf, mu=0.3, pos=(0.12 * (k % 4), 0.12 * (k // 4))) if k % 2 else \
            _l_shape(space, pf, mu=0.3, pos=(0.12 * (k % 4), 0.12 * (k // 4)), a=0.03)
        pf.activate(b, Active(force=0.05, angle=1.0, point=(0.01, 0.0), drag=2.0, rot_drag=3.0, diffusion=0.01,
                              rot_diffusion=0.5))
        bodies.append(b)
    for _ in range(steps):
        pf.step(1 / 240)
    return np.array([[*b.position, b.angle, *b.velocity, b.angular_velocity] for b in bodies])


def test_the_same_seed_gives_bit_identical_runs() -> None:
    a, b, c = _noisy_run(3), _noisy_run(3), _noisy_run(4)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)  # the noise acts: another seed, another run


# ---- conservation and dissipation ------------------------------------------------------------------
def test_collisions_without_friction_or_propulsion_conserve_momentum() -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    rng = np.random.default_rng(5)
    bodies = []
    for k in range(30):
        pos = (0.25 * (k % 6), 0.25 * (k // 6))
        b = _disk(space, pf, pos=pos, r=0.08) if k % 2 else _l_shape(space, pf, mu=0.0, pos=pos, a=0.05)
        b.velocity = tuple(rng.normal(0, 0.5, 2))
        b.angular_velocity = rng.normal(0, 3)
        pf.activate(b, Active(force=0.0))  # active, with nothing to add
        bodies.append(b)

    def momentum() -> np.ndarray:
        return sum(np.array(b.velocity) * b.mass for b in bodies)

    p0 = momentum()
    scale = sum(b.mass * abs(b.velocity) for b in bodies)
    hits = []
    on_begin(space, None, None, lambda arb, sp, data: hits.append(1))
    for _ in range(600):
        pf.step(1 / 240)
    assert len(hits) > 20  # the bodies did collide
    # equal and opposite impulses: the total changes by rounding only (1e-13 of the momenta's scale)
    assert np.max(np.abs(momentum() - p0)) < 1e-13 * scale, (momentum(), p0)


def test_dry_friction_never_raises_the_kinetic_energy_without_contacts_or_propulsion() -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    rng = np.random.default_rng(9)
    bodies = []
    for k in range(20):
        pos = (1.0 * (k % 5), 1.0 * (k // 5))  # 1 m apart: no contacts
        b = _disk(space, pf, mu=0.4, pos=pos) if k % 2 else _l_shape(space, pf, mu=0.4, pos=pos, a=0.05)
        b.velocity = tuple(rng.normal(0, 0.3, 2))
        b.angular_velocity = rng.normal(0, 8)
        bodies.append(b)

    def energy() -> float:
        return sum(0.5 * b.mass * b.velocity.dot(b.velocity) + 0.5 * b.moment * b.angular_velocity**2 for b in bodies)

    e = [energy()]
    for _ in range(400):
        pf.step(1 / 240)
        e.append(energy())
    assert e[-1] == 0.0 or e[-1] < 1e-6 * e[0]  # they come to rest
    # never up: to rounding of the sum (1e-15 relative per term)
    assert all(b <= a * (1 + 1e-14) for a, b in zip(e, e[1:])), np.diff(e).max()


# ---- bad input ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kw,match", [
    ({"force": -1.0}, r"force must be in \[0, 1e\+?0?9\] N, got -1.0"),
    ({"force": math.nan}, "force must be"),
    ({"force": 1.0, "angle": math.inf}, "angle must be a finite real number"),
    ({"force": 1.0, "point": (1.0,)}, "point must be a pair"),
    ({"force": 1.0, "point": (0.0, 2e6)}, r"point\[1\] must be in"),
    ({"force": 1.0, "drag": -2.0}, "drag must be in"),
    ({"force": 1.0, "rot_drag": math.inf}, "rot_drag must be in"),
    ({"force": 1.0, "diffusion": 0.1}, "diffusion > 0 needs drag > 0"),
    ({"force": 1.0, "rot_diffusion": 0.1}, "rot_diffusion > 0 needs rot_drag > 0"),
    ({"force": 1.0, "rot_drag": 1.0, "rot_diffusion": -0.1}, "rot_diffusion must be in"),
])
def test_bad_parameters_name_themselves(kw: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        Active(**kw)


def test_activate_and_seed_refuse_bad_input() -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    b = pymunk.Body(1.0, 1.0)
    with pytest.raises(ValueError, match="must be added to the PlaneFriction first"):
        pf.activate(b, Active(force=1.0))
    b2 = _disk(space, pf)
    with pytest.raises(ValueError, match="active must be an rrbody.plugin.Active"):
        pf.activate(b2, {"force": 1.0})  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"seed must be an integer in \[0, "):
        pf.seed(-1)
