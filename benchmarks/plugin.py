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
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

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
        rows.append({"bodies": n, "bare_us": b["bare"] * 1e6, "tank_us": b["tank"] * 1e6, "plugin_us": b["plugin"] * 1e6,
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
