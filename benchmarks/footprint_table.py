"""A footprint's wrench table (rrbody.physics.footprint_table) against the exact formula it replaces.

The plugin computes each body's area-integrated dry friction every step
(:func:`rrbody.physics.contact.footprint_wrench`). For a given footprint that wrench, per unit load and
mu g, is a fixed function of the instantaneous centre of rotation (ICR) and the spin's sign, which
:func:`rrbody.physics.footprint_table.build_footprint_table` tabulates once and
:func:`~rrbody.physics.footprint_table.footprint_table_wrench` evaluates, falling back to the exact
formula on the footprint's boundary and in the dead band. Footprints: the L of ``benchmarks/active.py``
(two boxes 0.16 x 0.08 and 0.08 x 0.08 m as two parts, about its centre of gravity) and a single box
0.16 x 0.08 m whose centre is 0.032 m from the centre of gravity. Twists, like those of the active
benchmark: with probability 1/2 the ICR uniform in the disc of radius 3 R about the centre of gravity
(R the reach) and |w| log-uniform in [0.1, 100] rad/s, else |v| uniform in [0.05, 1] m/s in a uniform
direction with |w| R / |v| log-uniform in [1e-3, 1]; the spin's sign random; v_eps = 1e-6 m/s.
Nanoseconds per call: compiled loops over the same twists (random order), the table and the exact
formula interleaved, best of ``REPEATS``; also for the two halves of the distribution apart ("near":
the ICR in the disc; "far": mostly translating), and "stepped": 500 bodies' twists, each drifting by
1 % per step, body after body for 80 steps, as the plugin meets them (a smaller working set of the
table than 40,000 independent twists: the blocks of 500 bodies, not of the whole table). Error: the largest difference
from the exact formula over the twists (force; torque / R). Fallback: the share of calls the table hands to the exact
formula. Build: best of 3 after a first (compiling) build.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
from numba import njit

from rrbody.physics.contact import footprint_wrench
from rrbody.physics.footprint_table import build_footprint_table, footprint_table_wrench, table_covers, table_reach

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "footprint_table"
TITLE = "Footprint wrench table vs the exact dry-friction formula"
A = 0.08  # m: the L's leg width (benchmarks/active.py)
V_EPS = 1e-6  # m/s
REPEATS = 9
BODIES = 500  # the L-shapes of the active benchmark's 1,000 bodies
# the active bound: plane friction + active force <= 30 % of pymunk's step, ~40 ns a body for friction
COST_TARGET_NS = 40.0


def _footprints() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    from rrbody.physics.footprint import combine, polygon_part
    from rrbody.physics.polygon import polygon_geometry

    legs = [np.array([(-A, -A), (A, -A), (A, 0.0), (-A, 0.0)]), np.array([(-A, 0.0), (0.0, 0.0), (0.0, A), (-A, A)])]
    geom = [polygon_geometry(p) for p in legs]
    g = sum(a * np.array([gx, gy]) for _, a, gx, gy, _ in geom) / sum(a for _, a, *_ in geom)
    lshape = combine([polygon_part(p - g) for p in legs])
    box = combine([polygon_part(np.array([(-A, -A / 2), (A, -A / 2), (A, A / 2), (-A, A / 2)]) + (0.03, 0.01))])
    return {"L": (lshape[0], lshape[1]), "box": (box[0], box[1])}


def stepped(V: np.ndarray, bodies: int, steps: int, seed: int) -> np.ndarray:
    """Twists as the plugin meets them: ``bodies`` twists of V, each drifting by a random 1 % per step
    (a step changes a body's motion little), for ``steps`` steps, body after body within a step."""
    rng = np.random.default_rng(seed)
    out = np.empty((steps, bodies, 3))
    cur = V[:bodies].copy()
    for k in range(steps):
        out[k] = cur
        cur = cur * (1.0 + 0.01 * rng.standard_normal(cur.shape))
    return np.ascontiguousarray(out.reshape(-1, 3))


def twists(R: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """n twists (vbx, vby, w) (m/s, rad/s) of the study's distribution and which are "near" (ICR in the disc)."""
    rng = np.random.default_rng(seed)
    near = rng.random(n) < 0.5
    sgn = rng.choice([-1.0, 1.0], n)
    r = 3.0 * R * np.sqrt(rng.random(n))
    a = rng.uniform(0.0, 2.0 * math.pi, n)
    w_near = sgn * 10.0 ** rng.uniform(-1.0, 2.0, n)
    cx, cy = r * np.cos(a), r * np.sin(a)
    sp = rng.uniform(0.05, 1.0, n)
    w_far = sgn * sp / R * 10.0 ** rng.uniform(-3.0, 0.0, n)
    V = np.where(near[:, None], np.column_stack([cy * w_near, -cx * w_near, w_near]),
                 np.column_stack([sp * np.cos(a), sp * np.sin(a), w_far]))
    return np.ascontiguousarray(V), near


# not cached: numba keys a cached function by its own file's time stamp alone, and these loops compile the
# table's kernel into themselves (a stale copy would read a table of another layout)
@njit
def _loop_table(T, shapes, geo, V, out):  # noqa: ANN001 (numba)
    for k in range(V.shape[0]):
        fx, fy, tq = footprint_table_wrench(T, 0, shapes, geo, 0, shapes.shape[0], V[k, 0], V[k, 1], V[k, 2], V_EPS)
        out[k, 0] = fx
        out[k, 1] = fy
        out[k, 2] = tq


@njit
def _loop_exact(shapes, geo, V, out):  # noqa: ANN001 (numba)
    for k in range(V.shape[0]):
        fx, fy, tq = footprint_wrench(shapes, geo, 0, shapes.shape[0], V[k, 0], V[k, 1], V[k, 2], V_EPS)
        out[k, 0] = fx
        out[k, 1] = fy
        out[k, 2] = tq


def _timed(T: np.ndarray, shapes: np.ndarray, geo: np.ndarray, V: np.ndarray, reps: int) -> tuple[float, float]:
    """Best ns per call of the table and of the exact formula over the twists V, interleaved."""
    out = np.empty((V.shape[0], 3))
    best = [math.inf, math.inf]
    for _ in range(reps):
        w0 = time.perf_counter()
        _loop_table(T, shapes, geo, V, out)
        best[0] = min(best[0], time.perf_counter() - w0)
        w0 = time.perf_counter()
        _loop_exact(shapes, geo, V, out)
        best[1] = min(best[1], time.perf_counter() - w0)
    return best[0] / V.shape[0] * 1e9, best[1] / V.shape[0] * 1e9


def run(out: Path, *, quick: bool = False) -> StudyResult:
    n = 5000 if quick else 40000
    reps = 3 if quick else REPEATS
    rows = []
    for name, (shapes, geo) in _footprints().items():
        s1 = shapes.shape[0]
        w0 = time.perf_counter()
        T = build_footprint_table(shapes, geo, 0, s1)  # the first build compiles the exact kernel's loop
        first = time.perf_counter() - w0
        build = math.inf
        for _ in range(1 if quick else 3):
            w0 = time.perf_counter()
            T2 = build_footprint_table(shapes, geo, 0, s1)
            build = min(build, time.perf_counter() - w0)
        if not np.array_equal(T, T2, equal_nan=True):
            raise RuntimeError(f"footprint table of {name} differs between two builds (it must be deterministic)")
        R = table_reach(shapes, geo, 0, s1)
        V, near = twists(R, n, seed=1)
        a, b = np.empty((n, 3)), np.empty((n, 3))
        _loop_table(T, shapes, geo, V, a)
        _loop_exact(shapes, geo, V, b)
        err_f = float(np.abs(a[:, :2] - b[:, :2]).max())
        err_t = float(np.abs(a[:, 2] - b[:, 2]).max() / R)
        covered = np.array([table_covers(T, 0, *v, V_EPS) for v in V])
        ns_t, ns_e = _timed(T, shapes, geo, V, reps)
        ns_tn, ns_en = _timed(T, shapes, geo, np.ascontiguousarray(V[near]), reps)
        ns_tf, ns_ef = _timed(T, shapes, geo, np.ascontiguousarray(V[~near]), reps)
        ns_ts, ns_es = _timed(T, shapes, geo, stepped(V, BODIES, n // BODIES, seed=2), reps)
        row = {"footprint": name, "reach_m": R, "build_s": build, "first_build_s": first, "table_mb": T.nbytes / 1e6,
               "rows": T.shape[0], "max_err_force": err_f, "max_err_torque_over_R": err_t,
               "fallback": 1.0 - float(covered.mean()), "fallback_near": 1.0 - float(covered[near].mean()),
               "fallback_far": 1.0 - float(covered[~near].mean()), "table_ns": ns_t, "exact_ns": ns_e,
               "speedup": ns_e / ns_t, "table_ns_near": ns_tn, "exact_ns_near": ns_en, "table_ns_far": ns_tf,
               "exact_ns_far": ns_ef, "table_ns_stepped": ns_ts, "exact_ns_stepped": ns_es, "twists": n}
        rows.append(row)
        print(f"[footprint_table] {name}: table {ns_t:.1f} ns vs exact {ns_e:.1f} ns per call ({ns_e / ns_t:.1f}x; "
              f"near {ns_tn:.1f} vs {ns_en:.1f}, far {ns_tf:.1f} vs {ns_ef:.1f}, stepped {ns_ts:.1f} vs {ns_es:.1f}), "
              f"fallback {row['fallback']:.2%}, "
              f"max error {err_f:.2g} / {err_t:.2g} R, build {build:.2f} s, {T.nbytes / 1e6:.2f} MB", flush=True)
    write_csv(out / "footprint_table.csv", rows)
    L = rows[0]
    worst = max(max(r["max_err_force"], r["max_err_torque_over_R"]) for r in rows)
    targets = [
        Target("footprint table: error vs footprint_wrench (L and box)", "<= 1e-10 (force; torque / R)",
               f"{worst:.2g} over {n} twists each", worst <= 1e-10),
        Target("footprint table: mean cost per call, L (active-benchmark twists)", f"<= {COST_TARGET_NS:g} ns",
               f"{L['table_ns']:.1f} ns vs exact {L['exact_ns']:.1f} ns ({L['speedup']:.1f}x; stepped "
               f"{L['table_ns_stepped']:.1f} vs {L['exact_ns_stepped']:.1f} ns); fallback {L['fallback']:.2%}; box "
               f"{rows[1]['table_ns']:.1f} vs {rows[1]['exact_ns']:.1f} ns",
               L["table_ns"] <= COST_TARGET_NS),
        Target("footprint table: build time and size, L", "<= ~1 s, <= 4 MB",
               f"{L['build_s']:.2f} s, {L['table_mb']:.2f} MB", L["build_s"] <= 1.0 and L["table_mb"] <= 4.0),
    ]
    if quick:
        targets = [Target(t.name, t.target, t.measured + " [quick]", None) for t in targets]
    cols = ["footprint", "table_ns", "exact_ns", "speedup", "table_ns_near", "exact_ns_near", "table_ns_far",
            "exact_ns_far", "table_ns_stepped", "exact_ns_stepped", "fallback", "fallback_near", "max_err_force",
            "max_err_torque_over_R", "build_s",
            "table_mb"]
    md = [f"## {TITLE}", "", __doc__.split("\n\n", 1)[1].strip(), "", machine_text(), "",
          md_table(cols, [[fmt(r[c]) for c in cols] for r in rows]), "",
          "Aims set when the table was built (kept out of the summary's targets table: no issue states them), "
          "measured in this run:", "",
          md_table(["target", "wanted", "measured", "verdict", "note"],
                   [(t.name, t.target, t.measured, t.verdict, t.note) for t in targets]), ""]
    return StudyResult(NAME, TITLE, targets=[], markdown="\n".join(md), files=["footprint_table.csv"],
                       extra={"highlights": [f"footprint table: the L's dry wrench in {L['table_ns']:.0f} ns per call "
                                             f"against {L['exact_ns']:.0f} ns exact, within {worst:.1g}"]})
