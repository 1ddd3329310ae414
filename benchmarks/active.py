"""Active bodies at scale: what the active effect and plane friction add to pymunk's own step.

A colliding space: N bodies, half disks (r = 0.1 m), half L-shapes (two boxes 0.16 x 0.08 and 0.08 x
0.16 m on one body), density 20 kg/m^2, placed on a jittered grid in a walled square box at packing
fraction 0.35, launched at 0.3 m/s in random directions; pymunk's default spatial index, 10 solver
iterations, dt = 1/120 s. Every body is active (:class:`rrbody.plugin.Active`): propulsion F = 2 mu g m
fixed in the body frame, through the centre for a disk, 0.03 m off it for an L (chiral: it turns), the
medium's drag 2/s and rotational drag 2/s, rotational noise D_r = 0.2 rad^2/s (one seeded PCG64 draw per
step); dry plane friction mu = 0.1 (terminal speed (F/m - mu g) / 2/s = 0.5 m/s). The L-shapes take
their footprint's wrench table (``pf.add(..., friction_method="table")``: within 1e-10 of the exact
wrench, :mod:`rrbody.physics.footprint_table`); the disks take the disk's table either way.

The bound is judged on ``pf.step``'s own blocks (``BLOCK`` steps each): each block's time against
pymunk's step inside it (``space.step`` timed within ``pf.step``), the same states, with nothing else
stepping the space between its blocks, as in use; at N = 1,000 over runs from launch (last paragraph),
for each N the best of several blocks. Then four variants
step the same space, in one run, interleaved (blocks of ``BLOCK`` steps of each in turn, best block of
each kind): ``pymunk`` (``space.step`` alone: pymunk's own step of the
colliding space, no friction, no propulsion), ``active`` (``pf.step``: the active effect and plane
friction, one compiled call for all bodies, then the same ``space.step``), ``exact`` (the same with the
L-shapes' exact polygon wrench every step, ``friction_method="auto"``: what the table saves) and, as a
breakdown, ``alone`` (a plugin on the same space whose bodies have mu = 0: the active effect, the noise
draw and the plugin's reads and writes, without friction). All keep colliding (under the bare step the
bodies coast at their speed; under ``pf.step`` propulsion, drag and friction hold them near 0.5 m/s),
so the bare step is lighter than the one ``pf.step`` calls: the time of that inner ``space.step`` is
measured too, and that ratio is given on the same states (``pf.step`` over its own ``space.step``).
Interleaved, ``pf.step`` costs more: the other plugins' blocks evict its data from the caches and
leave its velocity history a block old (its first step then extrapolates from it).

Twice: at launch (the rounds start 5 steps after the bodies leave their grid, before they have met
much), and after ``pf.step`` has run on for SETTLE = 20 s of simulated time, when the active bodies have
gathered into clusters and the number of touching pairs has levelled off (counted half-way through the
settling, at its end and during the rounds). The workload drifts at launch (pymunk's step grows as the
bodies meet: the launch columns against the settled ones), and a best block picks the lightest states,
so the launch figure is the ratio on the lightest states of a transient. The bound is judged on the
runs from launch (below), once the clusters have formed and over the whole run; the launch figure is
reported beside them. A breakdown on one frozen state (after the settling): the plugin's compiled call
with and without the ``active`` arrays (friction off in both), and the noise draw. N = 100, 300, 1,000,
3,000, 10,000; the fitted exponents are least-squares slopes of log(cost per step) against log N.
Last, RUNS = 5 runs from one launch on a
fresh box of 1,000 bodies (the same seed: the same states, checked bit for bit) time every block of
``pf.step`` against pymunk's step inside it for 25 s; per block the fastest run counts
(``active_drift.csv``, ``active_drift.png``). Judged: the blocks' total time over the total time of
pymunk's steps inside them, from DRIFT_FROM = 10 s on (the clusters) and over the whole run (what a
simulation of the colliding space costs, its launch included); given beside them: the first
LAUNCH_WINDOW = 1 s.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

from .common import (
    StudyResult,
    Target,
    fmt,
    loglog_slope,
    machine_text,
    md_table,
    module_available,
    save_figure,
    write_csv,
)

NAME = "active"
TITLE = "Active bodies: propulsion, noise and plane friction vs pymunk's own step, N = 100 ... 10,000"
SIZES = (100, 300, 1000, 3000, 10000)
DT, BLOCK, MU, PACKING = 1.0 / 120.0, 20, 0.1, 0.35
#: s of simulated time pf.step runs after the launch measurement, before the steady one (--quick: less)
SETTLE, SETTLE_QUICK = 20.0, 2.0
#: s from which the drift's blocks count as settled, for their median (--quick: from 1 s)
DRIFT_FROM = 10.0
#: runs from the same launch, for the run's best-of blocks; the first LAUNCH_WINDOW s of it is "at launch"
RUNS, LAUNCH_WINDOW = 5, 1.0
#: the jammed space the coupled step is timed on (bodies)
CLUSTER_N = 200
A = 0.08  # m: the L's leg width


def build(n: int, *, seed: int = 1, packing: float = PACKING, mu: float = MU, method: str = "table",
          scheme: str = "split") -> tuple:
    """n active disks and L-shapes in a walled box at ``packing`` (area fraction), on a plane of friction
    coefficient ``mu`` (plugin ``pf``, the L-shapes' friction by ``method``); plugin ``pf0`` on the same
    space holds the same bodies with mu = 0 and the same propulsion (the active effect alone), and
    ``pfx`` with the L-shapes' exact wrench: (space, pf, pf0, bodies, pfx). ``scheme``: the plugins' step
    (the split step, as the active-matter study runs: docs/active.md, "The split step in clusters")."""
    import numpy as np
    import pymunk

    from rrbody.plugin import Active, PlaneFriction

    rng = np.random.default_rng(seed)
    area_disk, area_l = math.pi * 0.1**2, 4 * A * A
    side = math.sqrt(n * 0.5 * (area_disk + area_l) / packing)
    space = pymunk.Space()
    space.iterations = 10
    pf = PlaneFriction(space, g=9.81, scheme=scheme)
    pf0 = PlaneFriction(space, g=9.81, scheme=scheme)
    pfx = PlaneFriction(space, g=9.81, scheme=scheme)
    for plane in (pf, pf0, pfx):
        plane.seed(seed)
    corners = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)]
    space.add(*[pymunk.Segment(space.static_body, a, b, 0.05) for a, b in zip(corners, corners[1:] + corners[:1])])
    k = int(math.ceil(math.sqrt(n)))
    cell = side / k
    bodies = []
    for i in range(n):
        b = pymunk.Body()
        if i % 2:
            shapes = [pymunk.Circle(b, 0.1)]
        else:  # an L about its own origin; pymunk puts the centre of gravity at the shapes' centroid
            shapes = [pymunk.Poly(b, [(-A, -A), (A, -A), (A, 0), (-A, 0)]),
                      pymunk.Poly(b, [(-A, 0), (0, 0), (0, A), (-A, A)])]
        for s in shapes:
            s.density = 20.0
            s.friction = 0.3
        b.position = (cell * (i % k + 0.5) + 0.1 * cell * rng.uniform(-1, 1), cell * (i // k + 0.5))
        b.angle = rng.uniform(0, 2 * math.pi)
        a = rng.uniform(0, 2 * math.pi)
        b.velocity = (0.3 * math.cos(a), 0.3 * math.sin(a))
        space.add(b, *shapes)
        act = Active(force=2.0 * MU * 9.81 * b.mass, point=(0.0, 0.0) if i % 2 else (0.0, 0.03), drag=2.0,
                     rot_drag=2.0, rot_diffusion=0.2)
        for plane, m, how in ((pf, mu, method), (pf0, 0.0, "auto"), (pfx, mu, "auto")):  # (pf0: no friction)
            plane.add(b, mu=m, friction_method=how)
            plane.activate(b, act)
        bodies.append(b)
    return space, pf, pf0, bodies, pfx


def _contacts(space: object) -> int:
    """Touching pairs in the space now (walls included; each arbiter seen from both bodies)."""
    seen: list[int] = []
    for b in space.bodies:  # type: ignore[attr-defined]
        b.each_arbiter(lambda arb: seen.append(1))
    return len(seen) // 2


def _frozen_call(pf: object) -> tuple[tuple, object, object, object]:
    """The plugin's compiled call on the space's state now, for timing it again and again: (its
    arguments up to ``active``, the ``active`` rows, the noise array, the compiled kernel). The
    plugin's own arrays are copies (``pf.step_arrays()``, the same types: the same compiled code), so the
    timed calls, which write the rows and the row cache, leave the plugin as it was."""
    io = pf._sio if pf._sio is not None else pf._io  # type: ignore[attr-defined]
    got, ids, out = io.read()
    rows, noise = pf._act.arrays(pf)  # type: ignore[attr-defined]
    lookup, cache, bodies, shapes, geo, tables = pf.step_arrays()  # type: ignore[attr-defined]
    base = (got, ids, lookup, cache, bodies, shapes, geo, tables, pf.t, DT, out)  # type: ignore[attr-defined]
    from rrbody.contact import kernel as K

    return base, rows, noise, K.plane_step


def _effect_share(pf: object, reps: int = 7, block: int = 20) -> tuple[float, float]:
    """(s per step) the active effect adds to the plugin's compiled call, measured on one frozen state
    (the call with the ``active`` arrays against the same call without them, interleaved, best block),
    and the noise draw (one vectorised PCG64 call for all bodies). Both calls run with friction off
    (every body's mu g zeroed): with friction, a body without its propulsion is stopped by the rest rule
    where it slid on, a different step; without it, the two calls differ by the active load alone
    (checked: the same count of stopped bodies, none)."""
    from rrbody.contact import kernel as K
    from rrbody.contact.columns import NO_ACTIVE

    base, rows, noise, kernel = _frozen_call(pf)
    act = pf._act  # type: ignore[attr-defined]
    B = base[4]  # the copy of the rows the timed calls take
    saved = B.copy()
    frozen = B.copy()
    frozen[:, K.FRICTION_COEFF] = 0.0
    calls = (lambda: kernel(*base, rows, noise), lambda: kernel(*base, *NO_ACTIVE))
    stops = []
    for call in calls:
        B[:] = frozen
        stops.append(call())
    if stops != [0, 0]:
        raise RuntimeError(f"the frictionless calls stopped bodies ({stops}): they would not differ by the active "
                           "load alone")
    best = [math.inf, math.inf, math.inf]
    for _ in range(reps):
        for k, call in enumerate((*calls, lambda: act.rng.standard_normal(out=noise))):
            w0 = time.perf_counter()
            for _ in range(block):
                B[:] = frozen  # the same state every call (the history columns)
                call()
            best[k] = min(best[k], (time.perf_counter() - w0) / block)
    B[:] = saved
    return best[0] - best[1], best[2]


def _breakdown(pf: object, reps: int = 15, block: int = 20) -> dict[str, float]:
    """Where ``pf.step``'s own time goes, on one frozen state (us per step, best block of each, interleaved;
    measured apart, so only roughly additive): the compiled call with friction off (every body's mu g
    zeroed), with the disks' friction alone, with the L-shapes' alone (from their table), and with the
    L-shapes' exact wrench in place of the table; the reads and writes through the bodies' structs and
    through ``pymunk.batch``; and the share of the L-shapes' table calls handed to the exact wrench
    (their instantaneous centre on or next to an edge of the L)."""
    import numpy as np

    from rrbody.contact import kernel as K
    from rrbody.physics.effects.drive_circular import sincos_reduced
    from rrbody.physics.footprint_table import table_covers

    base, rows, noise, kernel = _frozen_call(pf)
    got, cache, tables = base[0], base[3], base[7]
    B = base[4]  # the copy of the rows the timed calls take
    disk = B[:, K.TABLE_KIND] == K.TABLE_CIRCLE
    coeff = B[:, K.FRICTION_COEFF]
    states = {"no friction": B.copy(), "disks": B.copy(), "L-shapes (table)": B.copy(), "L-shapes (exact)": B.copy()}
    states["no friction"][:, K.FRICTION_COEFF] = 0.0
    states["disks"][:, K.FRICTION_COEFF] = np.where(disk, coeff, 0.0)
    for name in ("L-shapes (table)", "L-shapes (exact)"):
        states[name][:, K.FRICTION_COEFF] = np.where(disk, 0.0, coeff)
    states["L-shapes (exact)"][~disk, K.TABLE_KIND] = K.TABLE_NONE
    saved = B.copy()
    calls = {name: (lambda st=st: (B.__setitem__(slice(None), st), kernel(*base, rows, noise)))
             for name, st in states.items()}
    calls["copy only"] = lambda: B.__setitem__(slice(None), saved)
    calls["struct read + write"] = lambda: (pf._sio.read(), pf._sio.write_forces())  # type: ignore[attr-defined]
    calls["pymunk.batch read + write"] = lambda: (pf._io.read(), pf._io.write_forces())  # type: ignore[attr-defined]
    if pf._sio is None:  # type: ignore[attr-defined]
        del calls["struct read + write"]
    best = dict.fromkeys(calls, math.inf)
    for _ in range(reps):
        for name, call in calls.items():
            w0 = time.perf_counter()
            for _ in range(block):
                call()
            best[name] = min(best[name], (time.perf_counter() - w0) / block)
    B[:] = saved
    copy = best.pop("copy only")
    res = {name: 1e6 * (t - copy if name in states else t) for name, t in best.items()}
    for name in ("disks", "L-shapes (table)", "L-shapes (exact)"):
        res[name] -= res["no friction"]
    handed, n_l = 0, 0
    for i in range(got.shape[0]):
        j = cache[K.ROWMAP, i]
        if j < 0 or disk[j]:
            continue
        sa, ca = sincos_reduced(got[i, 0] + got[i, 3] * DT)
        vbx, vby = ca * got[i, 1] + sa * got[i, 2], -sa * got[i, 1] + ca * got[i, 2]
        n_l += 1
        handed += not table_covers(tables, int(B[j, K.TABLE_START]), vbx, vby, got[i, 3],
                                   B[j, K.SLIP_EPS])
    res["handed over"] = handed / max(n_l, 1)
    return res


class _Inside:
    """Blocks of steps timed together with pymunk's own step inside them: ``space.step`` is wrapped for
    a block so that the time of every pymunk step the block makes is summed (the same states);
    ``bare`` is pymunk's unwrapped step."""

    def __init__(self, space: object) -> None:
        self.space = space
        self.bare = space.step  # type: ignore[attr-defined]
        self._s = 0.0

    def _timed(self, dt: float) -> None:
        w = time.perf_counter()
        self.bare(dt)
        self._s += time.perf_counter() - w

    def block(self, step: object, block: int, wrapped: bool = True) -> tuple[float, float]:
        """(s per step of ``block`` calls of ``step(DT)``, s per step of pymunk's step inside them; 0
        unless ``wrapped``)."""
        self._s = 0.0
        self.space.step = self._timed if wrapped else self.bare  # type: ignore[attr-defined]
        try:
            w0 = time.perf_counter()
            for _ in range(block):
                step(DT)  # type: ignore[operator]
            took = (time.perf_counter() - w0) / block
        finally:
            self.space.step = self.bare  # type: ignore[attr-defined]
        return took, self._s / block


def _measure(space: object, pf: object, pf0: object, pfx: object, reps: int, block: int) -> dict[str, float]:
    """From the space's state now: ``own``, the best of ``reps`` blocks of ``block`` steps of ``pf.step``
    alone (s per step), and pymunk's own step inside it (``own_inside``: the same states); then the
    four variants' best block in ``reps`` interleaved rounds (blocks of each in turn): ``pymunk`` (the
    bare ``space.step``), ``active`` (``pf.step``), ``alone`` (``pf0.step``: mu = 0), ``exact``
    (``pfx.step``), and pymunk's own step inside the best ``active`` and ``exact`` blocks (``inside``,
    ``inside_x``); ``contacts``, the most touching pairs seen after a round."""
    best = {"pymunk": math.inf, "active": math.inf, "alone": math.inf, "exact": math.inf,
            "inside": math.inf, "inside_x": math.inf, "contacts": 0, "own": math.inf, "own_inside": math.inf}
    clock = _Inside(space)
    # pf.step's blocks on their own first: no other plugin or bare step between them, as in use (each
    # block's ratio is over its own pymunk steps, the same states, so nothing else need interleave)
    for _ in range(reps):
        took, inside = clock.block(pf.step, block)  # type: ignore[attr-defined]
        if took < best["own"]:
            best["own"], best["own_inside"] = took, inside
    variants = (("pymunk", clock.bare), ("active", pf.step), ("alone", pf0.step),  # type: ignore[attr-defined]
                ("exact", pfx.step))  # type: ignore[attr-defined]
    for _ in range(reps):
        for kind, step in variants:
            took, inside = clock.block(step, block, wrapped=kind in ("active", "exact"))
            if took < best[kind]:
                best[kind] = took
                if kind == "active":
                    best["inside"] = inside
                elif kind == "exact":
                    best["inside_x"] = inside
        best["contacts"] = max(best["contacts"], _contacts(space))
    return best


def _drift(n: int, t_end: float, runs: int = 3, block: int = BLOCK) -> list[dict[str, float]]:
    """``pf.step`` from launch to ``t_end`` (s of simulated time) on a fresh box of ``n`` bodies, in blocks
    of ``block`` steps, each timed against pymunk's step inside it: how what the plugin adds moves as
    the bodies meet and gather into clusters. ``runs`` runs from the same launch (the same seed: the
    same states, checked bit for bit at the end); per block the run whose ``pf.step`` block was fastest,
    with pymunk's step inside that block. Rows: the time at the block's end (s), both costs (ms per
    step), the added fraction, the touching pairs (counted every fifth block of the first run, else -1)
    and the blocks' spread over the runs (slowest over fastest ``pf.step`` block, minus 1)."""
    best: list[dict[str, float]] = []
    slowest: list[float] = []
    end = None
    for r in range(runs):
        space, pf, _, bodies, _ = build(n)
        for _ in range(5):  # compiled step, first allocations, the half kicks: not counted (as in run)
            pf.step(DT)
        clock = _Inside(space)
        for k in range(round(t_end / DT) // block):
            took, inside = clock.block(pf.step, block)
            row = {"t_s": pf.t, "pf_step_ms": took * 1e3, "inside_ms": inside * 1e3, "added": took / inside - 1.0,
                   "contacts": _contacts(space) if r == 0 and k % 5 == 0 else -1}
            if r == 0:
                best.append(row)
                slowest.append(took)
                continue
            slowest[k] = max(slowest[k], took)
            if took * 1e3 < best[k]["pf_step_ms"]:
                best[k].update({key: v for key, v in row.items() if key != "contacts"})
        state = [(b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y, b.angular_velocity) for b in bodies]
        if end is not None and state != end:  # best-of-runs blocks are only comparable on the same states
            raise RuntimeError("the runs from launch did not reach the same state: the seeded run is not reproducible")
        end = state
    for row, slow in zip(best, slowest):
        row["spread"] = slow / (row["pf_step_ms"] * 1e-3) - 1.0
    return best


def _run_added(rows: list[dict[str, float]], t_to: float = math.inf, t_from: float = 0.0) -> float:
    """What ``pf.step`` adds over :func:`_drift`'s blocks that end from ``t_from`` to ``t_to`` s: their
    total time over the total of pymunk's step inside them, minus 1 (from 0: the cost of the run,
    launch included)."""
    took = sum(r["pf_step_ms"] for r in rows if t_from <= r["t_s"] <= t_to)
    inside = sum(r["inside_ms"] for r in rows if t_from <= r["t_s"] <= t_to)
    return took / inside - 1.0


def _settled_median(rows: list[dict[str, float]], t_from: float) -> float:
    """The median added fraction of :func:`_drift`'s blocks from ``t_from`` s on (the clusters formed):
    each block's ratio is over its own pymunk steps, so the median over many blocks is what the
    plugin adds there, robust to the blocks a busy machine slowed."""
    import statistics

    return statistics.median(r["added"] for r in rows if r["t_s"] >= t_from)


def _plot_drift(path: Path, rows: list[dict[str, float]], n: int, t_from: float, runs: int) -> Path:
    """The drift of :func:`_drift` (``runs`` runs): both costs per step, and the added fraction against the
    bound."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    t = [r["t_s"] for r in rows]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.4, 5.2), sharex=True)
    a1.plot(t, [r["pf_step_ms"] for r in rows], ".", ms=3, color="tab:red", label="pf.step (active + friction)")
    a1.plot(t, [r["inside_ms"] for r in rows], ".", ms=3, color="0.3", label="pymunk's step inside it")
    a1.set_ylabel("ms per step")
    a1.set_title(f"{n} active bodies from launch (blocks of {BLOCK} steps, each the fastest of {runs} runs)",
                 fontsize=9)
    a1.legend(fontsize=7)
    a1.grid(True, alpha=0.3)
    a2.plot(t, [100 * r["added"] for r in rows], ".", ms=3, color="tab:red")
    a2.axhline(30, color="k", ls="--", lw=0.8, label="the bound, 30 %")
    settled = _run_added(rows, t_from=t_from)
    a2.axvspan(t_from, rows[-1]["t_s"], color="tab:red", alpha=0.06, lw=0, label=f"from {t_from:.0f} s: {settled:.1%}")
    whole = _run_added(rows)
    a2.axhline(100 * whole, color="tab:blue", ls="-.", lw=0.8, label=f"the whole run: {whole:.1%}")
    first = _run_added(rows, LAUNCH_WINDOW)
    a2.axvspan(0.0, LAUNCH_WINDOW, color="0.85", lw=0, label=f"the first {LAUNCH_WINDOW:.0f} s: {first:.1%}")
    a2.set_ylim(0, max(60.0, min(200.0, 1.1 * max(100 * r["added"] for r in rows))))
    a2.set_ylabel("added to pymunk's step (%)")
    a2.set_xlabel("simulated time since launch (s)")
    a2.set_ylim(bottom=0)
    a2.legend(fontsize=7)
    a2.grid(True, alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path


def _coupled_in_clusters(n: int, settle: float, steps: int) -> dict[str, float]:
    """The coupled step on a jammed colliding space: n bodies run ``settle`` s on the split step (the clusters
    form), then ``steps`` steps with the coupled step attached to the same plugin. Returns the median ms per
    ``pf.step`` and per pymunk step inside it, their ratio, the ratio of the sums (a few slow solves weigh
    there), and the warnings of unconverged solves."""
    import warnings

    import numpy as np

    from rrbody.engine.plugin.coupling import Coupling

    space, pf, _, _, _ = build(n)
    for _ in range(round(settle / DT)):
        pf.step(DT)
    pf._coupling = Coupling(space)  # (the benchmark's switch of scheme on a settled space)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pf.step(DT)  # (its first call loads the compiled solve: not timed)
    inner: list[float] = []
    outer: list[float] = []
    bare = space.step

    def timed(dt: float) -> None:
        t0 = time.perf_counter()
        bare(dt)
        inner.append(time.perf_counter() - t0)

    space.step = timed
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(steps):
            t0 = time.perf_counter()
            pf.step(DT)
            outer.append(time.perf_counter() - t0)
    space.step = bare
    return {"N": n, "steps": steps, "pf_step_ms": float(np.median(outer)) * 1e3,
            "inside_ms": float(np.median(inner)) * 1e3, "ratio": float(np.median(outer) / np.median(inner)),
            "sum_ratio": sum(outer) / sum(inner), "warned": len(caught)}


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("pymunk")
    if not ok:
        return StudyResult(NAME, TITLE, skipped=f"pymunk not importable ({why})")
    sizes = SIZES[:3] if quick else SIZES
    rows = []
    parts: dict[str, float] = {}
    for n in sizes:
        space, pf, pf0, _, pfx = build(n)
        for _ in range(5):  # compiled step, first allocations, the half kicks: not counted
            pf.step(DT)
            pf0.step(DT)
            pfx.step(DT)
        reps = 3 if quick else (5 if n >= 3000 else 11)
        block = max(3, BLOCK if n <= 1000 else BLOCK * 1000 // n * 2)
        launch = _measure(space, pf, pf0, pfx, reps, block)
        # the colliding space proper: pf.step runs on until the contacts have levelled off (the clusters
        # active bodies form), then the same measurement
        settle = round((SETTLE_QUICK if quick else SETTLE) / DT)
        c_mid = 0
        for k in range(settle):
            pf.step(DT)
            if k == settle // 2:
                c_mid = _contacts(space)
        c_end = _contacts(space)
        best = _measure(space, pf, pf0, pfx, reps, block)
        effect, draw = _effect_share(pf, reps=7 if n >= 10000 else 15)
        if n == 1000:
            parts = _breakdown(pf)
            print("[active] N=1000 breakdown (us per step, frozen state): " + ", ".join(
                f"{k} {v:.1%}" if k == "handed over" else f"{k} {v:.1f}" for k, v in parts.items()), flush=True)
        rows.append({"effect_us": effect * 1e6, "draw_us": draw * 1e6, "N": n, "pymunk_ms": best["pymunk"] * 1e3,
                     "active_ms": best["active"] * 1e3,
                     "added": best["active"] / best["pymunk"] - 1.0, "alone_ms": best["alone"] * 1e3,
                     "added_alone": best["alone"] / best["pymunk"] - 1.0, "contacts": best["contacts"],
                     "contacts_mid": c_mid, "contacts_end": c_end, "block": block,
                     "inside_ms": best["inside"] * 1e3, "added_same": best["active"] / best["inside"] - 1.0,
                     "exact_ms": best["exact"] * 1e3, "added_exact": best["exact"] / best["inside_x"] - 1.0,
                     "launch_active_ms": launch["active"] * 1e3, "launch_inside_ms": launch["inside"] * 1e3,
                     "launch_added_same": launch["active"] / launch["inside"] - 1.0,
                     "own_ms": best["own"] * 1e3, "own_inside_ms": best["own_inside"] * 1e3,
                     "added_own": best["own"] / best["own_inside"] - 1.0,
                     "launch_own_ms": launch["own"] * 1e3, "launch_own_inside_ms": launch["own_inside"] * 1e3,
                     "launch_added_own": launch["own"] / launch["own_inside"] - 1.0,
                     "launch_contacts": launch["contacts"], "repeats": reps})
        print(f"[active] N={n}: pymunk {best['pymunk'] * 1e3:.3f} ms, with active + friction "
              f"{best['active'] * 1e3:.3f} ms (+{rows[-1]['added']:.1%}; same states "
              f"+{rows[-1]['added_same']:.1%}; exact L-shapes +{rows[-1]['added_exact']:.1%}), active alone (mu = 0) "
              f"{best['alone'] * 1e3:.3f} ms (+{rows[-1]['added_alone']:.1%}), {best['contacts']} contacts; "
              f"the effect in the kernel {effect * 1e6:.1f} us, the noise draw {draw * 1e6:.1f} us; at launch: "
              f"+{rows[-1]['launch_added_same']:.1%} on the same states ({launch['contacts']} contacts); pf.step's "
              f"blocks alone: +{rows[-1]['added_own']:.1%} (at launch +{rows[-1]['launch_added_own']:.1%})",
              flush=True)
    write_csv(out / "active.csv", rows)
    drift_n, drift_from = (100, 1.0) if quick else (1000, DRIFT_FROM)
    runs = 2 if quick else RUNS
    drift = _drift(drift_n, SETTLE_QUICK if quick else SETTLE + 5.0, runs=runs)
    drift_med = _settled_median(drift, drift_from)
    run_added, first_added = _run_added(drift), _run_added(drift, LAUNCH_WINDOW)
    settled_added = _run_added(drift, t_from=drift_from)
    spread = sorted(r["spread"] for r in drift)[len(drift) // 2]
    write_csv(out / "active_drift.csv", drift)
    _plot_drift(out / "active_drift.png", drift, drift_n, drift_from, runs)
    ns = [r["N"] for r in rows]
    e_pm = loglog_slope(ns, [r["pymunk_ms"] for r in rows])
    e_ac = loglog_slope(ns, [r["active_ms"] for r in rows])
    e_in = loglog_slope(ns, [r["inside_ms"] for r in rows])
    e_launch = loglog_slope(ns, [r["launch_active_ms"] for r in rows])
    e_launch_in = loglog_slope(ns, [r["launch_inside_ms"] for r in rows])
    at = {r["N"]: r for r in rows}
    r1k = at.get(1000)
    targets = []
    if r1k is not None:
        share = (r1k["effect_us"] + r1k["draw_us"]) / (1e3 * r1k["pymunk_ms"])
        targets.append(Target("breakdown at N = 1,000: the active effect's own cost (kernel share + noise draw)",
                              "(no bound)", f"{share:.1%} of pymunk's step ({r1k['effect_us']:.0f} + "
                              f"{r1k['draw_us']:.0f} us); the plugin with mu = 0 adds {r1k['added_alone']:.0%}", None))
        # judged on the same states (the bare variant's bodies coast, no propulsion: its contacts and its
        # step are lighter than those pf.step drives), over the many blocks of the runs from launch once
        # the clusters have formed; the sweep's best single block is given beside it
        targets.append(Target(f"active effect + plane friction at N = {drift_n}, colliding (the runs from launch, "
                              f"from {drift_from:.0f} s on, the clusters formed)", "<= 30 % added",
                              f"{settled_added:.1%} over pymunk's step inside the blocks (their total times; the "
                              f"median block {drift_med:.1%}); in the sweep over N, after "
                              f"{SETTLE_QUICK if quick else SETTLE:.0f} s, pf.step's best block of {r1k['repeats']} "
                              f"{r1k['added_own']:.1%} ({r1k['own_ms']:.3f} vs {r1k['own_inside_ms']:.3f} ms per "
                              f"step), interleaved with the other variants {r1k['added_same']:.1%} "
                              f"({r1k['active_ms']:.3f} vs {r1k['inside_ms']:.3f} ms, {r1k['contacts']} contacts), "
                              f"{r1k['added']:.1%} over the bare space's step ({r1k['pymunk_ms']:.3f} ms, coasting "
                              "bodies)", None if quick else settled_added <= 0.30))
        # reported, not judged: the bodies have barely met, so pymunk's step is at its lightest; the run
        # from launch (judged below) carries these steps at their weight in a simulation
        targets.append(Target("the same at launch (the first steps from the grid, before the bodies have met)",
                              "(reported beside the bound)",
                              f"{r1k['launch_added_own']:.1%} over pymunk's step of the same states, pf.step's "
                              f"blocks alone ({r1k['launch_own_ms']:.3f} vs {r1k['launch_own_inside_ms']:.3f} ms "
                              f"per step); interleaved {r1k['launch_added_same']:.1%} ({r1k['launch_active_ms']:.3f} "
                              f"vs {r1k['launch_inside_ms']:.3f} ms, {r1k['launch_contacts']} contacts); the first "
                              f"{LAUNCH_WINDOW:.0f} s of the run from launch {first_added:.1%}"
                              + ("" if first_added <= 0.30 else " (above 30 %)"), None))
        targets.append(Target("the same with the L-shapes' exact polygon wrench every step (no table)", "(no bound)",
                              f"{r1k['added_exact']:.1%} over pymunk's step of the same states "
                              f"({r1k['exact_ms']:.3f} ms per step)", None))
    if r1k is not None and parts:
        targets.append(Target("breakdown at N = 1,000 (one frozen state, us per step; not additive exactly)",
                              "(no bound)", ", ".join(f"{k} {v:.1%}" if k == "handed over" else f"{k} {v:.0f}"
                                                      for k, v in parts.items()), None))
    if r1k is not None:  # "1,000 bodies on one core interactively": at least 60 steps per s of computing
        rate = 1e3 / r1k["active_ms"]
        targets.append(Target("1,000 active bodies interactively, one core", ">= 60 steps/s (pf.step <= 16.7 ms)",
                              f"{rate:.0f} steps/s ({r1k['active_ms']:.3f} ms per pf.step; at dt = 1/120 s "
                              f"{rate * DT:.1f}x real time)", None if quick else rate >= 60.0))
    # "no faster than pymunk's own": the exponents' difference within 0.05 (the fits' spread between runs)
    targets.append(Target("cost per step vs N: exponent no larger than pymunk's own",
                          "exponent(active) <= exponent(pymunk) + 0.05",
                          f"{e_ac:.3f} vs pymunk {e_pm:.3f} (N = {ns[0]} ... {ns[-1]}; pymunk's step inside "
                          f"pf.step {e_in:.3f}; at launch {e_launch:.3f} vs {e_launch_in:.3f})",
                          None if quick else e_ac <= e_pm + 0.05))
    targets.append(Target(f"active effect + plane friction at N = {drift_n}, a run from launch to "
                          f"{drift[-1]['t_s']:.0f} s (each block the fastest of {runs} runs)", "<= 30 % added",
                          f"{run_added:.1%} over pymunk's step inside the blocks (the whole run's time; the first "
                          f"{LAUNCH_WINDOW:.0f} s {first_added:.1%}, from {drift_from:.0f} s on "
                          f"{settled_added:.1%}; a block's slowest run over its fastest, median {spread:.0%})",
                          None if quick else run_added <= 0.30))
    # the coupled step (the plugin's default) in the same clusters: reported against the same bound, last
    cc = _coupled_in_clusters(100 if quick else CLUSTER_N, SETTLE_QUICK if quick else SETTLE, 5 if quick else 20)
    write_csv(out / "active_coupled.csv", [cc])
    targets.append(Target(f"the coupled step (the default) at N = {cc['N']}, clusters formed ({SETTLE:.0f} s on the "
                          "split step)", "<= 30 % added",
                          f"{cc['ratio']:.0f}x pymunk's step inside it ({cc['pf_step_ms']:.1f} vs "
                          f"{cc['inside_ms']:.2f} ms per step, medians of {cc['steps']} steps; the sums' ratio "
                          f"{cc['sum_ratio']:.0f}x; {cc['warned']} unconverged-solve warnings): use scheme='split' for "
                          "jammed clusters",
                          None if quick else cc["ratio"] <= 1.30))
    if quick:
        targets = [Target(t.name, t.target, t.measured + " [quick]", None) for t in targets]
    md = [f"## {TITLE}", "", __doc__.split("\n\n", 1)[1].strip(), "", machine_text(), "",
          md_table(["N", "pf.step alone (ms/step)", "pymunk inside it (ms/step)", "added (same states)",
                    "at launch: pf.step alone (ms/step)", "pymunk inside it (ms/step)", "added (same states)"],
                   [(r["N"], fmt(r["own_ms"]), fmt(r["own_inside_ms"]), f"{r['added_own']:.1%}",
                     fmt(r["launch_own_ms"]), fmt(r["launch_own_inside_ms"]), f"{r['launch_added_own']:.1%}")
                    for r in rows]), "",
          "Interleaved rounds (blocks of each variant in turn, after pf.step's own blocks):", "",
          md_table(["N", "pymunk (ms/step)", "active + friction (ms/step)", "added", "pymunk inside it (ms/step)",
                    "added (same states)", "exact L-shapes (ms/step)", "added (same states)",
                    "active alone, mu = 0 (ms/step)",
                    "added", "effect in the kernel (us)", "noise draw (us)", "effect + draw / pymunk",
                    "contacts (half-way, end of the settling, measured)", "at launch: active + friction (ms/step)",
                    "pymunk inside it (ms/step)", "added (same states)", "contacts"],
                   [(r["N"], fmt(r["pymunk_ms"]), fmt(r["active_ms"]), f"{r['added']:.1%}", fmt(r["inside_ms"]),
                     f"{r['added_same']:.1%}", fmt(r["exact_ms"]), f"{r['added_exact']:.1%}", fmt(r["alone_ms"]),
                     f"{r['added_alone']:.1%}", fmt(r["effect_us"]), fmt(r["draw_us"]),
                     f"{(r['effect_us'] + r['draw_us']) / (1e3 * r['pymunk_ms']):.1%}",
                     f"{r['contacts_mid']}, {r['contacts_end']}, {r['contacts']}", fmt(r["launch_active_ms"]),
                     fmt(r["launch_inside_ms"]), f"{r['launch_added_same']:.1%}", r["launch_contacts"])
                    for r in rows]), "",
          "From launch, what pf.step adds as the bodies meet and gather into clusters (a fresh box of "
          f"{drift_n} bodies, blocks of {BLOCK} steps, each the fastest of {runs} runs from the same launch; "
          f"`active_drift.csv`): over the whole run {run_added:.1%}, over its first {LAUNCH_WINDOW:.0f} s "
          f"{first_added:.1%}, from {drift_from:.0f} s on {settled_added:.1%} (the median block "
          f"{drift_med:.1%}).", "",
          "![the added cost from launch](active_drift.png)", "",
          f"Fitted exponents of cost per step vs N, after the settling: pymunk {e_pm:.3f} (its step inside "
          f"pf.step {e_in:.3f}), active + friction {e_ac:.3f}; at launch: active + friction {e_launch:.3f}, "
          f"pymunk's step inside it {e_launch_in:.3f}.", ""]
    return StudyResult(NAME, TITLE, targets=targets, markdown="\n".join(md),
                       files=["active.csv", "active_drift.csv", "active_drift.png"],
                       extra={"highlights": [f"active + plane friction add {settled_added:.0%} to pymunk's step "
                                             f"of the same states at N = 1,000 in clusters, {run_added:.0%} over a run "
                                             f"from launch ({first_added:.0%} in its first {LAUNCH_WINDOW:.0f} s; "
                                             f"exponents {e_ac:.2f} vs {e_pm:.2f})"] if r1k else []})


if __name__ == "__main__":  # a quick look without the runner
    t0 = time.perf_counter()
    print(run(Path("/tmp"), quick=True).markdown, f"\n({time.perf_counter() - t0:.0f} s)")
