"""Planar pushing in MuJoCo: a finger pushes a box off centre, rrbody's friction and MuJoCo's (no paper figure; mujoco).

A 0.2 m square box (2 cm thick, density 1000 kg/m^3, mu = 0.4) rests on a plane; a kinematic finger (a
MuJoCo mocap sphere of radius 1 cm) moves along +x at 0.1 m/s for 3 s, aimed 5 cm off the box's
centre line, so the box turns while the finger slides along its face, then draws back and the box
slides to rest. Once with rrbody.mujoco.PlaneFriction (the plane's contacts normal-only, the box's
exact footprint wrench), once with MuJoCo's own friction (condim 3, pyramidal cone), 1 ms steps.
Output: results/pushing/ (pushing.png, .svg: the box's outline every 0.25 s and the finger's path, top
view; summary.json: the final poses and the rest times).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import mujoco
import numpy as np

from rrbody.analysis.report import write_summary
from rrbody.mujoco import PlaneFriction
from rrbody.render.figures import save_figure

MU, DT, SPEED, PUSH, OFFSET, T_END = 0.4, 1e-3, 0.1, 3.0, 0.05, 4.0  # -, s, m/s, s, m, s
XML = f"""<mujoco><option timestep="{DT}"/><default><geom friction="{MU} 0.005 0.0001"/></default><worldbody>
<geom name="floor" type="plane" size="3 3 .1"/>
<body name="box" pos="0 0 0.01"><freejoint/><geom type="box" size="0.1 0.1 0.01" density="1000"/></body>
<body name="finger" mocap="true" pos="-0.125 {OFFSET} 0.01"><geom type="sphere" size="0.01"/></body>
</worldbody></mujoco>"""


def _push(exact: bool) -> dict:
    """Run the push; the box's pose (x, y, yaw) every step, the finger's x, and when the box came to rest."""
    m = mujoco.MjModel.from_xml_string(XML)
    d = mujoco.MjData(m)
    for _ in range(300):  # settle on MuJoCo's soft contact
        mujoco.mj_step(m, d)
    f = PlaneFriction(m, d, plane="floor", mu=MU, bodies=["box"]) if exact else None
    poses, fingers = [], []
    for k in range(int(T_END / DT)):
        # the finger moves along +x while pushing, then draws back out of the way
        d.mocap_pos[0, 0] += SPEED * DT if k * DT < PUSH else -SPEED * DT
        f.step() if f is not None else mujoco.mj_step(m, d)
        w, z = d.qpos[3], d.qpos[6]
        poses.append((d.qpos[0], d.qpos[1], 2.0 * math.atan2(z, w)))
        fingers.append(tuple(d.mocap_pos[0, :2]))
    return {"pose": np.array(poses), "finger": np.array(fingers),
            "rest_time_s": f.stop_time("box") if f is not None else None}


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    runs = {"rrbody (exact)": _push(True), "MuJoCo condim 3": _push(False)}
    fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    corners = np.array([(0.1, 0.1), (-0.1, 0.1), (-0.1, -0.1), (0.1, -0.1), (0.1, 0.1)])
    for (label, run), color in zip(runs.items(), ("tab:blue", "tab:orange")):
        every = int(0.25 / DT)
        for x, y, a in run["pose"][::every]:  # the box's outline every 0.25 s
            c, s = math.cos(a), math.sin(a)
            ax.plot(x + c * corners[:, 0] - s * corners[:, 1], y + s * corners[:, 0] + c * corners[:, 1],
                    color=color, lw=0.8, alpha=0.6)
        ax.plot(run["pose"][:, 0], run["pose"][:, 1], color=color, lw=2, label=f"{label}: centre")
    ax.plot(*runs["rrbody (exact)"]["finger"][: int(PUSH / DT)].T, "k--", lw=1, label="finger")
    ax.set(aspect="equal", xlabel="x (m)", ylabel="y (m)",
           title=f"a finger pushes a box {OFFSET * 100:.0f} cm off centre at {SPEED} m/s (mu = {MU})")
    ax.legend(loc="upper left", fontsize=8)
    save_figure(fig, out_dir, "pushing", force=force)
    summary = {label: {"final_pose": [round(float(v), 6) for v in run["pose"][-1]], "rest_time_s": run["rest_time_s"]}
               for label, run in runs.items()}
    write_summary(out_dir, summary, force=force)
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main(Path("results/pushing"))
