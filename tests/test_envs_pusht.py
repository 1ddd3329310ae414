"""rrbody/PushT-v0: gym-pusht's task without a table (checked against the installed gym-pusht), and the
T on a table of exact dry friction (checked against closed forms), its spaces and its errors.

The comparisons with gym-pusht run where it is installed (make test's oldest-versions pass, beside
pymunk 6.6, which gym-pusht pins); ``RRBODY_REQUIRE_PUSHT=1`` (set there) turns their skip into a failure.
"""
from __future__ import annotations

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest

import rrbody.envs  # noqa: F401 (registers rrbody/PushT-v0)
from rrbody.envs.pusht import OBS_TYPES, PushTEnv
from rrbody.envs.tabletop import MU, SCALE, G
from tests.pusht_support import need

#: mu g in workspace units/s^2 for the default table
A_DEFAULT = MU * G / SCALE
PARK = np.array([30.0, 30.0], dtype=np.float32)  # an action that keeps the agent far from the T
#: the walls' outer faces (gym-pusht's segments at 5 and 506, radius 2), units: a corner of the T beyond
#: one has crossed that wall. On a table each sub-step moves a point at most a wall's thickness (4 units),
#: so from inside the T can reach into a wall but not through it.
WALL_OUTER = (3.0, 508.0)


def _flat(obs: object) -> np.ndarray:
    return np.concatenate([np.ravel(v) for v in obs.values()]) if isinstance(obs, dict) else np.ravel(obs)


def _walk(obs: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
    """A seeded random walk of the agent's target from its start: pushes the T now and then."""
    start = np.asarray(obs, dtype=np.float64)[:2]
    return np.clip(start + np.cumsum(rng.normal(0.0, 30.0, (n, 2)), axis=0), 0, 512).astype(np.float32)


@pytest.mark.parametrize("obs_type", ["state", "environment_state_agent_pos"])
def test_without_a_table_it_is_gym_pusht(obs_type: str) -> None:
    """Same seeds and actions: the same observations (bit for bit: the same pymunk calls in the same
    order), rewards, flags and info; the coverage to rounding (gym-pusht's shapely overlay and
    rrbody.physics.overlap's exact clipping differ by ~1e-15: 1e-12 allows for it and no more)."""
    need("gym_pusht")
    steps = 0
    for seed in range(8):
        ref = gym.make("gym_pusht/PushT-v0", obs_type=obs_type)
        ours = gym.make("rrbody/PushT-v0", obs_type=obs_type, table=False)
        assert ours.observation_space == ref.observation_space and ours.action_space == ref.action_space
        o_ref, i_ref = ref.reset(seed=seed)
        o_ours, i_ours = ours.reset(seed=seed)
        np.testing.assert_array_equal(_flat(o_ours), _flat(o_ref))
        assert sorted(i_ours) == sorted(i_ref)
        agent = o_ref["agent_pos"] if isinstance(o_ref, dict) else o_ref
        for action in _walk(agent, np.random.default_rng(seed), 60):
            r_ref, r_ours = ref.step(action), ours.step(action)
            np.testing.assert_array_equal(_flat(r_ours[0]), _flat(r_ref[0]))
            assert abs(r_ours[1] - r_ref[1]) <= 1e-12 and type(r_ours[1]) is type(r_ref[1])
            assert r_ours[2:4] == r_ref[2:4]
            assert abs(r_ours[4]["coverage"] - r_ref[4]["coverage"]) <= 1e-12
            for key in ("pos_agent", "vel_agent", "block_pose", "goal_pose"):
                np.testing.assert_array_equal(r_ours[4][key], r_ref[4][key])
            assert r_ours[4]["n_contacts"] == r_ref[4]["n_contacts"]
            assert r_ours[4]["is_success"] == r_ref[4]["is_success"]
            steps += 1
            if r_ref[2] or r_ref[3]:
                break
    assert steps > 200


@pytest.mark.parametrize("obs_type", ["pixels", "pixels_agent_pos"])
def test_without_a_table_its_pictures_are_gym_pusht_s(obs_type: str) -> None:
    """The 96 x 96 observations and the 680 x 680 renders, pixel for pixel (rrbody.envs.pusht_draw
    repaints pygame's surface and OpenCV's resize exactly: tests/test_envs_draw.py), contact marks included."""
    need("gym_pusht")
    marked = 0
    for seed in range(3):
        ref = gym.make("gym_pusht/PushT-v0", obs_type=obs_type)
        ours = gym.make("rrbody/PushT-v0", obs_type=obs_type, table=False)
        assert ours.observation_space == ref.observation_space
        o_ref, _ = ref.reset(seed=seed)
        o_ours, _ = ours.reset(seed=seed)
        np.testing.assert_array_equal(_flat(o_ours), _flat(o_ref))
        block = ref.unwrapped.block
        for action in np.random.default_rng(seed).normal(0, 40, (6, 2)):
            # near the T (contacts), inside the action space (beyond it rrbody clips: test_out_of_range_...)
            action = np.clip(np.array(block.position) + action, 0, 512).astype(np.float32)
            r_ref, r_ours = ref.step(action), ours.step(action)
            np.testing.assert_array_equal(_flat(r_ours[0]), _flat(r_ref[0]))
            np.testing.assert_array_equal(ours.render(), ref.render())
            marked += r_ref[4]["n_contacts"] > 0
    assert marked >= 3


def test_reset_to_state_is_gym_pusht_s() -> None:
    need("gym_pusht")
    state = [100.0, 120.0, 300.0, 250.0, 1.0]
    ref = gym.make("gym_pusht/PushT-v0")
    ours = gym.make("rrbody/PushT-v0", table=False)
    np.testing.assert_array_equal(ours.reset(options={"reset_to_state": state})[0],
                                  ref.reset(options={"reset_to_state": state})[0])


def test_the_walk_pushes_the_t() -> None:
    """The fidelity check above means something only if the T moves in it."""
    env = gym.make("rrbody/PushT-v0", table=False)
    moved = 0
    for seed in range(8):
        obs, _ = env.reset(seed=seed)
        start = obs[2:5].copy()
        for action in _walk(obs, np.random.default_rng(seed), 60):
            obs = env.step(action)[0]
        moved += not np.allclose(obs[2:5], start)
    assert moved >= 3


def test_without_a_table_velocities_are_wiped_each_step() -> None:
    """gym-pusht's stand-in for a table: damping 0, velocity x 0^dt: a T set moving stops at once
    (pymunk moves positions before it updates velocities: one step's travel, v dt, then nothing)."""
    env = PushTEnv(table=False)
    env.reset(options={"reset_to_state": [30, 30, 256, 300, 0.3]})
    env.block.velocity = (200.0, 0.0)
    x0 = env.block.position.x
    env.step(PARK)
    assert env.block.velocity == (0.0, 0.0) and env.block.position.x == pytest.approx(x0 + 200.0 * 0.01, abs=1e-12)


def _slide(mu: float, v0: float, heading: float, angle: float = 0.3) -> PushTEnv:
    env = PushTEnv(mu=mu)
    env.reset(options={"reset_to_state": [30, 30, 256, 300, angle]})
    env.block.velocity = (v0 * math.cos(heading), v0 * math.sin(heading))
    return env


def test_on_a_frictionless_table_the_t_keeps_its_momentum() -> None:
    """mu = 0: free motion, exactly (no wipe, no force): 0.5 s at 200 units/s is 100 units."""
    env = _slide(0.0, 200.0, 0.7)
    p0 = np.array(env.block.position)
    for _ in range(5):
        env.step(PARK)
    assert np.linalg.norm(np.array(env.block.position) - p0) == pytest.approx(100.0, rel=1e-12)
    assert abs(env.block.velocity) == pytest.approx(200.0, rel=1e-14)


@pytest.mark.parametrize("angle", [0.3, 2.0])
def test_a_sliding_t_decelerates_at_mu_g_without_turning(angle: float) -> None:
    """A T translating on the table: dry friction integrated over its area under the pressure that
    puts the centre of pressure at gym-pusht's centre of gravity (the mean of the bars' centroids, off
    their area centroid) is mu m g against the velocity with no torque, so |v| falls by mu g t exactly
    (each step removes mu g dt) and the heading and angle stay (rounding: 1e-12 relative)."""
    v0 = 300.0
    env = _slide(MU, v0, 0.7, angle)
    a0 = env.block.angle
    env.step(PARK)  # 0.1 s, less than the stopping time v0 / (mu g) = 0.17 s
    v = env.block.velocity
    assert abs(v) == pytest.approx(v0 - A_DEFAULT * 0.1, rel=1e-12)
    assert math.atan2(v.y, v.x) == pytest.approx(0.7, abs=1e-12)
    assert abs(env.block.angular_velocity) < 1e-12 and env.block.angle == pytest.approx(a0, abs=1e-12)
    env.step(PARK)
    assert env.block.velocity == (0.0, 0.0) and env.block.angular_velocity == 0.0  # stopped, and held


def test_the_stopping_distance_is_v0_squared_over_2_mu_g() -> None:
    """To within one step's travel v0 dt: a velocity set by hand counts from the plugin's next half step."""
    v0 = 200.0
    env = _slide(MU, v0, -1.1)
    p0 = np.array(env.block.position)
    for _ in range(3):
        env.step(PARK)
    d = np.linalg.norm(np.array(env.block.position) - p0)
    assert abs(d - v0 ** 2 / (2 * A_DEFAULT)) <= v0 * 0.01


def test_static_friction_holds_a_t_at_rest() -> None:
    env = PushTEnv(mu=0.3, mu_static=0.5)
    env.reset(seed=3)
    pose = np.array([*env.block.position, env.block.angle])
    agent = np.array(env.agent.position, dtype=np.float32)
    for _ in range(5):
        env.step(agent)  # the agent stays where it is
    np.testing.assert_array_equal(np.array([*env.block.position, env.block.angle]), pose)


def test_a_push_on_a_table_leaves_the_t_sliding_then_stopped() -> None:
    """The agent drives up into the T's stem for 0.1 s, then backs off: without a table the T stops with
    the agent; on a table (mu = 0.5) it slides on, away from the walls, and friction alone stops it."""
    travelled = {}
    for table in (False, True):
        env = PushTEnv(table=table, mu=0.5)
        env.reset(options={"reset_to_state": [256, 430, 256, 250, 0.0]})  # the agent below the stem
        for y in (200, 470):
            env.step(np.array([256, y], np.float32))
        at_release = np.array(env.block.position)
        for _ in range(5):
            env.step(np.array([256, 470], np.float32))
        travelled[table] = np.linalg.norm(np.array(env.block.position) - at_release)
        assert env.block.velocity == (0.0, 0.0) and env.block.position.y > 60  # the top bar clear of the wall
    assert travelled[False] == 0.0 and travelled[True] > 5.0


def test_spaces_and_observations() -> None:
    for obs_type in OBS_TYPES[:2]:
        env = gym.make("rrbody/PushT-v0", obs_type=obs_type)
        obs, info = env.reset(seed=0)
        assert env.observation_space.contains(obs)
        assert info["is_success"] is False
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs) and 0.0 <= reward <= 1.0
        assert {"coverage", "is_success", "n_contacts", "block_pose", "goal_pose"} <= set(info)
    assert gym.spec("rrbody/PushT-v0").max_episode_steps == 300


def test_the_goal_pose_gives_full_coverage() -> None:
    env = PushTEnv()
    env.reset(seed=0)
    env.block.angle = math.pi / 4  # the angle first: it turns the T about its centre of gravity
    env.block.position = (256, 256)
    env.agent.position = (30, 30)
    _, reward, terminated, _, info = env.step(PARK)
    assert info["coverage"] == pytest.approx(1.0, abs=1e-12) and reward == 1.0 and terminated
    env.block.position = (256 + 30 * math.cos(math.pi / 4), 256 + 30 * math.sin(math.pi / 4))  # 30 along the bar
    _, reward, terminated, _, info = env.step(PARK)
    # the top bar keeps 90 x 30 of its 120 x 30 in the goal; the stem, 30 wide, moved off the goal stem
    assert info["coverage"] == pytest.approx(90 * 30 / 6300, abs=1e-12) and not terminated


def test_gymnasium_s_checker_passes() -> None:
    from gymnasium.utils.env_checker import check_env

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the checker's notes on bounds; a failure still raises
        check_env(PushTEnv(), skip_render_check=True)


def test_two_async_workers_run_it() -> None:
    envs = gym.vector.AsyncVectorEnv([lambda: gym.make("rrbody.envs:rrbody/PushT-v0")] * 2)
    try:
        obs, _ = envs.reset(seed=[1, 2])
        for _ in range(3):
            obs, reward, *_ = envs.step(envs.action_space.sample())
        assert obs.shape == (2, 5) and reward.shape == (2,)
    finally:
        envs.close()


@pytest.mark.parametrize(("kw", "err", "words"), [
    ({"frobnicate": 1}, TypeError, "frobnicate"),
    ({"mu": -0.1}, ValueError, "mu must be"),
    ({"mu": 0.4, "mu_static": 0.2}, ValueError, "mu_static must be >= mu"),
    ({"scale": 0.0}, ValueError, "scale must be in (0"),
    ({"scale": -1.0}, ValueError, "scale must be in (0"),
    ({"scale": 1e-7}, ValueError, "scale must be in [9.81e-6, 9.81e6] m per unit for g = 9.81"),
    ({"g": 0.0}, ValueError, "g must be"),
    ({"pressure": "bogus"}, ValueError, "pressure must be one of"),
    ({"obs_type": "keypoints"}, ValueError, "obs_type must be one of"),
    ({"table": "yes"}, TypeError, "table must be True or False"),
    ({"damping": 2.0}, ValueError, "damping must be in [0, 1]"),
    ({"observation_width": 0}, ValueError, "observation_width"),
])
def test_bad_input_names_the_parameter(kw: dict, err: type, words: str) -> None:
    with pytest.raises(err, match=None) as e:
        gym.make("rrbody/PushT-v0", **kw)
    assert words in str(e.value), str(e.value)


def test_bad_actions_and_states() -> None:
    with pytest.raises(ValueError, match="render_mode must be 'rgb_array' or None"):
        PushTEnv(render_mode="human")  # (gymnasium.make wraps an rgb_array env in its own HumanRendering)
    env = PushTEnv()
    with pytest.raises(RuntimeError, match="reset"):
        env.step(PARK)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be 2 finite numbers"):
        env.step(np.array([np.nan, 1.0]))
    with pytest.raises(ValueError, match="reset_to_state"):
        env.reset(options={"reset_to_state": [1, 2, 3]})


# ---- every input checked before anything changes ----------------------------------------------------
def _snapshot(env: gym.Env) -> tuple:
    """What a refused call must leave as it was: the agent, the T, the table's clock, the generator."""
    u = env.unwrapped
    return (tuple(u.agent.position), tuple(u.agent.velocity), tuple(u.block.position), u.block.angle,
            tuple(u.block.velocity), u.block.angular_velocity, None if u.plane is None else u.plane.t,
            u.np_random.bit_generator.state, u.n_contact_points, u._last_action)


BAD_ACTIONS = [[[256.0, 256.0]], [256.0, 256.0, 1.0], np.array([256.0, 256.0, 1.0]), [256.0], "ab", 5.0, None,
               [np.nan, 1.0], np.array([1.0, np.inf], dtype=np.float32), [True, False], np.array(["1", "2"]),
               {"x": 1}]


@pytest.mark.parametrize("table", [True, False])
@pytest.mark.parametrize("action", BAD_ACTIONS, ids=[repr(a) for a in BAD_ACTIONS])
def test_a_bad_action_is_refused_naming_it_and_changes_nothing(action: object, table: bool) -> None:
    env = gym.make("rrbody/PushT-v0", table=table, obs_type="pixels")
    env.reset(seed=2)
    env.step(np.array([200.0, 200.0], dtype=np.float32))  # the agent moving: a step would change it
    before = _snapshot(env)
    with pytest.raises(ValueError) as e:
        env.step(action)
    msg = str(e.value)
    assert msg.startswith("action must be 2 ") and "[0, 512]" in msg and repr(action) in msg, msg
    assert _snapshot(env) == before
    obs = env.step(np.array([200.0, 200.0], dtype=np.float32))[0]  # not stuck: the next step runs
    assert env.observation_space.contains(obs)


@pytest.mark.parametrize("table", [True, False])
@pytest.mark.parametrize("obs_type", ["state", "pixels_agent_pos"])
def test_out_of_range_actions_are_clipped_to_the_workspace(table: bool, obs_type: str) -> None:
    """[1e30, 1e30] drove the agent to 3e29 units (and the picture's drawing raised, every step until a
    reset); now it is [512, 512]: the same step, bit for bit, as that action."""
    far, edge = gym.make("rrbody/PushT-v0", table=table, obs_type=obs_type), \
        gym.make("rrbody/PushT-v0", table=table, obs_type=obs_type)
    for env in (far, edge):
        env.reset(seed=4)
    for big, clipped in (([1e30, 1e30], [512.0, 512.0]), ([-1e6, 600.0], [0.0, 512.0]), ([-0.5, 3.0], [0.0, 3.0])):
        got, want = far.step(np.array(big)), edge.step(np.array(clipped))
        np.testing.assert_array_equal(_flat(got[0]), _flat(want[0]))
        assert got[1:4] == want[1:4] and far.observation_space.contains(got[0])
        np.testing.assert_array_equal(far.render(), edge.render())  # the action's mark at the clipped target


def test_the_agent_stays_in_the_workspace() -> None:
    """The agent is kinematic (no wall stops it) and PD-driven without overshoot (the discrete law's
    eigenvalues are real, 0.927 and 0.863: it moves to a weighted mean of its start and its targets), so
    with targets in [0, 512] it stays there: jumps between the corners, and beyond them, clipped."""
    env = gym.make("rrbody/PushT-v0", table=True)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(200):
        agent = env.step(rng.choice([-1e9, -20.0, 0.0, 512.0, 530.0, 1e9], size=2))[0][:2]
        assert np.all((agent >= 0.0) & (agent <= 512.0)), agent


def test_in_range_actions_of_any_type_are_gym_pusht_s() -> None:
    """Lists, tuples, int and float arrays at the workspace's corners and edges: the same observations
    as gym-pusht, bit for bit (the clip leaves [0, 512] untouched)."""
    need("gym_pusht")
    actions = [[0, 0], (512.0, 512.0), np.array([0, 512]), np.array([512.0, 0.0], dtype=np.float32),
               [256.0, 0.0], (0.0, 256.5), np.array([511.9, 0.1]), [512, 512], [300, 200]] * 3
    ref = gym.make("gym_pusht/PushT-v0", obs_type="environment_state_agent_pos")
    ours = gym.make("rrbody/PushT-v0", obs_type="environment_state_agent_pos", table=False)
    np.testing.assert_array_equal(_flat(ours.reset(seed=5)[0]), _flat(ref.reset(seed=5)[0]))
    for a in actions:
        np.testing.assert_array_equal(_flat(ours.step(a)[0]), _flat(ref.step(a)[0]))


def test_out_of_range_actions_are_gym_pusht_s_clipped() -> None:
    """gym-pusht drives its agent to any target, through its walls and out of its observation space;
    rrbody's env (table=False) takes the nearest target inside its action space instead."""
    need("gym_pusht")
    ref = gym.make("gym_pusht/PushT-v0")
    ours = gym.make("rrbody/PushT-v0", table=False)
    np.testing.assert_array_equal(ours.reset(seed=6)[0], ref.reset(seed=6)[0])
    for a in ([530.0, 300.0], [-40.0, 600.0], [256.0, 1e30], [300.0, 200.0]):
        mine = ours.step(np.array(a))[0]
        np.testing.assert_array_equal(mine, ref.step(np.clip(a, 0, 512))[0])
        assert ours.observation_space.contains(mine)


BAD_STATES = ["abcde", [1, 2, 3], [[1, 2, 3, 4, 5]], [1, 2, 3, 4, "5"], {"a": 1}, [256, 256, 256, 256, np.nan],
              [256, 256, 1e6, 1e6, 0],            # the T far outside the walls
              [600, 256, 256, 256, 0], [-1, 256, 256, 256, 0],  # the agent outside the workspace
              [0.0, 10.0, 20.0, 30.0, 1.0],       # gym-pusht's own docstring example: the stem beyond the left wall
              [256, 256, 30, 256, math.pi / 2]]   # the stem's centre at x = 0: gym-pusht pushes the T out


@pytest.mark.parametrize("state", BAD_STATES, ids=[repr(s) for s in BAD_STATES])
def test_a_bad_reset_to_state_is_refused_naming_it_and_changes_nothing(state: object) -> None:
    env = gym.make("rrbody/PushT-v0")
    env.reset(seed=1)
    env.step(np.array([200.0, 300.0], dtype=np.float32))
    before = _snapshot(env)
    with pytest.raises(ValueError) as e:
        env.reset(seed=9, options={"reset_to_state": state})  # the seed is not taken either
    assert str(e.value).startswith("options['reset_to_state'] ") and repr(state) in str(e.value), str(e.value)
    assert _snapshot(env) == before
    env.step(np.array([200.0, 300.0], dtype=np.float32))


@pytest.mark.parametrize("options", ["reset_to_state", [1, 2]])
def test_options_that_are_not_a_dict_are_refused(options: object) -> None:
    env = gym.make("rrbody/PushT-v0")
    with pytest.raises(ValueError, match=r"^options must be None or a dict"):
        env.reset(options=options)


@pytest.mark.parametrize("table", [True, False])
@pytest.mark.parametrize("state", [[256, 256, 40, 256, math.pi / 2], [256, 256, 8, 256, 0.0], [30, 30, 470, 300, 0.0]])
def test_a_t_over_a_wall_with_its_bars_inside_is_pushed_back_in(state: list, table: bool) -> None:
    """Each bar's centre inside the walls' inner faces (7 to 504): the contact solve pushes the T in, as
    gym-pusht does (there, [40, 256, pi/2] ends inside and [30, 256, pi/2] outside, its stem beyond)."""
    env = gym.make("rrbody/PushT-v0", table=table)
    env.reset(options={"reset_to_state": state})
    for _ in range(10):
        obs = env.step(np.array(state[:2], dtype=np.float32))[0]
    assert env.observation_space.contains(obs)
    corners = env.unwrapped.keypoints()
    assert corners.min() >= WALL_OUTER[0] and corners.max() <= WALL_OUTER[1], corners


def test_random_resets_are_inside_the_walls() -> None:
    """gym-pusht's draws (the T's origin in [100, 400)^2, any angle) all pass the check."""
    env = PushTEnv(table=False)
    for seed in range(300):
        env.reset(seed=seed)


@pytest.mark.parametrize("value", [0.0, -0.01, 0.2, 1e-9, math.nan, "0.01"])
def test_a_bad_dt_is_refused_naming_it(value: object) -> None:
    env = PushTEnv()
    with pytest.raises(ValueError, match=r"^dt must be in \[1e-5, 0.1\] s, got"):
        env.dt = value
    assert env.dt == 0.01


@pytest.mark.parametrize(("cog", "table"), [([1.0], False), ("ab", False), (5, True), ((0.0, 1e300), True)])
def test_a_bad_block_cog_is_refused_naming_it(cog: object, table: bool) -> None:
    """Its shape and type; on a table also one the T's footprint cannot carry (refused when made, not at
    the first reset)."""
    with pytest.raises(ValueError, match=r"^block_cog "):
        PushTEnv(block_cog=cog, table=table)
    PushTEnv(block_cog=(0.0, 1e300), table=False)  # gym-pusht's world takes any finite one


# ---- no tunnelling: sub-steps where the T would cross more than a wall's thickness ----------------------

def _watch(env: gym.Env) -> list[tuple[float, float]]:
    """After every physics step, the extremes of the T's corners (x and y together), units."""
    u = env.unwrapped
    inner, seen = u._advance, []

    def advance(dt: float) -> None:
        inner(dt)
        k = u.keypoints()
        seen.append((k.min(), k.max()))

    u._advance = advance
    return seen


@pytest.mark.parametrize("speed", [3500.0, 20000.0])
def test_a_fast_t_stays_inside_the_walls(speed: float) -> None:
    """Launched at 3,500 units/s (faster than the study's squirts out of pinches: its fastest, 2,897)
    and at 20,000 in 12 directions: inside the walls at every physics step, every observation in the
    observation space. At 3,500 units/s the T used to come to rest straddling a wall; at 20,000 it left
    the workspace."""
    for k in range(12):
        env = gym.make("rrbody/PushT-v0", obs_type="environment_state_agent_pos")
        env.reset(options={"reset_to_state": [30, 30, 256, 256, 0.0]})
        heading = k * math.pi / 6
        env.unwrapped.block.velocity = (speed * math.cos(heading), speed * math.sin(heading))
        seen = _watch(env)
        for _ in range(20):
            obs = env.step(PARK)[0]
            assert env.observation_space.contains(obs), (k, obs)
        lo, hi = min(s[0] for s in seen), max(s[1] for s in seen)
        assert lo >= WALL_OUTER[0] and hi <= WALL_OUTER[1], (k, lo, hi)


def _space_steps(env: gym.Env) -> tuple[list[float], list[int]]:
    """From now on, the dt of every pymunk step the space takes (sub-steps included), and after each
    physics step how many there had been."""
    u, got, ends = env.unwrapped, [], []
    inner, advance = u.space.step, u._advance

    def step(dt: float) -> None:
        got.append(dt)
        inner(dt)

    def physics(dt: float) -> None:
        advance(dt)
        ends.append(len(got))

    u.space.step, u._advance = step, physics
    return got, ends


def test_sub_steps_only_where_the_t_is_fast() -> None:
    """Ordinary pushing and rest: one step of 0.01 s each. A T launched at 20,000 units/s near a wall:
    pymunk steps of 0.01 / 2^k s, each moving it less than the walls' 4 units (200 units in 0.01 s: 64
    of them), aligned so that every physics step's add up to 0.01 s, and none more than twice the one
    before (Chipmunk scales a step's first impulses by that ratio: docs/envs.md)."""
    env = PushTEnv()
    env.reset(seed=0)
    dts, _ = _space_steps(env)
    for action in _walk(env.get_obs(), np.random.default_rng(0), 60):
        env.step(action)
    assert dts == [0.01] * 600
    env.reset(options={"reset_to_state": [30, 30, 256, 256, 0.0]})
    dts, ends = _space_steps(env)
    env.block.velocity = (20000.0, 0.0)
    for _ in range(3):
        env.step(PARK)
    assert dts[0] == 0.01 / 64 and 20000.0 * dts[0] < 4.0 < 20000.0 * 2 * dts[0]
    assert all(math.log2(0.01 / h).is_integer() for h in dts)
    assert all(b <= 2 * a for a, b in zip(dts, dts[1:]))
    for i, j in zip([0] + ends, ends):  # (rounding: the pieces are exact, their sum rounds)
        assert sum(dts[i:j]) == pytest.approx(0.01, rel=1e-15)
    assert dts[-1] == 0.01 and len(ends) == 30  # the ramp back to whole steps, within the three actions


def test_a_body_faster_than_the_sub_steps_can_hold_costs_a_bounded_step() -> None:
    """Beyond 3.3e6 units/s (2^13 sub-steps of the walls' thickness in 0.01 s) a physics step starts with
    pymunk steps of 0.01 / 2^13 s, and makes no more than 2^13 (here the T leaves through the wall in the
    first, and once no wall is within its reach the steps double back to 0.01 s)."""
    env = PushTEnv(table=True)
    env.reset(options={"reset_to_state": [30, 30, 256, 256, 0.0]})
    dts, ends = _space_steps(env)
    env.block.velocity = (1e9, 0.0)
    env.step(PARK)
    assert dts[0] == 0.01 / 2 ** 13 and ends[0] <= 2 ** 13


def test_without_gymnasium_the_import_names_the_extra() -> None:
    import subprocess
    import sys

    from tests.test_extras import BLOCK

    code = BLOCK + "\nimport rrbody.envs\n"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode != 0
    assert "the optional package 'gymnasium'" in p.stderr and "[envs]" in p.stderr, p.stderr[-500:]


def test_the_package_exports_the_env_and_the_wrapper_function() -> None:
    """``rrbody.envs.table`` is the wrapper function, even once its module has been imported (the module
    is ``rrbody.envs.wrapper``: a submodule named ``table`` would shadow the function)."""
    import rrbody.envs.wrapper  # noqa: F401
    from rrbody.envs import PushTEnv as Env
    from rrbody.envs import table

    assert callable(table) and table.__module__ == "rrbody.envs.wrapper" and Env is PushTEnv
