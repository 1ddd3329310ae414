"""Each private fast path against the 10 % bar: what it saves on a benchmark a user sees.

docs/versions.md lists every use of another library's private internals with its public takeover. A
fast path stays only where it moves a user-visible benchmark by 10 % or more; this study measures each
one on the workload where it matters most, with the path and with its takeover, in one run,
interleaved (each round builds both variants afresh and times a block of each in turn), best of the
rounds (noise on a shared machine only ever adds time). Workloads:

- ``many``: 1,000 bodies sliding and spinning on the plane, apart (no contacts): ``pf.step`` at dt
  1/120 s (the engine study's many bodies); ``many, sleeping on``: the same with the space's sleeping
  on (``sleep_time_threshold`` 10 s, no body falls asleep in the blocks), where the plugin reads the
  space through ``pymunk.batch``;
- ``PushT-v0``: ``rrbody/PushT-v0``'s ``env.step`` along a random walk of the agent (the pusht study's);
- ``pushed``: gym-pusht's T pushed by a kinematic disk, ``pf.step`` coupled (the engine study's);
- ``driven``: rrbody's driven rod-mass (phixtpm) stepped by its plane (the engine study's);
- ``filmed``: the 1,000 bodies stepped and captured every step by a ``Recorder``;
- ``clusters``: 1,000 active disks and L-shapes in a walled box (the active study's), ``pf.step`` once
  they have gathered into clusters (12.5 s after launch), where pymunk's step between two calls leaves
  little of the L's wrench table in the CPU's caches;
- ``start-up``: one ``rrbody flip-time`` command, a fresh process (the start-up study's single call).

The takeover that changes how a kernel compiles (numba's ``_nrt=False``) runs in fresh
processes on cache folders of their own, compiled once before the timed rounds; the processes with
and without the path alternate. On ``clusters`` the gain is that of the figure the active-matter study
judges, the time ``pf.step`` adds to pymunk's step inside it; elsewhere that of the time per step. The
others switch in one process, each at the place it is decided (the same switch ``RRBODY_NO_PRIVATE``
flips for all of them at once). The numba cache locators are
not timed here: without them an installed rrbody cannot load the kernels it was installed with, and
its first use compiles them (the cold-start study measures that).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "private"
TITLE = "Private fast paths against the 10 % bar"
BAR = 0.10  # the least gain (1 - with / without) on a user-visible benchmark for a private path to stay
#: the paths measured on several workloads
STRUCT = "Chipmunk's struct memory"
NRT = "numba's _nrt=False (no reference counting)"
N_BODIES = 1000
DT = 1.0 / 120.0
CLUSTERED = 12.5  # s of simulated time after launch: the active bodies have gathered into clusters


# ---- workloads: each returns a block (a callable that runs some steps) and the steps it runs ----

def _many(sleeping: bool = False, film: bool = False, patch: Callable[[Any], None] | None = None
           ) -> tuple[Callable[[], None], int]:
    import pymunk

    from rrbody.plugin import PlaneFriction, Recorder

    from .plugin import MU, _bodies

    space = pymunk.Space()
    if sleeping:
        space.sleep_time_threshold = 10.0
    bodies = _bodies(space, N_BODIES)
    pf = PlaneFriction(space)
    for b in bodies:
        pf.add(b, mu=MU)
    if patch is not None:
        patch(pf)
    pf.step(DT)
    steps = 10
    if film:
        rec = Recorder(space, pf, max_mb=8000.0, reserve=20 * steps + 2)
        rec.capture()

        def block() -> None:
            for _ in range(steps):
                pf.step(DT)
                rec.capture()
        return block, steps

    def block() -> None:
        for _ in range(steps):
            pf.step(DT)
    return block, steps


def _pusht() -> tuple[Callable[[], None], int]:
    import gymnasium as gym

    import rrbody.envs  # noqa: F401 (registers rrbody/PushT-v0)

    from .pusht import _walk

    env = gym.make("rrbody/PushT-v0")
    env.reset(seed=0)
    acts = _walk(300)
    state = {"k": 0}
    steps = 10

    def block() -> None:
        if state["k"] + steps > len(acts):
            env.reset(seed=0)
            state["k"] = 0
        for i in range(steps):
            env.step(acts[state["k"] + i])
        state["k"] += steps
    block()
    return block, steps


def _pushed(route: str | None = None) -> tuple[Callable[[], None], int]:
    from rrbody.engine.plugin.coupling import Coupling

    from .plugin import _pushed as pushed_space

    pf = pushed_space("coupled")
    if route is not None:
        pf._coupling = Coupling(pf.space, route=route)  # (the benchmark's choice of route)
        pf.step(0.01)
    steps = 20

    def block() -> None:
        for _ in range(steps):
            pf.step(0.01)
    return block, steps


def _driven() -> tuple[Callable[[], None], int]:
    import pymunk

    from rrbody.engine import EngineSettings, attach
    from rrbody.model.scene import rod_mass_scene

    dt = 1e-3
    h = attach(pymunk.Space(), rod_mass_scene(0.2, 0.05, 0.6, math.pi), settings=EngineSettings(dt=dt))
    h.plane.step(dt)
    steps = 500

    def block() -> None:
        for _ in range(steps):
            h.plane.step(dt)
    return block, steps


def _clusters() -> tuple[Callable[[], None], int]:
    """The active bodies in clusters; the block's ``inner`` holds the time of pymunk's steps inside its
    last run (s), for the figure the active-matter study judges: what ``pf.step`` adds to them."""
    from .active import DT as ACTIVE_DT
    from .active import build

    space, pf, _, _, _ = build(N_BODIES)
    for _ in range(round(CLUSTERED / ACTIVE_DT)):
        pf.step(ACTIVE_DT)
    steps = 10
    bare = space.step
    inner = [0.0]

    def timed(dt: float) -> None:
        t0 = time.perf_counter()
        bare(dt)
        inner[0] += time.perf_counter() - t0

    space.step = timed

    def block() -> None:
        inner[0] = 0.0
        for _ in range(steps):
            pf.step(ACTIVE_DT)
    block.inner = inner  # type: ignore[attr-defined]
    return block, steps


WORKLOADS: dict[str, Callable[[], tuple[Callable[[], None], int]]] = {
    "many": _many, "PushT-v0": _pusht, "clusters": _clusters,
}


# ---- the switches: a context in which a workload is built without one fast path ----

@contextlib.contextmanager
def _attr(obj: Any, name: str, value: Any) -> Iterator[None]:
    old = getattr(obj, name)
    setattr(obj, name, value)
    try:
        yield
    finally:
        setattr(obj, name, old)


@contextlib.contextmanager
def _no_struct() -> Iterator[None]:
    """Chipmunk's struct layout unknown: the plugin and the recorder read through ``pymunk.batch``."""
    from rrbody.engine.memory import bodymem

    with _attr(bodymem, "_layout", None), _attr(bodymem, "_sleep", None):
        yield


@contextlib.contextmanager
def _no_setters() -> Iterator[None]:
    """A driven body's driver moved through its public properties."""
    from rrbody.engine.scenes import builder

    with _attr(builder, "private_allowed", lambda: False):
        yield


def _route(route: str) -> Callable[[Any], None]:
    def patch(pf: Any) -> None:
        from rrbody.engine.memory.batchio import BatchIO

        pf._io = BatchIO(pf.space, route=route)  # (the benchmark's choice of route)
    return patch


def _inline(name: str, where: str, with_path: Callable[[], tuple[Callable[[], None], int]],
            without: Callable[[], tuple[Callable[[], None], int]]) -> dict[str, Any]:
    return {"path": name, "benchmark": where, "with": with_path, "without": without}


def _in_process(rounds: int) -> list[dict[str, Any]]:
    """The fast paths switched in this process: us per step with and without each, best of ``rounds``."""
    cases = [
        _inline(STRUCT, "many", _many, lambda: _with(_no_struct, _many)),
        _inline(STRUCT, "PushT-v0", _pusht, lambda: _with(_no_struct, _pusht)),
        _inline(STRUCT, "filmed", lambda: _many(film=True), lambda: _with(_no_struct, lambda: _many(film=True))),
        _inline("pymunk.batch's buffers (route bulk)", "many, sleeping on",
                lambda: _many(sleeping=True, patch=_route("bulk")),
                lambda: _many(sleeping=True, patch=_route("per-body"))),
        _inline("Chipmunk's setters for the driver", "driven", _driven, lambda: _with(_no_setters, _driven)),
        _inline("Chipmunk's C functions (the coupled step's compiled route)", "pushed", _pushed,
                lambda: _pushed(route="public")),
    ]
    rows = []
    for case in cases:
        best = {"with": math.inf, "without": math.inf}
        for _ in range(rounds):
            for k in ("with", "without"):
                block, steps = case[k]()
                block()  # compiled kernels, entry points, first allocations: not counted
                t0 = time.perf_counter()
                block()
                best[k] = min(best[k], (time.perf_counter() - t0) / steps)
        rows.append(_row(case["path"], case["benchmark"], best["with"], best["without"], rounds))
    return rows


def _with(switch: Callable[[], Any], make: Callable[[], tuple[Callable[[], None], int]]
          ) -> tuple[Callable[[], None], int]:
    with switch():
        return make()


def _row(path: str, where: str, with_s: float, without_s: float, rounds: int,
         added: tuple[float, float] | None = None) -> dict[str, Any]:
    """A row of private.csv. The gain is 1 - with / without of the time per step, or, given ``added`` (the
    clusters: what pf.step adds to pymunk's step inside it, with and without the path, as fractions), of
    that figure, the one the active-matter study judges."""
    gain = 1.0 - (with_s / without_s if added is None else added[0] / added[1])
    what = "" if added is None else f", adding {100 * added[0]:.1f} vs {100 * added[1]:.1f} % to pymunk's step"
    print(f"[private] {path} on {where}: {with_s * 1e6:.2f} vs {without_s * 1e6:.2f} us per step "
          f"without it{what} ({100 * gain:.1f} %)", flush=True)
    return {"path": path, "benchmark": where, "with_us": with_s * 1e6, "without_us": without_s * 1e6,
            "added_with": "" if added is None else added[0], "added_without": "" if added is None else added[1],
            "gain": gain, "stays": gain >= BAR, "rounds": rounds}


# ---- the fast paths that change a kernel's compilation: fresh processes, cache folders of their own ----

#: what each compile-time switch does in a fresh process before rrbody's kernels are imported
_COMPILED = {
    "_nrt=False": "import rrbody._private as P; P.no_refcount = lambda: {}",
}


def _worker(workload: str, off: str | None, blocks: int) -> None:
    """In a fresh process: build ``workload`` (without the path ``off``) and print its best block, s per step."""
    if off is not None:
        exec(_COMPILED[off])  # noqa: S102 (one of this module's own lines)
    block, steps = WORKLOADS[workload]()
    block()
    best, added = math.inf, math.nan
    for _ in range(blocks):
        t0 = time.perf_counter()
        block()
        total = time.perf_counter() - t0
        if total / steps < best:
            best = total / steps
            if hasattr(block, "inner"):  # the clusters: what pf.step adds to pymunk's steps inside it
                added = total / block.inner[0] - 1.0
    print(json.dumps({"s_per_step": best, "added": added}))


def _child(workload: str, off: str | None, cache: str | None, blocks: int) -> dict[str, float]:
    """``_worker`` in a fresh process: with the path (``off`` None) on this process's own cache folder,
    without it on ``cache``, a folder of its own (its kernels are compiled differently)."""
    cmd = [sys.executable, "-m", "benchmarks.private", "--worker", workload, "--blocks", str(blocks)]
    env = dict(os.environ, MPLBACKEND="Agg")
    if off is not None:
        cmd += ["--off", off]
        env.update(RRBODY_CACHE_DIR=str(cache), RRBODY_NO_SEED="1")
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False,
                       cwd=str(Path(__file__).resolve().parents[1]))
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{p.stderr[-2000:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def _compiled(rounds: int, blocks: int) -> list[dict[str, Any]]:
    cases = [(NRT, "many", "_nrt=False"), (NRT, "PushT-v0", "_nrt=False"), (NRT, "clusters", "_nrt=False")]
    rows = []
    with tempfile.TemporaryDirectory(prefix="rrbody-private-") as tmp:
        for path, where, off in cases:
            off_cache = os.path.join(tmp, off)
            print(f"[private] {path} on {where}: the kernels without it (compiled at first: a minute or two)",
                  flush=True)
            _child(where, None, None, 1)
            _child(where, off, off_cache, 1)
            best = {"with": {"s_per_step": math.inf}, "without": {"s_per_step": math.inf}}
            for _ in range(rounds):
                for k, o, c in (("with", None, None), ("without", off, off_cache)):
                    got = _child(where, o, c, blocks)
                    if got["s_per_step"] < best[k]["s_per_step"]:
                        best[k] = got
            rows.append(_row(path, where, best["with"]["s_per_step"], best["without"]["s_per_step"], rounds,
                             added=(best["with"]["added"], best["without"]["added"]) if where == "clusters" else None))
    return rows


def _start_up(rounds: int) -> dict[str, Any]:
    """One ``rrbody flip-time`` command with and without the ``cython_blas`` preload, fresh processes."""
    from .startup import SINGLE

    root = str(Path(__file__).resolve().parents[1])
    on = [sys.executable, "-m", "rrbody.cli", *SINGLE]
    off = [sys.executable, "-c", "import sys, rrbody.cli.lean as L; L.preload_cython_blas = lambda: None; "
           "from rrbody.cli.main import entry; sys.argv[1:] = " + repr(SINGLE) + "; raise SystemExit(entry())"]
    best = {"with": math.inf, "without": math.inf}
    for cmd in (on, off):
        subprocess.run(cmd, check=True, capture_output=True, cwd=root)
    for _ in range(rounds):
        for k, cmd in (("with", on), ("without", off)):
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True, cwd=root)
            best[k] = min(best[k], time.perf_counter() - t0)
    return _row("scipy's cython_blas loaded alone", "start-up", best["with"], best["without"], rounds)


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    rounds = 3 if quick else 9
    # (a command's start-up varies more from run to run than a step: more rounds)
    rows = _in_process(rounds) + [_start_up(2 * rounds)] + _compiled(3 if quick else 5, 5 if quick else 20)
    write_csv(out / "private.csv", rows)
    below = [f"{r['path']} on {r['benchmark']}" for r in rows if not r["stays"]]
    table = md_table(["private fast path", "benchmark", "with (us per step)", "without (us per step)", "gain"],
                     [[r["path"], r["benchmark"], fmt(r["with_us"]), fmt(r["without_us"]), f"{100 * r['gain']:.1f} %"]
                      for r in rows])
    md = [f"## {TITLE}", "", machine_text(), "",
          f"Each path with and without its public takeover, interleaved, best of {rounds} rounds "
          "(start-up: one command's wall time, us).", "", table, "",
          "Below the bar: " + ("; ".join(below) if below else "none") + "."]
    best: dict[str, dict[str, Any]] = {}  # each path's row on the benchmark it moves most
    for r in rows:
        if r["path"] not in best or r["gain"] > best[r["path"]]["gain"]:
            best[r["path"]] = r
    targets = [Target(f"private path: {p}", f">= {100 * BAR:g} % of a user-visible benchmark",
                      f"{100 * r['gain']:.1f} % ({r['benchmark']})", r["gain"] >= BAR,
                      "the benchmark it moves most; every one in private.csv")
               for p, r in best.items()]
    return StudyResult(NAME, TITLE, targets=targets, markdown="\n".join(md), files=["private.csv"],
                       wall_s=time.perf_counter() - t0)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.private")
    ap.add_argument("--worker", choices=tuple(WORKLOADS), required=True)
    ap.add_argument("--off", choices=tuple(_COMPILED), default=None)
    ap.add_argument("--blocks", type=int, default=20)
    a = ap.parse_args(argv)
    _worker(a.worker, a.off, a.blocks)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
