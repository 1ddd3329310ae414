"""PlaneFriction in plain pymunk programs: the user's own bodies and shapes, exact references.

References: the disk's Farkas ratio from the closed-form wrench (rrbody.physics.area), the square's
spin torque a (sqrt2 + ln(1 + sqrt2))/6, constant-deceleration kinematics, and the independent polar
quadrature of tests/test_polygon.py for an L-shaped body.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from scipy.optimize import brentq

from rrbody.engine import PlaneFriction
from rrbody.engine.memory.batchio import ROUTES, BatchIO, batch_reads
from rrbody.physics.area import disk_closed_form_ratio
from rrbody.physics.polygon import box_spin_torque
from tests.test_polygon import L_PARTS, reference

G = 9.81
pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")


def _space_with(shape_factory, *, mu: float = 0.5, v=(0.0, 0.0), w: float = 0.0, angle: float = 0.0):  # noqa: ANN001, ANN202
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    body = pymunk.Body()
    shapes = shape_factory(body)
    for s in shapes:
        s.density = 2.0
    space.add(body, *shapes)
    body.angle = angle
    body.velocity = v
    body.angular_velocity = w
    pf.add(body, mu=mu)
    return space, pf, body


def _at_rest(b: pymunk.Body) -> bool:
    return b.velocity == (0.0, 0.0) and b.angular_velocity == 0.0


def _run_to_rest(pf: PlaneFriction, b: pymunk.Body, dt: float, hist: list | None = None, max_steps: int = 100_000):  # noqa: ANN202
    n = 0
    while not _at_rest(b):
        pf.step(dt)
        if hist is not None:
            hist.append((pf.t, *pf.velocity(b)))
        n += 1
        assert n < max_steps
    return n


# ---- the done-when physics --------------------------------------------------------------------
def test_disk_stops_sliding_and_spinning_together_at_the_farkas_ratio() -> None:
    """A Circle launched sliding and spinning: v/(R Omega) is attracted to eps* with f(eps*) = 2 eps* t(eps*)
    (Farkas et al. 2003: 0.653), from below and from above; both motions end in the same step and the
    disk then stays exactly at rest."""
    f = lambda e: disk_closed_form_ratio(e)[0] - 2 * e * disk_closed_form_ratio(e)[1]  # noqa: E731
    eps_star = brentq(f, 0.1, 2.0, xtol=1e-14)
    assert eps_star == pytest.approx(0.653, abs=5e-4)
    R, w0, dt = 0.1, 20.0, 2.5e-4
    last = []
    for e0 in (0.3, 2.0):
        space, pf, b = _space_with(lambda b: [pymunk.Circle(b, R)], v=(e0 * R * w0, 0.0), w=w0)
        hist: list = []
        _run_to_rest(pf, b, dt, hist)
        full = np.array(hist)
        # the last steps are the limiter's and the rest rule's (every point within ~mu g dt of rest):
        # there the discrete impulse, not the flow, sets the ratio
        h = full[:-3]
        eps = np.hypot(h[:, 1], h[:, 2]) / (R * h[:, 3])
        # neither motion stops first: the ratio stays finite and moves monotonically toward eps*
        assert np.all(np.isfinite(eps)) and np.all(h[:, 3] > 0)
        d = np.diff(eps)
        assert np.all(d > 0) if e0 < eps_star else np.all(d < 0)
        # measured: 0.3 -> 0.60 and 2.0 -> 0.66 (the approach is a slow power of Omega, ~Omega^0.23)
        assert abs(eps[-1] - eps_star) < 0.2 * abs(e0 - eps_star)
        last.append(eps[-1])
        # both stop together: in the final steps every point is slower than ~mu g dt, then exactly 0
        tail = full[-3:]
        assert np.all(np.hypot(tail[:, 1], tail[:, 2]) + R * np.abs(tail[:, 3]) < 2 * 0.5 * G * dt)
        assert np.all(full[-1, 1:] == 0.0)
        pos, ang = b.position, b.angle
        for _ in range(2000):
            pf.step(dt)
        assert b.position == pos and b.angle == ang and _at_rest(b)
    assert last[0] < eps_star < last[1]


def test_box_in_pure_spin_decelerates_at_the_exact_rate() -> None:
    """Poly.create_box of side a in pure spin: torque mu m g a (sqrt2 + ln(1+sqrt2))/6 (to 1e-9 asked;
    rounding measured), deceleration mu g (sqrt2 + ln(1+sqrt2))/a; the staggered scheme is exact for
    constant deceleration, and the final partial step errs by at most alpha dt^2/8 in the total turn."""
    a, mu, w0 = 0.2, 0.5, 10.0
    alpha = mu * G * (math.sqrt(2) + math.log1p(math.sqrt(2))) / a
    for dt in (2e-3, 1e-3, 5e-4):
        space, pf, b = _space_with(lambda b: [pymunk.Poly.create_box(b, (a, a))], mu=mu, w=w0)
        fx, fy, tq = pf.wrench(b)
        assert tq == pytest.approx(-mu * b.mass * G * box_spin_torque(a), rel=1e-9)
        assert abs(fx) < 1e-12 and abs(fy) < 1e-12
        assert b.moment == pytest.approx(b.mass * a * a / 6, rel=1e-12)
        worst = 0.0
        while not _at_rest(b):
            pf.step(dt)
            if pf.t < w0 / alpha - 2 * dt:
                worst = max(worst, abs(b.angle - (w0 * pf.t - 0.5 * alpha * pf.t ** 2)))
        assert worst < 1e-12  # measured 2e-15 .. 6e-15 rad
        # the stop step as for sliding (next test): within alpha dt^2/8 (measured 4.0e-6, 4.0e-6, 4.2e-7 rad)
        assert abs(b.angle - w0 ** 2 / (2 * alpha)) <= alpha * dt ** 2 / 8
        assert b.position == (0.0, 0.0)


def test_box_sliding_without_spin_stops_after_v0_squared_over_2_mu_g() -> None:
    a, mu, v0 = 0.2, 0.5, (1.0, 0.7)
    speed = math.hypot(*v0)
    for dt in (2e-3, 1e-3, 5e-4):
        space, pf, b = _space_with(lambda b: [pymunk.Poly.create_box(b, (a, a))], mu=mu, v=v0, angle=0.3)
        _run_to_rest(pf, b, dt)
        d = math.hypot(*b.position)
        # second order: the steps before the stop are exact (leapfrog, constant deceleration a = mu g);
        # the stop step moves v = v_{n+1/2} <= a dt dt and cancels v, where the exact motion from t_n had
        # (v + a dt/2)^2 / (2 a) left: the difference (v - a dt/2)^2 / (2 a) <= a dt^2 / 8
        # (measured 1.8e-6, 4.8e-8, 4.8e-8 m); the stop time is within one step
        assert abs(d - speed ** 2 / (2 * mu * G)) <= mu * G * dt ** 2 / 8
        assert abs(pf.stop_time(b) - speed / (mu * G)) <= dt
        assert b.angle == 0.3
        assert b.position.x / b.position.y == pytest.approx(v0[0] / v0[1], rel=1e-13)


@pytest.mark.parametrize("motion", [(0.3, 0.2, 1.0), (1.0, -0.5, 0.7), (0.05, 0.9, -2.0), (4.0, 1.0, 0.2)])
def test_l_shaped_body_gets_the_wrench_of_its_exact_area(motion: tuple) -> None:
    """Two Poly boxes on one body (a non-convex L), at an angle, against the independent quadrature."""
    body = pymunk.Body()
    shapes = [pymunk.Poly(body, [tuple(p) for p in part]) for part in L_PARTS]
    for s in shapes:
        s.density = 1.5
    space = pymunk.Space()
    space.add(body, *shapes)
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=0.3)
    cog = np.array(body.center_of_gravity)
    alpha = 0.7
    vx_b, vy_b, w = motion  # body frame, at the centre of gravity
    ca, sa = math.cos(alpha), math.sin(alpha)
    got = pf.wrench(body, velocity=(ca * vx_b - sa * vy_b, sa * vx_b + ca * vy_b, w), angle=alpha)
    ref = reference([p - cog for p in L_PARTS], vx_b, vy_b, w) * 0.3 * G * body.mass
    ref_world = (ca * ref[0] - sa * ref[1], sa * ref[0] + ca * ref[1], ref[2])
    scale = 0.3 * G * body.mass
    assert np.max(np.abs(np.array(got) - ref_world)) / scale < 1e-12


# ---- rest, energy, the user's program --------------------------------------------------------
def test_friction_never_adds_energy_and_bodies_stay_at_rest() -> None:
    """Disks, boxes, a thick segment and an L in one space (no contacts): kinetic energy never rises,
    every body stops and stays bit-identically at rest."""
    rng = np.random.default_rng(3)
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    bodies = []
    for i in range(8):
        b = pymunk.Body()
        b.position = (3.0 * i, 0.0)
        kind = i % 4
        shapes = {0: lambda: [pymunk.Circle(b, 0.2)], 1: lambda: [pymunk.Poly.create_box(b, (0.3, 0.5))],
                  2: lambda: [pymunk.Segment(b, (-0.3, 0), (0.3, 0), 0.1)],
                  3: lambda: [pymunk.Poly(b, [tuple(p / 4) for p in part]) for part in L_PARTS]}[kind]()
        for s in shapes:
            s.density = 1.0
        space.add(b, *shapes)
        b.velocity = tuple(rng.normal(size=2))
        b.angular_velocity = float(rng.normal() * 10)
        pf.add(b, mu=0.4)
        bodies.append(b)
    ke = [sum(b.kinetic_energy for b in bodies)]
    for _ in range(2000):
        pf.step(1e-3)
        ke.append(sum(b.kinetic_energy for b in bodies))
    assert max(np.diff(ke)) <= 0.0
    assert all(_at_rest(b) for b in bodies)
    state = [(b.position, b.angle) for b in bodies]
    for _ in range(500):
        pf.step(1e-3)
    assert state == [(b.position, b.angle) for b in bodies]


def test_other_bodies_and_user_forces_are_untouched() -> None:
    """Bodies outside the plugin keep their motion; a user's force on a plugin body still acts."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    ball = pymunk.Body(1.0, 1.0)
    ball.velocity = (1.0, 0.0)
    wall = space.static_body
    space.add(ball, pymunk.Circle(ball, 0.1), pymunk.Segment(wall, (-5, -5), (5, -5), 0.1))
    b = pymunk.Body()
    sh = pymunk.Circle(b, 0.1)
    sh.density = 1.0
    b.position = (0.0, 3.0)
    space.add(b, sh)
    pf.add(b, mu=0.5)
    push = 2.0 * 0.5 * G * b.mass  # twice the sliding friction
    for _ in range(1000):
        b.apply_force_at_local_point((push, 0.0))
        pf.step(1e-3)
    assert ball.velocity == (1.0, 0.0) and ball.position.x == pytest.approx(1.0, rel=1e-12)
    # net acceleration (push - mu m g)/m = mu g: v = mu g t after 1 s (first step's half kick: exact)
    assert pf.velocity(b)[0] == pytest.approx(0.5 * G * 1.0, rel=1e-3)


def test_add_remove_and_bodies() -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    made = []
    for i in range(3):
        b = pymunk.Body()
        s = pymunk.Circle(b, 0.1)
        s.density = 1.0
        b.position = (0.0, float(i))  # apart: no contacts
        space.add(b, s)
        b.velocity = (1.0, 0.0)
        pf.add(b, mu=0.5)
        made.append(b)
    assert pf.bodies == tuple(made)
    pf.step(1e-3)
    pf.remove(made[1])
    assert pf.bodies == (made[0], made[2])
    v1 = made[1].velocity
    for _ in range(10):
        pf.step(1e-3)
    assert made[1].velocity == v1  # no friction any more
    assert made[0].velocity.x < 1.0 and made[0].velocity == made[2].velocity
    space.remove(made[0], *made[0].shapes)  # a body leaving the space must leave the plugin too
    with pytest.raises(ValueError, match=r"pf.bodies\[0\] .* is no longer in the space.*pf.remove\(body\)"):
        pf.step(1e-3)
    pf.remove(made[0])
    pf.step(1e-3)
    with pytest.raises(ValueError, match="body is not in this PlaneFriction"):
        pf.remove(made[1])


def test_segment_footprint_and_mass_from_density() -> None:
    space, pf, b = _space_with(lambda b: [pymunk.Segment(b, (-0.5, 0.0), (0.5, 0.0), 0.1)], v=(1.0, 0.0))
    from rrbody.physics import contact as C

    shapes = pf._geo[0][0]
    stadium = 1.0 * 0.2 + math.pi * 0.01
    assert shapes[0, C.AREA] == pytest.approx(stadium, rel=7e-3)  # polygonal caps: 16 edges each
    fx, fy, tq = pf.wrench(b)
    assert fx == pytest.approx(-0.5 * G * b.mass, rel=1e-14) and abs(tq) < 1e-14


def test_every_batch_route_reads_and_writes_a_body() -> None:
    space, pf, b = _space_with(lambda b: [pymunk.Poly.create_box(b, (0.2, 0.3))], v=(1.0, 0.2), w=3.0)
    for route in ROUTES if batch_reads() else ("per-body",):
        io = BatchIO(space, route=route)
        got, ids, out = io.read()
        assert ids[0] == b.id and got[0, 1] == 1.0 and got[0, 3] == 3.0
        out[0] = (1.0, 2.0, 3.0)
        io.write_forces()
        assert b.force == (1.0, 2.0) and b.torque == 3.0


def test_bad_input() -> None:
    space = pymunk.Space()
    with pytest.raises(ValueError, match="space must be a pymunk.Space"):
        PlaneFriction("space")
    with pytest.raises(ValueError, match=r"g must be in \[1e-6, 1e6\] m/s\^2, got 0.0"):
        PlaneFriction(space, g=0.0)
    pf = PlaneFriction(space)
    b = pymunk.Body()
    s = pymunk.Circle(b, 0.1)
    s.density = 1.0
    with pytest.raises(ValueError, match="body must be added to the PlaneFriction's space"):
        pf.add(b, mu=0.5)
    space.add(b, s)
    with pytest.raises(ValueError, match=r"mu must be 0 or in"):
        pf.add(b, mu=-1.0)
    with pytest.raises(ValueError,
                       match="pressure must be one of uniform, ring:R, annulus:RIN,ROUT, hertz:A or points"):
        pf.add(b, mu=0.5, pressure="parabolic")
    with pytest.raises(ValueError, match="body must be a pymunk.Body"):
        pf.add("body", mu=0.5)
    with pytest.raises(ValueError, match="body must be a dynamic"):
        pf.add(space.static_body, mu=0.5)
    line = pymunk.Body()
    seg = pymunk.Segment(line, (0, 0), (1, 0), 0.0)
    seg.density = 1.0
    line.moment = 1.0
    line.mass = 1.0
    space.add(line, seg)
    with pytest.raises(ValueError, match="at least one shape with area"):
        pf.add(line, mu=0.5)
    with pytest.raises(ValueError, match="dt must be a number > 0"):
        pf.step(0.0)



def test_topdown_example_runs_to_rest(tmp_path) -> None:  # noqa: ANN001
    """scenes/topdown.py, the copyable example: both bodies stop within its 5 s and it says when."""
    import importlib.util
    import json
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "scenes" / "topdown.py"
    spec = importlib.util.spec_from_file_location("topdown", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.main(tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    for name in ("puck", "box"):
        # the slower stop: the puck, 2.06 m/s at mu g = 2.94 m/s^2, spinning: ~0.85 s (measured)
        assert 0.0 < summary[name]["stopped_at_s"] < 5.0


def test_collision_scene_counts_episodes() -> None:
    """The collisions scene's episode rule on a synthetic phi(t): a fall of more than pi while phi' < 0,
    marked as starting at a collision if a contact began within COLLISION_WINDOW before it."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "scenes" / "collisions.py"
    spec = importlib.util.spec_from_file_location("collisions", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    t = np.linspace(0.0, 30.0, 3001)
    phid = np.where((t > 5) & (t < 10), -1.0, 0.5) + np.where((t > 20) & (t < 20.5), -1.5, 0.0)
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (phid[1:] + phid[:-1]) * np.diff(t))])
    eps = mod._episodes(t, phi, phid, hits=[4.5, 19.0])
    assert len(eps) == 1  # the second dip falls by ~0.5 rad only
    assert eps[0]["starts_at_collision"] and eps[0]["t_start"] == pytest.approx(5.0, abs=0.02)
    assert eps[0]["turns_back"] == pytest.approx(5.0 / (2 * math.pi), rel=1e-2)
    assert not mod._episodes(t, phi, phid, hits=[1.0])[0]["starts_at_collision"]


@pytest.mark.parametrize("scheme", ["coupled", "split"])
@pytest.mark.parametrize("steps", [(1e-3, 2e-3), (1e-3, 2e-3, 0.5e-3, 3e-3)])
def test_a_step_that_changes_size_keeps_the_stop_exact(scheme: str, steps: tuple[float, ...]) -> None:
    """dt changed from step to step (alternating 1 and 2 ms, and an irregular cycle): a box launched at 1 m/s
    on mu 0.5 stops at v0^2 / (2 mu g) within mu g dt^2 / 8 for the largest step, the bound of a constant
    step (it stopped 3.3e-4 m long when each step's kick ignored the change); a square's spin-down too."""
    import pymunk

    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    box = pymunk.Body()
    shape = pymunk.Poly.create_box(box, (0.1, 0.1))
    shape.density = 100.0
    space.add(box, shape)
    box.velocity = (1.0, 0.0)
    spin = pymunk.Body()
    sq = pymunk.Poly.create_box(spin, (0.2, 0.2))
    sq.density = 100.0
    spin.position = (5.0, 0.0)
    space.add(spin, sq)
    spin.angular_velocity = 10.0
    pf = PlaneFriction(space, g=9.81, scheme=scheme)
    pf.add(box, mu=0.5)
    pf.add(spin, mu=0.5)
    k = 0
    while pf.t < 0.5:
        pf.step(steps[k % len(steps)])
        k += 1
    bound = 0.5 * 9.81 * max(steps) ** 2 / 8
    assert box.position.x == pytest.approx(1.0 / (2 * 0.5 * 9.81), abs=bound)
    # mu g (sqrt 2 + ln(1 + sqrt 2)) / a, a the side
    alpha = 0.5 * 9.81 * (math.sqrt(2) + math.log1p(math.sqrt(2))) / 0.2
    turn = 10.0 ** 2 / (2 * alpha)
    assert spin.angle == pytest.approx(turn, abs=alpha * max(steps) ** 2 / 8)


def test_step_refuses_a_dt_that_is_not_a_number() -> None:
    """``pf.step("0.01")`` is a ValueError naming dt and its value (it was a TypeError from the comparison),
    and nothing changes."""
    import pymunk

    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    b = pymunk.Body()
    s = pymunk.Circle(b, 0.1)
    s.density = 1.0
    space.add(b, s)
    b.velocity = (1.0, 0.0)
    pf = PlaneFriction(space)
    pf.add(b, mu=0.3)
    for bad in ("0.01", None, [0.01]):
        with pytest.raises(ValueError, match=r"dt must be a number > 0 s and finite, got "):
            pf.step(bad)
    assert pf.t == 0.0 and b.position == (0.0, 0.0)
