"""MuJoCo: its own plane friction against rrbody's exact wrench (rrbody.mujoco.PlaneFriction), and what the
adapter costs.

Accuracy: a disk (R = 0.1 m, 2 cm thick) and a square plate (side a = 0.2 m) on a plane, mu = 0.5, steps of
1 ms, settled for 0.3 s, then launched. Spin-down: launched spinning at 20 rad/s, the rate is the slope
of the spin against time between 90 % and 10 % of the launch spin, over the exact 4 mu g / (3 R) (disk)
and mu g (sqrt 2 + ln(1 + sqrt 2)) / a (plate). Stop ratio: the disk launched at v = R Omega (ratio 1);
v / (R Omega) read three steps before the first of the two ends (exact: attracted to 0.653, Farkas et al.
2003, approached slowly, and both end in the same step). MuJoCo's own
friction: condim 3, 4 and 6 with the pyramidal and the elliptic cone, friction "0.5 0.005 0.0001" (its
defaults for the torsional and rolling parts) on the disk as a cylinder geom and as a 64-gon prism mesh,
and on the plate as a box geom. The adapter: the same bodies, its footprint read from the geoms (a
circle for the cylinder, the square for the box) or, for the prism, given as the exact circle.
MuJoCo's cylinder-plane contact makes a spinning thin cylinder hop (millimetres, without friction too):
the adapter honours the normal load MuJoCo reports, so on the cylinder it inherits the hops.

Cost: 100 bodies (50 boxes, 50 cylinders, 0.5 m apart, mu = 0.05: sliding and spinning through the
measurement), MuJoCo's own step (condim 3, pyramidal: its default) against the adapter's step (the same
model, the plane's contacts normal-only, rrbody's wrench through xfrc_applied), blocks of 25 steps
interleaved in one run, the best block of each; then the same with every body at rest.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, write_csv

NAME = "mujoco"
TITLE = "MuJoCo: its plane friction against rrbody's exact wrench, and the adapter's cost"
R, A, MU, G, DT = 0.1, 0.2, 0.5, 9.81, 1e-3
EXACT = {"disk": 4 * MU * G / (3 * R), "plate": MU * G * (math.sqrt(2) + math.log1p(math.sqrt(2))) / A}
EPS_STAR = 0.653
N_COST, BLOCK = 100, 25


def _prism(k: int = 64) -> str:
    t = np.linspace(0.0, 2.0 * math.pi, k, endpoint=False)
    return " ".join(f"{R * math.cos(a):.12f} {R * math.sin(a):.12f} {z}" for z in (-0.01, 0.01) for a in t)


def _model(shape: str, condim: int, cone: str) -> tuple:
    import mujoco

    mass = math.pi * R * R * 0.02 * 1000.0
    geom = {"cylinder": f'<geom type="cylinder" size="{R} 0.01" density="1000"/>',
            "prism": (f'<inertial pos="0 0 0" mass="{mass}" diaginertia="{mass * (3 * R * R + 4e-4) / 12} '
                      f'{mass * (3 * R * R + 4e-4) / 12} {mass * R * R / 2}"/><geom type="mesh" mesh="prism"/>'),
            "box": f'<geom type="box" size="{A / 2} {A / 2} 0.01" density="1000"/>'}[shape]
    xml = f"""<mujoco><option timestep="{DT}" cone="{cone}"/><asset><mesh name="prism" vertex="{_prism()}"/></asset>
    <default><geom condim="{condim}" friction="{MU} 0.005 0.0001"/></default>
    <worldbody><geom name="floor" type="plane" size="5 5 .1"/>
    <body name="b" pos="0 0 0.01"><freejoint/>{geom}</body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    return m, mujoco.MjData(m)


def _run(shape: str, condim: int, cone: str, adapter: bool, v0: float, w0: float) -> np.ndarray:
    """Rows (t, speed, spin) of the body after it is launched, until both are below 1e-6 of the launch."""
    import mujoco

    from rrbody import planar
    from rrbody.mujoco import PlaneFriction

    m, d = _model(shape, condim, cone)
    for _ in range(300):
        mujoco.mj_step(m, d)
    d.qvel[0], d.qvel[5] = v0, w0
    t0 = d.time
    if adapter:
        feet = {"b": planar.circle(R)} if shape == "prism" else None
        f = PlaneFriction(m, d, plane="floor", mu=MU, footprints=feet)
        step = f.step

        def vel() -> tuple[float, float, float]:
            return f.velocity("b")
    else:
        def step() -> None:
            mujoco.mj_step(m, d)

        def vel() -> tuple[float, float, float]:
            return float(d.qvel[0]), float(d.qvel[1]), float(d.qvel[5])
    rows = []
    for _ in range(3000):
        step()
        vx, vy, w = vel()
        rows.append((d.time - t0, math.hypot(vx, vy), w))
        if math.hypot(vx, vy) < 1e-6 * max(v0, 1e-9) and abs(w) < 1e-6 * w0:
            break
    return np.array(rows)


def _rate(h: np.ndarray, w0: float) -> float:
    sel = (h[:, 2] < 0.9 * w0) & (h[:, 2] > 0.1 * w0)
    return float(-np.polyfit(h[sel, 0], h[sel, 2], 1)[0]) if sel.sum() > 3 else math.nan


def _stop_ratio(h: np.ndarray, v0: float, w0: float) -> float:
    """v / (R Omega) three steps before the first of the two motions ends (below 1e-6 of its launch
    value): the last steps are the limiter's and the rest rule's, where the impulse, not the flow,
    sets the ratio (the plugin's test reads it the same way)."""
    end = np.flatnonzero((h[:, 1] < 1e-6 * v0) | (np.abs(h[:, 2]) < 1e-6 * w0))
    k = (int(end[0]) if end.size else h.shape[0]) - 3
    return float(h[k, 1] / (R * abs(h[k, 2]))) if h[k, 2] != 0.0 else math.inf


def _cost_models(at_rest: bool) -> tuple:
    import mujoco

    from rrbody.mujoco import PlaneFriction

    def build() -> tuple:
        bodies = "".join(
            f'<body name="b{i}" pos="{(i % 10) * 0.5} {(i // 10) * 0.5} {0.02 if i % 2 else 0.05}"><freejoint/>'
            f'<geom type="{"cylinder" if i % 2 else "box"}" size="{".1 .02" if i % 2 else ".1 .1 .05"}" '
            f'density="1000" friction="0.05 0.005 0.0001"/></body>' for i in range(N_COST))
        m = mujoco.MjModel.from_xml_string(f'<mujoco><option timestep="0.002"/><worldbody><geom name="floor" '
                                           f'type="plane" size="50 50 .1" friction="0.05 0.005 0.0001"/>{bodies}'
                                           f'</worldbody></mujoco>')
        d = mujoco.MjData(m)
        for _ in range(200):
            mujoco.mj_step(m, d)
        if not at_rest:
            for i in range(N_COST):
                d.qvel[6 * i:6 * i + 2] = 0.3 * math.cos(i), 0.3 * math.sin(i)
                d.qvel[6 * i + 5] = 3.0 * math.sin(3.0 * i)
        return m, d

    m1, d1 = build()
    m2, d2 = build()
    f = PlaneFriction(m2, d2, plane="floor", mu=0.05)
    return (lambda: mujoco.mj_step(m1, d1)), f


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("mujoco")
    if not ok:
        return StudyResult(NAME, TITLE, skipped=f"mujoco not importable ({why}): pip install 'rrbody[mujoco]'")
    rows = []
    cases = [(f"MuJoCo condim {c}, {cone}", shape, c, cone, False) for c in (3, 4, 6)
             for cone in ("pyramidal", "elliptic") for shape in ("cylinder", "prism", "box")]
    cases += [("rrbody adapter", shape, 3, "pyramidal", True) for shape in ("cylinder", "prism", "box")]
    if quick:
        cases = [c for c in cases if c[2] == 3]
    for label, shape, c, cone, adapter in cases:
        body = "plate" if shape == "box" else "disk"
        h = _run(shape, c, cone, adapter, 0.0, 20.0)
        row = {"friction": label, "body": f"{body} ({shape})", "spin-down / exact": _rate(h, 20.0) / EXACT[body]}
        if body == "disk":
            h2 = _run(shape, c, cone, adapter, R * 20.0, 20.0)
            row["stop ratio v/(R Omega)"] = _stop_ratio(h2, R * 20.0, 20.0)
        else:
            row["stop ratio v/(R Omega)"] = math.nan
        rows.append(row)
        print(f"[mujoco] {label}, {row['body']}: spin-down {row['spin-down / exact']:.4f} x exact, "
              f"stop ratio {row['stop ratio v/(R Omega)']:.3f}", flush=True)
    write_csv(out / "mujoco.csv", rows)

    costs = {}
    for phase, at_rest in (("sliding", False), ("at rest", True)):
        own, f = _cost_models(at_rest)
        own()
        f.step(3)  # compiled kernels, first allocations: not counted
        best = [math.inf, math.inf]
        for _ in range(3 if quick else 9):  # interleaved: a block of each, the best of each kind
            w0 = time.perf_counter()
            for _ in range(BLOCK):
                own()
            best[0] = min(best[0], (time.perf_counter() - w0) / BLOCK)
            w0 = time.perf_counter()
            f.step(BLOCK)
            best[1] = min(best[1], (time.perf_counter() - w0) / BLOCK)
        costs[phase] = best
        print(f"[mujoco] cost, {N_COST} bodies {phase}: MuJoCo {best[0] * 1e6:.0f} us, adapter {best[1] * 1e6:.0f} us "
              f"({best[1] / best[0]:.2f}x)", flush=True)
    write_csv(out / "mujoco_cost.csv", [{"phase": k, "mujoco_step_us": v[0] * 1e6, "adapter_step_us": v[1] * 1e6,
                                         "ratio": v[1] / v[0]} for k, v in costs.items()])

    ours = {r["body"]: r for r in rows if r["friction"] == "rrbody adapter"}
    disk, plate = ours["disk (prism)"], ours["plate (box)"]
    cyl = ours["disk (cylinder)"]
    ratio = max(v[1] / v[0] for v in costs.values())
    theirs = [r for r in rows if r["friction"] != "rrbody adapter"]
    spread = (min(r["spin-down / exact"] for r in theirs), max(r["spin-down / exact"] for r in theirs))
    targets = [
        Target("adapter: disk spin-down rate, 4 mu g/(3R)", "within 1 %",
               f"{disk['spin-down / exact']:.5f} x exact (64-gon prism collision, circle footprint); "
               f"{cyl['spin-down / exact']:.4f} on MuJoCo's cylinder geom (its hops)",
               abs(disk["spin-down / exact"] - 1) < 0.01),
        Target("adapter: square plate spin-down, mu g (sqrt2 + ln(1+sqrt2))/a", "within 1 %",
               f"{plate['spin-down / exact']:.5f} x exact", abs(plate["spin-down / exact"] - 1) < 0.01),
        Target("adapter: disk stop ratio v/(R Omega)", "within 2 % of 0.653",
               f"{disk['stop ratio v/(R Omega)']:.4f} (launched at 1; read 3 steps before the stop)",
               abs(disk["stop ratio v/(R Omega)"] / EPS_STAR - 1) < 0.02),
        Target(f"adapter cost, {N_COST} bodies", "<= 1.5x MuJoCo's own step",
               "; ".join(f"{k}: {v[1] * 1e6:.0f} vs {v[0] * 1e6:.0f} us ({v[1] / v[0]:.2f}x)" for k,
                         v in costs.items()),
               ratio <= 1.5),
    ]
    if quick:
        targets = [Target(t.name, t.target, t.measured + " [quick]", None) for t in targets]
    table = md_table(["friction", "body", "spin-down / exact", "stop ratio v/(R Omega)"],
                     [(r["friction"], r["body"], f"{r['spin-down / exact']:.4f}",
                       "-" if math.isnan(r["stop ratio v/(R Omega)"]) else f"{r['stop ratio v/(R Omega)']:.4g}")
                      for r in rows])
    md = [f"## {TITLE}", "", __doc__.split("\n\n", 1)[1].strip(), "", machine_text(), "", table, "",
          md_table(["phase", "MuJoCo step (us)", "adapter step (us)", "ratio"],
                   [(k, fmt(v[0] * 1e6), fmt(v[1] * 1e6), fmt(v[1] / v[0])) for k, v in costs.items()]), ""]
    return StudyResult(NAME, TITLE, targets=targets, markdown="\n".join(md), files=["mujoco.csv", "mujoco_cost.csv"],
                       extra={"highlights": [f"MuJoCo's own friction spins a disk or a plate down at "
                                             f"{spread[0]:.2f}-{spread[1]:.2f}x the exact rate; the adapter at "
                                             f"{disk['spin-down / exact']:.4f}x, costing {ratio:.2f}x MuJoCo's step"]})
