"""The coupled step's two routes to pymunk's contacts (rrbody.engine.memory.arbiters): pymunk's public API and
Chipmunk's own C functions called from compiled code. Where the compiled route is taken (its probe found the
same bits), a scene stepped on each gives the same bits at every step; with RRBODY_NO_PRIVATE=1 the public
route is the one taken."""

from __future__ import annotations

import numpy as np
import pymunk
import pytest

from rrbody.engine.memory import arbiters
from rrbody.engine.plugin.coupling import Coupling
from rrbody.plugin import PlaneFriction


def _scene(route: str) -> tuple[PlaneFriction, list[pymunk.Body]]:
    """Bodies on the plane thrown into each other and into walls (restitution, contact friction, a kinematic
    pusher with a surface velocity, a dynamic body off the plane, a body held by a joint), the plugin's
    coupled step on ``route``."""
    space = pymunk.Space()
    walls = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    for a, b in zip(walls, walls[1:] + walls[:1]):
        seg = pymunk.Segment(space.static_body, a, b, 0.01)
        seg.elasticity, seg.friction = 0.5, 0.8
        space.add(seg)
    pf = PlaneFriction(space, g=9.81)
    pf._coupling = Coupling(space, route=route)  # (the test's choice of route)
    rng = np.random.default_rng(5)
    bodies = []
    for i in range(10):
        b = pymunk.Body()
        s = pymunk.Circle(b, 0.05, (0.01, 0.0)) if i % 2 else pymunk.Poly.create_box(b, (0.09, 0.07))
        s.density, s.elasticity, s.friction = 50.0, 0.3, 0.4
        b.position = (-0.35 + 0.23 * (i % 4), -0.3 + 0.25 * (i // 4))
        b.velocity = tuple(rng.uniform(-1.5, 1.5, 2))
        b.angular_velocity = rng.uniform(-10.0, 10.0)
        space.add(b, s)
        if i != 9:  # the last one slides without the plane: a body off the plane
            pf.add(b, mu=0.3)
        bodies.append(b)
    space.add(pymunk.PivotJoint(bodies[0], space.static_body, (-0.35, -0.3)))
    pusher = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    ps = pymunk.Circle(pusher, 0.04)
    ps.friction, ps.surface_velocity = 0.5, (0.1, 0.0)
    pusher.position, pusher.velocity = (0.0, -0.45), (0.0, 0.2)
    space.add(pusher, ps)
    return pf, bodies


@pytest.mark.skipif(arbiters.compiled_route() is None,
                    reason="the compiled route is not taken on this pymunk or platform")
def test_both_routes_step_a_scene_bit_for_bit() -> None:
    runs = {route: _scene(route) for route in arbiters.ROUTES}
    solved = 0
    for _ in range(300):
        states = []
        for pf, bodies in runs.values():
            pf.step(1 / 120)
            states.append(np.array([[*b.position, b.angle, *b.velocity, b.angular_velocity] for b in bodies]))
        assert np.array_equal(states[0].view(np.int64), states[1].view(np.int64))
        solved += int(runs["compiled"][0]._coupling.last_report.shape[0] > 0)
    # islands were solved in 47 of the 300 steps (the last report is the step's own: none where nothing touched),
    # so the bits compared hold the coupled solve's answers, not only steps it left to the engine
    assert solved >= 40


def test_no_private_takes_the_public_route(monkeypatch: pytest.MonkeyPatch) -> None:
    """RRBODY_NO_PRIVATE=1: no compiled route, and asking for it is a ValueError naming it."""
    monkeypatch.setenv("RRBODY_NO_PRIVATE", "1")
    assert arbiters.compiled_route() is None
    assert Coupling(pymunk.Space()).route == "public"
    with pytest.raises(ValueError, match="route 'compiled' is not available here"):
        Coupling(pymunk.Space(), route="compiled")
