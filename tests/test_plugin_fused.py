"""The plugin's one-call step on the struct route (rrbody.engine.structio.struct_step: read, kernel and write
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
from rrbody.contact.active import NO_ACTIVE
from rrbody.engine import PlaneFriction
from rrbody.engine.bodymem import layout
from rrbody.engine.structio import gather, still_entry, struct_still

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


def _would_be_still(pf: PlaneFriction, dt: float) -> bool:
    """Whether the coming step finds the record of the last idle step standing (an independent reading:
    gather into a spare array, compared with the record bit for bit in numpy)."""
    sio = pf._sio
    if sio._snap[-1, 0] != 1.0 or sio._snap[-1, 1] != dt:
        return False
    now = np.zeros_like(sio._got)
    if gather(sio._addr, sio._offs, sio._space, now) >= 0:
        return False
    return bool(np.array_equal(_bits(now), _bits(sio._snap[:-1])))


@pytest.mark.private
@pytest.mark.parametrize("tilt", [0.0, 0.15])
def test_the_still_check_skips_only_steps_that_change_nothing(tilt: float) -> None:
    """The same run with the record of idle steps and with it cleared before every step (so that every
    step reads the kernel's arrays and asks plane_idle): the same bits. The record stood at more than 100
    steps (the scene at rest, the held push included), and at exactly those steps the plugin's separate
    still call (struct_still) said True and took the step."""
    runs, stood, taken = [], 0, [0]
    for keep in (True, False):
        space, pf, bodies = _scene(tilt)
        dt = 1.0 / 120.0
        if keep:  # count the still call's True answers (the plugin finds this entry when it makes its plan)
            real = still_entry()

            def counted(*a: object) -> bool:
                r = real(*a)
                taken[0] += bool(r)
                return r

            pf._sio._still_entry = counted
        for n in range(600):
            if n >= 300:
                bodies[1].force = (0.05, -0.02)
            if n == 450:
                bodies[2].apply_impulse_at_local_point((0.02, 0.0))
            if keep:
                stood += _would_be_still(pf, dt)
            else:
                pf._sio.forget()
            pf.step(dt)
        state = [(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies]
        runs.append((state, [pf.friction(b) for b in pf.bodies], pf.n_stopped, pf.t))
    assert stood > 100 and taken[0] == stood
    assert runs[0] == runs[1]


def _at_rest() -> tuple[pymunk.Space, PlaneFriction, pymunk.Body]:
    """A box at rest under static friction, a held load on it, stepped until struct_step has recorded an idle step."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = pymunk.Body()
    s = pymunk.Poly.create_box(b, (0.2, 0.1))
    s.density = 10.0
    space.add(b, s)
    pf.add(b, mu=0.5)
    for _ in range(4):
        b.force = (0.3, 0.0)  # well inside mu m g = 0.98 N
        pf.step(0.01)
    assert pf._plan is not None and pf._sio._snap[-1, 0] == 1.0
    return space, pf, b


def _still(pf: PlaneFriction, dt: float) -> bool:
    sio = pf._sio
    keys = sio.keys()
    return bool(struct_still(keys.ctypes.data, dt))


@pytest.mark.private
def test_the_still_check_says_false_for_any_change() -> None:
    """struct_still says True for the recorded step again, False for a changed load (by one ulp), a zero of
    the other sign, another dt, a body gone from the space, or sleeping turned on; the compiled call clears
    the record where sleeping is on; every write of a row outside a step and every change of the arrays
    clears it and drops the plugin's still call."""
    space, pf, b = _at_rest()
    assert pf._still is not None  # the plugin's next step starts with the still call
    b.force = (0.3, 0.0)
    for bad in (0.0, -0.01, math.nan, math.inf):  # the still call says no: refused as on any step
        with pytest.raises(ValueError, match="dt must be a number > 0"):
            pf.step(bad)
    assert _still(pf, 0.01)  # (it writes the forces: the load is set again before each call)
    t = pf.t
    b.force = (0.3, 0.0)
    pf.step(np.float64(0.01))  # taken by the still call, with the float it recorded
    assert pf._still is not None and type(pf.t) is float and pf.t == t + 0.01
    b.force = (0.3, 0.0)
    assert _still(pf, 0.01)
    for change in ({"force": (math.nextafter(0.3, 1.0), 0.0)}, {"velocity": (-0.0, 0.0)}, {"angular_velocity": -0.0}):
        _, pf2, b2 = _at_rest()
        b2.force = (0.3, 0.0)
        for k, v in change.items():
            setattr(b2, k, v)
        assert not _still(pf2, 0.01), change
    b.force = (0.3, 0.0)
    assert not _still(pf, 0.02)
    space.remove(b, *b.shapes)
    assert not _still(pf, 0.01)
    space.add(b, *b.shapes)
    b.force = (0.3, 0.0)
    assert _still(pf, 0.01)
    space.sleep_time_threshold = 1.0
    assert not _still(pf, 0.01)  # read from the space's struct, as struct_step reads it
    pf.step(0.01)  # the bulk route: the compiled call said ASLEEP having cleared the record
    assert pf._sio._snap[-1, 0] == 0.0 and pf._still is None
    space.sleep_time_threshold = math.inf
    for _ in range(3):
        b.force = (0.3, 0.0)
        pf.step(0.01)
    assert pf._sio._snap[-1, 0] == 1.0
    assert pf._still is not None
    pf.drive(b, omega=1.0, d=0.1, anchor=(0.0, 0.0), t0=0.0)
    assert pf._plan is None and pf._still is None and pf._sio._snap[-1, 0] == 0.0
    _, pf3, b3 = _at_rest()
    pf3.activate(b3, None)
    assert pf3._still is None and pf3._sio._snap[-1, 0] == 0.0
    _, pf4, b4 = _at_rest()
    pf4.add(b4, mu=0.4)  # read again: new rows
    assert pf4._plan is None and pf4._still is None and pf4._sio._snap[-1, 0] == 0.0
