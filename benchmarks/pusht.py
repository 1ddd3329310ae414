"""Push-T on a table: what ``env.step`` costs against gym-pusht's own.

gym-pusht 0.1.8 (the competitor, its own code: ``gymnasium.make("gym_pusht/PushT-v0")``, state
observations) against rrbody/PushT-v0 on its default table (mu 0.3) and against gym-pusht's env put on
the same table by :func:`rrbody.envs.wrapper.table`, the same actions for each. Two phases: *moving*, a seeded
random walk of the agent's target that pushes the T now and then; *at rest*, the agent held where it
is and the T at rest (no body moves). Blocks of 20 steps of each env, interleaved in one run, the best
block of each (``min`` over 40 rounds; a measured spread of 10-20 % between rounds on this machine).
Each env is made INSTANCES times and the figure of an env in a run is the median of its instances'
best blocks, and the whole measurement runs PROCESSES times, each in a fresh process; a ratio is taken
within its run, and the study reports the median over the runs and every run's ratio. Why: the best
block of one instance of gym-pusht's own env was 595-610 us in some processes and 680-770 us in
others, the same code and actions, and the best of more rounds does not remove that (an instance's
speed is set when it is made): with one instance per env the wrapper's at-rest ratio moved between
1.00x and 1.17x from run to run; with four, between 1.05x and 1.07x, the same code. Also reported:
rrbody/PushT-v0 without its table (the table's own cost) and two ``gymnasium.vector.AsyncVectorEnv``
workers stepping rrbody/PushT-v0.

Runs where gym-pusht is installed (it pins pymunk < 7: make bench runs this study in the
oldest-versions venv, pymunk 6.6, beside it); elsewhere it is recorded as skipped.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, write_csv

NAME = "pusht"
TITLE = "Push-T on a table: env.step against gym-pusht's own"
BLOCK, ROUNDS, INSTANCES, PROCESSES = 20, 40, 4, 3
#: the bounds on env.step over gym-pusht's: (T pushed, at rest) for each env
BOUNDS = {"rrbody/PushT-v0": (0.4, 0.4), "gym-pusht + rrbody.envs.table": (1.2, 1.1)}


def _walk(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.clip(256 + np.cumsum(rng.normal(0.0, 25.0, (n, 2)), axis=0), 20, 492).astype(np.float32)


def _stepper(env: Any, actions: np.ndarray | None, seed: int) -> Callable[[], None]:
    """A block of BLOCK steps of ``env`` (reset with ``seed``); ``actions`` None: the agent held still."""
    state = {"k": 0}

    def reset() -> None:
        env.reset(seed=seed)
        if actions is None:  # the agent at rest, away from the T, which is at rest
            base = env.unwrapped
            base.agent.position = (40.0, 40.0)
            base.agent.velocity = (0.0, 0.0)
            base.block.velocity = (0.0, 0.0)
            base.block.angular_velocity = 0.0
            for _ in range(3):  # settled: a T the reset left touching a wall has stopped
                env.step(hold)
        state["k"] = 0

    hold = np.array([40.0, 40.0], dtype=np.float32)
    reset()

    episode = len(actions) if actions is not None else 300  # the at-rest episode as long as the walk

    def block() -> None:
        if state["k"] + BLOCK > episode:
            reset()  # a new episode, one per 15 blocks for every env; the best of 40 rounds is a block without one
        for i in range(BLOCK):
            env.step(hold if actions is None else actions[state["k"] + i])
        state["k"] += BLOCK

    return block


def _best(blocks: dict[Any, Callable[[], None]]) -> dict[Any, float]:
    best = {k: math.inf for k in blocks}
    for f in blocks.values():
        f()  # compiled kernels, first allocations: not counted
    for _ in range(ROUNDS):
        for k, f in blocks.items():
            t0 = time.perf_counter()
            f()
            best[k] = min(best[k], (time.perf_counter() - t0) / BLOCK)
    return best


def _vector(n_steps: int) -> float:
    import gymnasium as gym

    envs = gym.vector.AsyncVectorEnv([lambda: gym.make("rrbody.envs:rrbody/PushT-v0")] * 2)
    try:
        envs.reset(seed=[0, 1])
        acts = np.stack([_walk(n_steps, 0), _walk(n_steps, 1)], axis=1)
        envs.step(acts[0])
        t0 = time.perf_counter()
        for a in acts[1:]:
            envs.step(a)
        return (time.perf_counter() - t0) / (n_steps - 1)
    finally:
        envs.close()


def _measure(instances: int = INSTANCES) -> dict[str, dict[str, list[float]]]:
    """One run: {phase: {env: each instance's best block, s per step}}, the envs interleaved."""
    import gymnasium as gym

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import gym_pusht  # noqa: F401 (registers gym_pusht/PushT-v0)
    import rrbody.envs  # noqa: F401 (registers rrbody/PushT-v0)
    from rrbody.envs import table

    def make() -> dict[str, Any]:
        return {"gym-pusht": gym.make("gym_pusht/PushT-v0"), "rrbody/PushT-v0": gym.make("rrbody/PushT-v0"),
                "rrbody/PushT-v0, no table": gym.make("rrbody/PushT-v0", table=False),
                "gym-pusht + rrbody.envs.table": table(gym.make("gym_pusht/PushT-v0"))}

    got: dict[str, dict[str, list[float]]] = {}
    for phase, acts in (("moving", _walk(300)), ("at rest", None)):
        made = [make() for _ in range(instances)]
        each = _best({(k, i): _stepper(e, acts, 0) for i, envs in enumerate(made) for k, e in envs.items()})
        got[phase] = {k: sorted(each[k, i] for i in range(instances)) for k in made[0]}
    return got


class _TimedSpace:
    """gym-pusht's own space with its step timed: ``step`` in place of ``space.step`` (gym-pusht reads nothing
    else of its space in its step)."""

    __slots__ = ("_space", "step")

    def __init__(self, space: Any, step: Callable[[float], None]) -> None:
        self._space, self.step = space, step


def _physics_steps(n_steps: int = 200) -> dict[str, list[float]]:
    """Where the wrapper's time goes at rest: inside gym-pusht's loop, each of the 10 physics steps of an
    ``env.step`` timed alone, gym-pusht's own ``space.step`` against the wrapper's ``plane.step`` (the
    table's step, then the same ``space.step``). Returns {which: the lower
    quartile over ``n_steps`` env steps of each physics step's time, us}; both are timed through the
    same Python wrapper, whose cost (about 0.1 us) both figures include; blocks of BLOCK env steps of each
    env in turn, as in :func:`_measure`."""
    import gymnasium as gym

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import gym_pusht  # noqa: F401 (registers gym_pusht/PushT-v0)
    from rrbody.envs import table

    spent: dict[str, list[list[int]]] = {}
    where = {"k": 0}

    def timed(name: str, step: Callable[[float], None]) -> Callable[[float], None]:
        got = spent.setdefault(name, [[] for _ in range(10)])

        def run(dt: float) -> None:
            t0 = time.perf_counter_ns()
            step(dt)
            got[where["k"] % 10].append(time.perf_counter_ns() - t0)
            where["k"] += 1
        return run

    hold = np.array([40.0, 40.0], dtype=np.float32)
    bare, wrapped = gym.make("gym_pusht/PushT-v0"), table(gym.make("gym_pusht/PushT-v0"))
    for env in (bare, wrapped):
        _stepper(env, None, 0)  # reset, the agent and the T at rest, settled (as in the timing above)
    space = bare.unwrapped.space
    bare.unwrapped.space = _TimedSpace(space, timed("gym-pusht: space.step", space.step))
    proxy = wrapped.unwrapped.space
    object.__setattr__(proxy, "step", timed("wrapper: plane.step", proxy.step))
    for _ in range(n_steps // BLOCK):  # blocks of BLOCK steps of each env in turn, as the timing above
        for env in (bare, wrapped):
            for _ in range(BLOCK):
                where["k"] = 0
                env.step(hold)
    return {k: [float(np.percentile(v, 25)) / 1e3 for v in lists] for k, lists in spent.items()}


def _moving_parts(n_steps: int = 300, rounds: int = 3) -> dict[str, float]:
    """Where the wrapper's time goes while the T is pushed: over the walk of the timing above (the same actions
    for both envs, interleaved step by step), each ``env.step`` of gym-pusht and of the wrapper timed whole, and
    inside it the 10 physics steps (gym-pusht's ``space.step``; the wrapper's ``plane.step``: the table's
    friction, the same ``space.step`` and the coupled step). Returns per env.step, us, the median over the walk
    of the best of ``rounds`` passes: each env's whole step and its physics steps. The rest of a step is
    gym-pusht's own code (observation, reward, coverage), which runs on each env's own path of the T: the T on
    the table moves otherwise than without it."""
    import gymnasium as gym

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import gym_pusht  # noqa: F401 (registers gym_pusht/PushT-v0)
    from rrbody.envs import table

    inside = {"physics": 0}

    def timed(step: Callable[[float], None]) -> Callable[[float], None]:
        def run(dt: float) -> None:
            t0 = time.perf_counter_ns()
            step(dt)
            inside["physics"] += time.perf_counter_ns() - t0
        return run

    acts = _walk(n_steps)
    best = {k: np.full((n_steps, 2), np.inf) for k in ("gym-pusht", "wrapper")}
    for _ in range(rounds):
        envs = {"gym-pusht": gym.make("gym_pusht/PushT-v0"), "wrapper": table(gym.make("gym_pusht/PushT-v0"))}
        for k, env in envs.items():
            env.reset(seed=0)
            if k == "gym-pusht":
                space = env.unwrapped.space
                env.unwrapped.space = _TimedSpace(space, timed(space.step))
            else:
                proxy = env.unwrapped.space
                object.__setattr__(proxy, "step", timed(proxy.step))
        for i, a in enumerate(acts):
            for k, env in envs.items():
                inside["physics"] = 0
                t0 = time.perf_counter_ns()
                env.step(a)
                whole = time.perf_counter_ns() - t0
                best[k][i] = np.minimum(best[k][i], (whole / 1e3, inside["physics"] / 1e3))
    return {f"{k}: {part}": float(np.median(best[k][:, c])) for k in best for c, part in enumerate(("env.step",
                                                                                                      "physics"))}


def _runs(n: int) -> list[dict[str, dict[str, list[float]]]]:
    """:func:`_measure` in ``n`` fresh processes, one after the other (this interpreter, this environment)."""
    runs = []
    code = "import json, benchmarks.pusht as b; print('RESULT ' + json.dumps(b._measure()))"
    for p in range(n):
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=1800,
                           cwd=Path(__file__).resolve().parents[1], env=os.environ.copy())
        lines = [x for x in r.stdout.splitlines() if x.startswith("RESULT ")]
        if r.returncode or not lines:
            raise RuntimeError(f"run {p + 1} of the Push-T timing failed: {r.stderr.strip()[-2000:]}")
        runs.append(json.loads(lines[-1][len("RESULT "):]))
        print(f"[pusht] run {p + 1}/{n} done", flush=True)
    return runs


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("gym_pusht")
    if not ok:
        return StudyResult(NAME, TITLE, skipped=f"gym_pusht not importable ({why}): make bench runs this study "
                                                f"in the oldest-versions venv, beside gym-pusht")
    runs = _runs(1 if quick else PROCESSES)
    rows, ratio = [], {}
    for phase in ("moving", "at rest"):
        figs = [{k: float(np.median(v)) for k, v in r[phase].items()} for r in runs]  # each run: median instance
        for k in figs[0]:
            xs = [f[k] / f["gym-pusht"] for f in figs]  # each ratio measured within one run
            ratio[phase, k] = float(np.median(xs))
            rows.append({"phase": phase, "env": k, "us_per_step": float(np.median([f[k] for f in figs])) * 1e6,
                         "x_gym_pusht": ratio[phase, k], "runs_x": " ".join(f"{x:.3f}" for x in xs),
                         "runs_us": " ".join(f"{f[k] * 1e6:.0f}" for f in figs)})
            print(f"[pusht] {phase}: {k} {rows[-1]['us_per_step']:.0f} us/step ({ratio[phase, k]:.3f}x gym-pusht; "
                  f"runs {rows[-1]['runs_x']})", flush=True)
    vec = _vector(20 if quick else 100)
    print(f"[pusht] AsyncVectorEnv, 2 workers: {vec * 1e6:.0f} us per vector step", flush=True)
    write_csv(out / "pusht.csv", rows)
    phys = _physics_steps(50 if quick else 200)
    gym_s, plane_s = phys["gym-pusht: space.step"], phys["wrapper: plane.step"]
    write_csv(out / "pusht_physics.csv", [{"physics_step": i + 1, "gym_pusht_space_step_us": g,
                                           "wrapper_plane_step_us": w,
                                           "added_us": w - g} for i, (g, w) in enumerate(zip(gym_s, plane_s))])
    added = [w - g for g, w in zip(gym_s, plane_s)]
    rest_gym = next(r["us_per_step"] for r in rows if r["phase"] == "at rest" and r["env"] == "gym-pusht")
    print(f"[pusht] at rest, per physics step: space.step {gym_s[0]:.2f} us on the first of 10, "
          f"{float(np.median(gym_s[1:])):.2f} on the others; the table adds {added[0]:.2f} and "
          f"{float(np.median(added[1:])):.2f} us ({sum(added):.1f} us per env.step)", flush=True)

    parts = _moving_parts(100 if quick else 300, 1 if quick else 3)
    write_csv(out / "pusht_moving.csv", [{"part": k, "us_per_env_step": v} for k, v in parts.items()])
    own = {k: parts[f"{k}: env.step"] - parts[f"{k}: physics"] for k in ("gym-pusht", "wrapper")}
    added_phys = parts["wrapper: physics"] - parts["gym-pusht: physics"]
    print(f"[pusht] moving, per env.step: physics gym-pusht {parts['gym-pusht: physics']:.1f} us, wrapper "
          f"{parts['wrapper: physics']:.1f} us; gym-pusht's own code {own['gym-pusht']:.0f} us without the table, "
          f"{own['wrapper']:.0f} us on it", flush=True)

    targets = []
    for k in ("rrbody/PushT-v0", "gym-pusht + rrbody.envs.table"):
        for phase, bound in zip(("moving", "at rest"), BOUNDS[k]):
            r = ratio[phase, k]
            each = next(x["runs_x"] for x in rows if x["phase"] == phase and x["env"] == k)
            targets.append(Target(f"{k}, {phase}: env.step / gym-pusht's", f"<= {bound}x",
                                  f"{r:.3f}x (median of {len(runs)} runs: {each})", r <= bound))
    targets.append(Target("AsyncVectorEnv, 2 workers, runs rrbody/PushT-v0", "(no bound)", f"{vec * 1e6:.0f} us/step",
                          None))
    targets.append(Target("gym-pusht + rrbody.envs.table, moving: its physics steps per env.step (the table's work)",
                          "(no bound)", f"{parts['wrapper: physics']:.1f} us against gym-pusht's "
                          f"{parts['gym-pusht: physics']:.1f} us (gym-pusht's own code {own['wrapper']:.0f} us per "
                          f"step on the T's path on the table, {own['gym-pusht']:.0f} us without it)", None))
    table_md = md_table(["phase", "env", "us per step", "x gym-pusht", "each run's x", "each run's us per step"],
                        [(r["phase"], r["env"], fmt(r["us_per_step"]), f"{r['x_gym_pusht']:.3f}", r["runs_x"],
                          r["runs_us"]) for r in rows])
    md = (f"## {TITLE}\n\n{machine_text()}\n\nState observations, the same actions for each env. {len(runs)} runs, "
          f"each a fresh process: blocks of {BLOCK} steps interleaved, best of {ROUNDS} rounds for each of "
          f"{INSTANCES} instances of every env, an env's figure the median of its instances and each ratio taken "
          f"within its run; the table gives the medians over the runs (why: the study's docstring). gym-pusht "
          f"spends most of its step in shapely's overlay for the coverage; rrbody's exact clipping "
          f"(rrbody.physics.overlap) takes about a microsecond, which pays for the table in rrbody/PushT-v0; the "
          f"wrapper keeps gym-pusht's own coverage.\n\n{table_md}\n\n"
          f"Two AsyncVectorEnv workers: {vec * 1e6:.0f} us per vector step (two env steps).\n\n"
          f"Where the wrapper's time goes at rest (pusht_physics.csv): each of the 10 physics steps of an "
          f"env.step timed alone inside gym-pusht's loop, the lower quartile over {50 if quick else 200} env "
          f"steps. gym-pusht's space.step takes {gym_s[0]:.2f} us on the first (after its observation and "
          f"coverage) and {float(np.median(gym_s[1:])):.2f} us (median) on the others; the wrapper's "
          f"plane.step adds {added[0]:.2f} and {float(np.median(added[1:])):.2f} us to them: "
          f"{sum(added):.1f} us per env.step, {sum(added) / rest_gym:.1%} "
          f"of gym-pusht's step (the whole step's ratio above also holds what these timers cannot see: the "
          f"caches the table's work takes from gym-pusht's own code).\n\n"
          f"Where the wrapper's time goes while the T is pushed (pusht_moving.csv): over the walk of the timing above, "
          f"the same actions for both envs interleaved step by step, each env.step and the 10 physics steps inside "
          f"it timed (per env.step, the median over the walk of the best of {1 if quick else 3} passes). The "
          f"physics steps take {parts['gym-pusht: physics']:.1f} us in gym-pusht and {parts['wrapper: physics']:.1f}"
          f" us in the wrapper (the table adds {added_phys:.1f} us, {added_phys / own['gym-pusht']:.1%} of "
          f"gym-pusht's own code); gym-pusht's own code (observation, reward, shapely's coverage) takes "
          f"{own['gym-pusht']:.0f} us per step on the path the T takes without the table and {own['wrapper']:.0f} "
          f"us on the path it takes on the table (the T on the table takes another path, whose coverage costs "
          f"what it costs, and the table's work takes caches from gym-pusht's code: these timers cannot tell the "
          f"two apart).\n")
    return StudyResult(NAME, TITLE, targets=targets, markdown=md, files=["pusht.csv", "pusht_physics.csv",
                                                                         "pusht_moving.csv"])
