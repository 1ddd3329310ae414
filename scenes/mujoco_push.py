"""A T pushed in MuJoCo: its turn per unit travel against the step, on rrbody's split adapter (no paper figure; mujoco).

Does the MuJoCo adapter turn a pushed body right at the step Push-T runs? Its friction is an applied
wrench (``xfrc_applied``), computed before MuJoCo's contact solve and held fixed in it (docs/mujoco.md,
"Pushing: friction and contacts"). The push: gym-pusht's T (a 120 x 30 top bar and a 30 x 90 stem,
units of 1/600 m, so 0.2 x 0.05 m and 0.05 x 0.15 m, 1 cm thick; mass 1 kg, moment 3000 units^2 kg about
its centre of gravity at (0, 45) units, gym-pusht's; the load spread by area, made linear to centre it
there, as the adapter does) on a plane of exact friction mu = 0.3 or 0.6. A kinematic pusher (a MuJoCo
mocap sphere of radius 15 units at the T's mid-thickness, so a disk of radius 15 in the plane;
frictionless, it touches only the T) starts 0.5 units below the top bar's face at x = 60 (the bar's end)
and moves along +y at 10, 30 or 100 units/s. The measure is the T's rotation per unit travel of its
centre of gravity, read when that travel first reaches 3 and 30 units, at MuJoCo steps of 10, 1 and
0.1 ms (0.1 ms: the dt -> 0 limit of MuJoCo's soft contacts at its default solref). References: m b / I
(inertia alone, b = 60 units) and quasi-static pushing (the twist whose friction wrench balances the
push, from rrbody.planar: the limit surface); a control on a frictionless plane (MuJoCo alone).
Outputs: results/mujoco-push/ (pushes.csv; table.md, the table docs/mujoco.md shows; summary.json).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from rrbody.mujoco import PlaneFriction

UNIT = 1.0 / 600.0  # m per workspace unit (gym-pusht's 512-unit workspace is 0.85 m)
THICK = 0.01  # the T's thickness (m)
MASS, MOMENT, COG_Y = 1.0, 3000.0, 45.0  # kg; units^2 kg about the centre of gravity; units (gym-pusht's)
PUSHER_R, OFFSET, GAP = 15.0, 60.0, 0.5  # the pusher's radius, its x (the bar's end), its start below the face (units)
MUS, SPEEDS = (0.3, 0.6), (10.0, 30.0, 100.0)  # friction coefficients; push speeds (units/s)
DTS = (0.01, 0.001, 0.0001)  # MuJoCo steps (s): Push-T's, and two towards the limit
READS = (3.0, 30.0)  # the travel of the centre of gravity at which the turn per unit travel is read (units)
SETTLE = 0.2  # s on the plane before the pusher moves


def xml(dt: float) -> str:
    """The model: plane, T (two boxes, gym-pusht's inertia; about in-plane axes half of it, a thin plate's), mocap
    pusher; every contact normal-only (the pusher's is frictionless; the plane's friction is the adapter's)."""
    u, h = UNIT, THICK / 2
    i = MOMENT * u * u
    return f"""<mujoco><option timestep="{dt}"/><default><geom condim="1"/></default><worldbody>
<geom name="floor" type="plane" size="2 2 .1" contype="1" conaffinity="1"/>
<body name="tee" pos="0 0 {h}"><freejoint/>
 <inertial pos="0 {COG_Y * u} 0" mass="{MASS}" diaginertia="{i / 2} {i / 2} {i}"/>
 <geom type="box" size="{60 * u} {15 * u} {h}" pos="0 {15 * u} 0" contype="3" conaffinity="3"/>
 <geom type="box" size="{15 * u} {45 * u} {h}" pos="0 {75 * u} 0" contype="3" conaffinity="3"/></body>
<body name="pusher" mocap="true" pos="{OFFSET * u} {-(PUSHER_R + GAP) * u} {h}">
 <geom type="sphere" size="{PUSHER_R * u}" contype="2" conaffinity="2"/></body>
</worldbody></mujoco>"""


def push(mu: float | None, speed: float, dt: float, reads: tuple[float, ...] = READS) -> dict[float, float]:
    """One push: {travel (units): the T's turn per unit travel of its centre of gravity then (mrad/unit)}.
    ``mu`` None: a frictionless plane and MuJoCo's own step (the control)."""
    m = mujoco.MjModel.from_xml_string(xml(dt))
    d = mujoco.MjData(m)
    f = None if mu is None else PlaneFriction(m, d, plane="floor", mu=mu, bodies=["tee"])
    step = (lambda: mujoco.mj_step(m, d)) if f is None else f.step
    for _ in range(round(SETTLE / dt)):  # settled on the plane, the pusher clear
        step()
    ipos, R = m.body_ipos[1], np.zeros(9)

    def pose() -> tuple[np.ndarray, float]:
        """The centre of gravity in the plane (units) and the angle (rad), from qpos (MuJoCo's xipos is the
        step's start)."""
        mujoco.mju_quat2Mat(R, d.qpos[3:7])
        return (d.qpos[:2] + (R.reshape(3, 3) @ ipos)[:2]) / UNIT, 2.0 * math.atan2(d.qpos[6], d.qpos[3])

    c0, a0 = pose()
    out: dict[float, float] = {}
    # the contact at the bar's end moves ~2.8x as fast as the centre of gravity while the T turns at ~30 mrad/unit
    for _ in range(math.ceil((5.0 * max(reads) + GAP) / (speed * dt))):
        d.mocap_pos[0, 1] += speed * UNIT * dt
        step()
        c, a = pose()
        s = float(np.hypot(*(c - c0)))
        for r in reads:
            if r not in out and s >= r:
                out[r] = 1e3 * (a - a0) / s
        if len(out) == len(reads):
            return out
    raise RuntimeError(f"push mu={mu} speed={speed} dt={dt}: the T's centre of gravity never travelled "
                       f"{max(reads)} units (it reached {sorted(out)})")


def predictions() -> dict[str, float]:
    """Exact turns per unit travel (mrad/unit) at the start of the push: inertia alone, m b / I; quasi-static
    pushing, the twist (v_x, 1, w) whose friction wrench (rrbody.planar: the T's footprint from its centre
    of gravity, each bar pressing by its area's share, made linear to centre the load there) balances a
    frictionless push along +y through (b, -COG_Y): f_x = 0 and torque = b f_y; then w / |v| (any mu)."""
    from scipy.optimize import fsolve

    from rrbody import planar

    area = 120 * 30 + 30 * 90
    feet = planar.Footprints([[planar.box(120, 30, (0, 15 - COG_Y), mass=120 * 30 / area),
                               planar.box(30, 90, (0, 75 - COG_Y), mass=30 * 90 / area)]])

    def residual(z: np.ndarray) -> list[float]:
        force, torque = feet.wrench(angle=0.0, velocity=[[float(z[0]), 1.0]], spin=[float(z[1])], mu=1.0, load=1.0)
        return [float(force[0, 0]), float(torque[0] - OFFSET * force[0, 1])]

    vx, w = fsolve(residual, [0.0, OFFSET / 2000.0], xtol=1e-12)
    return {"m b / I (inertia)": 1e3 * MASS * OFFSET / MOMENT,
            "quasi-static (limit surface)": 1e3 * float(w) / math.hypot(float(vx), 1.0)}


def markdown(summary: dict[str, Any]) -> str:
    """The table docs/mujoco.md shows (from ``summary.json``): each push at each step, and the 10 ms step's
    error against 0.1 ms."""
    def cells(r: dict[str, Any]) -> list[str]:
        out = []
        for at in READS:
            v = [r[f"rate_{at:g}_dt_{dt:g}"] for dt in DTS]
            out += [f"{x:.3f}" for x in v] + [f"{100 * (v[0] / v[-1] - 1):+.2f} %"]
        return out

    steps = [f"{1e3 * dt:g} ms" for dt in DTS] + ["10 ms vs 0.1 ms"]
    head = ["mu", "push (units/s)"] + [f"{at:g} units: {s}" for at in READS for s in steps]
    rows = [[f"{r['mu']:g}", f"{r['speed']:g}", *cells(r)] for r in summary["pushes"]]
    rows += [["none (MuJoCo alone)", f"{r['speed']:g}", *cells(r)] for r in summary["control"]]
    rows += [[f"{name}, exact at the start", "any", *[f"{v:.3f}"] * len(DTS), "-", *["-"] * len(steps)]
             for name, v in summary["exact_mrad_per_unit"].items()]
    return "\n".join("| " + " | ".join(r) + " |" for r in [head, ["---"] * len(head), *rows]) + "\n"


def main(out_dir: Path, *, force: bool = True) -> None:
    from rrbody.analysis.report import write_summary, write_table
    from rrbody.model.io import atomic_write_text

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # every push at every step; the control (no table, MuJoCo alone) at the slowest speed
    rows, control = [], []
    for mu in (*MUS, None):
        for speed in SPEEDS if mu is not None else SPEEDS[:1]:
            r: dict[str, Any] = {"mu": mu, "speed": speed}
            for dt in DTS:
                r.update({f"rate_{at:g}_dt_{dt:g}": v for at, v in push(mu, speed, dt).items()})
            (rows if mu is not None else control).append(r)
            print(r)
    exact = predictions()
    names = list(rows[0])
    write_table(out_dir / "pushes.csv", names, [[r[c] for c in names] for r in rows + control], force=force,
                meta={"units": "mu (empty: frictionless plane, MuJoCo alone), speed units/s (1/600 m), rate mrad "
                               "per unit travel of the centre of gravity, read at travel 3 or 30 units, dt s",
                      "mujoco": mujoco.__version__})
    summary = {"unit_m": UNIT, "mus": MUS, "speeds_units_per_s": SPEEDS, "dts_s": DTS, "reads_units": READS,
               "mujoco": mujoco.__version__, "exact_mrad_per_unit": exact, "pushes": rows, "control": control}
    write_summary(out_dir, summary, force=force)
    atomic_write_text(out_dir / "table.md", markdown(summary), force=force, name="table.md")
    print(markdown(summary))


if __name__ == "__main__":
    main(Path("results/mujoco-push"))
