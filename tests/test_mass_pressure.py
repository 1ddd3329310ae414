"""Pressure follows the mass: each shape presses with its own weight over its own area, and a centre
of gravity set elsewhere gets the linear pressure that puts the centre of pressure there (or a
ValueError naming the body where none is non-negative: it would tip). The pymunk plugin and
rrbody.planar; the MuJoCo adapter is tests/test_mass_pressure_mujoco.py.

The exact reference of a pure translation: every element slides along v, so the friction force is
-mu m g v_hat whatever the pressure, and the torque about the centre of gravity is -mu m g (P x v_hat),
P the centre of pressure from it: zero exactly when P is the centre of gravity.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pymunk = pytest.importorskip("pymunk")

from rrbody import planar  # noqa: E402
from rrbody.engine.plugin.shapes import body_footprint, body_parts  # noqa: E402
from rrbody.model.pressure import ring, uniform  # noqa: E402
from rrbody.physics import contact as C  # noqa: E402
from rrbody.physics.footprint import apply_pressure, combine  # noqa: E402
from rrbody.physics.loads import CENTRE_TOL  # noqa: E402
from rrbody.plugin import PlaneFriction  # noqa: E402

G, MU = 9.81, 0.5
S = 30.0  # gym-pusht's scale: a 120 x 30 bar and a 30 x 90 stem (areas 3600 and 2700)
BAR = [(-2 * S, S), (2 * S, S), (2 * S, 0.0), (-2 * S, 0.0)]
STEM = [(-S / 2, S), (-S / 2, 4 * S), (S / 2, 4 * S), (S / 2, S)]


def tee(how: str) -> tuple:
    """gym-pusht's T: "gym" as it builds it (body mass 1 set by hand, shapes of no mass, the centre of
    gravity set by hand midway between the bars' centroids: equal masses), "masses" with mass 1 on each
    bar (pymunk puts the centre of gravity there itself)."""
    if how == "gym":
        body = pymunk.Body(1.0, 1e4)
        bar, stem = pymunk.Poly(body, BAR), pymunk.Poly(body, STEM)
        body.center_of_gravity = (bar.center_of_gravity + stem.center_of_gravity) / 2
    else:
        body = pymunk.Body()
        bar, stem = pymunk.Poly(body, BAR), pymunk.Poly(body, STEM)
        bar.mass = stem.mass = 1.0
    space = pymunk.Space()
    space.add(body, bar, stem)
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=MU)
    return space, pf, body


def centre_of_pressure(shapes: np.ndarray, geo: np.ndarray) -> tuple[float, np.ndarray]:
    """(load, centre of pressure) of footprint rows, integrated independently of the kernel's sums: a
    Gauss rule of 12 points per direction on each polygon (exact for the linear pressure's moments)
    and the points' own positions."""
    from rrbody.physics.polygon import gauss_rule

    load, mom = 0.0, np.zeros(2)
    for row in shapes:
        if row[C.KIND] == C.POLYGON:
            v = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]
            q = gauss_rule(v, 12)
            p = row[C.LOAD_SHARE] / row[C.AREA] * (1.0 + row[C.SLOPE_X] * (q[:, 0] - row[C.CENTRE_X])
                                                   + row[C.SLOPE_Y] * (q[:, 1] - row[C.CENTRE_Y]))
            load += float(q[:, 2] @ p)
            mom += (q[:, 2] * p) @ q[:, :2]
        else:
            load += row[C.LOAD_SHARE]
            mom += row[C.LOAD_SHARE] * row[[C.CENTRE_X, C.CENTRE_Y]]
    return load, mom / load


# ---- the T: slides straight ------------------------------------------------------------------
@pytest.mark.parametrize("how", ["gym", "masses"])
@pytest.mark.parametrize("v", [(1.0, 0.3), (-0.2, 2.0), (0.0, -1.0)])
def test_the_tee_translating_feels_no_torque(how: str, v: tuple) -> None:
    """Pure translation: force -mu m g v_hat and zero torque about the centre of gravity (closed form)."""
    _, pf, body = tee(how)
    speed = math.hypot(*v)
    fx, fy, tq = pf.wrench(body, velocity=(v[0], v[1], 0.0), angle=0.4)
    scale = MU * G * body.mass
    # the translation kernels return -v_hat itself: exact but for the rounding of v / |v|
    assert fx == pytest.approx(-scale * v[0] / speed, rel=1e-15, abs=1e-15 * scale)
    assert fy == pytest.approx(-scale * v[1] / speed, rel=1e-15, abs=1e-15 * scale)
    # the centre of pressure is the centre of gravity to the rounding of the moment solve (~1e-16 of the
    # T's 120 size); the lever-arm scale is mu m g x 120
    assert abs(tq) <= 1e-14 * scale * 4 * S


def test_the_tee_spread_by_area_would_turn() -> None:
    """The old loading (by area, the centre of pressure at the area centroid, 30/7 below the centre of
    gravity) has torque -mu m g (P x v_hat) != 0: the test above can fail."""
    _, _, body = tee("gym")
    shapes, geo, *_ = apply_pressure(body_parts(body), uniform())  # no balance: the load where the areas put it
    py = (3600 * 15.0 + 2700 * 75.0) / 6300 - 45.0  # area centroid - centre of gravity (body frame): -30/7
    load, P = centre_of_pressure(shapes, geo)
    assert load == pytest.approx(1.0, rel=1e-14) and P == pytest.approx([0.0, py], abs=1e-12)
    _, _, tq = C.footprint_wrench(shapes, geo, 0, shapes.shape[0], 1.0, 0.0, 0.0, 0.0)
    assert tq == pytest.approx(py, rel=1e-13)  # -(P x x_hat) = P_y: -4.3 m per unit load, far from 0


@pytest.mark.parametrize("how", ["gym", "masses"])
def test_the_tee_slides_straight_to_rest(how: str) -> None:
    """Pushed at an angle, it slides to rest without turning (the old loading turned it: previous test);
    the stop distance is v^2 / (2 mu g) to the staggered scheme's order."""
    space, pf, body = tee(how)
    body.angle = 0.4
    body.velocity = (2.4, -1.8)  # 3 m/s
    pf.add(body, mu=MU)  # re-read at the new pose and velocity
    p0 = body.local_to_world(body.center_of_gravity)
    dt = 1e-3
    for _ in range(2000):
        pf.step(dt)
    assert pf.stop_time(body) is not None
    # the torque is ~1e-14 of mu m g x size each step: the angle moves by less than 1e-12 rad
    assert abs(body.angle - 0.4) < 1e-12 and abs(body.angular_velocity) < 1e-12
    d = (body.local_to_world(body.center_of_gravity) - p0).length
    assert abs(d - 9.0 / (2 * MU * G)) <= MU * G * dt ** 2 / 8 + 1e-12  # test_plugin's stop-distance bound


# ---- each shape its own weight -----------------------------------------------------------------
def _mixed() -> tuple:
    """A box (density 1), a circle (density 5) and a thick segment (mass 0.7): unequal densities."""
    body = pymunk.Body()
    box = pymunk.Poly.create_box(body, (0.2, 0.1))
    disk = pymunk.Circle(body, 0.05, (0.15, 0.02))
    seg = pymunk.Segment(body, (-0.2, -0.1), (-0.05, -0.12), 0.02)
    box.density, disk.density, seg.mass = 1.0, 5.0, 0.7
    space = pymunk.Space()
    space.add(body, box, disk, seg)
    return space, body, (box, disk, seg)  # (the space too: a freed space takes its shapes' masses away)


def test_each_shape_presses_with_its_own_weight() -> None:
    _space, body, shapes3 = _mixed()
    shapes, geo, _, (gx, gy), _ = body_footprint(body)
    total = sum(s.mass for s in shapes3)
    # rows in the footprint's stable order: circle, segment, polygon (rrbody.engine.plugin.shapes)
    assert shapes[:, C.LOAD_SHARE] == pytest.approx([shapes3[1].mass / total, shapes3[2].mass / total,
                                                 shapes3[0].mass / total], rel=1e-14)
    assert not np.any(shapes[shapes[:, C.KIND] == C.POLYGON][:, [C.SLOPE_X, C.SLOPE_Y]])  # no tilt: the CG is theirs
    # total load 1 (x m g) and its centre at the centre of gravity: the segment's polygonal stadium keeps
    # its centroid at the segment's middle, so to rounding
    load, P = centre_of_pressure(shapes, geo)
    assert load == pytest.approx(1.0, rel=1e-14) and np.hypot(*P) < 1e-15
    assert math.hypot(gx, gy) < 1e-15  # the footprint's own load-weighted mean agrees


def test_one_density_keeps_the_area_shares_bit_for_bit() -> None:
    body = pymunk.Body()
    parts = [pymunk.Poly(body, BAR), pymunk.Poly(body, STEM), pymunk.Circle(body, 10.0, (0.0, -10.0))]
    for p in parts:
        p.density = 2.5
    space = pymunk.Space()
    space.add(body, *parts)
    got = body_footprint(body)  # (space still alive: it holds the shapes' masses on the body)
    bare = body_parts(body)
    for p in bare:
        p[0][C.LOAD_SHARE] = 0.0  # no masses: the area shares of before
    old = combine(bare)
    assert np.array_equal(got[0], old[0]) and np.array_equal(got[1], old[1])


def test_a_pressure_profile_is_taken_as_given() -> None:
    """A ring (a stated load) ignores the shapes' masses and the centre of gravity: as before."""
    _space, body, _ = _mixed()
    got = body_footprint(body, ring(0.005))  # (the centre of gravity lies 1.2 cm inside the 2 cm segment)
    assert got[0].shape[0] == 1 and got[0][0, C.KIND] == C.RING and got[0][0, C.LOAD_SHARE] == 1.0


def test_a_footprint_table_carries_the_mass_shares() -> None:
    """friction_method="table" on a T of bars of masses 1 and 3 (shares 1/4, 3/4, no tilt): within 1e-10 of
    the exact wrench (the table's stated accuracy, units mu m g and mu m g x reach), docs/footprint-table.md."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    bodies = []
    for _ in range(2):
        body = pymunk.Body()
        bar, stem = pymunk.Poly(body, [(x / S * 0.03, y / S * 0.03) for x, y in BAR]), \
            pymunk.Poly(body, [(x / S * 0.03, y / S * 0.03) for x, y in STEM])  # in metres: a 0.12 m T
        bar.mass, stem.mass = 1.0, 3.0
        space.add(body, bar, stem)
        bodies.append(body)
    pf.add(bodies[0], mu=MU, friction_method="table")
    pf.add(bodies[1], mu=MU)
    rng = np.random.default_rng(5)
    scale, reach = MU * G * 4.0, 0.12
    worst = 0.0
    for _ in range(100):
        v = (float(rng.normal()), float(rng.normal()), float(rng.choice([-1, 1]) * 10.0 ** rng.uniform(-1, 2)))
        a, e = (np.array(pf.wrench(b, velocity=v, angle=0.3)) for b in bodies)
        worst = max(worst, *(np.abs(a - e) / [scale, scale, scale * reach]))
    assert worst < 1e-10


# ---- a centre of gravity set by hand: the linear pressure ---------------------------------------
W, H = 0.3, 0.1


def _box_cg(e: float) -> tuple:
    """A W x H box of mass 2 set by hand (shape of no mass), its centre of gravity moved e along x."""
    body = pymunk.Body(2.0, 0.05)
    shape = pymunk.Poly.create_box(body, (W, H))
    body.center_of_gravity = (e, 0.0)
    space = pymunk.Space()
    space.add(body, shape)
    return space, body


@pytest.mark.parametrize("e", [0.01, -0.03, 0.99 * W / 6])
def test_a_centre_of_gravity_set_by_hand_gets_the_linear_pressure(e: float) -> None:
    """p = a + b x with b/a = 12 e / W^2 puts the centre of pressure at e (closed form: Int x^2 dA = W^3 H / 12);
    pure translation then has no torque."""
    space, body = _box_cg(e)
    shapes, geo, *_ = body_footprint(body)
    assert shapes[0, C.SLOPE_X] == pytest.approx(12.0 * e / W ** 2, rel=1e-12) and abs(shapes[0, C.SLOPE_Y]) < 1e-12
    load, P = centre_of_pressure(shapes, geo)
    assert load == pytest.approx(1.0, rel=1e-14) and np.hypot(*P) < 1e-15
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=MU)
    _, _, tq = pf.wrench(body, velocity=(0.3, -0.7, 0.0), angle=0.0)
    assert abs(tq) < 1e-14 * MU * G * 2.0 * W


def test_a_centre_of_gravity_past_the_middle_third_tips() -> None:
    """Beyond |e| = W/6 (the kern) the linear pressure would be negative at the far edge: ValueError naming
    the body, saying why; nothing is added."""
    space, body = _box_cg(1.01 * W / 6)
    pf = PlaneFriction(space, g=G)
    with pytest.raises(ValueError, match=r"body .*Body.*tip") as err:
        pf.add(body, mu=MU)
    assert "centre of gravity" in str(err.value) and pf.bodies == ()


def test_a_centre_of_gravity_within_tolerance_is_left_alone() -> None:
    """An offset below CENTRE_TOL x reach (rounding of the sums that place it) changes nothing."""
    _, body = _box_cg(0.5 * CENTRE_TOL * math.hypot(W, H) / 2)  # half the tolerance x the reach
    shapes, *_ = body_footprint(body)
    assert shapes[0, C.SLOPE_X] == 0.0 and shapes[0, C.SLOPE_Y] == 0.0


def test_a_tilted_circle_and_a_table_are_refused() -> None:
    body = pymunk.Body(1.0, 0.01)
    disk = pymunk.Circle(body, 0.1)
    body.center_of_gravity = (0.02, 0.0)
    space = pymunk.Space()
    space.add(body, disk)
    pf = PlaneFriction(space, g=G)
    with pytest.raises(ValueError, match=r"body .*not on circles or ellipses"):
        pf.add(body, mu=MU)
    space2, box = _box_cg(0.02)
    pf2 = PlaneFriction(space2, g=G)
    with pytest.raises(ValueError, match=r"body .*friction_method 'table' needs each polygon uniformly loaded"):
        pf2.add(box, mu=MU, friction_method="table")
    assert pf.bodies == () and pf2.bodies == ()


# ---- rrbody.planar: per-part masses ------------------------------------------------------------
def test_planar_parts_with_masses_press_with_their_weight() -> None:
    """Two boxes of masses 1 and 3 about their centre of mass: shares 1/4, 3/4, no torque in translation;
    the same boxes without masses share by area (the old rule) and turn."""
    a, b = planar.box(0.2, 0.1, (-0.15, 0.0), mass=1.0), planar.box(0.1, 0.1, (0.05, 0.0), mass=3.0)
    feet = planar.Footprints([[a, b], [planar.box(0.2, 0.1, (-0.15, 0.0)), planar.box(0.1, 0.1, (0.05, 0.0))]])
    assert feet._shapes[:2, C.LOAD_SHARE] == pytest.approx([0.25, 0.75], rel=1e-15)
    f, t = feet.wrench(0.0, [[0.0, 1.0], [0.0, 1.0]], 0.0, mu=MU, load=G)
    assert f[0] == pytest.approx([0.0, -MU * G], abs=1e-15) and abs(t[0]) < 1e-15
    px = 2 / 3 * -0.15 + 1 / 3 * 0.05  # the area shares' centre of pressure
    assert t[1] == pytest.approx(-MU * G * px, rel=1e-13)  # -(P x y_hat) = -P_x per unit load


def test_planar_masses_off_the_origin_get_the_linear_pressure() -> None:
    feet = planar.Footprints([[planar.box(0.2, 0.1, (0.03, 0.0), mass=2.0), planar.point(-0.05, 0.02, mass=0.5)]])
    load, P = centre_of_pressure(feet._shapes, feet._geo)
    assert load == pytest.approx(1.0, rel=1e-14) and np.hypot(*P) < 1e-15


@pytest.mark.parametrize("make, words", [
    (lambda: planar.box(0.1, 0.1, mass=-1.0), ["mass", "-1", "(0, inf]"]),
    (lambda: planar.circle(0.1, mass=math.nan), ["mass", "nan"]),
    (lambda: planar.point(0.0, 0.0, mass=True), ["mass", "True"]),
    (lambda: planar.Footprints([[planar.box(0.1, 0.1, mass=1.0), planar.circle(0.05, (0.1, 0.0))]]),
     ["bodies[0]", "mass", "every part", "1 of 2"]),
    (lambda: planar.Footprints([[planar.box(0.1, 0.1, (0.06, 0.0), mass=1.0), planar.box(0.1, 0.1, (0.3, 0.0),
                                                                                       mass=1.0)]]),
     ["bodies[0]", "tip"]),
])
def test_planar_bad_masses_are_named(make, words: list[str]) -> None:  # noqa: ANN001
    with pytest.raises(ValueError) as err:
        make()
    for w in words:
        assert w in str(err.value), (w, str(err.value))
