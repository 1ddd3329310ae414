"""The PlaneFriction plugin against what pymunk users write today (part of the engine study).

Every baseline is pymunk's own step, never rrbody's. Ratios come from one run, the variants
interleaved (each repeat times every variant in turn on a freshly built space), best of the repeats
(noise on a shared machine only ever adds time).

1. **Many bodies**: N bodies, half circles (r = 0.1 m), half boxes (0.2 x 0.2 m), density 1, on a grid
   1 m apart (no contacts), launched sliding (0.5-1.5 m/s) and spinning (2-6 rad/s), mu = 0.05, g =
   9.81, dt = 1/120 s; 120 steps timed (all bodies keep moving). Variants: ``bare`` (``space.step``,
   no friction), ``tank`` (pymunk's tank example: per body a kinematic control body at rest, a
   ``PivotJoint`` and a ``GearJoint`` to it with ``max_bias`` 0 and ``max_force`` mu m g and
   mu m g r_mean, the decoupled force and torque caps), ``plugin`` (``PlaneFriction.step``).
2. **phixtpm engine step**: rrbody's driven rod-mass (H = 0.2, k = 0.05, w = 0.6) stepped by
   ``h.plane.step`` against the same driven body in plain pymunk (a kinematic driver with a constant
   velocity and a ``PivotJoint``; no friction, no per-step Python).
3. **Adding and removing bodies one by one**: the bodies of study 1 already in a space,
   then N ``pf.add`` calls timed, the first ``pf.step`` after them (half kicks, the id table) timed
   apart, then N ``pf.remove`` calls in a random order; N = 1,000 and 10,000, interleaved, best of
   the repeats. Target: 10,000 adds cost at most 15x 1,000 (linear growth is 10x; rebuilding the
   arrays on every add made it quadratic).

4. **One pushed body**: gym-pusht's T (mass 1, moment 3000 units^2, frictionless shapes) on a table of
   mu 0.3 (g = 5886 units/s^2), pushed 30 units off its axis by a kinematic disk of radius 15 at 10
   units/s (below mu g dt: where the coupled step matters), dt = 0.01 s, 150 steps of contact timed after
   20; ``pf.step`` with the coupled step (the default) against the split step (``scheme="split"``), and
   the coupled step on its public route (pymunk's Python arbiter API) beside its compiled one. Target:
   the coupled step at most 2x the split step.

The engine study (``python -m benchmarks.run --only engine``) runs all four and records study 3 in
``engine_plugin_adds.csv`` and study 4 in ``engine_plugin_push.csv``, the last two of its targets.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from .common import Target

DT = 1.0 / 120.0
STEPS = 120
MU = 0.05


def _bodies(space: Any, n: int) -> list[Any]:
    import pymunk

    rng = np.random.default_rng(7)
    side = int(math.ceil(math.sqrt(n)))
    out = []
    for i in range(n):
        b = pymunk.Body()
        b.position = (float(i % side), float(i // side))
        s = pymunk.Circle(b, 0.1) if i % 2 == 0 else pymunk.Poly.create_box(b, (0.2, 0.2))
        s.density = 1.0
        space.add(b, s)
        speed, ang = rng.uniform(0.5, 1.5), rng.uniform(0, 2 * math.pi)
        b.velocity = (speed * math.cos(ang), speed * math.sin(ang))
        b.angular_velocity = float(rng.uniform(2.0, 6.0))
        out.append(b)
    return out


def build(variant: str, n: int) -> Any:
    """A step function for ``variant`` ("bare", "tank", "plugin") with ``n`` bodies."""
    import pymunk

    from rrbody.engine import PlaneFriction

    space = pymunk.Space()
    bodies = _bodies(space, n)
    if variant == "bare":
        return lambda: space.step(DT)
    if variant == "tank":
        for b in bodies:
            ctrl = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            ctrl.position = b.position
            pivot = pymunk.PivotJoint(ctrl, b, (0, 0), (0, 0))
            pivot.max_bias = 0.0  # velocity-level only: a sliding-friction cap
            pivot.max_force = MU * b.mass * 9.81
            gear = pymunk.GearJoint(ctrl, b, 0.0, 1.0)
            gear.max_bias = 0.0
            gear.max_force = MU * b.mass * 9.81 * 0.08  # a torque cap (mean lever ~0.08 m)
            space.add(ctrl, pivot, gear)
        return lambda: space.step(DT)
    pf = PlaneFriction(space)
    for b in bodies:
        pf.add(b, mu=MU)
    pf.step(DT)  # first step: half kicks and the kernel's compilation, not timed
    return lambda: pf.step(DT)


def per_step(variants: list[str], n: int, repeats: int) -> dict[str, float]:
    """Best seconds per step of each variant, interleaved over ``repeats`` fresh builds."""
    best = {v: math.inf for v in variants}
    for _ in range(repeats):
        for v in variants:
            step = build(v, n)
            t0 = time.perf_counter()
            for _ in range(STEPS):
                step()
            best[v] = min(best[v], (time.perf_counter() - t0) / STEPS)
    return best


def many_bodies(ns: list[int], repeats: int) -> list[dict[str, Any]]:
    rows = []
    for n in ns:
        b = per_step(["bare", "tank", "plugin"], n, repeats)
        rows.append({"bodies": n, "bare_us": b["bare"] * 1e6, "tank_us": b["tank"] * 1e6,
                     "plugin_us": b["plugin"] * 1e6,
                     "tank_over_bare": b["tank"] / b["bare"], "plugin_over_tank": b["plugin"] / b["tank"],
                     "plugin_us_per_body": b["plugin"] * 1e6 / n})
        print(f"[engine/plugin] N={n}: bare {b['bare'] * 1e6:.1f} us, tank {b['tank'] * 1e6:.1f} us, "
              f"plugin {b['plugin'] * 1e6:.1f} us ({b['plugin'] / b['tank']:.2f}x tank)", flush=True)
    return rows


def phixtpm_step(repeats: int, steps: int = 5000) -> dict[str, float]:
    """Seconds per step: rrbody's phixtpm engine step and the same driven body in plain pymunk."""
    import pymunk

    from rrbody.engine import EngineSettings, attach
    from rrbody.model.scene import rod_mass_scene

    sc = rod_mass_scene(0.2, 0.05, 0.6, math.pi)
    dt = 1e-3

    def rr() -> Any:
        space = pymunk.Space()
        h = attach(space, sc, settings=EngineSettings(dt=dt))
        h.plane.step(dt)
        return lambda: h.plane.step(dt)

    def plain() -> Any:
        space = pymunk.Space()
        drv = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        drv.position = (1.0, 0.0)
        drv.velocity = (0.0, 0.6)
        m, l = 1.0, 0.2
        b = pymunk.Body(m, 1e-9 * m * l * l)
        b.position = (1.2, 0.0)
        b.velocity = (0.0, 0.6)
        joint = pymunk.PivotJoint(drv, b, (0.0, 0.0), (-l, 0.0))
        space.add(drv, b, joint)
        space.iterations = 10
        return lambda: space.step(dt)

    best = {"rrbody": math.inf, "plain": math.inf}
    for _ in range(repeats):
        for name, make in (("plain", plain), ("rrbody", rr)):
            step = make()
            t0 = time.perf_counter()
            for _ in range(steps):
                step()
            best[name] = min(best[name], (time.perf_counter() - t0) / steps)
    print(f"[engine/plugin] phixtpm step: rrbody {best['rrbody'] * 1e6:.2f} us, plain pymunk "
          f"{best['plain'] * 1e6:.2f} us ({best['rrbody'] / best['plain']:.2f}x)", flush=True)
    return best


def growth_slope(rows: list[dict[str, Any]]) -> float:
    """Least-squares slope of log(plugin cost) vs log(N): 1 is linear growth."""
    x = np.log([r["bodies"] for r in rows])
    y = np.log([r["plugin_us"] for r in rows])
    return float(np.polyfit(x, y, 1)[0])


#: the add/remove target: N adds may cost at most this many times the adds of N / 10 bodies (10x is linear)
ADDS_RATIO_MAX = 15.0


def _adds_once(n: int, seed: int) -> dict[str, float]:
    """Seconds of n ``pf.add`` calls, the first ``pf.step`` after them and n ``pf.remove`` calls."""
    import pymunk

    from rrbody.engine import PlaneFriction

    space = pymunk.Space()
    bodies = _bodies(space, n)
    pf = PlaneFriction(space)
    t0 = time.perf_counter()
    for b in bodies:
        pf.add(b, mu=MU)
    t1 = time.perf_counter()
    pf.step(DT)
    t2 = time.perf_counter()
    order = np.random.default_rng(seed).permutation(n)
    t3 = time.perf_counter()
    for k in order:
        pf.remove(bodies[k])
    t4 = time.perf_counter()
    return {"adds": t1 - t0, "first_step": t2 - t1, "removes": t4 - t3}


def add_scaling(ns: Sequence[int] = (1000, 10_000), repeats: int = 3) -> tuple[list[dict[str, Any]], Target]:
    """Study 3: best seconds of n adds, the first step and n removes for each n, interleaved over
    ``repeats`` fresh spaces; and the target (adds of the largest n over the smallest, <= 15x for 10x
    the bodies)."""
    _adds_once(100, 0)  # warm: the compiled kernels load, not timed
    best = {n: {"adds": math.inf, "first_step": math.inf, "removes": math.inf} for n in ns}
    for r in range(repeats):
        for n in ns:
            for k, v in _adds_once(n, r).items():
                best[n][k] = min(best[n][k], v)
    n0 = ns[0]
    rows = [{"bodies": n, "adds_s": b["adds"], "us_per_add": b["adds"] / n * 1e6, "first_step_s": b["first_step"],
             "removes_s": b["removes"], "us_per_remove": b["removes"] / n * 1e6,
             "adds_ratio": b["adds"] / best[n0]["adds"], "removes_ratio": b["removes"] / best[n0]["removes"]}
            for n, b in best.items()]
    for r in rows:
        print(f"[engine/plugin] {r['bodies']} adds {r['adds_s']:.3f} s ({r['us_per_add']:.0f} us each, "
              f"{r['adds_ratio']:.2f}x {n0}), first step {r['first_step_s'] * 1e3:.1f} ms, removes "
              f"{r['removes_s'] * 1e3:.1f} ms ({r['removes_ratio']:.2f}x)", flush=True)
    top = rows[-1]
    want = ADDS_RATIO_MAX * (top["bodies"] / n0) / 10.0
    target = Target(f"PlaneFriction: {top['bodies']:,} adds one by one vs {n0:,}", f"<= {want:g}x",
                    f"{top['adds_ratio']:.2f}x ({top['adds_s']:.3g} s vs {rows[0]['adds_s']:.3g} s; removes "
                    f"{top['removes_ratio']:.2f}x)", top["adds_ratio"] <= want,
                    f"best of {repeats}, interleaved; half circles, half boxes")
    return rows, target


PUSH_STEPS, PUSH_WARM = 150, 20
PUSHED_MAX = 2.0  # the coupled step's cost over the split step's, for one pushed body


def _pushed(variant: str) -> Any:
    """Study 4's space: the T pushed by the disk, warmed up ``PUSH_WARM`` steps into its contact."""
    import pymunk

    from rrbody.engine.plugin.coupling import Coupling
    from rrbody.envs.pusht import tee_body
    from rrbody.plugin import PlaneFriction

    space = pymunk.Space()
    body, _ = tee_body(space)
    agent = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    agent.position = (286.0, 284.5)
    space.add(agent, pymunk.Circle(agent, 15.0))
    agent.velocity = (0.0, 10.0)
    pf = PlaneFriction(space, g=5886.0, scheme="split" if variant == "split" else "coupled")
    if variant == "coupled, public route":
        pf._coupling = Coupling(space, route="public")  # (the benchmark's choice of route)
    pf.add(body, mu=0.3)
    for _ in range(PUSH_WARM):
        pf.step(0.01)
    return pf


def pushed_body(repeats: int) -> tuple[dict[str, float], Target]:
    """Study 4: us per ``pf.step`` of each variant (best of ``repeats`` fresh spaces, interleaved) and the
    target."""
    variants = ["split", "coupled", "coupled, public route"]
    for v in variants:  # warm: the compiled kernels load, not timed
        _pushed(v).step(0.01)
    best = {v: math.inf for v in variants}
    for _ in range(repeats):
        for v in variants:
            pf = _pushed(v)
            t0 = time.perf_counter()
            for _ in range(PUSH_STEPS):
                pf.step(0.01)
            best[v] = min(best[v], (time.perf_counter() - t0) / PUSH_STEPS)
    us = {v: b * 1e6 for v, b in best.items()}
    ratio = us["coupled"] / us["split"]
    print("[engine/plugin] one pushed body, us per pf.step: " + ", ".join(f"{v} {u:.2f}" for v, u in us.items()),
          flush=True)
    target = Target("one pushed body (gym-pusht's T pushed at 10 units/s, dt 0.01 s): pf.step coupled vs split",
                    f"<= {PUSHED_MAX:g}x", f"{ratio:.2f}x ({us['coupled']:.2f} vs {us['split']:.2f} us per step; "
                    f"the coupled step on the public route {us['coupled, public route']:.2f} us)",
                    ratio <= PUSHED_MAX, f"best of {repeats} fresh spaces x {PUSH_STEPS} steps, interleaved")
    return us, target
