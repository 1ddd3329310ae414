"""The plugin kernel's lean sweep against its reference: every body stepped by the limit-set loop's step.

:func:`rrbody.contact.kernel.plane_step` steps most bodies in a sweep compiled without reference counting
(:func:`rrbody.contact.kernel._sweep`: three passes), and hands to its limit-set loop
(:func:`rrbody.contact.body.step_one`, whose test of a load allocates) only the bodies that need static
friction's limit-set test: at rest, about to stop under a load static friction may hold, or on a held
foot whose spin runs out. Stepping every body with ``_one`` instead is the reference: it must give the
same forces, the same stop count and the same state, bit for bit. The only columns allowed to differ
are the memo of the last limit-set test (HELD_LOAD_X, HELD_LOAD_Y, HELD_LOAD_TORQUE, HELD_ANGLE, HELD), which the
reference fills for loads the sweep knows static friction cannot hold (:func:`rrbody.contact.rest.may_hold`) and so
never tests.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

pymunk = pytest.importorskip("pymunk")

from rrbody.contact import kernel as K  # noqa: E402
from rrbody.plugin import Active, PlaneFriction  # noqa: E402

#: three point feet on a circle of radius 0.06 m, equal loads (the contacts benchmark's)
FEET = ("points:0.06,0,0.3333333333333333;-0.03,0.05196152422706632,0.3333333333333333;"
        "-0.03,-0.05196152422706632,0.3333333333333334")
#: the memo of the last limit-set test: a cache, not a result
MEMO = [K.HELD_LOAD_X, K.HELD_LOAD_Y, K.HELD_LOAD_TORQUE, K.HELD_ANGLE, K.HELD]


@njit(cache=True)
def _every_body_by_the_limit_set_step(got, ids, lookup, cache, bodies, shapes, geo, tables,  # noqa: ANN001, ANN202
                                      t, dt, out, active, noise):
    """plane_step's reference: its check, then every plugin body through ``_one``."""
    if not K.plane_check(got, ids, lookup, cache, bodies.shape[0]):
        return -1
    n_stop = 0
    for i in range(got.shape[0]):
        out[i, 0] = got[i, 4]
        out[i, 1] = got[i, 5]
        out[i, 2] = got[i, 6]
        j = cache[K.ROWMAP, i]
        if j >= 0:
            n_stop += K.B.step_one(i, j, got, bodies, shapes, geo, tables, t, dt, out, active, noise)
    return n_stop


def _scene(seed: int = 3) -> tuple[object, PlaneFriction, list]:
    """Disks on a tilt (atan 0.3; mu_static 0.5 holds them at rest), half on three point feet, some
    launched sliding and spinning; and active boxes whose propulsion (0.6 m g) static friction cannot hold."""
    rng = np.random.default_rng(seed)
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81, tilt=math.atan(0.3))
    pf.seed(seed)
    bodies = []
    for i in range(40):
        b = pymunk.Body()
        s = pymunk.Circle(b, 0.1) if i < 34 else pymunk.Poly.create_box(b, (0.16, 0.08))
        s.density = 2.0
        b.position = (0.3 * (i % 10), 0.3 * (i // 10))
        b.angle = rng.uniform(0, 6)
        if i % 3 == 0:
            b.velocity = (rng.uniform(-1, 1), rng.uniform(-1, 1))
            b.angular_velocity = rng.uniform(-5, 5)
        space.add(b, s)
        pf.add(b, mu=0.35 if i % 4 else 0.2, mu_static=0.5, pressure=FEET if i % 2 and i < 34 else "uniform",
               friction_method="table" if i >= 34 else "auto")
        if i >= 34:
            pf.activate(b, Active(force=0.6 * 9.81 * b.mass, point=(0.0, 0.02), rot_drag=2.0, rot_diffusion=0.5))
        bodies.append(b)
    return space, pf, bodies


def test_the_lean_sweep_gives_the_bits_of_the_limit_set_step_for_every_body(monkeypatch: pytest.MonkeyPatch) -> None:
    space, pf, bodies = _scene()
    pf.step(1 / 240)
    real = K.plane_step
    seen = {"steps": 0, "stops": 0, "pinned": 0, "held at rest": 0, "differ": []}

    def both(got, ids, lookup, cache, rows, shapes, geo, tables, t, dt, out, active, noise):  # noqa: ANN001, ANN202
        b2, c2, o2 = rows.copy(), cache.copy(), out.copy()
        n2 = _every_body_by_the_limit_set_step(got, ids, lookup, c2, b2, shapes, geo, tables, t, dt, o2, active, noise)
        n1 = real(got, ids, lookup, cache, rows, shapes, geo, tables, t, dt, out, active, noise)
        keep = np.ones(rows.shape[1], bool)
        keep[MEMO] = False
        same = n1 == n2 and np.array_equal(out, o2) and np.array_equal(rows[:, keep], b2[:, keep], equal_nan=True)
        if not same:
            seen["differ"].append(pf.t)
        seen["steps"] += 1
        seen["stops"] += n1 > 0
        seen["pinned"] += bool((rows[:, K.PINNED_FOOT] > 0).any())
        seen["held at rest"] += bool(((got[:, 1] == 0.0) & (got[:, 2] == 0.0) & (got[:, 3] == 0.0)).any())
        return n1

    monkeypatch.setattr(K, "plane_step", both)  # the plugin's separate calls reach the kernel through K
    if pf._sio is not None:  # the separate calls, through which every step reaches the kernel
        pf._sio.step = lambda plane, t, dt, act: -1
    rng = np.random.default_rng(5)
    for k in range(400):
        if k % 50 == 0:  # pushes: bodies at rest break away, held feet let go
            for b in bodies[::7]:
                b.apply_force_at_local_point((rng.uniform(-3, 3), rng.uniform(-3, 3)), (0.02, 0.0))
        pf.step(1 / 240)
    assert seen["differ"] == []
    # what the run went through (else the comparison proves less than it says): stops by the rest
    # rule, bodies turning on a held foot, bodies held exactly at rest
    assert seen["steps"] == 400 and seen["stops"] > 0 and seen["pinned"] > 0 and seen["held at rest"] > 0, seen
    # the boxes read their footprint table, whose blocks the sweep fetches ahead (kernel._fetch)
    assert (pf._bodies[:, K.TABLE_KIND] == K.TABLE_FOOTPRINT).sum() == len(bodies) - 34
