"""rrbody.envs.table (rrbody/envs/wrapper.py): gym-pusht's own Push-T env (and any env meeting the contract) on a table.

Against the real gym-pusht (0.1.8 in the oldest-versions venv); its tests skip where it is not installed,
unless RRBODY_REQUIRE_PUSHT=1, which makes a missing gym-pusht an error. The contract env at the end (a puck
in a pymunk space of its own) runs wherever gymnasium and pymunk are installed.

Reference values are exact for these set-ups. A body translating without turning feels |F| = mu m g
against its velocity, and no torque, under any pressure whose centre is its centre of gravity (the
plugin's rule: gym-pusht's T, whose centre of gravity (0, 45) is not its area centroid (0, 40.7), gets a
linear pressure), so its speed falls by mu g_space dt per step of dt (g_space = g / scale, units/s^2), and
the staggered scheme integrates constant deceleration exactly: the only error is rounding. gym-pusht steps
10 substeps of DT = 0.01 s per env step.
"""
from __future__ import annotations

import math
import sys
import warnings
from typing import Any

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pymunk = pytest.importorskip("pymunk")

from rrbody.envs.tabletop import SCALE, G  # noqa: E402
from rrbody.envs.wrapper import TableSpace, TableWrapper, table  # noqa: E402
from tests.pusht_support import have  # noqa: E402

needs_pusht = pytest.mark.skipif(not have("gym_pusht"), reason="gym-pusht is not installed "
                                 "(RRBODY_REQUIRE_PUSHT=1 turns this into a failure)")

DT = 0.01        # s: gym-pusht's substep
N_SUB = 10       # substeps per env step
EPS = sys.float_info.epsilon
G_SPACE = G / SCALE  # units/s^2
#: agent right above the stem's end of a T at angle 0, on its symmetry axis: a push along -y through the
#: centre of gravity, which sets the T translating without turning
PUSH_STATE = [256.0, 495.0, 256.0, 350.0, 0.0]
#: agent far from a T at rest
APART_STATE = [100.0, 100.0, 300.0, 300.0, 0.5]


def _pusht(**kwargs: Any) -> Any:
    return gymnasium.make("gym_pusht/PushT-v0", **kwargs)


Row = tuple[int, tuple[float, float], float, tuple[float, float]]


def _push(env: Any, n: int, target_y: float = 420.0) -> list[Row]:
    """Reset to PUSH_STATE, push the T down for 2 env steps, then pull the agent back up; per env step:
    (contact points, T velocity, T spin, T position)."""
    env.reset(seed=0, options={"reset_to_state": PUSH_STATE})
    t = env.unwrapped.block
    out = []
    for k in range(n):
        _, _, _, _, info = env.step(np.array([256.0, target_y if k < 2 else 500.0]))
        out.append((info["n_contacts"], tuple(t.velocity), t.angular_velocity, tuple(t.position)))
    return out


def _free(rows: list[Row]) -> list[int]:
    """Indices k > 0 of the env steps with no contact in any of their substeps."""
    return [k for k in range(1, len(rows)) if rows[k][0] == 0]


# ---- (1) no friction, no wipe: free motion ----------------------------------------------------------
@needs_pusht
def test_mu_zero_keeps_the_momentum_and_gym_pusht_alone_wipes_it() -> None:
    env = table(_pusht(), mu=0.0)
    rows = _push(env, 6)
    assert env.unwrapped.space.damping == 1.0  # gym-pusht's 0 (the wipe) made 1
    free = _free(rows)
    assert len(free) >= 3, rows
    for k in free:  # no force at all: pymunk's v * 1**dt + 0 is the same float, bit for bit
        assert rows[k][1] == rows[k - 1][1] and rows[k][2] == rows[k - 1][2]
    assert math.hypot(*rows[free[0]][1]) > 100.0  # it moves (units/s)
    bare = _push(_pusht(), 6)  # gym-pusht alone: the velocity is gone the first step without contact
    k = next(k for k in range(1, 6) if bare[k][0] == 0)
    assert bare[k][1] == (0.0, 0.0) and bare[k][2] == 0.0


# ---- (2) the table: mu g / scale deceleration, then a stop ---------------------------------------------
@needs_pusht
def test_a_pushed_t_decelerates_at_mu_g_over_scale_and_stops() -> None:
    mu = 0.05  # a slow slide (294 units/s^2): eight env steps without contact before the stop
    a = mu * G_SPACE
    env = table(_pusht(), mu=mu)
    rows = _push(env, 14)
    sliding = [k for k in _free(rows) if rows[k][1] != (0.0, 0.0)]
    assert len(sliding) >= 5, rows
    v_max = max(math.hypot(*r[1]) for r in rows)
    w_max = max(abs(r[2]) for r in rows)
    # Without turning: the spin is rounding only (the push is along the symmetry axis).
    assert w_max < 1e-12
    # Each substep subtracts a*DT from a speed <= v_max: a few roundings of size eps*v_max each (8 allowed);
    # a spin w < 1e-12 rad/s tilts the force by w R / v, which changes the speed at second order (< 1e-20).
    tol = N_SUB * 8 * EPS * v_max
    for k in sliding:
        drop = math.hypot(*rows[k - 1][1]) - math.hypot(*rows[k][1])
        assert abs(drop - a * N_SUB * DT) <= tol, (k, drop, a * N_SUB * DT, tol)
    # it stops after the agent left: exactly at rest, then the pose stays bit-identical
    stop = next(k for k in range(len(rows)) if rows[k][1] == (0.0, 0.0) and rows[k][2] == 0.0)
    assert all(r[0] == 0 for r in rows[sliding[0]:])
    assert all(r[1:] == rows[stop][1:] for r in rows[stop:]) and len(rows) - stop >= 3
    assert env.plane.stop_time(env.unwrapped.block) is not None


@needs_pusht
def test_the_stop_distance_is_v2_over_2a() -> None:
    """From the centre of gravity's velocity at an env step's end (plane.velocity: second order at the
    step's time) the T slides v^2 / (2a) further; the stop's step lands within a DT^2 / 8 of the exact
    turn (docs/plugin.md, the scheme)."""
    mu = 0.05
    a = mu * G_SPACE
    env = table(_pusht(), mu=mu)
    env.reset(seed=0, options={"reset_to_state": PUSH_STATE})
    t, plane = env.unwrapped.block, env.plane
    seen = []
    for k in range(14):
        _, _, _, _, info = env.step(np.array([256.0, 420.0 if k < 2 else 500.0]))
        seen.append((info["n_contacts"], t.position.y, plane.velocity(t)))
    y_end = seen[-1][1]
    checked = 0
    for k in range(len(seen) - 1):
        if all(c == 0 for c, _, _ in seen[k + 1:]) and seen[k][2][1] != 0.0:
            v = math.hypot(seen[k][2][0], seen[k][2][1])
            assert abs((seen[k][1] - y_end) - v * v / (2 * a)) <= a * DT * DT / 8
            checked += 1
    assert checked >= 5


# ---- (3) observations, actions, rewards unchanged ---------------------------------------------------
def _structure(x: Any) -> Any:
    """Keys, shapes and dtypes of an observation or info value."""
    if isinstance(x, dict):
        return {k: _structure(v) for k, v in x.items()}
    if isinstance(x, np.ndarray):
        return ("array", x.shape, x.dtype)
    return type(x)


@needs_pusht
@pytest.mark.parametrize("obs_type", ["state", "environment_state_agent_pos", "pixels_agent_pos"])
def test_observations_rewards_and_spaces_are_the_envs_own(obs_type: str) -> None:
    bare, wrapped = _pusht(obs_type=obs_type), table(_pusht(obs_type=obs_type))
    assert wrapped.observation_space == bare.observation_space
    assert wrapped.action_space == bare.action_space
    for seed in (0, 7):
        ob, ib = bare.reset(seed=seed)
        ow, iw = wrapped.reset(seed=seed)
        assert _structure(ow) == _structure(ob) and _structure(iw) == _structure(ib)
        for x, y in zip(_leaves(ow) + _leaves(iw), _leaves(ob) + _leaves(ib)):
            np.testing.assert_array_equal(x, y)  # the reset's own step runs without the table
        bare.action_space.seed(seed)
        for _ in range(2):
            act = bare.action_space.sample()
            sb, sw = bare.step(act), wrapped.step(act)
            assert [_structure(x) for x in sw] == [_structure(x) for x in sb]
            assert wrapped.observation_space.contains(sw[0]) == bare.observation_space.contains(sb[0])
            assert 0.0 <= sw[1] <= 1.0
    frame = wrapped.render()  # debug_draw through TableSpace
    assert frame.shape == bare.render().shape and frame.dtype == np.uint8


def _leaves(x: Any) -> list[Any]:
    return [v for k in sorted(x) for v in _leaves(x[k])] if isinstance(x, dict) else [x]


# ---- (4) resets: a new space each time, the table under each --------------------------------------
@needs_pusht
def test_every_reset_gets_a_new_space_and_the_table() -> None:
    mu = 0.3
    a = mu * G_SPACE
    env = table(_pusht(), mu=mu)
    spaces = []
    for seed in range(4):
        env.reset(seed=seed, options={"reset_to_state": [100.0 + 20 * seed, 100.0, 300.0, 300.0, 0.5 * seed]})
        u, plane = env.unwrapped, env.plane
        assert isinstance(u.space, TableSpace) and plane.space is u.block.space
        assert all(plane.space is not s for s in spaces)  # gym-pusht's _setup built a new one
        spaces.append(plane.space)
        assert plane.bodies == (u.block,) and plane.space.damping == 1.0  # the agent is kinematic: not on the table
        x0 = u.block.position
        u.block.velocity = (0.0, 100.0)  # a fresh body: its velocity at the next step's start
        _, _, _, _, info = env.step(np.array(u.agent.position))
        assert info["n_contacts"] == 0 and u.block.velocity == (0.0, 0.0)
        # the slide is v^2 / (2a) = 2.83 units (no table and no wipe: 10 units; the wipe: 1 unit), within
        # a DT^2 / 8 of the stop's step (docs/plugin.md); x unchanged but for rounding
        d = u.block.position - x0
        assert abs(d.y - 100.0**2 / (2 * a)) <= a * DT * DT / 8 and abs(d.x) < 1e-12


# ---- (5) static friction ------------------------------------------------------------------------------
@needs_pusht
def test_a_t_at_rest_stays_exactly_at_rest_until_the_load_exceeds_mu_static() -> None:
    env = table(_pusht(), mu=0.2, mu_static=0.4)
    env.reset(seed=0, options={"reset_to_state": APART_STATE})
    u = env.unwrapped
    t = u.block
    pose = (tuple(t.position), t.angle)
    for k in range(8):  # the agent wanders far from the T; nothing pushes it
        env.step(np.array([100.0 + 10 * k, 100.0]))
        assert (tuple(t.position), t.angle) == pose and t.velocity == (0.0, 0.0) and t.angular_velocity == 0.0
    # a load between mu m g and mu_static m g (at the centre of gravity, in the first substep of each env
    # step: pymunk resets forces after each substep) does not move it either
    for _ in range(4):
        t.force = (0.3 * t.mass * G_SPACE, 0.0)
        env.step(np.array(u.agent.position))
        assert (tuple(t.position), t.angle) == pose and t.velocity == (0.0, 0.0)
    t.force = (0.5 * t.mass * G_SPACE, 0.0)  # beyond mu_static: it breaks away
    env.step(np.array(u.agent.position))
    assert t.position.x > pose[0][0]


# ---- an env of our own that meets the contract (used where gym-pusht is absent too) ------------------
class _Puck(gymnasium.Env):  # type: ignore[misc]
    """A disk (radius 10 units) in a pymunk space built once: the env keeps its space across resets, and
    launches the puck at 300 units/s after the reset's own step. Observation: (x, y, vx, vy)."""

    observation_space = gymnasium.spaces.Box(-np.inf, np.inf, (4,), dtype=np.float64)
    action_space = gymnasium.spaces.Discrete(1)
    n_sub = 5

    def __init__(self, damping: float = 0.0) -> None:
        self.space = pymunk.Space()
        self.space.damping = damping
        self.puck = pymunk.Body()
        shape = pymunk.Circle(self.puck, 10.0)
        shape.density = 1.0
        self.space.add(self.puck, shape)
        self.seen: list[tuple[type, float]] = []  # the space's type and damping during each reset's step

    def _obs(self) -> np.ndarray:
        return np.array([*self.puck.position, *self.puck.velocity])

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        super().reset(seed=seed)
        self.puck.position, self.puck.velocity = (0.0, 0.0), (0.0, 0.0)
        self.seen.append((type(self.space), self.space.damping))
        self.space.step(DT)
        self.puck.velocity = (300.0, 0.0)
        return self._obs(), {}

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict]:
        for _ in range(self.n_sub):
            self.space.step(DT)
        return self._obs(), 0.0, False, False, {}


# ---- (6) bad input ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, error, match", [
    ({"mu_s": 0.4}, TypeError, "mu_s"),
    ({"mu": -0.1}, ValueError, "mu must be"),
    ({"mu": 0.4, "mu_static": 0.3}, ValueError, "mu_static must be >= mu"),
    ({"scale": 0.0}, ValueError, "scale must be in"),
    ({"scale": -1.0}, ValueError, "scale must be in"),
    ({"scale": 1e-7}, ValueError, r"scale must be in \[9.81e-6, 9.81e6\] m per unit for g = 9.81"),  # g/scale > 1e6
    ({"pressure": "nonsense"}, ValueError, "pressure"),
    ({"bodies": [1, 2]}, TypeError, "bodies"),
])
def test_bad_arguments_are_refused_at_wrap_time(kwargs: dict[str, Any], error: type, match: str) -> None:
    env = _Puck()
    space = env.space
    with pytest.raises(error, match=match):
        table(env, **kwargs)
    env.reset(seed=0)  # nothing changed: the env resets and steps on its own space, with its wipe
    env.step(0)
    assert env.space is space and space.damping == 0.0 and env.puck.velocity == (0.0, 0.0)


@needs_pusht
def test_misuse_is_refused() -> None:
    with pytest.raises(TypeError, match="gymnasium.Env"):
        table(object())  # type: ignore[arg-type]
    env = table(_pusht())
    with pytest.raises(ValueError, match="already on a table"):
        table(env)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.plane  # noqa: B018 (the property's read is what raises)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(np.zeros(2))
    # a body the table cannot carry (the kinematic agent): the ValueError names it; the space is unchanged
    bad = table(_pusht(), bodies=lambda u: [u.agent])
    with pytest.raises(ValueError, match=r"bodies\(env.unwrapped\)\[0\] \(.*\) cannot go on the table: .*dynamic"):
        bad.reset(seed=0)
    assert isinstance(bad.unwrapped.space, pymunk.Space) and bad.unwrapped.space.damping == 0.0
    bad = table(_pusht(), bodies=lambda u: u.block)
    with pytest.raises(TypeError, match="iterable"):
        bad.reset(seed=0)
    # the env replaces its space outside reset: the table would be gone, so the next step refuses
    env.reset(seed=0)
    env.unwrapped.space = pymunk.Space()
    with pytest.raises(ValueError, match="replaced outside reset"):
        env.step(np.zeros(2))


class _Bare(gymnasium.Env):  # type: ignore[misc]
    """An env with no pymunk space, or with ``space`` set to something else."""

    observation_space = gymnasium.spaces.Box(-1.0, 1.0, (1,))
    action_space = gymnasium.spaces.Box(-1.0, 1.0, (1,))

    def __init__(self, space: Any = None) -> None:
        if space is not None:
            self.space = space

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[Any, dict]:
        super().reset(seed=seed)
        return np.zeros(1, dtype=np.float32), {}


def test_an_env_without_a_pymunk_space_is_refused() -> None:
    with pytest.raises(TypeError, match="must be a pymunk.Space, got int at wrap time"):
        table(_Bare(space=42))
    env = table(_Bare())  # no space yet (gym-pusht builds its own in reset): checked after the first reset
    with pytest.raises(TypeError, match="no attribute 'space' after reset.*pymunk.Space"):
        env.reset()


# ---- (7) under gymnasium.make's wrappers ---------------------------------------------------------------
@needs_pusht
def test_under_gymnasium_make_with_its_wrappers() -> None:
    env = table(_pusht(max_episode_steps=3), mu=0.3)  # TimeLimit(OrderEnforcing(PassiveEnvChecker(PushTEnv)))
    assert isinstance(env.env, gymnasium.wrappers.TimeLimit)
    for _ in range(2):
        env.reset(seed=1, options={"reset_to_state": APART_STATE})
        truncated = [env.step(np.array(env.unwrapped.agent.position))[3] for _ in range(3)]
        assert truncated == [False, False, True]
        assert env.plane.bodies == (env.unwrapped.block,)
    # and bare, as gym-pusht's class
    from gym_pusht.envs import PushTEnv
    bare = table(PushTEnv(), mu=0.3)
    bare.reset(seed=0, options={"reset_to_state": APART_STATE})
    assert isinstance(bare.unwrapped.space, TableSpace)


# ---- the contract env on the table ----------------------------------------------------------------------
def test_an_env_of_our_own_that_meets_the_contract() -> None:
    mu = 0.1
    a = mu * G_SPACE
    bare = _Puck()
    ob, _ = bare.reset(seed=0)
    env = table(_Puck(), mu=mu)
    u = env.unwrapped
    for _ in range(2):  # the same space both times: the env gets it back, with its own damping, in reset
        ow, _ = env.reset(seed=0)
        np.testing.assert_array_equal(ow, ob)
        assert u.seen[-1] == (pymunk.Space, 0.0) and isinstance(u.space, TableSpace)
        assert u.space.damping == 1.0 and env.plane.bodies == (u.puck,)
        speeds = [300.0]
        for _ in range(20):  # it stops in the 11th env step (0.55 s)
            speeds.append(math.hypot(*env.step(0)[0][2:]))
        speeds = speeds[:speeds.index(0.0) + 1]
        # body.velocity after a substep is the staggered scheme's, at its end + DT/2: the first env step
        # takes (n_sub + 1/2) a DT off the launch speed (the half kick), each next one n_sub a DT, exact
        # but for rounding
        tol = _Puck.n_sub * 8 * EPS * 300.0
        assert abs(speeds[0] - speeds[1] - a * (_Puck.n_sub + 0.5) * DT) <= tol
        assert np.allclose(np.diff(speeds[1:-1]), -a * _Puck.n_sub * DT, rtol=0, atol=tol)
        # the stop comes in the substep in which the exact motion turns, at 300 / a = 0.51 s
        assert 0.0 <= env.plane.stop_time(u.puck) - 300.0 / a <= DT
    # every other attribute reaches the real space: reads, writes, dir
    u.space.gravity = (1.0, 2.0)
    assert env.plane.space.gravity == (1.0, 2.0) and u.space.bodies == env.plane.space.bodies
    assert "add" in dir(u.space) and "TableSpace" in repr(u.space)
    # a damping other than 0 is the env's own drag: kept
    kept = table(_Puck(damping=0.5))
    kept.reset(seed=0)
    assert kept.unwrapped.space.damping == 0.5


# ---- (8) gymnasium's checker, and the spec it re-makes the wrapper from ---------------------------------
def _checked(env: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    from gymnasium.utils.env_checker import check_env

    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")  # gym-pusht's "human" render mode opens no window
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the checker's notes (bounds, float32); a failure still raises
        check_env(env)


@needs_pusht
def test_gymnasiums_checker_passes_on_gym_pusht(monkeypatch: pytest.MonkeyPatch) -> None:
    """check_env makes the env again from its spec (gymnasium.make(env.spec), for each render mode):
    the wrapper records its keywords as gymnasium's own wrappers do."""
    _checked(table(_pusht(), mu=0.2), monkeypatch)


def test_gymnasiums_checker_passes_on_rrbodys_env(monkeypatch: pytest.MonkeyPatch) -> None:
    import rrbody.envs  # noqa: F401 (registers rrbody/PushT-v0)

    env = table(gymnasium.make("rrbody/PushT-v0", table=False), mu=0.2, mu_static=0.4, g=9.8)
    _checked(env, monkeypatch)
    again = gymnasium.make(env.spec)  # the wrapper made again, with its keywords
    assert isinstance(again, TableWrapper) and again.table == env.table
    assert again.spec.additional_wrappers[-1].kwargs["mu_static"] == 0.4


# ---- (9) rrbody/PushT-v0 under the wrapper ---------------------------------------------------------------
def test_rrbodys_env_without_its_table_gets_the_wrappers() -> None:
    """rrbody/PushT-v0 with table=False steps its space through env.unwrapped.space, as gym-pusht does:
    the wrapper's table is under it (a T launched at 100 units/s slides v^2 / (2a) and stops; before, it
    went on at 100 units/s, the table never stepped)."""
    import rrbody.envs  # noqa: F401

    mu = 0.3
    a = mu * G_SPACE
    env = table(gymnasium.make("rrbody/PushT-v0", table=False), mu=mu)
    env.reset(options={"reset_to_state": APART_STATE})
    u = env.unwrapped
    x0 = u.block.position
    u.block.velocity = (100.0, 0.0)
    env.step(np.array(u.agent.position))
    assert u.block.velocity == (0.0, 0.0) and env.plane.t == pytest.approx(N_SUB * DT)  # the table stepped
    d = u.block.position - x0
    assert abs(d.x - 100.0**2 / (2 * a)) <= a * DT * DT / 8 and abs(d.y) < 1e-12  # (as test (4): the stop's step)


def test_rrbodys_env_on_its_own_table_is_refused() -> None:
    import rrbody.envs  # noqa: F401

    with pytest.raises(ValueError, match=r"already on a table \(rrbody/PushT-v0's own.*table=False"):
        table(gymnasium.make("rrbody/PushT-v0"))


# ---- (10) no tunnelling: sub-steps where a body would cross more than a wall's thickness ------------------
#: the walls' outer faces (gym-pusht's segments at 5 and 506, radius 2), units: a corner beyond one has
#: crossed that wall. Each sub-step moves a point at most a wall's thickness (4 units).
WALL_OUTER = (3.0, 508.0)


def _launch(env: Any, speed: float) -> None:
    """Launch the T at ``speed`` (units/s) in 12 directions, one env each reset; check its corners after
    every physics step and every observation against the observation space."""
    for k in range(12):
        env.reset(seed=0, options={"reset_to_state": [30.0, 30.0, 256.0, 256.0, 0.0]})
        u = env.unwrapped
        proxy, t, seen = u.space, u.block, []
        inner = object.__getattribute__(proxy, "step")

        def step(dt: float, inner: Any = inner, t: Any = t, seen: list = seen) -> None:
            inner(dt)
            seen.extend(t.local_to_world(v) for s in t.shapes for v in s.get_vertices())

        object.__setattr__(proxy, "step", step)
        t.velocity = (speed * math.cos(k * math.pi / 6), speed * math.sin(k * math.pi / 6))
        for _ in range(20):
            obs = env.step(np.array([30.0, 30.0]))[0]
            assert env.observation_space.contains(obs), (k, obs)
        xy = np.array(seen)
        assert xy.min() >= WALL_OUTER[0] and xy.max() <= WALL_OUTER[1], (k, xy.min(), xy.max())


@needs_pusht
@pytest.mark.parametrize("speed", [3500.0, 20000.0])
def test_a_fast_t_stays_inside_gym_pushts_walls(speed: float) -> None:
    """At 3,500 units/s (faster than the study's squirts: its fastest, 2,897) the T came to rest
    straddling a wall; at 20,000 it left the workspace. gym-pusht alone cannot do this: it wipes the
    velocity every step."""
    _launch(table(_pusht(obs_type="environment_state_agent_pos")), speed)


def test_a_fast_t_stays_inside_the_walls_of_rrbodys_env() -> None:
    import rrbody.envs  # noqa: F401

    _launch(table(gymnasium.make("rrbody/PushT-v0", table=False, obs_type="environment_state_agent_pos")), 20000.0)


def test_without_walls_there_are_no_sub_steps() -> None:
    """The puck's space has no static shape: its table is plane.step itself."""
    env = table(_Puck(), mu=0.1)
    env.reset(seed=0)
    assert env.unwrapped.space.step == env.plane.step


def test_a_wall_without_thickness_holds_a_fast_puck() -> None:
    """Segments of radius 0 (common in pymunk programs): the sub-steps are bounded by half the body's
    thinnest width instead (a shape is pushed back while less than half of it has crossed a wall)."""
    from rrbody.engine.plugin import PlaneFriction
    from rrbody.envs.substep import guarded

    space = pymunk.Space()
    space.damping = 1.0
    space.add(pymunk.Segment(space.static_body, (100.0, -100.0), (100.0, 100.0), 0.0))
    puck = pymunk.Body()
    shape = pymunk.Circle(puck, 10.0)
    shape.density = 1.0
    space.add(puck, shape)
    plane = PlaneFriction(space, g=G_SPACE)
    plane.add(puck, mu=0.3)
    step = guarded(plane.step, [puck], space)
    puck.velocity = (20000.0, 0.0)
    for _ in range(10):
        step(DT)
        assert puck.position.x < 100.0  # its centre never crosses the wall
    assert puck.velocity.x <= 0.0
