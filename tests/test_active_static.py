"""Active propulsion under static friction: a body at rest whose propulsion static friction can hold
stays exactly at rest; above static friction it breaks away and slides under kinetic friction.

References: a hand-applied force of the same size through the body's centre of gravity (``body.force``
set before every step), which the plugin's rest rule and static friction already treat exactly: the
active body's run must be that run, bit for bit (the propulsion enters the step as the same load, in
the same order of additions). Once sliding straight, the velocity gains (F - mu m g)/m per second
exactly per step (symplectic Euler with a constant net force: rounding only, 1e-9 relative).
"""

from __future__ import annotations

import pymunk
import pytest

from rrbody.plugin import Active, PlaneFriction

G = 9.81
MU, MU_S = 0.3, 0.5
DT = 1e-3


def _body(kind: str) -> tuple[pymunk.Space, PlaneFriction, pymunk.Body]:
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = pymunk.Body()
    s = pymunk.Circle(b, 0.05) if kind == "disk" else pymunk.Poly.create_box(b, (0.2, 0.1))  # (m)
    s.density = 100.0
    space.add(b, s)
    # three feet under the box (x, y, share of the load; m): a triangle round its centre of gravity
    options = {"pressure": "points:0.08,0.04,0.25;0.08,-0.04,0.25;-0.08,0.0,0.5"} if kind == "feet" else {}
    if kind == "table":
        options = {"friction_method": "table"}
    pf.add(b, mu=MU, mu_static=MU_S, **options)
    return space, pf, b


def _run(kind: str, frac: float, active: bool, n: int = 400) -> list[tuple]:
    """``n`` steps of a body released at rest under a push of ``frac`` m g along x: by propulsion
    (``active``) or by a hand-applied force; the pose and velocity after every step."""
    space, pf, b = _body(kind)
    f = frac * b.mass * G
    if active:
        pf.activate(b, Active(force=f))
    states = []
    for _ in range(n):
        if not active:
            b.force = (f, 0.0)
        pf.step(DT)
        states.append((tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity))
    return states


@pytest.mark.parametrize("kind", ["box", "disk", "feet", "table"])
@pytest.mark.parametrize("frac", [0.2, 0.4])
def test_propulsion_static_friction_can_hold_keeps_the_body_exactly_at_rest(kind: str, frac: float) -> None:
    """Below mu (0.2 m g) and between mu and mu_static (0.4 m g): never moves, not by one ulp."""
    states = _run(kind, frac, active=True)
    assert all(s == ((0.0, 0.0), 0.0, (0.0, 0.0), 0.0) for s in states), states[:3]


@pytest.mark.parametrize("kind", ["box", "disk", "feet", "table"])
@pytest.mark.parametrize("frac", [0.2, 0.4, 0.6, 0.9])
def test_propulsion_acts_as_a_hand_force_of_the_same_size(kind: str, frac: float) -> None:
    """Held or breaking away, the active body's run is the hand-pushed body's, bit for bit. (A
    footprint table's wrench is exact to its stated 1e-10 of mu m g: sliding, it turns the body by
    ~1e-17 rad, where the propulsion, fixed in the body, and the hand force, fixed in the world, round
    differently: there the two runs agree to 1e-10 of their scale.)"""
    active, hand = _run(kind, frac, active=True, n=200), _run(kind, frac, active=False, n=200)
    if kind != "table" or frac <= MU_S:
        assert active == hand
        return
    for a, h in zip(active, hand):
        assert a[0][0] == pytest.approx(h[0][0], rel=1e-10) and a[2][0] == pytest.approx(h[2][0], rel=1e-10)
        assert abs(a[0][1] - h[0][1]) <= 1e-10 * abs(h[0][0]) and abs(a[2][1] - h[2][1]) <= 1e-10 * abs(h[2][0])


@pytest.mark.parametrize("kind", ["box", "disk", "table"])
def test_above_static_friction_it_breaks_away_and_slides_with_kinetic_friction(kind: str) -> None:
    """0.6 m g > mu_s m g: it moves at once, and its velocity gains (F - mu m g)/m = 0.3 g per second,
    straight on (exactly for the exact wrenches; within the footprint table's 1e-10 of mu g)."""
    states = _run(kind, 0.6, active=True)
    assert states[0][2][0] > 0.0  # broken away in the first step
    (v1, _), (v2, _) = states[99][2], states[399][2]
    accel = (v2 - v1) / (300 * DT)
    assert abs(accel - (0.6 - MU) * G) < 1e-9 * G, accel
    side = 0.0 if kind != "table" else 1e-10 * MU * G * DT * len(states)  # the table's error, accumulated
    assert all(abs(s[2][1]) <= side and abs(s[3]) <= side / 0.05 for s in states)  # straight, no turn
