"""Contacts: what pressure profiles, static friction and a tilted plane cost in the plugin.

Every figure is the cost of ``PlaneFriction.step`` (the friction kernel, pymunk's bulk read and
write, then ``space.step``), wall clock. Ratios come from one run: the variants are interleaved
(each repeat times every variant in turn on a freshly built space) and each variant keeps its best
repeat (noise on a shared machine only ever adds time). The first ``pf.step`` of every space (the
pass over newly added bodies and, once per process, loading the compiled kernels) is made before
the timed steps unless a row says it times that step. The machine is stated in the section.

1. **Pressure profiles** (target: a radial profile or feet cost at most 2x a uniform body per step):
   N = 1,000 disks (R = 0.1 m, density 2) on a grid 4 m apart in one collision group (no contacts
   ever), launched sliding (1-3 m/s) and spinning (5-20 rad/s), mu = 0.05, g = 9.81, dt = 1e-3 s,
   300 timed steps; one space per pressure: uniform, ring(0.1), annulus(0.05, 0.1), hertz(0.1), three
   feet at 0.06 m from the centre (1/3 each). The annulus is reported, not judged: it is a uniform
   disk minus a uniform disk by construction (two exact disk terms).
2. **Static friction where nothing sticks** (target: at most 10 % on the step): the sliding disks of 1
   with uniform pressure, mu_static = mu (the default: static friction is always on for dry bodies)
   against mu_static = 2 mu (same cost expected: the static code runs only for a body at rest) and
   against static friction switched off through the plugin's package-internal ``add_footprint(..., static=0.0)`` (the
   builder's path; no public switch exists). The per-step cost is quoted beside the plugin figure
   recorded by the engine study in ``engine_plugin.csv`` (an earlier run: quoted, not divided), and
   that scene (benchmarks/plugin.py: half circles, half boxes, dt = 1/120 s) is measured again now.
3. **Held on a tilt** (target: 1,000 bodies with static friction on a tilt still step in one
   compiled call): 1,000 disks released at rest on a plane tilted atan(0.3), mu = 0.4, mu_static =
   0.5 (held: 0.3 < 0.5). Timed: the first ``pf.step`` after the adds (the pass over new bodies and
   every body's limit-surface test), later steps (the held load is cached: no test), and steps in
   which every body's load is new (a small extra force, 0.5 m/s^2 across the slope, set on every
   body before the step and gone after it: every body runs the limit-surface test again, still
   held). Checked: positions and angles bit-identical and velocities exactly zero after the run;
   the compiled step is called once per ``pf.step`` and the plugin's per-body bookkeeping in Python
   is never entered; the number of Python-level calls (``sys.setprofile``) made by one ``pf.step``
   is the same for 1,000 bodies as for 10.
4. **One body**: ``pf.step`` with one disk under each pressure (the fixed cost per step dominates).
5. **Break-away**: 1,000 boxes (0.2 x 0.2 m) at rest on a plane tilted atan(0.8) > mu_static = 0.5:
   all break away in the first step. Timed: that first ``pf.step`` after the adds; the same
   break-away in a step after one held step (in the held step a force on every body cancels the
   slope's pull, so the pass over new bodies is out of the timed step); the same boxes on
   atan(0.3), held, in a step with a new load; and the sliding steps after the break-away.

``python -m benchmarks.run --only contacts`` writes ``contacts.csv`` (one row per measurement) and the
section below; ``--quick`` uses 100 bodies and fewer steps and repeats (a smoke run of seconds).
"""

from __future__ import annotations

import csv
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, write_csv

NAME = "contacts"
TITLE = "Contacts: pressure profiles, static friction, tilt"

DT = 1e-3
G = 9.81
MU = 0.05  # sliding scenes: weak friction, every body keeps moving through the timed steps
RADIUS = 0.1
DENSITY = 2.0
SPACING = 4.0  # m between grid points: no two bodies come near each other (and one collision group)
FOOT = 0.06  # m: the three feet's distance from the centre
PROFILES = ("uniform", "ring", "annulus", "hertz", "points")
PROFILE_TEXT = {"uniform": "uniform", "ring": "ring(0.1)", "annulus": "annulus(0.05, 0.1)", "hertz": "hertz(0.1)",
                "points": f"3 feet at {FOOT:g} m (1/3 each)"}
JUDGED = ("ring", "hertz", "points")  # target 1; the annulus is two uniform disks by construction
PROFILE_RATIO_MAX = 2.0
STATIC_RATIO_MAX = 1.10
# the tilted scenes
TILT_HELD = math.atan(0.3)
TILT_BREAK = math.atan(0.8)
MU_T, MUS_T = 0.4, 0.5
NUDGE = 0.5  # m/s^2 across the slope: a new load that static friction still holds

COLUMNS = ["part", "scene", "variant", "bodies", "steps", "repeats", "us_per_step", "us_per_body_step", "ratio",
           "ratio_to", "check", "note"]


# ---- scenes ------------------------------------------------------------------------------------
def _pressure(kind: str) -> Any:
    from rrbody import pressure as rp

    if kind == "uniform":
        return rp.uniform()
    if kind == "ring":
        return rp.ring(RADIUS)
    if kind == "annulus":
        return rp.annulus(0.05, RADIUS)
    if kind == "hertz":
        return rp.hertz(RADIUS)
    if kind == "points":
        c = 0.5 * math.sqrt(3.0)
        return rp.points([(FOOT, 0.0, 1 / 3), (-0.5 * FOOT, c * FOOT, 1 / 3), (-0.5 * FOOT, -c * FOOT, 1 / 3)])
    raise ValueError(kind)


def _scene(n: int, kind: str = "uniform", *, mu: float = MU, mu_static: float | None = None, tilt: float = 0.0,
           box: bool = False, moving: bool = True, static_off: bool = False, seed: int = 11) -> tuple[Any, Any,
                                                                                                      list[Any]]:
    """A space with ``n`` bodies on a grid, in the plugin: disks (or boxes), sliding and spinning
    (``moving``) or at rest; ``static_off`` adds them through the plugin's package-internal ``add_footprint`` with no
    static friction (STATIC_COEFF 0)."""
    import pymunk

    from rrbody.engine import PlaneFriction

    rng = np.random.default_rng(seed)
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G, tilt=tilt)
    side = int(math.ceil(math.sqrt(n)))
    group = pymunk.ShapeFilter(group=1)  # shapes of one group never collide
    bodies = []
    for i in range(n):
        b = pymunk.Body()
        b.position = (SPACING * (i % side), SPACING * (i // side))
        s = pymunk.Poly.create_box(b, (2 * RADIUS, 2 * RADIUS)) if box else pymunk.Circle(b, RADIUS)
        s.density = DENSITY
        s.filter = group
        space.add(b, s)
        if moving:
            speed, ang = rng.uniform(1.0, 3.0), rng.uniform(0.0, 2 * math.pi)
            b.velocity = (speed * math.cos(ang), speed * math.sin(ang))
            b.angular_velocity = float(rng.uniform(5.0, 20.0) * rng.choice([-1.0, 1.0]))
        bodies.append(b)
    pressure = _pressure(kind)
    if static_off:
        from rrbody.contact import kernel as K
        from rrbody.engine.plugin.shapes import body_footprint

        for b in bodies:
            pf.add_footprint(b, law=K.LAW_DRY, coeff=mu * pf.g * math.cos(pf.tilt),
                             footprint=body_footprint(b, pressure), snap=True, history=None, static=0.0)
    else:
        for b in bodies:
            pf.add(b, mu=mu, pressure=pressure, mu_static=mu_static)
    return space, pf, bodies


def _steps(pf: Any, steps: int, dt: float = DT) -> float:
    """Seconds per ``pf.step`` over ``steps`` consecutive steps."""
    t0 = time.perf_counter()
    for _ in range(steps):
        pf.step(dt)
    return (time.perf_counter() - t0) / steps


def _one(pf: Any, dt: float = DT) -> float:
    t0 = time.perf_counter()
    pf.step(dt)
    return time.perf_counter() - t0


def _sliding(bodies: list[Any]) -> int:
    """How many bodies still slide and spin (neither velocity nor spin zero)."""
    return sum(1 for b in bodies if b.velocity.length > 0.0 and b.angular_velocity != 0.0)


def _state(bodies: list[Any]) -> list[tuple[float, ...]]:
    return [(b.position.x, b.position.y, b.angle) for b in bodies]


def _at_rest(bodies: list[Any], start: list[tuple[float, ...]]) -> bool:
    """Positions and angles bit-identical to ``start``, velocities and spins exactly zero."""
    return _state(bodies) == start and all(b.velocity.x == 0.0 and b.velocity.y == 0.0 and b.angular_velocity == 0.0
                                           for b in bodies)


def _push(bodies: list[Any], fx_per_kg: float, fy_per_kg: float) -> None:
    """A force on every body for the next step only (pymunk resets forces after a step)."""
    for b in bodies:
        b.force = (fx_per_kg * b.mass, fy_per_kg * b.mass)


def _warm() -> None:
    """Load the compiled kernels (and compile them if the cache is stale) for every path timed: not timed."""
    for kind in PROFILES:
        _, pf, _ = _scene(4, kind)
        _steps(pf, 3)
    for box in (False, True):
        for tilt in (TILT_HELD, TILT_BREAK):
            _, pf, _ = _scene(4, mu=MU_T, mu_static=MUS_T, tilt=tilt, box=box, moving=False)
            _steps(pf, 3)
    try:
        _, pf, _ = _scene(4, static_off=True)
        _steps(pf, 3)
    except Exception:  # noqa: BLE001 - the internal path is optional (reported as not measured)
        pass


# ---- 1 and 4: pressure profiles ----------------------------------------------------------------
def profiles(n: int, steps: int, reps: int) -> dict[str, dict[str, float]]:
    """Best seconds per step of each pressure profile with ``n`` sliding disks, interleaved."""
    best = {k: math.inf for k in PROFILES}
    still = {k: n for k in PROFILES}
    for r in range(reps):
        for kind in PROFILES:
            _, pf, bodies = _scene(n, kind, seed=11 + r)
            pf.step(DT)  # the first step (pass over the new bodies): not timed
            best[kind] = min(best[kind], _steps(pf, steps))
            still[kind] = min(still[kind], _sliding(bodies))
    return {k: {"s": best[k], "ratio": best[k] / best["uniform"], "sliding": still[k]} for k in PROFILES}


# ---- 2: static friction where nothing sticks ---------------------------------------------------
def static_moving(n: int, steps: int, reps: int) -> dict[str, dict[str, Any]]:
    """Best seconds per step of the sliding uniform disks: mu_static = mu, 2 mu, static off (internal
    path), and the engine study's plugin scene; interleaved."""
    from . import plugin as plugin_study

    makers: dict[str, Callable[[int], tuple[Any, Any, list[Any]]]] = {
        "mu_s = mu": lambda s: _scene(n, seed=s),
        "mu_s = 2 mu": lambda s: _scene(n, mu_static=2 * MU, seed=s),
        "static off": lambda s: _scene(n, static_off=True, seed=s),
    }
    best: dict[str, float] = {k: math.inf for k in makers}
    still = {k: n for k in makers}
    err: dict[str, str] = {}
    eng = math.inf
    for r in range(reps):
        for k, make in makers.items():
            if k in err:
                continue
            try:
                _, pf, bodies = make(11 + r)
            except Exception as e:  # noqa: BLE001 - only the internal path can fail (an interface change)
                err[k] = f"{type(e).__name__}: {e}"
                continue
            pf.step(DT)
            best[k] = min(best[k], _steps(pf, steps))
            still[k] = min(still[k], _sliding(bodies))
        step = plugin_study.build("plugin", n)  # its first step is made inside build
        t0 = time.perf_counter()
        for _ in range(plugin_study.STEPS):
            step()
        eng = min(eng, (time.perf_counter() - t0) / plugin_study.STEPS)
    out: dict[str, dict[str, Any]] = {k: {"s": best[k], "sliding": still[k], "error": err.get(k, "")} for k in makers}
    out["engine scene"] = {"s": eng, "sliding": None, "error": ""}
    return out


def recorded_plugin(out: Path, n: int) -> tuple[dict[str, float] | None, str]:
    """The plugin's per-step cost recorded by the engine study (engine_plugin.csv) for ``n`` bodies
    (or the largest recorded), and where it was read: ``out`` first, then benchmarks/results."""
    for folder in (out, Path(__file__).resolve().parent / "results"):
        path = folder / "engine_plugin.csv"
        if not path.exists():
            continue
        try:
            with open(path, newline="") as fh:
                rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]
        except (OSError, ValueError, KeyError, TypeError):
            continue
        rows = [r for r in rows if "bodies" in r and "plugin_us" in r]
        if not rows:
            continue
        row = next((r for r in rows if int(r["bodies"]) == n), max(rows, key=lambda r: r["bodies"]))
        stamp = time.strftime("%Y-%m-%d %H:%M", time.localtime(path.stat().st_mtime))
        return row, f"{path} (written {stamp})"
    return None, "no engine_plugin.csv found"


# ---- 3: held on a tilt -------------------------------------------------------------------------
def held(n: int, steps: int, reps: int, fresh_loads: int) -> dict[str, Any]:
    """Best seconds of the first step, of later (cached) steps and of steps with a new load for ``n``
    disks held at rest on the tilt; and whether every body stayed exactly at rest in every repeat."""
    best = {"first": math.inf, "later": math.inf, "new_load": math.inf}
    still = True
    for _ in range(reps):
        _, pf, bodies = _scene(n, mu=MU_T, mu_static=MUS_T, tilt=TILT_HELD, moving=False)
        start = _state(bodies)
        best["first"] = min(best["first"], _one(pf))
        best["later"] = min(best["later"], _steps(pf, steps))
        for k in range(fresh_loads):
            _push(bodies, 0.0, NUDGE if k % 2 == 0 else -NUDGE)  # untimed: sets the load of the next step
            best["new_load"] = min(best["new_load"], _one(pf))
            best["new_load"] = min(best["new_load"], _one(pf))  # the slope's pull alone again: new as well
        still = still and _at_rest(bodies, start)
    return {**best, "at_rest": still}


def one_call(n: int, steps: int, small: int = 10) -> dict[str, Any]:
    """Target 3's evidence on the held scene: compiled-step calls per ``pf.step`` and entries into the
    plugin's per-body Python bookkeeping (``_rest``) over ``steps`` steps, and the Python-level calls
    (``sys.setprofile`` events 'call' and 'c_call') one ``pf.step`` makes with ``n`` and ``small`` bodies."""
    res: dict[str, Any] = {"kernel_calls_per_step": None, "rest_entries": None, "note": ""}
    _, pf, bodies = _scene(n, mu=MU_T, mu_static=MUS_T, tilt=TILT_HELD, moving=False)
    start = _state(bodies)
    pf.step(DT)
    pf.step(DT)  # (the first step, with its half kicks, takes the separate calls; the second finds the one call's)
    try:  # internal attributes: the counting is skipped (and said) if they were renamed
        from rrbody.contact import kernel as K
        from rrbody.engine.memory import structio

        calls = [0, 0]
        kernel, entry, rest = K.plane_step, structio.struct_step, pf._rest

        def counted(*a: Any) -> Any:
            calls[0] += 1
            return kernel(*a)

        def counted_entry(*a: Any) -> Any:  # the struct route's one call (read, step, write), where it is taken
            calls[0] += 1
            return entry(*a)

        def counted_rest(dt: float) -> None:
            calls[1] += 1
            rest(dt)

        K.plane_step, structio.struct_step, pf._rest = counted, counted_entry, counted_rest
        pf._plan = None  # the steady step holds the one call: the next step plans it again, counted
        try:
            _steps(pf, steps)
        finally:
            K.plane_step, structio.struct_step, pf._rest = kernel, entry, rest
            pf._plan = None
        res["kernel_calls_per_step"] = calls[0] / steps
        res["rest_entries"] = calls[1]
    except AttributeError as e:
        res["note"] = f"call count not made ({e})"

    def py_calls(pf_: Any) -> int:
        count = [0]

        def prof(frame: Any, event: str, arg: Any) -> None:
            if event in ("call", "c_call"):
                count[0] += 1

        pf_.step(DT)  # (unprofiled: the step after a change makes the steady step's arguments again)
        sys.setprofile(prof)
        try:
            pf_.step(DT)
        finally:
            sys.setprofile(None)
        return count[0]

    res["py_calls_n"] = py_calls(pf)
    _, pf_small, _ = _scene(small, mu=MU_T, mu_static=MUS_T, tilt=TILT_HELD, moving=False)
    _steps(pf_small, 3)
    res["py_calls_small"] = py_calls(pf_small)
    res["small"] = small
    res["at_rest"] = _at_rest(bodies, start)
    return res


# ---- 4: one body -------------------------------------------------------------------------------
def one_body(steps: int, reps: int) -> dict[str, float]:
    """Best seconds per step of one sliding disk under each pressure, interleaved."""
    best = {k: math.inf for k in PROFILES}
    for _ in range(reps):
        for kind in PROFILES:
            _, pf, bodies = _scene(1, kind)
            bodies[0].velocity = (2.5, 0.5)  # slides and spins through all timed steps
            bodies[0].angular_velocity = 15.0
            pf.step(DT)
            best[kind] = min(best[kind], _steps(pf, steps))
    return best


# ---- 5: break-away -----------------------------------------------------------------------------
def breakaway(n: int, reps: int, slide_steps: int) -> dict[str, Any]:
    """Best seconds of the break-away step of ``n`` boxes (first step after the adds, and after one held
    step), of a held step with a new load for the same boxes on the gentler tilt, and of the sliding
    steps after; whether all boxes broke away and the held ones stayed at rest."""
    best = {"first": math.inf, "after_held": math.inf, "held_new_load": math.inf, "sliding": math.inf}
    broke = True
    kept = True
    pull = G * math.sin(TILT_BREAK)  # along downhill = +x
    for _ in range(reps):
        # (a) the first step after the adds
        _, pf, bodies = _scene(n, mu=MU_T, mu_static=MUS_T, tilt=TILT_BREAK, box=True, moving=False)
        best["first"] = min(best["first"], _one(pf))
        broke = broke and all(b.velocity.x > 0.0 for b in bodies)
        best["sliding"] = min(best["sliding"], _steps(pf, slide_steps))
        # (b) one held step (a force cancelling the slope's pull), then the break-away step
        _, pf, bodies = _scene(n, mu=MU_T, mu_static=MUS_T, tilt=TILT_BREAK, box=True, moving=False)
        start = _state(bodies)
        _push(bodies, -pull, 0.0)
        pf.step(DT)
        kept = kept and _at_rest(bodies, start)
        best["after_held"] = min(best["after_held"], _one(pf))
        broke = broke and all(b.velocity.x > 0.0 for b in bodies)
        # (c) the same boxes held on the gentler tilt, a step with a new load
        _, pf, bodies = _scene(n, mu=MU_T, mu_static=MUS_T, tilt=TILT_HELD, box=True, moving=False)
        start = _state(bodies)
        _push(bodies, 0.0, NUDGE)
        pf.step(DT)
        best["held_new_load"] = min(best["held_new_load"], _one(pf))
        kept = kept and _at_rest(bodies, start)
    return {**best, "all_broke": broke, "held_kept": kept}


# ---- the study ---------------------------------------------------------------------------------
def _us(x: float) -> float | int:
    """Microseconds for a table cell: whole numbers from 1,000 up (fmt would print 4.24e+03)."""
    return int(round(x)) if math.isfinite(x) and x >= 1000.0 else x


def run(out: Path, *, quick: bool = False) -> StudyResult:
    for mod in ("pymunk", "rrbody.engine", "rrbody.model.pressure"):
        ok, why = module_available(mod)
        if not ok:
            print(f"[contacts] skipped: {mod} not importable ({why})", flush=True)
            return StudyResult(NAME, TITLE, skipped=f"{mod} not importable ({why})")
    t0 = time.perf_counter()
    n = 100 if quick else 1000
    steps = 50 if quick else 300
    reps = 3 if quick else 9
    one_steps = 200 if quick else 1000
    loads = 3 if quick else 10
    slide = 20 if quick else 100
    print(f"[contacts] N = {n}, {steps} steps x best of {reps} (warming the kernels first)", flush=True)
    _warm()
    rows: list[dict[str, Any]] = []
    us = 1e6

    def row(part: str, scene: str, variant: str, bodies: int, nsteps: int, s: float, ratio: float | None = None,
            ratio_to: str = "", check: str = "", note: str = "", repeats: int = reps) -> None:
        rows.append({"part": part, "scene": scene, "variant": variant, "bodies": bodies, "steps": nsteps,
                     "repeats": repeats, "us_per_step": s * us, "us_per_body_step": s * us / bodies,
                     "ratio": ratio, "ratio_to": ratio_to, "check": check, "note": note})

    # 1. profiles
    prof = profiles(n, steps, reps)
    for k in PROFILES:
        p = prof[k]
        row("profiles", f"{n} sliding disks", PROFILE_TEXT[k], n, steps, p["s"], p["ratio"], "uniform",
            f"{p['sliding']}/{n} still sliding and spinning",
            "two uniform disks by construction: reported, not judged" if k == "annulus" else "")
        print(f"[contacts] {PROFILE_TEXT[k]}: {p['s'] * us:.1f} us/step ({p['s'] * us / n:.3f} us/body), "
              f"{p['ratio']:.2f}x uniform", flush=True)
    # 2. static friction, nothing sticks
    st = static_moving(n, steps, reps)
    base = st["mu_s = mu"]["s"]
    for k in ("mu_s = mu", "mu_s = 2 mu", "static off"):
        v = st[k]
        if v["error"]:
            row("static_moving", f"{n} sliding disks, uniform", k, n, steps, math.nan,
                note=f"not measured: {v['error']}")
            continue
        ratio = base / v["s"] if k != "mu_s = mu" else 1.0
        row("static_moving", f"{n} sliding disks, uniform", k, n, steps, v["s"], ratio,
            "mu_s = mu over this" if k != "mu_s = mu" else "", f"{v['sliding']}/{n} still sliding and spinning",
            "package-internal add_footprint(static=0.0): no public switch" if k == "static off" else "")
    from . import plugin as plugin_study

    eng = st["engine scene"]["s"]
    row("static_moving", "engine study scene (half circles, half boxes, dt 1/120 s, mu 0.05)", "measured now", n,
        plugin_study.STEPS, eng)
    rec, rec_where = recorded_plugin(out, n)
    if rec is not None:
        rows.append({"part": "static_moving",
                     "scene": "engine study scene (half circles, half boxes, dt 1/120 s, mu 0.05)",
                     "variant": "recorded earlier", "bodies": int(rec["bodies"]), "steps": plugin_study.STEPS,
                     "repeats": None, "us_per_step": rec["plugin_us"],
                     "us_per_body_step": rec["plugin_us"] / rec["bodies"],
                     "ratio": None, "ratio_to": "", "check": "", "note": f"from an earlier run: {rec_where}"})
    off = st["static off"]
    r_off = base / off["s"] if not off["error"] else math.nan
    r_2mu = base / st["mu_s = 2 mu"]["s"]
    print(f"[contacts] static, nothing sticks: mu_s=mu {base * us:.1f} us/step, x{r_2mu:.3f} of mu_s=2mu, "
          f"x{r_off:.3f} of static off; engine scene now {eng * us:.1f} us", flush=True)
    # 3. held on a tilt
    h = held(n, steps, reps, loads)
    oc = one_call(n, min(steps, 100))
    held_scene = f"{n} disks held on tilt atan(0.3), mu 0.4, mu_s 0.5"
    row("tilt_held", held_scene, "first pf.step after the adds", n, 1, h["first"],
        note="includes the pass over newly added bodies; every body's limit-surface test")
    row("tilt_held", held_scene, "step with a new load on every body", n, 1, h["new_load"], h["new_load"] / h["later"],
        "cached steps", note=f"every body's limit-surface test; best of {reps} x {2 * loads} single steps")
    row("tilt_held", held_scene, "later steps (held load cached)", n, steps, h["later"],
        check=f"bit-identical positions and angles, zero velocities: {'yes' if h['at_rest'] else 'NO'}")
    calls_ok = oc["kernel_calls_per_step"] == 1.0 and oc["rest_entries"] == 0
    row("tilt_held", held_scene, "compiled calls per pf.step", n, min(steps, 100), math.nan,
        check=(f"{fmt(oc['kernel_calls_per_step'])} compiled-step call(s) per pf.step, per-body bookkeeping entered "
               f"{oc['rest_entries']} times; Python-level calls in one pf.step: {oc['py_calls_n']} ({n} bodies) vs "
               f"{oc['py_calls_small']} ({oc['small']} bodies)"), note=oc["note"], repeats=1)
    print(f"[contacts] held on tilt: first {h['first'] * us / n:.3f} us/body, new load {h['new_load'] * us / n:.3f}, "
          f"cached {h['later'] * us / n:.3f}; at rest {h['at_rest']}; calls/step {oc['kernel_calls_per_step']}, "
          f"rest entries {oc['rest_entries']}, py calls {oc['py_calls_n']} vs {oc['py_calls_small']}", flush=True)
    # 4. one body
    ob = one_body(one_steps, reps)
    for k in PROFILES:
        row("one_body", "1 sliding disk", PROFILE_TEXT[k], 1, one_steps, ob[k], ob[k] / ob["uniform"], "uniform")
    print("[contacts] one body: " + ", ".join(f"{k} {ob[k] * us:.2f} us" for k in PROFILES), flush=True)
    # 5. break-away
    ba = breakaway(n, reps, slide)
    bscene = f"{n} boxes 0.2 x 0.2 m, mu 0.4, mu_s 0.5"
    row("breakaway", bscene + ", tilt atan(0.8)", "first pf.step after the adds: all break away", n, 1, ba["first"],
        check=f"all broke away: {'yes' if ba['all_broke'] else 'NO'}", note="includes the pass over newly added bodies")
    row("breakaway", bscene + ", tilt atan(0.8)", "break-away step after one held step", n, 1, ba["after_held"],
        ba["after_held"] / ba["held_new_load"], "held, new load")
    row("breakaway", bscene + ", tilt atan(0.3)", "held, new load", n, 1, ba["held_new_load"],
        check=f"held boxes stayed exactly at rest: {'yes' if ba['held_kept'] else 'NO'}")
    row("breakaway", bscene + ", tilt atan(0.8)", "sliding steps after the break-away", n, slide, ba["sliding"])
    print(f"[contacts] break-away: first step {ba['first'] * us / n:.3f} us/body, after a held step "
          f"{ba['after_held'] * us / n:.3f}, held new load {ba['held_new_load'] * us / n:.3f}, sliding "
          f"{ba['sliding'] * us / n:.3f}; all broke {ba['all_broke']}", flush=True)

    files = [str(write_csv(out / "contacts.csv", rows, COLUMNS))]

    # ---- targets ----
    worst = max(JUDGED, key=lambda k: prof[k]["ratio"])
    all_sliding = all(prof[k]["sliding"] == n for k in PROFILES)
    t1 = Target(f"radial profile or feet vs uniform, per plugin step ({n:,} sliding disks)",
                f"<= {PROFILE_RATIO_MAX:g}x (ring, hertz, points)",
                ", ".join(f"{k} {prof[k]['ratio']:.2f}x" for k in JUDGED)
                + f" (annulus {prof['annulus']['ratio']:.2f}x, reported only: two uniform disks); uniform "
                  f"{fmt(prof['uniform']['s'] * us / n)} us per body (since the active-matter work the uniform disk, "
                  "the ring "
                  f"and the Hertz patch read their disk tables: ring {fmt(prof['ring']['s'] * us / n)} us per "
                  f"body; the feet stay exact, in the same loop; before, stepped after the others: 3.29x)",
                all(prof[k]["ratio"] <= PROFILE_RATIO_MAX for k in JUDGED) and all_sliding,
                f"worst {worst}; interleaved, best of {reps} x {steps} steps"
                + ("" if all_sliding else "; some bodies stopped during the timed steps"))
    same_2mu = 1 / STATIC_RATIO_MAX <= r_2mu <= STATIC_RATIO_MAX
    met2 = same_2mu and (math.isnan(r_off) or r_off <= STATIC_RATIO_MAX)
    rec_txt = (f"; engine-study scene now {fmt(eng * us / n)} us per body, recorded earlier "
               f"{fmt(rec['plugin_us'] / rec['bodies'])} us per body ({int(rec['bodies'])} bodies; an earlier run, "
               "not a ratio)"
               if rec is not None else "; no earlier plugin figure recorded")
    t2 = Target(f"static friction in a step where nothing sticks ({n:,} sliding disks)",
                f"<= {STATIC_RATIO_MAX:.2f}x",
                (f"mu_s = mu vs static off {r_off:.3f}x; " if not math.isnan(r_off) else "static off not measured; ")
                + f"mu_s = mu vs mu_s = 2 mu {r_2mu:.3f}x ({fmt(base * us / n)} us per body){rec_txt}",
                met2, "static off through the plugin's package-internal add_footprint(static=0.0) (no public switch); "
                      f"interleaved, best of {reps}")
    t3 = Target(f"{n:,} bodies held by static friction on a tilt step in one compiled call",
                "1 compiled call per pf.step, no per-body Python",
                f"{fmt(oc['kernel_calls_per_step'])} call per step, per-body bookkeeping entered {oc['rest_entries']} "
                f"times, {oc['py_calls_n']} Python-level calls per step ({oc['py_calls_small']} with {oc['small']} "
                f"bodies); {fmt(h['later'] * us)} us per step ({fmt(h['later'] * us / n)} us per body) held, "
                f"{fmt(h['new_load'] * us / n)} us per body with a new load",
                (calls_ok and oc["py_calls_n"] == oc["py_calls_small"]) if oc["kernel_calls_per_step"] is not None
                else None,
                oc["note"] or "tilt atan(0.3), mu 0.4, mu_s 0.5, released at rest")
    t4 = Target(f"{n:,} bodies held on a tilt stay exactly at rest", "bit-identical positions, zero velocities",
                f"{'yes' if h['at_rest'] and oc['at_rest'] else 'no'} after {1 + steps + 2 * loads} steps x {reps} "
                f"repeats (incl. {2 * loads} steps with a new load)", h["at_rest"] and oc["at_rest"])
    targets = [t1, t2, t3, t4]

    # ---- Markdown ----
    prow = [(PROFILE_TEXT[k], _us(prof[k]["s"] * us), prof[k]["s"] * us / n, prof[k]["ratio"],
             f"{prof[k]['sliding']}/{n}",
             "reported only (two uniform disks)" if k == "annulus"
             else ("judged: <= 2x" if k in JUDGED else "baseline"))
            for k in PROFILES]
    srow = [(k, _us(st[k]["s"] * us) if not st[k]["error"] else math.nan,
             st[k]["s"] * us / n if not st[k]["error"] else math.nan,
             (base / st[k]["s"] if k != "mu_s = mu" else 1.0) if not st[k]["error"] else math.nan,
             f"{st[k]['sliding']}/{n}" if not st[k]["error"] else f"not measured: {st[k]['error']}")
            for k in ("mu_s = mu", "mu_s = 2 mu", "static off")]
    trow = [("held: first pf.step after the adds", n, _us(h["first"] * us), h["first"] * us / n,
             "pass over new bodies + every body's limit-surface test"),
            ("held: step with a new load on every body", n, _us(h["new_load"] * us), h["new_load"] * us / n,
             f"every body's limit-surface test ({h['new_load'] / h['later']:.1f}x a cached step)"),
            ("held: later steps (load cached)", n, _us(h["later"] * us), h["later"] * us / n,
             "check: positions bit-identical, velocities zero: " + ("yes" if h["at_rest"] else "NO")),
            ("held: compiled calls per pf.step", n, math.nan, math.nan,
             f"check: {fmt(oc['kernel_calls_per_step'])} per step; per-body Python entered {oc['rest_entries']} "
             f"times; {oc['py_calls_n']} Python-level calls per step ({oc['py_calls_small']} with {oc['small']} "
             "bodies)"),
            ("boxes: first pf.step after the adds, all break away (tilt atan(0.8))", n, _us(ba["first"] * us),
             ba["first"] * us / n, "check: all broke away: " + ("yes" if ba["all_broke"] else "NO")),
            ("boxes: break-away step after one held step", n, _us(ba["after_held"] * us), ba["after_held"] * us / n,
             f"{ba['after_held'] / ba['held_new_load']:.2f}x the held new-load step"),
            ("boxes: held on atan(0.3), new load", n, _us(ba["held_new_load"] * us), ba["held_new_load"] * us / n,
             "check: stayed at rest: " + ("yes" if ba["held_kept"] else "NO")),
            ("boxes: sliding after the break-away", n, _us(ba["sliding"] * us), ba["sliding"] * us / n,
             f"{slide} steps")]
    orow = [(PROFILE_TEXT[k], ob[k] * us, ob[k] / ob["uniform"]) for k in PROFILES]
    rec_line = (f"Recorded earlier (not this run; {rec_where}): the plugin on the engine study's scene (half circles, "
                f"half boxes, dt = 1/120 s, mu = 0.05), {int(rec['bodies'])} bodies: {fmt(rec['plugin_us'])} us per "
                f"step ({fmt(rec['plugin_us'] / rec['bodies'])} us per body). The same scene measured now: "
                f"{fmt(eng * us)} us per step ({fmt(eng * us / n)} us per body) with {n} bodies. Different runs: "
                f"quoted side by side, not divided."
                if rec is not None else f"No earlier plugin figure recorded ({rec_where}); the engine study's scene "
                f"measured now: {fmt(eng * us)} us per step with {n} bodies.")
    md = [f"## {TITLE}", "", machine_text(), "",
          f"Every time is one `PlaneFriction.step` (friction kernel, pymunk's bulk read/write, `space.step`), wall "
          f"clock. Variants interleaved in one run, each on freshly built spaces, best of {reps} repeats; the first "
          f"step of each space is untimed unless a row says so. Disks R = 0.1 m, density 2, on a grid {SPACING:g} m "
          f"apart in one collision group (no contacts); dt = {DT:g} s, g = {G:g}.", "",
          f"Pressure profiles: {n} disks sliding (1-3 m/s) and spinning (5-20 rad/s), mu = {MU:g}, {steps} timed steps "
          f"(target: ring, hertz, feet <= {PROFILE_RATIO_MAX:g}x uniform):", "",
          md_table(["pressure", "us per step", "us per body", "x uniform", "still sliding at the end", "role"], prow),
          "",
          "The annulus is a uniform disk minus a uniform disk (two exact disk terms), so it costs about two uniform "
          "bodies by construction; it is reported, not judged.", "",
          f"Static friction in steps where nothing sticks (the same {n} sliding disks, uniform; target: <= "
          f"{STATIC_RATIO_MAX:.2f}x). Static friction is always on for dry bodies (mu_s defaults to mu); `static off` "
          "adds the bodies through the plugin's package-internal `add_footprint(..., static=0.0)`, the only way to "
          "switch it off:", "",
          md_table(["variant", "us per step", "us per body", "mu_s = mu over this", "still sliding at the end"], srow),
          "", rec_line, "",
          f"Static friction on a tilted plane: {n} disks released at rest on atan(0.3), mu = {MU_T:g}, mu_s = "
          f"{MUS_T:g} (held); a new load is a force of {NUDGE:g} m/s^2 across the slope on every body for one step "
          f"(and the step after it, the slope's pull alone again); break-away: {n} boxes 0.2 x 0.2 m on atan(0.8) > "
          f"mu_s (in the 'after one held step' row a force cancelling the slope's pull held them for one untimed "
          f"step, so the pass over newly added bodies is outside the timed step):", "",
          md_table(["scene / step", "bodies", "us per step", "us per body", "note / check"], trow), "",
          f"One body (a disk sliding at 2.5 m/s and spinning at 15 rad/s, {one_steps} timed steps; the fixed cost "
          f"of a step dominates):", "",
          md_table(["pressure", "us per step", "x uniform"], orow), "",
          "Data: `contacts.csv` (one row per measurement). The machine is shared: re-run on a quiet machine before "
          "quoting absolute times (the ratios are measured interleaved in one run)."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    res.extra = {"highlights": [
        f"pressure profiles per plugin step vs uniform ({n} sliding disks): "
        + ", ".join(f"{k} {prof[k]['ratio']:.2f}x" for k in ("ring", "annulus", "hertz", "points"))
        + f"; {n} bodies held on a tilt: {fmt(h['later'] * us / n)} us per body per step, "
          f"{fmt(h['new_load'] * us / n)} with a new load, all exactly at rest: {'yes' if h['at_rest'] else 'no'}."]}
    return res
