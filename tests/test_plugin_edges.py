"""PlaneFriction at scale and at its edges.

Scale is asserted through structure, not wall time (the timing lives in benchmarks/plugin.py): the
per-body arrays move only when their capacity doubles, removals move one row, and the bodies that stay
get exactly the friction a fresh plugin gives them. Edges: a non-finite state, mass or moment, and a
body that left the space, each a ValueError naming the body; a refused step changes nothing, so a run
that is repaired and continued is bit-identical to one that never failed.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from rrbody.engine import PlaneFriction

DT = 1e-3


def _body(space: pymunk.Space, i: int, kind: int = 0) -> pymunk.Body:
    """Body i on a grid 1 m apart (no contacts), sliding and spinning: a disk, a box or a thick segment."""
    b = pymunk.Body()
    b.position = (float(i % 100), float(i // 100))
    s = {0: lambda: pymunk.Circle(b, 0.1), 1: lambda: pymunk.Poly.create_box(b, (0.2, 0.15)),
         2: lambda: pymunk.Segment(b, (-0.2, 0.0), (0.2, 0.0), 0.05)}[kind]()
    s.density = 1.0
    space.add(b, s)
    b.velocity = (0.5 + 0.001 * i, -0.3)
    b.angular_velocity = 2.0 + 0.01 * i
    return b


def _state(bodies: list[pymunk.Body]) -> list[tuple]:
    return [(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies]


def _scene(n: int = 3) -> tuple[pymunk.Space, PlaneFriction, list[pymunk.Body]]:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    bodies = [_body(space, i, i % 3) for i in range(n)]
    for b in bodies:
        pf.add(b, mu=0.4)
    return space, pf, bodies


# ---- scale: amortised O(1) add and remove ------------------------------------------------------
def test_ten_thousand_adds_move_the_arrays_only_when_their_capacity_doubles() -> None:
    """Each add appends one row: the body array is reallocated ceil(log2(n / 16)) times over n adds
    (16: the initial capacity), not once per add, and between reallocations it is the same buffer."""
    space = pymunk.Space()
    pf = PlaneFriction(space)
    last = pf._rows.buf
    moves = 0
    for i in range(10_000):
        b = pymunk.Body()
        s = pymunk.Circle(b, 0.1)
        s.density = 1.0
        b.position = (float(i % 100), float(i // 100))
        space.add(b, s)
        b.velocity = (1.0, 0.0)
        pf.add(b, mu=0.5)
        if pf._rows.buf is not last:  # the rows were copied to a new buffer
            last = pf._rows.buf
            moves += 1
        if i + 1 == 1000:
            at_1000 = pf._rows.reallocs
    assert at_1000 == math.ceil(math.log2(1000 / 16)) == 6
    assert moves == pf._rows.reallocs == math.ceil(math.log2(10_000 / 16)) == 10
    # the ids and the footprint rows grow alike (a disk has one footprint row and no geo rows)
    assert (pf._idrows.reallocs, pf._feet._shapes.reallocs, pf._feet._geo.reallocs) == (10, 10, 0)
    pf.step(DT)  # every one of them feels friction in the one compiled call
    assert all(b.velocity.x < 1.0 for b in pf.bodies)


def test_removals_move_one_row_and_the_others_keep_their_exact_friction() -> None:
    """Remove and re-add bodies in random order: no array is reallocated, dead footprint rows stay
    bounded (compacted once they outnumber the live ones), pf.bodies keeps the order of addition, and
    every body left gets bit for bit the wrench of a fresh plugin holding it (same rows, same kernel)."""
    space = pymunk.Space()
    pf = PlaneFriction(space)
    bodies = [_body(space, i, i % 3) for i in range(600)]
    for b in bodies:
        pf.add(b, mu=0.3)
    grown = [r.reallocs for r in (pf._rows, pf._idrows, pf._feet._shapes, pf._feet._geo)]
    rng = np.random.default_rng(5)
    gone = set()
    for k in rng.permutation(len(bodies))[:400]:
        pf.remove(bodies[k])
        gone.add(int(k))
    for k in sorted(gone)[:50]:  # re-added: to the end of the order
        pf.add(bodies[k], mu=0.3)
        gone.discard(k)
    for k in range(0, 600, 7):  # re-read in place (its old footprint rows become garbage)
        if k not in gone:
            pf.add(bodies[k], mu=0.3)
    assert [r.reallocs for r in (pf._rows, pf._idrows, pf._feet._shapes, pf._feet._geo)] == grown
    kept = [b for i, b in enumerate(bodies) if i not in gone]
    assert set(pf.bodies) == set(kept) and len(pf.bodies) == len(kept)
    # garbage is bounded by the live rows plus the slack of Footprints.compact_if_sparse (64, 1024):
    # without compaction the 400 removed footprints (a third of them 34-gon stadiums) would exceed it
    for k, (rows, slack) in enumerate(((pf._feet._shapes, 64), (pf._feet._geo, 1024))):
        live = sum(pf._geo[j][k].shape[0] for j in range(len(kept)))
        assert rows.n - pf._feet._dead[k] == live and pf._feet._dead[k] <= live + slack
    ref = PlaneFriction(space)
    for b in kept:
        ref.add(b, mu=0.3)
    for b in kept:
        assert pf.wrench(b) == ref.wrench(b)
    # after removals the step's id table is rebuilt: removed bodies feel nothing, the others friction
    v_gone = {k: (tuple(bodies[k].velocity), bodies[k].angular_velocity) for k in gone}
    ke = [b.kinetic_energy for b in kept]
    pf.step(DT)
    assert all((tuple(bodies[k].velocity), bodies[k].angular_velocity) == v for k, v in v_gone.items())
    assert all(b.kinetic_energy < e for b, e in zip(kept, ke))


def test_order_of_bodies_is_the_order_of_addition_after_removals() -> None:
    space, pf, bodies = _scene(5)
    pf.remove(bodies[1])  # the last row moves into row 1; the public order does not change
    assert pf.bodies == (bodies[0], bodies[2], bodies[3], bodies[4])
    pf.add(bodies[1], mu=0.4)
    pf.add(bodies[3], mu=0.2)  # a re-read keeps its place
    assert pf.bodies == (bodies[0], bodies[2], bodies[3], bodies[4], bodies[1])


def test_a_space_that_grows_past_the_plugins_cache_still_gets_friction_right() -> None:
    """After the first step, 40 more bodies (not in the plugin) join the space: the kernel's row cache
    (16 to start) grows and the plugin's body moves exactly as in a space without them (no contacts)."""
    runs = []
    for extra in (0, 40):
        space, pf, bodies = _scene(1)
        pf.step(DT)
        others = [_body(space, 100 + i) for i in range(extra)]
        for _ in range(20):
            pf.step(DT)
        runs.append(_state(bodies))
        assert all(o.velocity == (0.5 + 0.001 * (100 + i), -0.3) for i, o in enumerate(others))
    assert runs[0] == runs[1]


# ---- non-finite input ----------------------------------------------------------------------------
BAD = [("position", (math.nan, 0.0)), ("angle", math.inf), ("velocity", (0.0, -math.inf)),
       ("angular_velocity", math.nan)]


@pytest.mark.parametrize("what,value", BAD)
def test_add_refuses_a_non_finite_state_naming_the_body_and_quantity(what: str, value: object) -> None:
    space, pf, bodies = _scene(2)
    b = _body(space, 7)
    setattr(b, what, value)
    with pytest.raises(ValueError, match=rf"body Body\(.*\): {what} must be finite \(.*\), got .*(nan|inf)"):
        pf.add(b, mu=0.4)
    assert pf.bodies == tuple(bodies)
    setattr(bodies[1], what, value)  # a re-read of a body already in the plugin names its place
    with pytest.raises(ValueError, match=rf"body pf.bodies\[1\] \(Body\(.*\)\): {what} must be finite"):
        pf.add(bodies[1], mu=0.4)


def test_add_refuses_an_infinite_moment_naming_the_body() -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space)
    b = pymunk.Body(1.0, math.inf)  # pymunk allows it (a body that cannot turn); friction's torque needs I
    space.add(b, pymunk.Circle(b, 0.1))
    with pytest.raises(ValueError, match=r"body Body\(.*\): mass and moment must be positive and finite "
                                         r"\(kg, kg m\^2\), got mass 1.0, moment inf"):
        pf.add(b, mu=0.4)


def _fault_and_repair(inject, repair, *, first_step: bool) -> tuple[list, list]:  # noqa: ANN001
    """Two identical scenes; in one, ``inject`` spoils a body before a step, the step must raise, then
    ``repair`` undoes it. Returns both final states (after 30 more steps)."""
    finals = []
    for faulty in (False, True):
        space, pf, bodies = _scene(3)
        if not first_step:
            for _ in range(5):
                pf.step(DT)
        if faulty:
            t = pf.t
            undo = inject(space, pf, bodies)
            with pytest.raises(ValueError) as err:
                pf.step(DT)
            assert pf.t == t
            repair(space, pf, bodies, undo)
            finals.append(str(err.value))
        for _ in range(30):
            pf.step(DT)
        finals.append(_state(bodies))
    return finals[0], finals[1:]


@pytest.mark.parametrize("first_step", [False, True], ids=["between-steps", "before-the-first-step"])
@pytest.mark.parametrize("what,value", [b for b in BAD if b[0] != "position"])
def test_step_refuses_a_non_finite_state_and_changes_nothing(what: str, value: object, first_step: bool) -> None:
    """The issue's case: a velocity that became NaN between steps raised ZeroDivisionError. Now a
    ValueError names the body and the quantity, the step is refused whole (no friction, no half kick,
    no space.step), and once the value is restored the run is bit-identical to one never spoiled."""
    def inject(space, pf, bodies):  # noqa: ANN001, ANN202
        old = getattr(bodies[1], what)
        setattr(bodies[1], what, value)
        return old

    def repair(space, pf, bodies, old):  # noqa: ANN001, ANN202
        setattr(bodies[1], what, old)

    clean, (msg, repaired) = _fault_and_repair(inject, repair, first_step=first_step)
    assert "body pf.bodies[1] (Body(" in msg and f"{what} must be finite" in msg and "pf.remove(body)" in msg
    assert repaired == clean


@pytest.mark.parametrize("first_step", [False, True], ids=["between-steps", "before-the-first-step"])
def test_step_refuses_a_body_removed_from_the_space_only(first_step: bool) -> None:
    """A body taken out of the space but not out of the plugin was skipped silently; now the step is
    refused naming it and the fix. After pf.remove the others go on exactly as if it had never been there."""
    finals = []
    for faulty in (False, True):
        space, pf, bodies = _scene(3)
        if not first_step:
            for _ in range(5):
                pf.step(DT)
        space.remove(bodies[2], *bodies[2].shapes)
        if faulty:
            with pytest.raises(ValueError, match=r"body pf.bodies\[2\] \(Body\(.*\)\) is no longer in the space "
                                                 r"but still in this PlaneFriction.*call pf.remove\(body\)"):
                pf.step(DT)
        pf.remove(bodies[2])
        for _ in range(30):
            pf.step(DT)
        finals.append(_state(bodies[:2]))
    assert finals[0] == finals[1]


def test_a_subnormal_speed_stops_cleanly() -> None:
    """A body crawling at a subnormal speed (m * speed underflows to 0) under a push: the rest rule's
    pull-along-the-motion must not divide by that product (it raised ZeroDivisionError with 1,000 bodies
    sliding to rest). The push (0.1 N, inside mu m g) is held once the body is at rest."""
    import pymunk

    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    body = pymunk.Body()
    shape = pymunk.Circle(body, 0.1)
    shape.density = 1.0
    space.add(body, shape)
    pf = PlaneFriction(space, g=9.81)
    pf.add(body, mu=0.5)
    pf.step(1e-3)
    body.velocity = (5e-324, 5e-324)
    for _ in range(3):
        body.force = (0.1, 0.0)
        pf.step(1e-3)
    assert tuple(body.velocity) == (0.0, 0.0) and body.angular_velocity == 0.0
