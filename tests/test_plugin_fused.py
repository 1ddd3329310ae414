"""The plugin's one-call step on the struct route (rrbody.engine.memory.structio.struct_step: read, kernel and write
in one compiled call, plane_step skipped where rrbody.contact.kernel.plane_idle finds it would change
nothing) against the separate calls it replaces.

References: the separate calls of the same route (read, plane_step, write: the step every earlier release
took), bit for bit; and plane_step itself, which plane_idle must agree with wherever it answers True (every
row, the forces and the answer the same bits).
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from rrbody.contact import kernel as K
from rrbody.contact.columns import NO_ACTIVE
from rrbody.engine import PlaneFriction
from rrbody.engine.memory.bodymem import layout

G = 9.81


def _scene(tilt: float) -> tuple[pymunk.Space, PlaneFriction, list[pymunk.Body]]:
    """Disks, boxes and an L on a plane tilted by ``tilt`` (rad) that slide into each other and come to rest
    (static friction holding the tilt's pull), one with mu_static above mu, one outside the plugin."""
    space = pymunk.Space()
    space.iterations = 10
    pf = PlaneFriction(space, g=G, tilt=tilt, downhill=0.4)
    corners = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
    space.add(*[pymunk.Segment(space.static_body, a, b, 0.02) for a, b in zip(corners, corners[1:] + corners[:1])])
    rng = np.random.default_rng(11)
    bodies = []
    for i in range(9):
        b = pymunk.Body()
        if i % 3 == 0:
            shapes = [pymunk.Circle(b, 0.08)]
        elif i % 3 == 1:
            shapes = [pymunk.Poly.create_box(b, (0.15, 0.1))]
        else:
            shapes = [pymunk.Poly(b, [(-0.08, -0.08), (0.08, -0.08), (0.08, 0.0), (-0.08, 0.0)]),
                      pymunk.Poly(b, [(-0.08, 0.0), (0.0, 0.0), (0.0, 0.08), (-0.08, 0.08)])]
        for s in shapes:
            s.density = 20.0
        b.position = (0.3 + 0.6 * (i % 3), 0.3 + 0.6 * (i // 3))
        b.angle = float(rng.uniform(0, 2 * math.pi))
        b.velocity = tuple(rng.uniform(-0.6, 0.6, 2))
        b.angular_velocity = float(rng.uniform(-3, 3))
        space.add(b, *shapes)
        if i != 4:  # body 4 moves without plane friction
            pf.add(b, mu=0.4, mu_static=0.6 if i == 2 else None)
        bodies.append(b)
    return space, pf, bodies


def _run(tilt: float, fused: bool, check_idle: bool = False) -> tuple[list, list, int, int]:
    """600 steps of the scene, a held push on body 1 from step 300, body 2 pushed out of its rest at step 450;
    ``fused`` False: the separate calls of the same route. With ``check_idle``, before every step plane_idle
    and plane_step are run on copies of the step's arrays and compared (the count of idle steps returned)."""
    space, pf, bodies = _scene(tilt)
    if not fused:
        pf._sio.step = lambda plane, t, dt, act: -1  # the compiled call declines: the separate calls take the step
    n_idle = 0
    for n in range(600):
        if n >= 300:
            bodies[1].force = (0.05, -0.02)  # the user's load, inside static friction: held at rest
        if n == 450:
            bodies[2].apply_impulse_at_local_point((0.02, 0.0))
        if check_idle and n > 0:
            n_idle += _idle_agrees(pf, 1.0 / 120.0)
        pf.step(1.0 / 120.0)
    state = [(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies]
    return state, [pf.friction(b) for b in pf.bodies], pf.n_stopped, n_idle


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).view(np.int64)


def _idle_agrees(pf: PlaneFriction, dt: float) -> int:
    """plane_idle and plane_step on copies of this step's arrays: where plane_idle says True, plane_step
    changes no row, writes the same forces and answers 0. Returns 1 if plane_idle said True."""
    got, ids, _ = pf._sio.read()
    lookup, cache, bodies, shapes, geo, tables = pf.step_arrays()
    b_idle, b_step = bodies.copy(), bodies.copy()
    out_idle, out_step = np.full((got.shape[0], 3), np.nan), np.full((got.shape[0], 3), np.nan)
    idle = K.plane_idle(got, ids, lookup, cache.copy(), b_idle, dt, out_idle, NO_ACTIVE[0])
    assert np.array_equal(_bits(b_idle), _bits(bodies))  # it writes no row, whatever its answer
    if not idle:
        return 0
    n = K.plane_step(got, ids, lookup, cache.copy(), b_step, shapes, geo, tables, pf.t, dt, out_step, *NO_ACTIVE)
    assert n == 0 and np.array_equal(_bits(b_step), _bits(bodies)) and np.array_equal(_bits(out_idle), _bits(out_step))
    return 1


@pytest.mark.private
@pytest.mark.parametrize("tilt", [0.0, 0.15])
def test_the_one_call_steps_as_the_separate_calls(tilt: float) -> None:
    """Collisions, bodies coming to rest (on a tilt: held against its pull), a held push, a break-away: the
    one-call step and the separate calls give the same run, bit for bit."""
    assert layout() is not None  # the struct route is proven on every pymunk the suite runs on
    one, apart = _run(tilt, True), _run(tilt, False)
    assert one == apart
    assert one[2] > 0  # the rest rule stopped bodies: the runs reached the idle steps


@pytest.mark.private
def test_plane_idle_answers_true_only_where_plane_step_changes_nothing() -> None:
    """Every step of a scene that comes to rest on a tilt, checked against plane_step; it does say True
    (once every body is at rest and held as in the step before) and the run is the plain one."""
    got = _run(0.15, True, check_idle=True)
    assert got[3] > 100
    assert got[:3] == _run(0.15, True)[:3]
