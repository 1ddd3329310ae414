"""The plugin's routes to its bodies (their structs, pymunk.batch's C iterator or public functions, each
body's public properties) and its disk table.

References: the bulk read through pymunk's own functions (the route every earlier release took):
every other route must step every scene bit for bit as it does (the same kernel, the same numbers in,
the same forces out), on every pymunk the suite runs on (6.6 and later, 7.x: docs/versions.md); the
exact footprint wrench (rrbody.physics.contact.footprint_wrench), which the disk's table must match to
its stated 1e-10.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from rrbody.contact import kernel as K
from rrbody.engine import PlaneFriction
from rrbody.engine.memory.batchio import ROUTES, BatchIO, batch_reads, body_uid
from rrbody.engine.memory.bodymem import FX, FY, TORQUE, layout
from rrbody.engine.memory.structio import StructIO
from rrbody.physics.contact import footprint_wrench

G = 9.81


def _scene(route: str) -> tuple[pymunk.Space, PlaneFriction, list[pymunk.Body]]:
    """A walled box of disks, boxes and L-shapes that collide, one body outside the plugin, one with
    static friction under a push it cannot hold. ``route``: "struct" (the plugin's own choice, which is
    the struct route where the layout is proven) or one of BatchIO's ROUTES, forced."""
    space = pymunk.Space()
    space.iterations = 10
    pf = PlaneFriction(space, g=G)
    if route != "struct":
        pf._sio = None
        pf._io = BatchIO(space, route=route)
    corners = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
    space.add(*[pymunk.Segment(space.static_body, a, b, 0.02) for a, b in zip(corners, corners[1:] + corners[:1])])
    rng = np.random.default_rng(3)
    bodies = []
    for i in range(16):
        b = pymunk.Body()
        if i % 3 == 0:
            shapes = [pymunk.Circle(b, 0.08, (0.01 * (i % 2), 0.0))]  # an offset disk too
        elif i % 3 == 1:
            shapes = [pymunk.Poly.create_box(b, (0.15, 0.1))]
        else:
            shapes = [pymunk.Poly(b, [(-0.08, -0.08), (0.08, -0.08), (0.08, 0.0), (-0.08, 0.0)]),
                      pymunk.Poly(b, [(-0.08, 0.0), (0.0, 0.0), (0.0, 0.08), (-0.08, 0.08)])]
        for s in shapes:
            s.density = 20.0
        b.position = (0.25 + 0.45 * (i % 4), 0.25 + 0.45 * (i // 4))
        b.angle = float(rng.uniform(0, 2 * math.pi))
        b.velocity = tuple(rng.uniform(-1.5, 1.5, 2))
        b.angular_velocity = float(rng.uniform(-8, 8))
        space.add(b, *shapes)
        if i != 5:  # body 5 moves without plane friction
            pf.add(b, mu=0.2, mu_static=0.3 if i == 7 else None)
        bodies.append(b)
    return space, pf, bodies


def _state(bodies: list[pymunk.Body]) -> list[tuple]:
    return [(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies]


def _routes() -> list[str]:
    """The routes this pymunk can take: the struct route where the probe proved the layout, pymunk.batch's
    public functions where its batch reads and writes forces (pymunk >= 6.11), per body always."""
    return (["struct"] if layout() is not None else []) + (["bulk"] if batch_reads() else []) + ["per-body"]


@pytest.mark.private
def test_every_route_steps_bit_for_bit() -> None:
    """Collisions, user forces and torques, a body outside the plugin, one removed and added back
    mid-run, static friction: every route to the bodies gives exactly the same run."""
    routes = _routes()
    # the struct route is proven on every pymunk the suite runs on (6.6, 6.11, 7.x): else it is never taken
    assert layout() is not None
    runs = []
    for route in routes:
        space, pf, bodies = _scene(route)
        for n in range(400):
            bodies[1].force = (0.3, -0.2)  # the user's own loads on plugin bodies, every step
            bodies[7].torque = 0.05 if n < 200 else 0.0
            if n == 150:
                pf.remove(bodies[3])
            if n == 250:
                pf.add(bodies[3], mu=0.2)
            pf.step(1.0 / 240.0)
            if n == 10:
                taken = pf._route()[0]
                assert taken is (pf._sio if route == "struct" else pf._io)
                assert isinstance(taken, StructIO) if route == "struct" else taken.route == route
        runs.append((_state(bodies), [pf.friction(b) for b in pf.bodies], pf.n_stopped))
    assert all(run == runs[0] for run in runs[1:]), routes
    assert runs[0][2] > 0 or any(v != (0.0, 0.0) for _, _, v, _ in runs[0][0])  # something moved or stopped


@pytest.mark.private
def test_the_default_route_is_the_fastest_this_pymunk_offers() -> None:
    """BatchIO takes pymunk.batch's public functions where they read and write forces (pymunk >= 6.11),
    else the per-body route; a pose reader (the recorder's) takes them from pymunk 6.6 on. A route
    that does not exist, or that this pymunk cannot take, is refused, naming it."""
    space, _, bodies = _scene("struct")
    assert BatchIO(space).route == ("bulk" if batch_reads() else "per-body")
    assert batch_reads(poses=True) and BatchIO(space, poses=True).route == "bulk"
    with pytest.raises(ValueError, match="route must be one of 'bulk', 'per-body' or None, got 'fast'"):
        BatchIO(space, route="fast")
    if not batch_reads():
        with pytest.raises(ValueError, match=r"route 'bulk' needs a pymunk.batch that reads and writes forces "
                                             r"\(pymunk >= 6.11\); this is pymunk 6\."):
            BatchIO(space, route="bulk")
    # every pose route reads the same numbers, those of the bodies' public properties (the per-body route
    # leaves out the space's static body, which cpSpaceEachBody visits: no reader uses it)
    want = {body_uid(b): (*b.position, b.angle, *b.velocity, b.angular_velocity) for b in bodies}
    for r in ROUTES:
        got, ids, _ = BatchIO(space, poses=True, route=r).read()
        rows = {int(i): tuple(row) for i, row in zip(ids, got.tolist())}
        assert {i: rows[i] for i in want} == want and len(rows) == 16 + (r != "per-body"), r


@pytest.mark.private
def test_sleeping_space_and_a_removed_body_take_the_bulk_route() -> None:
    """With sleeping enabled a raw store would not wake a body (pymunk's setter does): the bulk route.
    A body that left the space: the bulk read finds it and the step is refused as before."""
    space, pf, bodies = _scene("struct")
    pf.step(1e-3)
    assert pf._route()[0] is pf._sio
    space.sleep_time_threshold = 0.5
    assert pf._route()[0] is pf._io
    pf.step(1e-3)
    space.sleep_time_threshold = math.inf
    space.remove(bodies[0], *bodies[0].shapes)
    assert pf._sio.read() is None
    with pytest.raises(ValueError, match=r"pf.bodies\[0\] .* is no longer in the space"):
        pf.step(1e-3)


@pytest.mark.private
def test_layout_reads_and_writes_force_and_torque() -> None:
    """The probed offsets of force and torque: a raw store reads back through pymunk's getters."""
    from rrbody.engine.memory.structio import scatter

    offs = layout()
    assert offs is not None and len({int(offs[k]) for k in (FX, FY, TORQUE)}) == 3
    space, pf, bodies = _scene("struct")
    sio = StructIO(pf)
    got, ids, out = sio.read()
    out[:] = np.arange(3 * out.shape[0], dtype=float).reshape(-1, 3)
    scatter(sio._addr, offs, out)
    for k, b in enumerate(pf.bodies):
        assert (b.force.x, b.force.y, b.torque) == tuple(out[k])


@pytest.mark.parametrize("pressure", ["uniform", "ring:0.08", "hertz:0.1"])
@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.03, -0.02)])
def test_disk_table_matches_the_exact_wrench(offset: tuple[float, float], pressure: str) -> None:
    """A disk body's friction comes from its profile's disk table (kernel.TABLE_CIRCLE; uniform
    pressure, a ring, Hertz's): within 1e-10 of the exact footprint wrench (icr_table's stated accuracy;
    units mu m g and mu m g R), at spins from pure translation to pure spin, both senses, a disk off the
    centre of gravity too."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = pymunk.Body()
    s = pymunk.Circle(b, 0.1, offset)
    s.density = 5.0
    space.add(b, s)
    pf.add(b, mu=0.4, pressure=pressure)
    j = pf._slots[b]
    assert pf._bodies[j, K.TABLE_KIND] == K.TABLE_CIRCLE
    sh, geo = pf._k_shapes, pf._k_geo
    s0, s1 = int(pf._bodies[j, K.SHAPE_FIRST]), int(pf._bodies[j, K.SHAPE_END])
    rng = np.random.default_rng(5)
    scale = 0.4 * G * b.mass
    r = 0.1 + math.hypot(*offset)
    worst = 0.0
    for _ in range(400):
        v = rng.normal(size=2) * 10.0 ** rng.uniform(-3, 1)
        w = float(rng.choice([-1, 1]) * 10.0 ** rng.uniform(-4, 2))
        if rng.random() < 0.1:
            w = 0.0
        a = float(rng.uniform(-4, 4))
        fx, fy, tq = pf.wrench(b, velocity=(float(v[0]), float(v[1]), w), angle=a)
        ca, sa = math.cos(a), math.sin(a)
        ex, ey, et = footprint_wrench(sh, geo, s0, s1, ca * v[0] + sa * v[1], -sa * v[0] + ca * v[1], w, 0.0)
        wx, wy = ca * ex - sa * ey, sa * ex + ca * ey
        worst = max(worst, abs(fx - scale * wx) / scale, abs(fy - scale * wy) / scale,
                    abs(tq - scale * et) / (scale * r))
    assert worst < 1e-10


def _l_body(space: pymunk.Space, x: float) -> pymunk.Body:
    b = pymunk.Body()
    arms = [pymunk.Poly(b, [(-0.08, -0.08), (0.08, -0.08), (0.08, 0.0), (-0.08, 0.0)]),
            pymunk.Poly(b, [(-0.08, 0.0), (0.0, 0.0), (0.0, 0.08), (-0.08, 0.08)])]
    for s in arms:
        s.density = 20.0
    b.position = (x, 0.0)
    space.add(b, *arms)
    return b


def test_footprint_table_in_the_plugin() -> None:
    """friction_method="table": the L's friction from its footprint's table, one table for two bodies of
    the same shape; the wrench within 1e-10 of the exact one (the table's stated accuracy: units mu m g
    and mu m g R); a run to rest next to the same body with the exact wrench: each step's force differs
    by at most 1e-10 mu m g, so the velocities by at most 1e-10 mu g t and the positions by
    1e-10 mu g t^2 / 2 (1.3e-11 m over the 0.3 s compared: the motion is dissipative, nothing grows);
    1e-9 m and 1e-8 rad leave room for rounding. A bad method is refused, naming it."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    a, b, c = _l_body(space, 0.0), _l_body(space, 1.0), _l_body(space, 2.0)
    pf.add(a, mu=0.3, friction_method="table")
    pf.add(b, mu=0.3, friction_method="table")
    pf.add(c, mu=0.3)  # "auto": exact
    ja, jb, jc = (pf._slots[x] for x in (a, b, c))
    assert pf._bodies[ja, K.TABLE_KIND] == pf._bodies[jb, K.TABLE_KIND] == K.TABLE_FOOTPRINT
    assert pf._bodies[ja, K.TABLE_START] == pf._bodies[jb, K.TABLE_START] and pf._feet.tables == 1
    assert pf._bodies[jc, K.TABLE_KIND] == K.TABLE_NONE
    rng = np.random.default_rng(8)
    scale = 0.3 * G * a.mass
    reach = pf._bodies[ja, K.REACH]
    worst = 0.0
    for _ in range(300):
        v = (float(rng.normal()), float(rng.normal()))
        w = float(rng.choice([-1, 1]) * 10.0 ** rng.uniform(-2, 2))
        ang = float(rng.uniform(-3, 3))
        ft = pf.wrench(a, velocity=(*v, w), angle=ang)
        fe = pf.wrench(c, velocity=(*v, w), angle=ang)
        worst = max(worst, abs(ft[0] - fe[0]) / scale, abs(ft[1] - fe[1]) / scale, abs(ft[2] - fe[2]) / (scale * reach))
    assert worst < 1e-10
    for body in (a, c):
        body.velocity, body.angular_velocity, body.angle = (1.2, -0.4), 6.0, 0.3
    for _ in range(144):  # 0.3 s at dt = 1/480 s: both still moving (they stop near 0.43 s)
        pf.step(1.0 / 480.0)
    assert a.velocity != (0.0, 0.0) and c.velocity != (0.0, 0.0)
    assert math.dist(a.position, c.position - (2.0, 0.0)) < 1e-9 and abs(a.angle - c.angle) < 1e-8
    with pytest.raises(ValueError, match="friction_method must be one of 'auto', 'table', got 'fast'"):
        pf.add(a, mu=0.3, friction_method="fast")


@pytest.mark.parametrize("method", ["auto", "table"])
def test_a_subnormal_velocity_steps_to_rest(method: str) -> None:
    """Collisions once left a disk with a velocity of 1e-319 m/s (subnormal: its square underflows),
    and the disk's table divided by zero. Disk, box and L with such twists: the step runs, and every
    body is exactly at rest within a few steps (the rest rule: slower than mu g dt)."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    bodies = []
    for k, make in enumerate((lambda b: [pymunk.Circle(b, 0.1)], lambda b: [pymunk.Poly.create_box(b, (0.2, 0.1))])):
        b = pymunk.Body()
        shapes = make(b)
        for s in shapes:
            s.density = 10.0
        b.position = (float(k), 0.0)
        space.add(b, *shapes)
        bodies.append(b)
    bodies.append(_l_body(space, 3.0))
    for b in bodies:
        pf.add(b, mu=0.2, friction_method=method)
        b.velocity, b.angular_velocity = (-1.34495e-319, -7.21e-320), 3.95e-322
    for _ in range(4):
        pf.step(1e-3)
    assert all(b.velocity == (0.0, 0.0) and b.angular_velocity == 0.0 for b in bodies)
