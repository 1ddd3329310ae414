"""Push-T on a table: the same actions without one and on mu 0.3 and 0.6, measured (no paper figure; rrbody.envs).

Worlds of ``rrbody/PushT-v0`` (:class:`rrbody.envs.pusht.PushTEnv`): ``table=False`` (gym-pusht's own
world: every velocity wiped each 0.01 s step); the same from a start with the T moved 1 unit (a
control: how much a replay drifts by itself); the T on tables of exact dry friction with mu = 0.3
(the environment's default: a 3D-printed PLA T on wood or laminate, rrbody.envs.tabletop) and
mu = 0.6 (twice that, a grippy mat: the sliding distance v^2 / (2 mu g) halves and friction's
impulse per step mu g dt doubles, so the pair tells friction's presence from its strength).
1. Every action sequence is replayed open-loop in every world: demonstrations (DEMO_SEEDS, a scripted
   closed-loop pusher, :func:`demonstrate`, drives the T to the goal without a table; its actions are
   recorded) and random walks (WALK_SEEDS, an Ornstein-Uhlenbeck walk of the agent's target about the
   T's starting centre of gravity, :func:`walk`); each ends with SETTLE actions that move the agent
   off (demonstrations) or hold it (walks). Per episode: the final coverage, the T's pose error
   (origin to (256, 256), units; angle to pi/4, wrapped to [-pi, pi), rad), and its travel after the
   agent's last contact: contact is pymunk's own (an arbiter between the agent's and the T's shapes
   in a 0.01 s step), and the release pose is one step after the last contact step, since pymunk
   moves a body by the velocity its last impulse gave at the start of the next step. Without a
   table that travel is exactly 0 unless a wall touched the T after its release (checked: RuntimeError).
2. The demonstrator in closed loop on each table (does feedback make up for the table?).
3. An off-centre push square to the top bar's upper face at offsets b = 0-60 units from the T's
   axis, at 10-300 units/s: the T's rotation per unit travel (limit surface against inertia). The
   agent is driven by its targets, as an action drives it. Stepped at the environment's 10 ms with the
   plugin's coupled step (its default: the env's table) and with its split step (friction before
   pymunk's contact solve, ``PlaneFriction(scheme="split")``), and at 0.1 ms (the dt -> 0 limit of
   this push), beside three exact answers: inertia, dtheta/ds = m b / I; quasi-static pushing, the
   twist whose friction wrench balances the push (the plugin's footprint); and at b = 60 the exact push
   of a disk at constant speed (rrbody.analysis.pushing.push_limit, an ODE, not the plugin: the push of
   ``rrbody scene coupled-push``, which differs from the driven one in its start from rest).
Outputs: results/pusht-table/ (episodes.csv: a row per sequence and world; closed_loop.csv; pushes.csv;
summary.json; table.md, the tables docs/envs-study.md shows; recorder.mp4 and recorder.rrd: the movie's
table run filmed by rrbody's Recorder), docs/figures/pusht_table.png, movies/pusht_table.mp4 (one
demonstration, no table | mu 0.3). One core; the replays and the off-centre pushes at 0.1 ms take most
of its time; ``--episodes N`` runs fewer.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

#: the worlds: name -> PushTEnv keywords, and ``nudge``: the T's start moved this far along x (units), a
#: control that tells a replay's own sensitivity from the table's effect
WORLDS: dict[str, dict[str, Any]] = {"no table": {"table": False}, "no table, nudged": {"table": False, "nudge": 1.0},
                                     "mu 0.3": {"table": True, "mu": 0.3}, "mu 0.6": {"table": True, "mu": 0.6}}
PUSH_WORLDS = ("no table", "mu 0.3", "mu 0.6")
DEMO_SEEDS, WALK_SEEDS = tuple(range(100, 200)), tuple(range(0, 100))  # env.reset seeds (walks: also the walk's)
N_ACTIONS, SETTLE = 300, 10  # actions per episode (gym's truncation), of which the last SETTLE settle
OU_RHO, OU_SIGMA = 0.9, 25.0  # the walk: target - centre <- rho (target - centre) + N(0, sigma^2) per action, units
GOAL = (256.0, 256.0, math.pi / 4)  # the goal pose of the T's origin (units, units, rad)
COG = (0.0, 45.0)  # the T's centre of gravity in its body frame (gym-pusht's), units
AGENT_R, REACH = 15.0, 76.5  # the agent's radius; the T's farthest point from its centre of gravity (units)
PUSH_OFFSETS = (0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0)  # units from the T's axis along the top bar
PUSH_SPEEDS = (10.0, 30.0, 50.0, 100.0, 300.0)  # the push's target speed, units/s (x 1/600: 1.7 cm/s to 0.5 m/s)
PUSH_DTS = (0.01, 0.0001)  # physics steps (s): the environment's, and a hundredth of it (the dt -> 0 limit)
#: the push series: (world, physics step, the plugin's scheme; None without a table). The split step only at
#: the environment's step, where it and the coupled step differ (both tend to the same limit as dt -> 0)
PUSH_SERIES: tuple[tuple[str, float, str | None], ...] = (
    ("no table", PUSH_DTS[0], None), ("mu 0.3", PUSH_DTS[0], "coupled"), ("mu 0.6", PUSH_DTS[0], "coupled"),
    ("mu 0.3", PUSH_DTS[0], "split"), ("mu 0.6", PUSH_DTS[0], "split"),
    ("mu 0.3", PUSH_DTS[1], "coupled"), ("mu 0.6", PUSH_DTS[1], "coupled"))
SQUIRT = 1.5  # a T released faster than this x the agent's speed was squirted out of a pinch
PUSH_TRAVEL, RATE_AT = 60.0, 3.0  # the agent's push travel; the T's travel at which dtheta/ds is read (units)


def wrap(a: float) -> float:
    """An angle (rad) wrapped to [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def cog(x: float, y: float, a: float) -> np.ndarray:
    """The T's centre of gravity (units, world) for its origin (x, y) and angle a (rad)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([x + c * COG[0] - s * COG[1], y + s * COG[0] + c * COG[1]])


def make(world: str, seed: int | None = None, state: Sequence[float] | None = None, *,
         scheme: str = "coupled") -> Any:
    """A fresh environment of ``world`` (the class gymnasium.make("rrbody/PushT-v0", ...) wraps; unwrapped,
    so that no time limit or order check stands between the study and its actions), reset with ``seed``
    or to ``state`` ([agent x, agent y, T x, T y, T angle]), then the world's nudge. ``scheme``: the
    plugin's step on a table ("coupled", the env's own; "split": :func:`split_table`)."""
    from rrbody.envs.pusht import PushTEnv

    kw = dict(WORLDS[world])
    nudge = kw.pop("nudge", 0.0)
    env = PushTEnv(render_mode=None, **kw)
    env.reset(seed=seed, options=None if state is None else {"reset_to_state": list(state)})
    if nudge:
        env.block.position = (env.block.position.x + nudge, env.block.position.y)
    if scheme == "split":
        split_table(env)
    elif scheme != "coupled":
        raise ValueError(f"scheme must be 'coupled' or 'split', got {scheme!r}")
    return env


def split_table(env: Any) -> None:
    """Put the split step (``PlaneFriction(scheme="split")``: the table's friction applied before pymunk's
    contact solve, the plugin's step before the coupled one) under ``env``'s T in place of the env's
    coupled table, after its reset (which rebuilds the space and the table): the same table (g, mu,
    mu_static, pressure) and the same sub-steps near a wall. The env takes no scheme of its own. The
    reset's one physics step ran on the coupled table; a T at rest that nothing touches steps alike on
    both. Call it again after every reset."""
    from rrbody.engine.plugin import PlaneFriction
    from rrbody.envs.substep import guarded

    t = env.table
    if t is None:
        raise ValueError("the split step needs a table (table=True)")
    env.plane = PlaneFriction(env.space, g=t.g_space, scheme="split")
    env.plane.add(env.block, mu=t.mu, mu_static=t.mu_static, pressure=t.pressure)
    env._advance = guarded(env.plane.step, [env.block], env.space)


class Probe:
    """Reads the T after every physics step of ``env`` (``env.dt``, 0.01 s): whether the agent touched
    it (an arbiter of the agent's and the T's shapes in that step: pymunk's own contact), whether a
    wall did, and the T's and the agent's poses. Install after ``reset`` (which rebuilds the space).
    It wraps the environment's per-step advance (``env._advance``: PushTEnv has no public per-step
    hook, and an action is 10 steps), so ``env.step`` runs exactly as before. ``each`` is called after
    every step (a Recorder's capture)."""

    def __init__(self, env: Any, each: Callable[[], Any] | None = None) -> None:
        self.touch: list[bool] = []
        self.wall: list[bool] = []
        self.pose: list[tuple[float, float, float, float, float]] = []  # T x, y, angle; agent x, y (units, rad)
        agent_shapes = set(env.agent.shapes)
        static = env.space.static_body
        inner, block, agent = env._advance, env.block, env.agent

        def advance(dt: float) -> None:
            inner(dt)
            hit: list[Any] = []
            block.each_arbiter(lambda arb: hit.append(arb.shapes))
            self.touch.append(any(s in agent_shapes for pair in hit for s in pair))
            self.wall.append(any(s.body is static for pair in hit for s in pair))
            self.pose.append((block.position.x, block.position.y, block.angle, agent.position.x, agent.position.y))
            if each is not None:
                each()

        env._advance = advance


def rollout(world: str, seed: int, actions: np.ndarray, *, each: Any = None) -> dict[str, Any]:
    """Replay ``actions`` (n, 2; units) in ``world`` from the reset of ``seed`` and measure.

    Returns the final coverage, the first action at which the coverage passed 0.95 (gym's success; -1
    never), the pose error, and about the agent's last contact (NaN when it never touched; see
    :class:`Probe` for the release step): the T's travel (units) and turn (rad) after it, the speeds
    (units/s) of the T's centre of gravity in the step after it and of the agent in it, whether a
    wall touched the T in the last 5 contact steps (a pinch) or after the release; whether the T ended
    at rest (below 1e-9 units/s and rad/s); the per-step log and the coverage per action.
    ``each(env)``, if given, returns a function to call after every physics step."""
    env = make(world, seed)
    probe = Probe(env, None if each is None else each(env))
    coverage, success = [], -1
    for k, a in enumerate(actions):
        info = env.step(a)[4]
        coverage.append(info["coverage"])
        if success < 0 and info["coverage"] > env.success_threshold:
            success = k
    pose = np.array(probe.pose)
    touched = np.flatnonzero(probe.touch)
    x, y, a = pose[-1, :3]
    out = {"coverage": coverage[-1], "success_action": success, "pos_err": math.hypot(x - GOAL[0], y - GOAL[1]),
           "ang_err": wrap(a - GOAL[2]), "contact_steps": len(touched), "last_contact_s": math.nan,
           "travel_after": math.nan, "turn_after": math.nan, "release_speed": math.nan, "agent_speed": math.nan,
           "pinch": False, "wall_after": False,
           "at_rest": abs(env.block.velocity) < 1e-9 and abs(env.block.angular_velocity) < 1e-9,
           "pose": pose, "coverage_per_action": np.array(coverage), "env": env}
    if len(touched):
        k = touched[-1]
        r = min(k + 1, len(pose) - 1)  # the release: one step after the last contact step
        dt = env.dt
        out.update(travel_after=math.hypot(x - pose[r, 0], y - pose[r, 1]), turn_after=abs(a - pose[r, 2]),
                   last_contact_s=dt * (k + 1), wall_after=bool(np.any(probe.wall[r + 1:])),
                   pinch=bool(np.any(np.array(probe.wall)[touched[-5:]])),
                   release_speed=float(np.hypot(*(cog(*pose[r, :3]) - cog(*pose[k, :3])))) / dt,
                   agent_speed=float(np.hypot(*(pose[k, 3:5] - pose[max(k - 1, 0), 3:5]))) / dt)
    return out


# ---- the action sequences ------------------------------------------------------------------------
def walk(seed: int, n: int = N_ACTIONS) -> np.ndarray:
    """The random walk of ``seed``: the agent's target about the T's starting centre of gravity c0,
    target_k = c0 + u_k, u_k = OU_RHO u_(k-1) + N(0, OU_SIGMA^2) (units; stationary spread 57 units, a
    T's reach), u_0 the agent's start; the last SETTLE actions hold the target. Open-loop: it reads
    only the reset state, the same in every world."""
    obs = make("no table", seed).get_obs()
    c0 = cog(*obs[2:5])
    rng = np.random.default_rng(seed)
    u, out = obs[:2] - c0, np.empty((n, 2))
    for k in range(n - SETTLE):
        u = OU_RHO * u + rng.normal(0.0, OU_SIGMA, 2)
        out[k] = np.clip(c0 + u, 0.0, 512.0)
    out[n - SETTLE:] = out[n - SETTLE - 1]
    return out


def _entry(polys: np.ndarray, p0: np.ndarray, d: np.ndarray) -> float | None:
    """The least t at which the line p0 + t d enters the union of convex polygons (k, 4, 2), or None."""
    best = None
    for poly in polys:
        (ax, ay), (bx, by) = poly[1] - poly[0], poly[2] - poly[1]
        ccw = ax * by - ay * bx > 0
        lo, hi = -math.inf, math.inf
        for i in range(len(poly)):
            e = poly[(i + 1) % len(poly)] - poly[i]
            normal = np.array([e[1], -e[0]]) if ccw else np.array([-e[1], e[0]])  # outward
            num, den = normal @ (p0 - poly[i]), normal @ d
            if abs(den) < 1e-12:
                lo = lo if num <= 0 else math.inf  # parallel to this edge: inside its half-plane or never
            elif den < 0:
                lo = max(lo, -num / den)
            else:
                hi = min(hi, -num / den)
        if lo <= hi and (best is None or lo < best):
            best = lo
    return best


def _push_line(env: Any, obs: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool, float, float]:
    """Where to push the T next and along which unit direction (units, world): turn it first (a push
    square to the top bar near an end, on the face whose torque turns it toward pi/4), else push its
    centre of gravity toward the goal's with an offset that corrects the angle. Also: turning or not,
    the distance to the goal's centre of gravity, the angle error (rad)."""
    x, y, a = obs[2:5]
    c, g = cog(x, y, a), cog(*GOAL)
    ep, eth = g - c, wrap(GOAL[2] - a)
    dist = float(np.linalg.norm(ep))
    turning = abs(eth) > 0.25 or (dist < 5.0 and abs(eth) > 0.03)
    cs, sn = math.cos(a), math.sin(a)
    rot = np.array([[cs, -sn], [sn, cs]])
    if turning:  # (x along the bar, face y, push along body y): torque x * push about the centre of gravity
        options = [(48.0, 0.0, 1.0), (-48.0, 30.0, -1.0), (-48.0, 0.0, 1.0), (48.0, 30.0, -1.0)]
        xb, yf, dy = max((o for o in options if o[0] * o[2] * eth > 0), key=lambda o: (rot @ (0.0, o[2])) @ ep)
        return np.array([x, y]) + rot @ (xb, yf), rot @ (0.0, dy), True, dist, eth
    d = ep / dist
    n = np.array([-d[1], d[0]])
    b = float(np.clip(-40.0 * eth, -20.0, 20.0))  # a push along d offset by b n turns the T by -b |F|
    polys = env.keypoints().reshape(2, 4, 2)
    t = _entry(polys, c + b * n - 300.0 * d, d)
    while t is None and abs(b) > 1.0:
        b *= 0.5
        t = _entry(polys, c + b * n - 300.0 * d, d)
    return c + b * n - 300.0 * d + (t or 300.0) * d, d, False, dist, eth


def _target(env: Any, obs: np.ndarray) -> np.ndarray:
    """The demonstrator's next action (units): on the push line and behind the contact, push (slower as
    the error shrinks); elsewhere go to the line's far point, round the T when the way is blocked
    (pymunk's segment query with the agent's radius plus 3)."""
    import pymunk

    q, d, turning, dist, eth = _push_line(env, obs)
    n, ag = np.array([-d[1], d[0]]), obs[:2]
    along, lat = (ag - q) @ d, (ag - q) @ n
    if along <= -(AGENT_R - 4.0) and abs(lat) < 6.0:
        if along < -(AGENT_R + 8.0):  # on the line, short of the T: close in
            return q - d * (AGENT_R + 2.0) - 0.5 * lat * n
        step = float(np.clip(60.0 * abs(eth) if turning else 0.6 * dist, 1.0, 12.0))
        return ag + step * d - 0.5 * lat * n
    c, safe = cog(*obs[2:5]), REACH + AGENT_R + 12.0
    w = q - c
    length = w @ d + math.sqrt(max((w @ d) ** 2 - (w @ w - safe ** 2), 0.0))  # the line's far point is `safe` out
    far = q - d * length
    while not (np.all(far >= 20.0) and np.all(far <= 492.0)) and length > 1.0:
        length *= 0.9  # a far point inside the walls
        far = q - d * length
    hits = env.space.segment_query(tuple(ag), tuple(far), AGENT_R + 3.0, pymunk.ShapeFilter())
    if not any(h.shape.body is env.block for h in hits):
        return far
    pa, pf = math.atan2(*(ag - c)[::-1]), math.atan2(*(far - c)[::-1])
    phi = pa + float(np.clip(wrap(pf - pa), -0.6, 0.6))  # round the T on a circle clear of it
    return c + safe * np.array([math.cos(phi), math.sin(phi)])


def demonstrate(seed: int, world: str = "no table", n: int = N_ACTIONS) -> tuple[np.ndarray, int]:
    """The scripted demonstration of ``seed``: closed-loop on the state in ``world`` (the demonstrations
    are made without a table) until success (coverage > 0.95) or n - SETTLE actions, then SETTLE actions
    that send the agent 60 units straight away from the T. Returns the actions (<= n, 2; units) and the
    action at which it succeeded (-1: never)."""
    env = make(world, seed)
    obs, out, done = env.get_obs(), [], False
    while len(out) < n - SETTLE and not done:
        out.append(np.clip(_target(env, obs), 15.0, 497.0))
        obs, _, done, _, _ = env.step(out[-1])
    away = obs[:2] - cog(*obs[2:5])
    out += [np.clip(obs[:2] + 60.0 * away / np.linalg.norm(away), 15.0, 497.0)] * SETTLE
    return np.array(out), len(out) - SETTLE - 1 if done else -1


# ---- the off-centre push -------------------------------------------------------------------------
def push(world: str, offset: float, speed: float, dt: float = 0.01, scheme: str | None = None) -> dict[str, Any]:
    """The T at rest at origin (256, 300), angle 0; the agent just above its top bar's upper face (0.5
    units clear) at ``offset`` (units) from its axis; the agent's target runs PUSH_TRAVEL units down at
    ``speed`` (units/s), stays 0.5 s, then the agent backs off for 1 s; physics steps of ``dt`` (s; the
    environment's is 0.01, 10 per action); on a table the plugin's ``scheme`` (None: the env's, coupled).
    Returns the T's rotation per unit travel of its centre of gravity when that travel first reaches
    RATE_AT units (rad/unit), its rotation (rad) and travel (units) at the end."""
    y0 = 300.0 - AGENT_R - 0.5  # the face is the T's origin's line, y = 300
    table = WORLDS[world]["table"]
    if scheme is not None and not table:
        raise ValueError(f"world {world!r} has no table: its scheme is None, got {scheme!r}")
    scheme = ("coupled" if scheme is None else scheme) if table else None
    env = make(world, state=[256.0 + offset, y0, 256.0, 300.0, 0.0], scheme=scheme or "coupled")
    env.dt = dt  # PushTEnv.step runs 1 / (dt x 10 Hz) physics steps per action
    probe = Probe(env)
    targets = [y0 + min(speed * 0.1 * k, PUSH_TRAVEL) for k in range(1, math.ceil(PUSH_TRAVEL / (speed * 0.1)) + 1)]
    for y in targets + [y0 + PUSH_TRAVEL] * 5 + [100.0] * 10:
        env.step(np.array([256.0 + offset, y]))
    pose = np.array(probe.pose)
    s = np.hypot(*(np.array([cog(*p[:3]) for p in pose]) - cog(256.0, 300.0, 0.0)).T)
    i = int(np.argmax(s >= RATE_AT))
    return {"world": world, "dt": dt, "scheme": scheme or "", "speed": speed, "offset": offset,
            "rate": pose[i, 2] / s[i], "turn": pose[-1, 2], "travel": s[-1]}


def predictions(offsets: Sequence[float]) -> dict[str, list[float]]:
    """dtheta/ds (rad/unit) of a push along the top bar's face normal at ``offsets`` b (units) from the
    axis: without a table, the impulse's own ratio m b / I (gym-pusht's I, 3000 units^2 for m = 1);
    quasi-static on a table, the twist (v_x, 1, w) whose friction wrench (the plugin's own footprint,
    uniform pressure; body frame from the centre of gravity) balances a push along +y through (b, -45):
    f_x = 0 and torque = b f_y, solved for (v_x, w); then w / |v|. Independent of mu."""
    from scipy.optimize import fsolve

    from rrbody.engine.plugin.shapes import body_footprint
    from rrbody.model.pressure import as_pressure
    from rrbody.physics.contact import footprint_wrench

    env = make("mu 0.3", seed=0)
    shapes, geo = body_footprint(env.block, as_pressure("uniform"))[:2]
    n = shapes.shape[0]

    def quasi_static(b: float) -> float:
        def residual(z: np.ndarray) -> list[float]:
            fx, fy, tq = footprint_wrench(shapes, geo, 0, n, float(z[0]), 1.0, float(z[1]), 0.0)
            return [fx, tq - b * fy]
        vx, w = fsolve(residual, [0.0, b / 2000.0], xtol=1e-12)
        return float(w / math.hypot(vx, 1.0))

    return {"m b / I (inertia)": [env.block.mass * b / env.block.moment for b in offsets],
            "quasi-static (limit surface)": [quasi_static(b) for b in offsets]}


def exact_push(offset: float, speeds: Sequence[float], worlds: Sequence[str]) -> dict[str, dict[str, float]]:
    """dtheta/ds (rad/unit) at RATE_AT units of the centre of gravity's travel of the exact push
    (rrbody.analysis.pushing.push_limit: the dt -> 0 limit, an ODE with impacts and releases, not the
    plugin): the T as :func:`push` places it, the agent's disk from where it starts there, at ``offset``,
    moving along +y at each of ``speeds`` (units/s) from the start, on each of ``worlds``' tables
    (mu g, g the env's). That is ``rrbody scene coupled-push``'s push: a kinematic disk at constant speed,
    where the study's agent is driven by its targets (from rest, lagging them); the two agree where the
    agent reaches the target's speed before the T has turned much. {world: {speed: rate}}."""
    from rrbody.analysis.pushing import PushGeometry, push_limit

    y0 = 300.0 - AGENT_R - 0.5
    out: dict[str, dict[str, float]] = {}
    for world in worlds:
        env = make(world, state=[256.0 + offset, y0, 256.0, 300.0, 0.0])
        mu_g = env.table.mu * env.table.g_space
        out[world] = {f"{v:g}": push_limit(PushGeometry(env.block, AGENT_R, (256.0 + offset, y0), (0.0, v)), mu_g,
                                           [RATE_AT])[RATE_AT] for v in speeds}
    return out


# ---- the study -----------------------------------------------------------------------------------
COLUMNS = ("family", "seed", "world", "actions", "coverage", "success_action", "pos_err", "ang_err", "contact_steps",
           "last_contact_s", "travel_after", "turn_after", "release_speed", "agent_speed", "pinch", "wall_after",
           "at_rest", "apart_from_no_table")


def episode(family: str, seed: int) -> tuple[list[dict[str, Any]], float]:
    """One action sequence replayed in every world: a row of measures per world (``COLUMNS``), and the
    replays' wall time (s)."""
    actions = demonstrate(seed)[0] if family == "demonstrations" else walk(seed)
    rows, end0, t0 = [], None, time.perf_counter()
    for world in WORLDS:  # "no table" first: the other worlds' ends are measured from its end
        r = rollout(world, seed, actions)
        end = r["pose"][-1, :2]
        end0 = end if end0 is None else end0
        rows.append({"family": family, "seed": seed, "world": world, "actions": len(actions),
                     **{k: r[k] for k in COLUMNS if k in r}, "apart_from_no_table": float(np.hypot(*(end - end0)))})
    return rows, time.perf_counter() - t0


def quartiles(values: Sequence[float]) -> dict[str, float]:
    """Median and quartiles (numpy's linear interpolation) of the finite values, and how many there are."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not len(v):
        return {"n": 0}
    q1, med, q3 = np.percentile(v, [25, 50, 75])
    return {"n": int(len(v)), "q1": float(q1), "median": float(med), "q3": float(q3)}


def summarize(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Per family and world: the success rate (coverage > 0.95 at some action, as gym ends an episode)
    and the median and quartiles of each measure (the after-contact ones over the episodes with a
    contact). ``squirted``: the T's centre of gravity left faster than SQUIRT x the agent's own speed
    (one push of a T at rest cannot do that: v_cg = J / m is below the contact point's normal speed;
    a pinch between the agent and a wall can, through frictionless contacts), ``squirted_in_pinch`` of
    them with a wall in the last 5 contact steps; ``travel_after_unsquirted`` over the others."""
    out: dict[str, Any] = {}
    for family in dict.fromkeys(r["family"] for r in rows):
        out[family] = {}
        for world in WORLDS:
            sel = [r for r in rows if r["family"] == family and r["world"] == world]
            squirted = [r["release_speed"] > SQUIRT * r["agent_speed"] for r in sel]
            out[family][world] = {
                "episodes": len(sel), "success_rate": float(np.mean([r["success_action"] >= 0 for r in sel])),
                "touched": int(sum(r["contact_steps"] > 0 for r in sel)),
                **{k: quartiles([r[k] for r in sel]) for k in ("coverage", "pos_err", "travel_after", "turn_after",
                                                               "release_speed", "agent_speed", "apart_from_no_table")},
                "abs_ang_err": quartiles([abs(r["ang_err"]) for r in sel]),
                "pinched": int(sum(bool(r["pinch"]) for r in sel)),
                "squirted": int(sum(squirted)),
                "squirted_in_pinch": int(sum(q and r["pinch"] for q, r in zip(squirted, sel))),
                "travel_after_unsquirted": quartiles([r["travel_after"] for q, r in zip(squirted, sel) if not q]),
                "wall_after_release": int(sum(bool(r["wall_after"]) for r in sel)),
                "ended_at_rest": int(sum(bool(r["at_rest"]) for r in sel))}
    return out


def push_key(world: str, dt: float, scheme: str | None = None) -> str:
    """The name of a push series: its world, physics step and, on a table, the plugin's scheme."""
    return f"{world}, dt {1e3 * dt:g} ms" + (f", {scheme} step" if scheme else "")


def by_series(pushes: list[dict[str, Any]], series: Sequence[tuple[str, float, str | None]],
              m: str) -> dict[str, dict[str, list]]:
    """The pushes' measure ``m``: {series name: {speed: [one per offset, in PUSH_OFFSETS' order]}}."""
    return {push_key(w, dt, sch): {f"{v:g}": [p[m] for p in pushes
                                              if (p["world"], p["dt"], p["scheme"], p["speed"]) == (w, dt, sch or "",
                                                                                                    v)]
                                   for v in PUSH_SPEEDS} for w, dt, sch in series}


def _q(s: dict[str, float], digits: int = 2) -> str:
    return "-" if not s["n"] else f"{s['median']:.{digits}f} [{s['q1']:.{digits}f}, {s['q3']:.{digits}f}]"


def markdown(summary: dict[str, Any]) -> str:
    """The tables of docs/envs-study.md, from summary.json alone (tests/test_envs_study.py checks the
    page's copy against it): the replays (medians [quartiles]), the pusher in closed loop, and
    dtheta/ds of the push at the top bar's end against its speed: each series of the driven push, the
    exact push of a disk at constant speed, and the two speed-free answers."""
    lines = ["| actions | world | success | final coverage | position error (units) | abs angle error (rad) "
             "| end apart from no table (units) | travel after the last contact (units) | squirted out "
             "| travel, the others (units) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for family, worlds in summary["episodes"].items():
        for world, s in worlds.items():
            lines.append(f"| {family} | {world} | {100 * s['success_rate']:.0f} % | {_q(s['coverage'])} | "
                         f"{_q(s['pos_err'], 1)} | {_q(s['abs_ang_err'])} | {_q(s['apart_from_no_table'], 1)} | "
                         f"{_q(s['travel_after'])} | {s['squirted']} of {s['touched']} | "
                         f"{_q(s['travel_after_unsquirted'])} |")
    lines += ["", "| the pusher in closed loop | success | actions to success |", "|---|---|---|"]
    for world, s in summary["closed_loop"].items():
        lines.append(f"| {world} | {100 * s['success_rate']:.0f} % | {_q(s['actions_to_success'], 0)} |")
    p = summary["push"]
    i = p["offsets"].index(max(p["offsets"]))
    lines += ["", f"| dtheta/ds (mrad per unit), push at b = {p['offsets'][i]:g} units | "
              + " | ".join(f"{v:g} units/s" for v in p["speeds"]) + " |", "|---|" + "---|" * len(p["speeds"])]
    for key, by_speed in p["rate"].items():
        lines.append(f"| {key} | " + " | ".join(f"{1e3 * by_speed[f'{v:g}'][i]:.2f}" for v in p["speeds"]) + " |")
    for world, by_speed in p["exact_push"].items():
        lines.append(f"| {world}, exact push at constant speed (dt -> 0) | "
                     + " | ".join(f"{1e3 * by_speed[f'{v:g}']:.2f}" for v in p["speeds"]) + " |")
    for name, values in p["predictions"].items():
        cells = " | ".join([f"{1e3 * values[i]:.2f}"] * len(p["speeds"]))
        lines.append(f"| {name} (exact, any speed) | {cells} |")
    return "\n".join(lines) + "\n"


# ---- pictures ------------------------------------------------------------------------------------
COLOURS = {"no table": "0.3", "no table, nudged": "0.65", "mu 0.3": "tab:blue", "mu 0.6": "tab:orange"}


def figure(rows: list[dict[str, Any]], summary: dict[str, Any], path: Path, *, force: bool) -> Path:
    """Box plots per family and world (coverage, position error, angle error, travel after the last
    contact) and the off-centre pushes (dtheta/ds against the offset at 50 units/s and against the
    speed at the top bar's end, beside both speed-free answers and, there, the exact push): the
    coupled step filled, the split step crosses, the fine step open."""
    import matplotlib.pyplot as plt

    from rrbody.model.io import atomic_path
    from rrbody.render.figures import savefig_reproducible

    fig, axes = plt.subplots(2, 3, figsize=(16, 9), constrained_layout=True)
    families, worlds = list(summary["episodes"]), list(WORLDS)
    measures = [("final coverage", lambda r: r["coverage"]), ("final position error (units)", lambda r: r["pos_err"]),
                ("final |angle error| (rad)", lambda r: abs(r["ang_err"])),
                ("the T's travel after the agent's last contact (units)", lambda r: r["travel_after"])]
    for ax, (label, get) in zip(axes.flat, measures):
        for i, family in enumerate(families):
            for j, world in enumerate(worlds):
                v = np.array([get(r) for r in rows if r["family"] == family and r["world"] == world], float)
                v = v[np.isfinite(v)]
                pos = i * (len(worlds) + 1) + j
                box = ax.boxplot([v], positions=[pos], widths=0.7, patch_artist=True, showfliers=False)
                box["boxes"][0].set(facecolor=COLOURS[world], alpha=0.45)
                jitter = np.random.default_rng(pos).uniform(-0.25, 0.25, len(v))  # fixed: the same picture each run
                ax.plot(pos + jitter, v, ".", color=COLOURS[world], ms=2.5, alpha=0.6)
        ax.set_xticks([i * (len(worlds) + 1) + (len(worlds) - 1) / 2 for i in range(len(families))], families)
        ax.set_title(label, fontsize=10)
    axes[0, 0].legend(handles=[plt.Rectangle((0, 0), 1, 1, color=COLOURS[w], alpha=0.6) for w in worlds], labels=worlds,
                      fontsize=8, loc="center right")
    axes[1, 0].set_yscale("symlog", linthresh=0.1)
    axes[1, 0].set_ylim(bottom=0.0)
    p, a, b = summary["push"], axes[1, 1], axes[1, 2]
    i60, v50 = p["offsets"].index(max(p["offsets"])), PUSH_SPEEDS.index(50.0)
    for (name, values), style in zip(p["predictions"].items(), ("k--", "k:")):
        a.plot(p["offsets"], 1e3 * np.array(values), style, lw=1.2, label=name)
        b.axhline(1e3 * values[i60], color="k", ls=style[1:], lw=1.2, label=name)
    for key, by_speed in p["rate"].items():
        world, fine, split = key.split(", dt")[0], f"dt {1e3 * PUSH_DTS[0]:g} ms" not in key, "split" in key
        look = {"color": COLOURS[world], "mfc": "none" if fine else COLOURS[world], "ls": ":" if fine else "-",
                "marker": "x" if split else "o", "ms": 7 if split else 5, "alpha": 0.6 if split else 1.0}
        if split:
            look["ls"] = "--"
        a.plot(p["offsets"], 1e3 * np.array(by_speed[f"{PUSH_SPEEDS[v50]:g}"]), label=key, **look)
        b.plot(p["speeds"], [1e3 * by_speed[f"{v:g}"][i60] for v in p["speeds"]], label=key, **look)
    for world, by_speed in p["exact_push"].items():
        b.plot(p["speeds"], [1e3 * by_speed[f"{v:g}"] for v in p["speeds"]], "-", color=COLOURS[world], lw=3,
               alpha=0.35, label=f"{world}, exact push at constant speed")
    a.set(xlabel="push offset b from the T's axis (units)", ylabel="dtheta/ds (mrad per unit)")
    a.set_title(f"a push along the top bar's normal at 50 units/s: rotation per unit travel\n"
                f"of the centre of gravity over its first {RATE_AT:g} units", fontsize=10)
    b.set(xscale="log", xlabel="push speed (units/s; x 1/600 for m/s)", ylabel="dtheta/ds (mrad per unit)")
    b.set_title(f"the same at the top bar's end (b = {p['offsets'][i60]:g} units)\nagainst the push's speed",
                fontsize=10)
    a.legend(fontsize=7)
    b.legend(fontsize=7)
    n = len(rows) // len(worlds)
    fig.suptitle(f"Push-T: the same actions ({n} sequences) without a table, without a table from a start 1 unit off, "
                 f"and on tables of mu 0.3 and 0.6")
    with atomic_path(path, force=force, name="figure") as tmp:
        savefig_reproducible(fig, tmp, fmt="png", dpi=90)
    plt.close(fig)
    return path


def side_by_side(runs: dict[str, dict[str, Any]], actions: np.ndarray, path: Path, *, force: bool,
                 fps: float = 20.0) -> Path:
    """An MP4 of the same actions in two worlds, one panel each, a frame per action (0.1 s) at ``fps``
    frames per s of playback: the goal (green), the T, the agent and its target (+); pictures y down,
    as gym-pusht draws them."""
    import matplotlib.figure as mfig
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.patches import Circle, Polygon

    from rrbody.envs.pusht import tee_corners as placed
    from rrbody.render.movie_figure import check_movie
    from rrbody.render.mp4 import write_frames

    size = (960, 480)
    final = check_movie(path, force=force, fps=fps, speed=2.0, size=size)[0]
    fig = mfig.Figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
    canvas = FigureCanvasAgg(fig)
    art = []
    for i, (world, run) in enumerate(runs.items()):
        ax = fig.add_axes((i / 2 + 0.01, 0.01, 0.48, 0.9))
        ax.set(xlim=(0, 512), ylim=(512, 0), aspect="equal", xticks=[], yticks=[])
        ax.set_title({"no table": "no table (gym-pusht)"}.get(world, f"table, {world}"), fontsize=11)
        for bar in placed(*GOAL):
            ax.add_patch(Polygon(bar, color="lightgreen", alpha=0.6))
        tee = [ax.add_patch(Polygon(bar, color="lightslategray")) for bar in placed(256.0, 300.0, 0.0)]
        agent = ax.add_patch(Circle((0, 0), AGENT_R, color="royalblue"))
        target, = ax.plot([], [], "r+", ms=10)
        label = ax.text(8, 500, "", fontsize=9)
        art.append((run, tee, agent, target, label))

    def frames() -> Any:
        for k in range(len(actions)):
            for run, tee, agent, target, label in art:
                x, y, a, ax_, ay = run["pose"][10 * k + 9]  # the state at the end of action k
                for patch, bar in zip(tee, placed(x, y, a)):
                    patch.set_xy(bar)
                agent.center = (ax_, ay)
                target.set_data([actions[k, 0]], [actions[k, 1]])
                label.set_text(f"t = {0.1 * (k + 1):4.1f} s   coverage {run['coverage_per_action'][k]:.2f}")
            canvas.draw()
            yield canvas.buffer_rgba()

    return write_frames(final, frames(), len(actions), size=size, fps=fps, force=force, progress=sys.stderr.isatty())


# ---- main ----------------------------------------------------------------------------------------
def closed_loop(seed: int) -> list[dict[str, Any]]:
    """The demonstrator in closed loop on each table from the reset of ``seed`` (without a table its
    closed loop is the demonstration itself, which the replay there repeats bit for bit)."""
    return [{"seed": seed, "world": w, "success_action": demonstrate(seed, w)[1]} for w in PUSH_WORLDS[1:]]


def check_no_table(rows: list[dict[str, Any]]) -> dict[str, int]:
    """Without a table a released T does not move (every velocity is wiped at each step): its travel and
    turn after the release are exactly 0 in every episode with a contact, bar those where a wall touched
    it after the release (pymunk's overlap correction can move a body at rest). RuntimeError otherwise."""
    flat = [r for r in rows if not WORLDS[r["world"]]["table"] and r["contact_steps"] > 0]
    moved = [r for r in flat if not r["wall_after"] and (r["travel_after"] != 0.0 or r["turn_after"] != 0.0)]
    if moved:
        raise RuntimeError(f"without a table the T moved after its release in {len(moved)} episodes, e.g. {moved[0]}")
    walled = [r["travel_after"] for r in flat if r["wall_after"]]
    return {"episodes_with_contact": len(flat), "moved": len(moved), "wall_after_release": len(walled),
            "wall_after_release_moved": sum(t > 0.0 for t in walled),
            "wall_after_release_max_travel": max(walled, default=0.0)}


def main(out_dir: Path, *, force: bool = True) -> None:
    """The whole study (``rrbody scene pusht-table``): see :func:`run`."""
    run(out_dir, force=force)


def run(out_dir: Path, *, force: bool = True, episodes: int | None = None, movies: bool = True) -> None:
    """Run the study into ``out_dir`` (results/pusht-table/), the figure into docs/figures/ and the movie
    into movies/ (both beside results/). ``episodes``: per family (default: all of DEMO_SEEDS, WALK_SEEDS);
    ``movies``: also film (the movie, the Recorder's MP4 and rerun recording)."""
    import matplotlib

    matplotlib.use("Agg")
    from tqdm import tqdm

    from rrbody.analysis.report import write_summary, write_table
    from rrbody.model.io import atomic_write_text

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    root = out_dir.parent.parent  # results/, docs/ and movies/ are siblings (the runner's layout)
    seeds = {"demonstrations": DEMO_SEEDS[:episodes], "walks": WALK_SEEDS[:episodes]}
    # 1-2. every action sequence replayed in every world
    rows: list[dict[str, Any]] = []
    replay, t0 = 0.0, time.perf_counter()
    for family, family_seeds in seeds.items():
        for seed in tqdm(family_seeds, desc=f"{family} x {len(WORLDS)} worlds", unit="sequence", file=sys.stderr):
            new, wall = episode(family, seed)
            rows, replay = rows + new, replay + wall
    steps = sum(r["actions"] for r in rows)
    # printed, never stored: tracked files hold no timings
    print(f"{len(rows)} replays, {steps} env steps: {1e3 * replay / steps:.2f} ms per env step with the probe "
          f"({time.perf_counter() - t0:.0f} s with the demonstrations)")
    no_table = check_no_table(rows)
    closed = [r for seed in tqdm(seeds["demonstrations"], desc="closed loop on the tables", unit="seed",
                                 file=sys.stderr) for r in closed_loop(seed)]
    closed += [{"seed": r["seed"], "world": "no table", "success_action": r["success_action"]} for r in rows
               if r["family"] == "demonstrations" and r["world"] == "no table"]
    # 3. the off-centre pushes
    pushes = [push(w, b, v, dt, sch) for w, dt, sch in tqdm(PUSH_SERIES, desc="off-centre pushes", file=sys.stderr)
              for v in PUSH_SPEEDS for b in PUSH_OFFSETS]
    summary = {
        "worlds": WORLDS, "seeds": {f: [s[0], s[-1]] for f, s in seeds.items() if s}, "actions_per_episode": N_ACTIONS,
        "settle_actions": SETTLE, "walk": {"rho": OU_RHO, "sigma_units": OU_SIGMA}, "no_table_release": no_table,
        "episodes": summarize(rows),
        "closed_loop": {w: {"success_rate": float(np.mean([r["success_action"] >= 0 for r in by_world])),
                            "actions_to_success": quartiles([r["success_action"] + 1 for r in by_world
                                                             if r["success_action"] >= 0])}
                        for w in PUSH_WORLDS for by_world in [[r for r in closed if r["world"] == w]]},
        "push": {"offsets": PUSH_OFFSETS, "speeds": PUSH_SPEEDS, "travel_units": PUSH_TRAVEL, "rate_at_units": RATE_AT,
                 "predictions": predictions(PUSH_OFFSETS),
                 "exact_push": exact_push(max(PUSH_OFFSETS), PUSH_SPEEDS, PUSH_WORLDS[1:]),
                 **{m: by_series(pushes, PUSH_SERIES, m) for m in ("rate", "turn", "travel")}}}
    write_table(out_dir / "episodes.csv", COLUMNS, [[r[c] for c in COLUMNS] for r in rows], force=force,
                meta={"worlds": WORLDS, "units": "workspace units (1/600 m), rad, s, units/s"})
    write_table(out_dir / "closed_loop.csv", ("seed", "world", "success_action"),
                [[r[c] for c in ("seed", "world", "success_action")] for r in closed], force=force)
    names = ("world", "dt", "scheme", "speed", "offset", "rate", "turn", "travel")
    write_table(out_dir / "pushes.csv", names, [[p[c] for c in names] for p in pushes], force=force,
                meta={"units": "dt s, speed units/s, offset units, rate rad/unit, turn rad, travel units",
                      "scheme": "the plugin's step on a table (coupled: the env's; split: friction before "
                                "pymunk's contact solve); empty without a table"})
    # the movie's episode: of the demonstrations that succeed without a table within 16 s, the one the
    # mu 0.3 table spoils most (the largest drop in final coverage)
    end = {(r["seed"], r["world"]): r for r in rows if r["family"] == "demonstrations"}
    good = [s for s in seeds["demonstrations"] if 0 <= end[s, "no table"]["success_action"] < 160]
    if good:
        seed = max(good, key=lambda s: end[s, "no table"]["coverage"] - end[s, "mu 0.3"]["coverage"])
        summary["movie"] = {"seed": seed, "family": "demonstrations", "rule": "succeeds without a table within 16 s; "
                            "the largest drop in final coverage on the mu 0.3 table"}
    write_summary(out_dir, summary, force=force)
    atomic_write_text(out_dir / "table.md", markdown(summary), force=force, name="table.md")
    (root / "docs" / "figures").mkdir(parents=True, exist_ok=True)
    print("figure:", figure(rows, summary, root / "docs" / "figures" / "pusht_table.png", force=force))
    if movies and good:
        film(seed, out_dir, root / "movies", force=force)


def film(seed: int, out_dir: Path, movies: Path, *, force: bool) -> None:
    """The demonstration of ``seed`` replayed without a table and on the mu 0.3 table: side by side in
    movies/pusht_table.mp4; the table's run also filmed by rrbody's Recorder (created after the reset,
    which rebuilds the space; a frame every 5 steps) into out_dir/recorder.mp4 and recorder.rrd."""
    from rrbody.plugin import Recorder

    actions = demonstrate(seed)[0]
    held: list[Any] = []

    def recorder(env: Any) -> Callable[[], bool]:
        held.append(Recorder(env.space, env.plane, bodies=[env.block, env.agent], labels=["T", "agent"], every=5))
        return held[-1].capture

    runs = {"no table": rollout("no table", seed, actions), "mu 0.3": rollout("mu 0.3", seed, actions, each=recorder)}
    movies.mkdir(parents=True, exist_ok=True)
    path = side_by_side(runs, actions, movies / "pusht_table.mp4", force=force)
    rec = held[0]
    rec.movie(out_dir / "recorder.mp4", fps=20, speed=2.0, size=(480, 480), box=(0, 512, 0, 512),
              title=f"seed {seed}, mu 0.3 (units, y up)", force=force)
    rec.rerun(out_dir / "recorder.rrd", force=force)
    for p in (path, out_dir / "recorder.mp4", out_dir / "recorder.rrd"):
        print(f"{p} ({p.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--episodes", type=int, default=None, help="action sequences per family (default: every seed)")
    ap.add_argument("--no-movies", action="store_true", help="skip the movies and the Recorder's outputs")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent.parent / "results" / "pusht-table",
                    help="output folder (default: %(default)s)")
    args = ap.parse_args()
    run(args.out, episodes=args.episodes, movies=not args.no_movies)
