"""Static friction under an active body's propulsion, beyond tests/test_active_static.py: the loads
together, the limit surface, a stop against the propulsion, many bodies in one call, the ODE path.

docs/active.md: plane friction sees the propulsion as a load, as it sees a force of the user's or a
tilt's pull, so a body at rest whose load lies inside its contact's static limit surface stays there,
exactly (position and angle unchanged bit for bit, the friction exactly minus the load); above it the
body breaks away and, pushed straight through its centre of gravity, slides with the acceleration
(F - mu m g) / m of the closed form. Both paths: the pymunk plugin through Python, and the ODE path
(and both through ``rrbody simulate``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pymunk = pytest.importorskip("pymunk")

from rrbody.analysis.simulate import simulate  # noqa: E402
from rrbody.model.active import Active  # noqa: E402
from rrbody.model.bodies import Disk  # noqa: E402
from rrbody.model.friction import Friction  # noqa: E402
from rrbody.model.pressure import points  # noqa: E402
from rrbody.model.scene import Scene  # noqa: E402
from rrbody.plugin import PlaneFriction  # noqa: E402
from tests.clirun import run_many  # noqa: E402

G = 9.81
MU, MU_S = 0.3, 0.5
DT = 1 / 120
#: three point feet of equal load on a circle of radius 0.06 m (tests/test_lean_sweep.py's)
FEET = [(0.06, 0.0, 1.0), (-0.03, 0.06 * math.sin(2 * math.pi / 3), 1.0),
        (-0.03, -0.06 * math.sin(2 * math.pi / 3), 1.0)]
#: the footprints: a box (exact polygon wrench), a disk (its table), a disk on feet, a box from its own
#: footprint table, an L from its own table
KINDS = ("box", "disk", "feet", "box-table", "L-table")


def _body(space: object, pf: PlaneFriction, kind: str, *, x: float = 0.0, mu_static: float = MU_S) -> object:
    """A body of footprint ``kind`` at rest at (x, 0), angle 0, added to ``pf`` with mu and mu_static."""
    b = pymunk.Body()
    if kind in ("disk", "feet"):
        shapes = [pymunk.Circle(b, 0.08)]
    elif kind == "L-table":
        shapes = [pymunk.Poly(b, [(-0.08, -0.08), (0.08, -0.08), (0.08, 0.0), (-0.08, 0.0)]),
                  pymunk.Poly(b, [(-0.08, 0.0), (0.0, 0.0), (0.0, 0.08), (-0.08, 0.08)])]
    else:
        shapes = [pymunk.Poly.create_box(b, (0.2, 0.1))]
    for s in shapes:
        s.density = 800.0
    b.position = (x, 0.0)
    space.add(b, *shapes)
    pf.add(b, mu=MU, mu_static=mu_static, pressure=points(FEET) if kind == "feet" else "uniform",
           friction_method="table" if kind.endswith("table") else "auto")
    return b


def _state(b: object) -> tuple[float, ...]:
    return (b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y, b.angular_velocity)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("share", [0.4, 0.49])  # F / (m g): between mu and mu_static, and just below it
def test_a_propulsion_static_friction_can_hold_leaves_the_body_exactly_at_rest(kind: str, share: float) -> None:
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = _body(space, pf, kind)
    f = share * b.mass * G
    pf.activate(b, Active(force=f))
    start = _state(b)
    for _ in range(600):  # 5 s
        pf.step(DT)
        assert _state(b) == start  # bit for bit: nothing moves, not even by rounding
    # static friction supplies exactly minus the load (the kernel cancels it, so the subtraction is exact)
    assert pf.friction(b) == (-f, 0.0, 0.0)


@pytest.mark.parametrize("kind", KINDS)
def test_propulsion_tilt_and_hand_force_are_held_as_one_load(kind: str) -> None:
    """The three loads together, their sum inside the limit surface though the propulsion alone is more
    than mu m g: held. Turned round (the same sizes adding up to 0.65 m g > mu_static m g): it breaks away."""
    for sign, held in ((-1.0, True), (1.0, False)):
        space = pymunk.Space()
        pf = PlaneFriction(space, g=G, tilt=math.atan(0.1), downhill=0.0 if sign > 0 else math.pi)
        b = _body(space, pf, kind)
        m = b.mass
        pull = G * math.sin(math.atan(0.1))  # the tilt's pull, 0.0995 g along downhill
        pf.activate(b, Active(force=0.45 * m * G))
        start = _state(b)
        for _ in range(120):
            b.apply_force_at_local_point((0.0, sign * 0.1 * m * G))  # a hand's push across
            pf.step(DT)
        # the load: (0.45 g + sign pull, sign 0.1 g) per unit mass, of size 0.36 g or 0.56 g (g cos(tilt) ~ g)
        size = math.hypot(0.45 * G + sign * pull, 0.1 * G)
        assert (size < MU_S * G * math.cos(math.atan(0.1))) == held
        if held:
            assert _state(b) == start
        else:
            assert b.position.x > 0.01  # slid off (0.5 a t^2 with a ~ 0.26 g over 1 s: ~1 m)


def test_a_body_that_comes_to_rest_against_its_propulsion_is_then_held() -> None:
    """Launched at 1 m/s against a propulsion of 0.4 m g: it stops (deceleration (mu + 0.4) g) and static
    friction then holds the propulsion: not a bit of motion after the stop."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = _body(space, pf, "box")
    b.velocity = (-1.0, 0.0)
    pf.activate(b, Active(force=0.4 * b.mass * G))
    for _ in range(120):  # the stop takes 1 / (0.7 g) = 0.146 s
        pf.step(DT)
    assert pf.stop_time(b) is not None and pf.stop_time(b) < 0.2
    rest = _state(b)
    assert rest[3:] == (0.0, 0.0, 0.0)
    for _ in range(300):
        pf.step(DT)
        assert _state(b) == rest


def test_a_body_activated_as_the_rest_rule_stops_it_is_held() -> None:
    """Activated right after the step in which the rest rule stopped it (its velocity then a rounding
    residue, set exactly to zero in the next step): it gets no half kick either, and is held."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = _body(space, pf, "box")
    b.velocity = (0.3, 0.0)
    while pf.stop_time(b) is None:  # (0.3 / (mu g) = 0.1 s)
        pf.step(DT)
    pf.activate(b, Active(force=0.4 * b.mass * G))
    pf.step(DT)
    rest = _state(b)
    assert rest[3:] == (0.0, 0.0, 0.0)
    for _ in range(120):
        pf.step(DT)
        assert _state(b) == rest


@pytest.mark.parametrize("kind", ["box", "feet", "L-table"])
def test_an_off_centre_propulsion_is_held_where_the_limit_surface_holds_the_same_hand_force(kind: str) -> None:
    """Propulsion 0.45 m g at lever arms from 0 to 0.1 m: its torque takes the load out of the limit
    surface somewhere in between. Held or not, the body does in its first step what the same force
    applied by hand at the same body point makes it do (the verdict is the limit surface's)."""
    verdicts = []
    for lever in (0.0, 0.02, 0.05, 0.1):
        space = pymunk.Space()
        pf = PlaneFriction(space, g=G)
        act = _body(space, pf, kind)
        hand = _body(space, pf, kind, x=5.0)
        f = 0.45 * act.mass * G
        pf.activate(act, Active(force=f, point=(0.0, lever)))
        cog = hand.center_of_gravity  # (the L's is off its body origin; the propulsion's point is from it)
        hand.apply_force_at_local_point((f, 0.0), (cog.x, cog.y + lever))
        pf.step(DT)
        held = _state(act)[2:] == (0.0, 0.0, 0.0, 0.0)
        assert held == (_state(hand)[2:] == (0.0, 0.0, 0.0, 0.0))
        np.testing.assert_allclose(_state(act)[2:], _state(hand)[2:], rtol=1e-12, atol=1e-15)
        verdicts.append(held)
    assert verdicts[0] and not verdicts[-1]  # both verdicts occur: the test discriminates


def test_many_bodies_through_the_lean_sweep_each_get_their_verdict() -> None:
    """40 bodies of every kind in one plugin, every other one held (0.45 m g) and the others breaking away
    (0.55 m g): the one compiled call (its lean sweep and its limit-set loop) gives each its verdict."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    bodies = []
    for i in range(40):
        b = _body(space, pf, KINDS[i % len(KINDS)], x=0.5 * i)
        pf.activate(b, Active(force=(0.45 if i % 2 == 0 else 0.55) * b.mass * G))
        bodies.append((b, _state(b), i % 2 == 0))
    for _ in range(60):
        pf.step(DT)
    for b, start, held in bodies:
        assert (_state(b) == start) == held


def _scene(share: float, **kw: object) -> Scene:
    disk = Disk(R=0.05, mass=0.2)
    return Scene(body=disk, drive=None, friction=Friction("dry", MU * G), mu_static=MU_S, g=G,
                 active=Active(force=share * disk.mass * G, **kw))


def test_the_ode_path_holds_a_propulsion_between_mu_and_mu_static() -> None:
    run = simulate(_scene(0.4), method="ode", t_max=2.0, dt_out=0.1)
    assert np.all(run.x_cm == 0.0) and np.all(run.y_cm == 0.0) and np.all(run.vx_cm == 0.0)
    assert np.all(run.body_angle == run.body_angle[0]) and run.events["t_stop"] == 0.0


def test_the_ode_path_breaks_away_above_mu_static_with_the_closed_form_acceleration() -> None:
    """From rest the body leaves along the break-away acceleration (F - mu m g) / m, then slides on with it:
    v = a t and x = a t^2 / 2, to the break-away start's O(tau^2) (tau = 1e-6 t_max) and the integrator's
    tolerance (rtol 1e-10)."""
    run = simulate(_scene(0.6), method="ode", t_max=2.0, dt_out=0.1)
    a = (0.6 - MU) * G
    np.testing.assert_allclose(run.vx_cm, a * run.t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.x_cm, 0.5 * a * run.t**2, rtol=0, atol=1e-9)
    eng = simulate(_scene(0.6), method="engine", t_max=2.0, dt_out=0.1, dt=1 / 400)
    # the engine's break-away waits for its first step: its position lags by a dt t / 2 (first order in dt)
    np.testing.assert_allclose(eng.x_cm, run.x_cm, rtol=0, atol=a * (1 / 400) * 2.0)


def test_the_ode_path_refuses_a_held_noisy_body_at_rest() -> None:
    with pytest.raises(ValueError, match="v0 and spin0.*method='engine'"):
        simulate(_scene(0.4, rot_drag=1.0, rot_diffusion=0.1), method="ode", t_max=1.0, dt_out=0.1)


def test_rrbody_simulate_holds_and_breaks_away_on_both_paths(tmp_path: Path) -> None:
    """The real command: a 1 kg disk (--mu 0.3 --mu-static 0.5), propulsion 0.4 m g held on both paths,
    0.6 m g sliding at (F - mu m g) / m (the engine's velocity belongs to the half step: its step's a dt)."""
    base = ["simulate", "--body", "disk", "--R0", "0.05", "--no-drive", "--mu", "0.3",
            "--mu-static", "0.5", "--t-max", "1", "--dt-out", "0.25"]
    argvs = []
    for share in (0.4, 0.6):
        force = repr(share * 1.0 * G)
        argvs += [[*base, "--active-force", force, "--out", f"ode-{share}.csv"],
                  [*base, "--active-force", force, "--method", "engine", "--dt", "0.01", "--out", f"eng-{share}.csv"]]
    runs = run_many(argvs, cwd=tmp_path, parallel=2, timeout=1800)  # the real command (compiles on a first use)
    for r in runs:
        assert r.code == 0, (r.argv, r.err)
    cols = np.genfromtxt(tmp_path / "ode-0.4.csv", delimiter=",", skip_header=1, names=True)
    names = cols.dtype.names
    x, vx = [n for n in names if n.startswith("x_cm")][0], [n for n in names if n.startswith("vx_cm")][0]
    for path in ("ode-0.4.csv", "eng-0.4.csv"):
        held = np.genfromtxt(tmp_path / path, delimiter=",", skip_header=1, names=True)
        assert np.all(held[x] == 0.0) and np.all(held[vx] == 0.0), path
    a = 0.3 * G
    ode = np.genfromtxt(tmp_path / "ode-0.6.csv", delimiter=",", skip_header=1, names=True)
    np.testing.assert_allclose(ode[vx], a * ode["t"], atol=1e-9)
    eng = np.genfromtxt(tmp_path / "eng-0.6.csv", delimiter=",", skip_header=1, names=True)
    np.testing.assert_allclose(eng[vx][1:], a * eng["t"][1:], atol=a * 0.01)
