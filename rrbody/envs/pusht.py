"""Push-T on a table: the planar pushing task of Diffusion Policy, with the T sliding on rrbody's exact
dry friction.

The task, written from its published description and gym-pusht 0.1.8's behaviour (the environment
robot-learning users run; LeRobot's pusht): a 512 x 512 workspace (units; y down in pictures) inside
four walls; a T of two bars (the top bar 120 x 30 units, the stem 30 x 90 below it) on one body of mass
1 whose moment of inertia and centre of gravity are gym-pusht's, quirks included (the moment is twice
the top bar's about the body origin; the centre of gravity is the mean of the two bars' centroids, not
their area-weighted mean); a kinematic disk agent of radius 15 whose velocity a PD law (k_p 100,
k_v 20) drives to the action, the target position, at every 0.01 s physics step, 10 steps per action
(10 Hz control); the goal pose (256, 256, pi/4); reward = coverage / 0.95 clipped to [0, 1], where
the coverage is the T's area inside the goal T over the goal's area; success, and termination, above
0.95 coverage; episodes truncated at 300 actions by the registration (``rrbody/PushT-v0``).

The table. gym-pusht has none: it sets ``space.damping = 0``, which pymunk applies as
velocity x 0^dt, so every velocity is wiped at every step and the T moves only while it is pushed,
as its mass and inertia answer the contact impulse. Here (``table=True``, the default) the space keeps
its momentum and :class:`rrbody.engine.plugin.plane.PlaneFriction` presses the T on the table with its
weight (``pressure``: how the weight spreads; the centre of pressure follows the centre of gravity)
and applies dry friction integrated over its area: ``mu`` sliding, ``mu_static`` at rest (None: equal
to ``mu``), ``g`` in m/s^2, and ``scale`` metres per workspace unit (:mod:`rrbody.envs.tabletop`
states the defaults and where they come from). ``table=False`` is gym-pusht's environment: the same
observations for the same seeds and actions (tests/test_envs_pusht.py checks it against the package).
``damping`` is pymunk's, as gym-pusht takes it (default: 0 without a table, 1 on one).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from rrbody.engine.memory.compat import on_post_solve
from rrbody.envs.pusht_draw import draw
from rrbody.envs.substep import guarded
from rrbody.envs.tabletop import MU, SCALE, G, make_table
from rrbody.model.checks import check_choice, check_int, check_range
from rrbody.physics.overlap import overlap_area, pieces_area

__all__ = ["OBS_TYPES", "TEE", "PushTEnv", "tee_body", "tee_corners"]

#: gym-pusht 0.1.8's observation types
OBS_TYPES = ("state", "environment_state_agent_pos", "pixels", "pixels_agent_pos")
#: this environment's keywords (a keyword not among them is a TypeError naming it and these)
KEYWORDS = ("obs_type", "render_mode", "block_cog", "damping", "observation_width", "observation_height",
            "visualization_width", "visualization_height", "table", "mu", "mu_static", "pressure", "g", "scale")
WORKSPACE = 512.0
SUCCESS = 0.95
#: the four walls (segments, end points in units) and their radius, as gym-pusht builds them
WALLS = (((5, 506), (5, 5)), ((5, 5), (506, 5)), ((506, 5), (506, 506)), ((5, 506), (506, 506)))
WALL_RADIUS = 2
#: the walls' inner faces, units: a bar of the T whose centre lies between them is pushed back in by the
#: contact solve when it overlaps a wall (pymunk separates two shapes the shorter way); one beyond is pushed out
INSIDE = (5 + WALL_RADIUS, 506 - WALL_RADIUS)
#: what an action is (quoted by its errors)
ACTION = "the agent's target x, y in units, in [0, 512]; beyond it, clipped to it"


def _tee_vertices(scale: float = 30.0, length: float = 4.0) -> tuple[list[tuple[float, float]], ...]:
    """The T's two bars in the body frame (units), in gym-pusht's shape and vertex order."""
    top = [(-length * scale / 2, scale), (length * scale / 2, scale), (length * scale / 2, 0.0),
           (-length * scale / 2, 0.0)]
    stem = [(-scale / 2, scale), (-scale / 2, length * scale), (scale / 2, length * scale), (scale / 2, scale)]
    return top, stem


#: the T's corners in the body frame, (2, 4, 2) units: the top bar's 4, then the stem's
TEE = np.array(_tee_vertices(), dtype=np.float64)


def tee_body(space: Any, position: tuple[float, float] = (256.0, 300.0), angle: float = 0.0) -> tuple[Any, list[Any]]:
    """gym-pusht's T (its ``add_tee``) added to the pymunk ``space``: mass 1 and gym-pusht's moment (the top
    bar's about the body origin, twice: its second term reuses the top bar), the centre of gravity midway
    between the two bars' centroids, frictionless shapes; its body origin at ``position`` (units) turned by
    ``angle`` (rad). Returns (the body, its two shapes: the top bar, the stem)."""
    import pymunk

    top, stem = _tee_vertices()
    block = pymunk.Body(1, 2 * pymunk.moment_for_poly(1, vertices=top))
    shapes = [pymunk.Poly(block, top), pymunk.Poly(block, stem)]
    block.center_of_gravity = (shapes[0].center_of_gravity + shapes[1].center_of_gravity) / 2
    block.angle = angle
    block.position = position
    space.add(block, *shapes)
    return block, shapes


def tee_corners(x: float, y: float, angle: float) -> np.ndarray:
    """The T's corners (2, 4, 2), units, world frame, for its body origin at (x, y) turned by ``angle``
    (rad). (Pictures place them with pymunk's own arithmetic instead, for pixel-exact agreement.)"""
    c, s = math.cos(angle), math.sin(angle)
    out = np.empty_like(TEE)
    out[..., 0] = x + c * TEE[..., 0] - s * TEE[..., 1]
    out[..., 1] = y + s * TEE[..., 0] + c * TEE[..., 1]
    return out


def _reals(name: str, value: Any, n: int, what: str) -> np.ndarray:
    """``value`` as n finite float64 numbers, or a ValueError naming ``name``, the value and what it holds."""
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):  # ragged sequences
        a = np.asarray(None)
    if a.shape != (n,) or a.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be {n} real numbers ({what}), got {value!r}")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers ({what}), got {value!r}")
    return a


def _target(action: Any) -> tuple[float, float]:
    """The agent's target from an action: 2 finite real numbers (units), clipped to the workspace
    [0, 512]. gym-pusht drives its agent to any target, past its walls (the agent is kinematic) and out of
    its observation space; its action space, and its documentation, say [0, 512]."""
    a = action if isinstance(action, np.ndarray) else _reals("action", action, 2, ACTION)
    if a.shape != (2,) or a.dtype.kind not in "iuf":
        raise ValueError(f"action must be 2 real numbers ({ACTION}), got {action!r}")
    ax, ay = float(a[0]), float(a[1])
    if 0.0 <= ax <= WORKSPACE and 0.0 <= ay <= WORKSPACE:  # (also False for a NaN)
        return ax, ay
    if not (math.isfinite(ax) and math.isfinite(ay)):
        raise ValueError(f"action must be 2 finite numbers ({ACTION}), got {action!r}")
    return min(max(ax, 0.0), WORKSPACE), min(max(ay, 0.0), WORKSPACE)


def _box(lo: float, hi: float, n: int) -> spaces.Box:
    return spaces.Box(low=np.full(n, lo), high=np.full(n, hi), dtype=np.float64)


class PushTEnv(gym.Env):
    """Push-T (gym-pusht 0.1.8's task, spaces and seeding) on a table of exact dry friction.

    Observations (``obs_type``), in workspace units: ``state`` [agent x, agent y, T x, T y, T angle
    in [0, 2 pi)], the T's position being its body origin (the top bar's lower edge centre);
    ``environment_state_agent_pos`` {the T's 8 corners (16 numbers), the agent's position};
    ``pixels`` an (observation_height, observation_width, 3) uint8 picture; ``pixels_agent_pos``
    {the picture, the agent's position}. Actions: the agent's target position, 2 numbers in [0, 512]
    (beyond it, clipped to it). ``env.unwrapped.plane`` is the table
    (:class:`rrbody.engine.plugin.plane.PlaneFriction`, None without one); ``env.unwrapped.space`` the pymunk
    space, rebuilt by every reset. On a table a physics step is cut into sub-steps where the T would cross
    more than a wall's thickness in it (:mod:`rrbody.envs.substep`).

    Every input is checked before anything changes: a refused ``step`` or ``reset`` is a ValueError
    naming the parameter, its value and the valid range, and leaves the environment as it was.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, obs_type: str = "state", render_mode: str | None = "rgb_array",
                 block_cog: Any = None, damping: float | None = None, observation_width: int = 96,
                 observation_height: int = 96, visualization_width: int = 680, visualization_height: int = 680,
                 *, table: bool = True, mu: float = MU, mu_static: float | None = None, pressure: Any = "uniform",
                 g: float = G, scale: float = SCALE, **unknown: Any) -> None:
        if unknown:
            name = next(iter(unknown))
            raise TypeError(f"PushTEnv got an unknown keyword {name!r}; valid keywords: {', '.join(KEYWORDS)}")
        super().__init__()
        self.obs_type = check_choice("obs_type", obs_type, OBS_TYPES)
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be 'rgb_array' or None (no window: pictures are arrays), "
                             f"got {render_mode!r}")
        self.render_mode = render_mode
        self.observation_width = check_int("observation_width", observation_width, 1, 4096)
        self.observation_height = check_int("observation_height", observation_height, 1, 4096)
        self.visualization_width = check_int("visualization_width", visualization_width, 1, 4096)
        self.visualization_height = check_int("visualization_height", visualization_height, 1, 4096)
        if block_cog is not None:
            block_cog = tuple(float(c) for c in _reals("block_cog", block_cog, 2, "the T's centre of gravity in "
                                                                "its body frame, units"))
        self.block_cog = block_cog
        self.damping = None if damping is None else check_range("damping", damping, 0.0, 1.0)
        if not isinstance(table, bool):
            raise TypeError(f"table must be True or False, got {table!r}")
        self.table = make_table(mu, mu_static, pressure, g, scale) if table else None
        self.k_p, self.k_v = 100, 20
        self.control_hz = self.metadata["render_fps"]
        self.dt = 0.01
        self.success_threshold = SUCCESS
        self.action_space = spaces.Box(low=0, high=512, shape=(2,), dtype=np.float32)
        self.observation_space = self._observation_space()
        self._last_action: Any = None
        self.space: Any = None
        self.plane: Any = None
        if self.table is not None and block_cog is not None:
            try:  # a centre of gravity the T's footprint cannot carry: say so now, naming it, not at reset
                self._setup()
            except ValueError as e:
                raise ValueError(f"block_cog {block_cog!r} is one the table cannot carry under the T: {e}") from None
            finally:
                self.space = self.plane = None

    @property
    def dt(self) -> float:
        """The physics step, s (gym-pusht's 0.01): 1 / (dt x 10 Hz) of them, rounded down, per action."""
        return self._dt

    @dt.setter
    def dt(self, value: float) -> None:
        # at most 0.1 s: one physics step per action; at least 1e-5 s: 10,000 of them per action
        self._dt = check_range("dt", value, 1e-5, 0.1, unit="s")

    def _observation_space(self) -> spaces.Space:
        """gym-pusht 0.1.8's spaces, bounds and dtypes for ``obs_type``."""
        pixels = spaces.Box(low=0, high=255, shape=(self.observation_height, self.observation_width, 3),
                            dtype=np.uint8)
        agent = spaces.Box(low=np.array([0, 0]), high=np.array([512, 512]), dtype=np.float64)
        if self.obs_type == "state":
            return spaces.Box(low=np.array([0, 0, 0, 0, 0]), high=np.array([512, 512, 512, 512, 2 * np.pi]),
                              dtype=np.float64)
        if self.obs_type == "environment_state_agent_pos":
            return spaces.Dict({"environment_state": _box(0, 512, 16), "agent_pos": agent})
        if self.obs_type == "pixels":
            return pixels
        return spaces.Dict({"pixels": pixels, "agent_pos": agent})

    # ---- the world -----------------------------------------------------------------------------
    def _setup(self) -> None:
        """A new space: walls, the agent, the T, the goal, the contact counter, the table."""
        import pymunk

        space = pymunk.Space()
        space.gravity = 0, 0
        space.damping = self.damping if self.damping is not None else (0.0 if self.table is None else 1.0)
        space.add(*(pymunk.Segment(space.static_body, a, b, WALL_RADIUS) for a, b in WALLS))
        agent = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        agent.position = (256, 400)
        space.add(agent, pymunk.Circle(agent, 15))
        block, shapes = tee_body(space, (256, 300), 0)
        if self.block_cog is not None:
            block.center_of_gravity = self.block_cog
        self.space, self.agent, self.block, self._block_shapes = space, agent, block, shapes
        self.goal_pose = np.array([256, 256, np.pi / 4])
        # the goal as gym-pusht places it for its pictures: a body at the goal pose (pymunk's arithmetic)
        self._goal_body = pymunk.Body(1, pymunk.moment_for_box(1, (50, 100)))
        self._goal_body.position = self.goal_pose[:2].tolist()
        self._goal_body.angle = self.goal_pose[2]
        self._goal = tee_corners(256.0, 256.0, math.pi / 4)
        self._goal_area = pieces_area(self._goal)
        on_post_solve(space, 0, 0, self._handle_collision)
        self.n_contact_points = 0
        self.plane = None
        # without a table the space is stepped as gym-pusht steps it, through self.space (a wrapper that
        # puts a table under it, rrbody.envs.table, replaces that)
        self._advance = self._step_space
        if self.table is not None:
            from rrbody.engine.plugin import PlaneFriction

            t = self.table
            self.plane = PlaneFriction(space, g=t.g_space)
            self.plane.add(block, mu=t.mu, mu_static=t.mu_static, pressure=t.pressure)
            # the T keeps its momentum here: sub-steps where it would cross more than a wall in one step
            self._advance = guarded(self.plane.step, [block], space)

    def _step_space(self, dt: float) -> None:
        self.space.step(dt)

    def _handle_collision(self, arbiter: Any, space: Any, data: Any) -> None:
        self.n_contact_points += len(arbiter.contact_point_set.points)

    def _set_state(self, state: np.ndarray) -> None:
        """The agent at state[:2], the T's origin at state[2:4] then its angle state[4] (gym-pusht's
        order: the angle turns the T about its centre of gravity), then one physics step."""
        self.agent.position = list(state[:2])
        self.block.position = list(state[2:4])
        self.block.angle = state[4]
        self._advance(self.dt)

    def _reset_state(self, options: Any) -> np.ndarray | None:
        """``options["reset_to_state"]`` checked: 5 finite numbers, the agent in the workspace [0, 512]^2
        (it is kinematic: it passes over the walls, as the actions let it), each bar of the T with its centre
        inside the walls' inner faces once placed as :meth:`_set_state` places it; None without one."""
        if options is None:
            return None
        if not isinstance(options, Mapping):
            raise ValueError(f"options must be None or a dict (its key 'reset_to_state': [agent x, agent y, T x, "
                             f"T y, T angle]), got {options!r}")
        value = options.get("reset_to_state")
        if value is None:
            return None
        name = "options['reset_to_state']"
        state = _reals(name, value, 5, "agent x, agent y, T x, T y in units, T angle in rad")
        if not (0.0 <= state[0] <= WORKSPACE and 0.0 <= state[1] <= WORKSPACE):
            raise ValueError(f"{name} puts the agent at ({state[0]:.6g}, {state[1]:.6g}): its x and y must be in "
                             f"[0, 512] units (the workspace, the actions' range), got {value!r}")
        # the T's origin placed at angle 0, then turned by the angle about its centre of gravity c
        c = np.array(self.block_cog) if self.block_cog is not None else TEE.mean(axis=(0, 1))
        turn = math.cos(state[4]), math.sin(state[4])
        for bar, centre in zip(("top bar", "stem"), TEE.mean(axis=1)):
            rx, ry = centre - c
            x = state[2] + c[0] + turn[0] * rx - turn[1] * ry
            y = state[3] + c[1] + turn[1] * rx + turn[0] * ry
            if not (INSIDE[0] <= x <= INSIDE[1] and INSIDE[0] <= y <= INSIDE[1]):
                raise ValueError(f"{name} puts the T's {bar} with its centre at ({x:.6g}, {y:.6g}), outside the "
                                 f"walls: each bar's centre must be inside their inner faces, x and y in "
                                 f"[{INSIDE[0]}, {INSIDE[1]}] units (a bar over a wall with its centre inside is "
                                 f"pushed back in; one with its centre beyond is pushed out), got {value!r}")
        return state

    def _coverage(self) -> float:
        """The T's area inside the goal T over the goal's area (exact: rrbody.physics.overlap)."""
        x, y = self.block.position
        return overlap_area(tee_corners(x, y, self.block.angle), self._goal) / self._goal_area

    # ---- gymnasium -----------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict]:
        """A new episode: random agent position in [50, 450)^2, T position in [100, 400)^2 and angle in
        [-pi, pi) from the env's generator (gym-pusht's draws), or ``options["reset_to_state"]``
        ([agent x, agent y, T x, T y, T angle])."""
        state = self._reset_state(options)  # checked before anything changes, the generator included
        super().reset(seed=seed)
        if state is None:
            r = self.np_random
            state = np.array([r.integers(50, 450), r.integers(50, 450), r.integers(100, 400),
                              r.integers(100, 400), r.uniform(-np.pi, np.pi)])
        self._setup()
        self._set_state(state)
        info = self._get_info()
        info["is_success"] = False
        return self.get_obs(), info

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict]:
        """Drive the agent toward ``action`` for 0.1 s (10 physics steps of PD control), then observe."""
        if self.space is None:
            raise RuntimeError("call reset() before step()")
        ax, ay = _target(action)  # checked before anything changes
        self.n_contact_points = 0
        self._last_action = (ax, ay)
        agent, dt, kp, kv, advance = self.agent, self.dt, self.k_p, self.k_v, self._advance
        # the agent's velocity is read once: pymunk never changes a kinematic body's velocity (no forces, no
        # impulses act on its infinite mass), so the one set below is the one pymunk holds at the next step
        vx, vy = agent.velocity
        for _ in range(int(1 / (dt * self.control_hz))):
            px, py = agent.position
            # the PD law in gym-pusht's arithmetic (float64, the same order of operations)
            vx, vy = (vx + (kp * (ax - px) + kv * (0.0 - vx)) * dt, vy + (kp * (ay - py) + kv * (0.0 - vy)) * dt)
            agent.velocity = (vx, vy)
            advance(dt)
        coverage = self._coverage()
        reward = np.clip(coverage / self.success_threshold, 0.0, 1.0)
        terminated = is_success = coverage > self.success_threshold
        info = self._get_info()
        info["is_success"] = is_success
        info["coverage"] = coverage
        return self.get_obs(), reward, terminated, False, info

    def get_obs(self) -> Any:
        """The observation of ``obs_type`` (units; angle in rad)."""
        if self.obs_type == "state":
            return np.array([*self.agent.position, *self.block.position, self.block.angle % (2 * np.pi)],
                            dtype=np.float64)
        if self.obs_type == "environment_state_agent_pos":
            return {"environment_state": self.keypoints().flatten(), "agent_pos": np.array(self.agent.position)}
        pixels = self._picture(self.observation_width, self.observation_height, None)
        if self.obs_type == "pixels":
            return pixels
        return {"pixels": pixels, "agent_pos": np.array(self.agent.position)}

    def keypoints(self) -> np.ndarray:
        """The T's 8 corners (8, 2), units: the top bar's 4 then the stem's, each turned by the T's
        angle about its origin with pymunk's own arithmetic (as gym-pusht computes them)."""
        body = self.block
        return np.vstack([np.array(v.rotated(body.angle) + body.position)
                          for shape in self._block_shapes for v in shape.get_vertices()])

    def _get_info(self) -> dict[str, Any]:
        # gym-pusht's count per step divides by 1 / dt * control_hz = 1000 (sic), kept so info agrees
        per_step = int(np.ceil(self.n_contact_points / int(1 / self.dt * self.control_hz)))
        return {"pos_agent": np.array(self.agent.position), "vel_agent": np.array(self.agent.velocity),
                "block_pose": np.array([*self.block.position, self.block.angle]),
                "goal_pose": np.array(self.goal_pose), "n_contacts": per_step}

    def _picture(self, width: int, height: int, action: Any) -> np.ndarray:
        """gym-pusht's picture (rrbody.envs.pusht_draw: pixel for pixel): the goal, the walls, the agent,
        the T and pymunk's marks of the last physics step's contact points."""
        def corners(body: Any) -> np.ndarray:  # the bar, then the stem, as pymunk places them
            return np.array([[body.local_to_world(v) for v in s.get_vertices()] for s in self._block_shapes])

        marks: list[Any] = []

        def contact(arbiter: Any) -> None:  # pymunk's debug draw: a segment across each contact point
            cps = arbiter.contact_point_set
            n = np.array(cps.normal)
            marks.extend([np.array(p.point_a) - 2 * n, np.array(p.point_b) + 2 * n] for p in cps.points)

        self.block.each_arbiter(contact)
        return draw(tuple(self.agent.position), corners(self.block), corners(self._goal_body), width, height,
                    action=None if action is None else np.asarray(action, dtype=np.float64),
                    contacts=np.array(marks) if marks else None)

    def render(self) -> np.ndarray | None:
        """The (visualization_height, visualization_width, 3) uint8 picture with the last action's
        marker, or None when ``render_mode`` is None."""
        if self.render_mode is None or self.space is None:
            return None
        return self._picture(self.visualization_width, self.visualization_height, self._last_action)
