"""rrbody.mujoco.PlaneFriction: the issue's physics checks in MuJoCo (spin-down of a disk and a square
plate, the disk's stop ratio, a pure slide's stop distance), a tilted plane, a pushing finger, footprints
from geoms, bad input, and the import without the extra."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from rrbody import planar  # noqa: E402
from rrbody.contact import kernel as K  # noqa: E402
from rrbody.mujoco import PlaneFriction  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
G, MU, R, DT = 9.81, 0.5, 0.1, 1e-3
EPS_STAR = 0.653  # Farkas et al. (2003), the disk's stop ratio


def _prism(radius: float, half: float, k: int = 64) -> str:
    t = np.linspace(0.0, 2.0 * math.pi, k, endpoint=False)
    return " ".join(f"{radius * math.cos(a):.12f} {radius * math.sin(a):.12f} {z}" for z in (-half, half) for a in t)


def _model(body: str, *, tilt: float = 0.0, extra: str = "") -> tuple:
    """A plane (tilted about y by ``tilt`` rad) with one body on it, settled for 0.3 s."""
    xml = f"""<mujoco><option timestep="{DT}"/><asset><mesh name="prism" vertex="{_prism(R, 0.01)}"/></asset>
    <worldbody><geom name="floor" type="plane" size="5 5 .1" euler="0 {math.degrees(tilt)} 0"/>{body}{extra}
    </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    return m, d


# MuJoCo's cylinder-plane contact makes a spinning thin cylinder hop (measured 3 mm at 1 ms steps even
# without friction: docs/mujoco.md), which changes the normal load; a 64-gon prism mesh collides
# smoothly, its inertia set to the disk's and its footprint the exact circle
MASS = math.pi * R * R * 0.02 * 1000.0
DISK = (f'<body name="disk" pos="0 0 0.01"><freejoint/><inertial pos="0 0 0" mass="{MASS}" '
        f'diaginertia="{MASS * (3 * R * R + 4e-4) / 12} {MASS * (3 * R * R + 4e-4) / 12} {MASS * R * R / 2}"/>'
        f'<geom type="mesh" mesh="prism"/></body>')
PLATE = '<body name="plate" pos="0 0 0.01"><freejoint/><geom type="box" size="0.1 0.1 0.01" density="1000"/></body>'


def _run(f: PlaneFriction, name: str, steps: int) -> np.ndarray:
    """Rows (t, vx, vy, spin) from f.velocity after each step."""
    out = []
    for _ in range(steps):
        f.step()
        out.append((f.data.time, *f.velocity(name)))
    return np.array(out)


def _launched(body: str, name: str, v: tuple[float, float], w: float, *, footprint=None,  # noqa: ANN001
              **kw) -> PlaneFriction:
    m, d = _model(body, **{k: kw.pop(k) for k in ("tilt", "extra") if k in kw})
    for _ in range(300):  # settle on the plane (MuJoCo's soft contact)
        mujoco.mj_step(m, d)
    d.qvel[0:2] = v
    d.qvel[5] = w
    return PlaneFriction(m, d, plane="floor", mu=MU, footprints=None if footprint is None else {name: footprint}, **kw)


@pytest.mark.parametrize("body, name, footprint, rate", [
    (DISK, "disk", planar.circle(R), 4 * MU * G / (3 * R)),
    (PLATE, "plate", None, MU * G * (math.sqrt(2) + math.log1p(math.sqrt(2))) / 0.2),  # a = the side, 0.2 m
])
def test_spin_down_at_the_exact_rate(body: str, name: str, footprint, rate: float) -> None:  # noqa: ANN001
    """The issue's bound is 1 %; the staggered scheme is exact for constant deceleration, and MuJoCo's
    normal force is m g to 1e-5 (measured: the prism's contacts move as it turns), so the steps'
    deceleration matches to 1e-4."""
    f = _launched(body, name, (0.0, 0.0), 20.0, footprint=footprint)
    h = _run(f, name, int(20.0 / rate / DT) + 20)
    spin = h[:, 3]
    moving = spin > 0.05 * 20.0
    decel = -np.diff(spin)[moving[1:]] / DT
    assert np.median(decel) == pytest.approx(rate, rel=1e-4)
    assert np.all(np.abs(decel / rate - 1.0) < 1e-2)
    assert f.stop_time(name) == pytest.approx(0.3 + 20.0 / rate, abs=DT)  # launched at 0.3 s
    assert np.all(np.abs(h[-10:, 1:]) < 1e-8)  # at rest (MuJoCo's residue, below RESIDUE mu g dt)


def test_disk_stops_sliding_and_spinning_together_near_0653() -> None:
    """Launched at v/(R Omega) = 1: the ratio is attracted to 0.653 (slowly, ~Omega^0.23: the plugin's
    test) and both motions end in the same step. The issue's bound: within 2 % of 0.653."""
    f = _launched(DISK, "disk", (R * 20.0, 0.0), 20.0, footprint=planar.circle(R))
    h = _run(f, "disk", 1200)
    speed = np.hypot(h[:, 1], h[:, 2])
    spin_end = int(np.flatnonzero(np.abs(h[:, 3]) > 1e-6)[-1])
    slide_end = int(np.flatnonzero(speed > 1e-6)[-1])
    assert spin_end == slide_end  # the same step
    # the last steps are the limiter's and the rest rule's: there the impulse, not the flow, sets the ratio
    eps = speed[spin_end - 3] / (R * h[spin_end - 3, 3])
    assert abs(eps / EPS_STAR - 1.0) < 0.02, eps  # measured 0.6598 (1.0 %)


def test_pure_slide_stops_at_v0_squared_over_2_mu_g() -> None:
    """Second order in dt (the plugin's test): within mu g dt^2/8 (6e-7 m; measured 4.4e-8 m), plus 1e-6 m
    for MuJoCo's settling on its soft contact."""
    v0 = (1.0, 0.7)
    f = _launched(PLATE, "plate", v0, 0.0)
    x0 = f.data.qpos[:2].copy()
    _run(f, "plate", 400)
    d = float(np.hypot(*(f.data.qpos[:2] - x0)))
    exact = (v0[0] ** 2 + v0[1] ** 2) / (2 * MU * G)
    assert d == pytest.approx(exact, abs=MU * G * DT ** 2 / 8 + 1e-6)
    assert abs(d / exact - 1.0) < 0.01  # the bound
    assert f.stop_time("plate") - 0.3 == pytest.approx(math.hypot(*v0) / (MU * G), abs=DT)  # launched at 0.3 s
    # launched again by hand: restart() gives it the half kick back, and the slide is exact again
    f.data.qvel[0:2] = v0
    f.restart()
    x0 = f.data.qpos[:2].copy()
    _run(f, "plate", 400)
    assert float(np.hypot(*(f.data.qpos[:2] - x0))) == pytest.approx(exact, abs=MU * G * DT ** 2 / 8 + 1e-6)


def test_a_push_on_the_plane_adds_to_the_load_and_your_xfrc_stays_yours() -> None:
    """A box sliding under a steady downward push F (your xfrc_applied) decelerates at mu (g + F/m): the
    normal load is MuJoCo's contact force, m g + F (to its fluctuation, measured < 1e-6); after every step
    xfrc_applied holds your push bit for bit."""
    m, d = _model(PLATE)
    mass = float(m.body_mass[1])
    push = np.array([0.0, 0.0, -2.0 * mass * G, 0.0, 0.0, 0.0])  # pressing down with twice the weight
    d.xfrc_applied[1] = push
    for _ in range(300):  # MuJoCo's soft contact takes the load
        mujoco.mj_step(m, d)
    d.qvel[0] = 1.0
    f = PlaneFriction(m, d, plane="floor", mu=MU)
    f.step()
    assert f.normal_force("plate") == pytest.approx(3.0 * mass * G, rel=1e-6)
    h = _run(f, "plate", 40)
    assert np.median(np.diff(h[:, 1]) / DT) == pytest.approx(-3.0 * MU * G, rel=1e-4)
    assert np.array_equal(d.xfrc_applied[1], push)


def test_a_tilted_plane_holds_below_mu_static_and_slides_above() -> None:
    """On a plane tilted by theta, a box stays at rest if tan(theta) < mu_static; with tan(theta) > mu it
    slides down at g (sin - mu cos): the load is MuJoCo's normal force, m g cos (staggered scheme: exact
    for a constant acceleration, to MuJoCo's normal-force fluctuation, measured < 1e-6)."""
    for tilt, held in ((0.9 * math.atan(MU), True), (1.3 * math.atan(MU), False)):
        m, d = _model(PLATE, tilt=tilt)
        # the box turned with the plane (about y) and laid on it, its centre 0.01 m along the normal
        d.qpos[3:7] = [math.cos(tilt / 2), 0.0, math.sin(tilt / 2), 0.0]
        d.qpos[0:3] = [0.01 * math.sin(tilt), 0.0, 0.01 * math.cos(tilt)]
        f = PlaneFriction(m, d, plane="floor", mu=MU)
        t1 = f._frame[0]
        f.step(200)  # MuJoCo's soft contact settles (along the normal)
        assert f.normal_force("plate") == pytest.approx(m.body_mass[1] * G * math.cos(tilt), rel=1e-3)
        x0 = d.qpos[:3].copy()
        h = _run(f, "plate", 300)
        along = float((d.qpos[:3] - x0) @ t1)
        if held:
            assert abs(along) < 1e-12, along  # static friction holds it (measured 2e-17 m: rounding)
        else:
            a = G * (math.sin(tilt) - MU * math.cos(tilt))  # downhill is +t1 here
            assert np.median(np.diff(h[:, 1]) / DT) == pytest.approx(a, rel=1e-4)


def test_a_finger_pushes_a_box_against_exact_friction() -> None:
    """A kinematic finger (mocap sphere) pushes a box at 0.2 m/s: while pushed the box moves with it and
    friction is mu m g against the motion; released, it slides v^2/(2 mu g) further."""
    finger = ('<body name="finger" mocap="true" pos="-0.13 0 0.01"><geom type="sphere" size="0.02" '
              'contype="1" conaffinity="1"/></body>')
    m, d = _model(PLATE, extra=finger)
    for _ in range(300):
        mujoco.mj_step(m, d)
    f = PlaneFriction(m, d, plane="floor", mu=MU, bodies=["plate"])
    speed = 0.2
    for _ in range(1000):
        d.mocap_pos[0, 0] += speed * DT
        f.step()
    vx, vy, w = f.velocity("plate")
    mass = float(m.body_mass[m.body("plate").id])
    assert vx == pytest.approx(speed, rel=1e-3) and abs(vy) < 1e-6 and abs(w) < 1e-6
    fx, fy, _ = f.friction("plate")
    assert fx == pytest.approx(-MU * mass * G, rel=1e-3) and abs(fy) < 1e-6 * mass
    x_release = float(d.qpos[0])
    d.mocap_pos[0, 0] -= 0.05  # the finger draws back
    f.step(300)
    assert float(d.qpos[0]) - x_release == pytest.approx(speed ** 2 / (2 * MU * G), abs=2 * speed * DT)


def test_footprints_come_from_boxes_and_cylinders() -> None:
    body = ('<body name="two" pos="0 0 0.01"><freejoint/><geom type="box" size="0.1 0.05 0.01" pos="0.05 0 0" '
            'density="1000"/><geom type="cylinder" size="0.04 0.01" pos="-0.1 0 0" density="1000"/></body>')
    m, d = _model(body)
    f = PlaneFriction(m, d, plane="floor", mu=MU)
    assert f.bodies == ("two",)
    com = d.xipos[1][:2]
    feet = planar.Footprints([[planar.box(0.2, 0.1, (0.05 - com[0], -com[1])),
                               planar.circle(0.04, (-0.1 - com[0], -com[1]))]])
    shapes = feet._shapes
    assert np.allclose(f._shapes, shapes, atol=1e-12)
    Ri = d.ximat[1].reshape(3, 3)  # MuJoCo's principal axes: the moment about z is (Ri I Ri^T)_zz
    assert f._bodies[0, K.INERTIA_PER_MASS] == pytest.approx((Ri @ np.diag(m.body_inertia[1]) @ Ri.T)[2, 2]
                                                / m.body_mass[1], rel=1e-12)


@pytest.mark.parametrize("kw, words", [
    ({"plane": "nope"}, ["plane", "'nope'"]),
    ({"plane": "floor", "mu": -1.0}, ["mu", "-1"]),
    ({"plane": "floor", "mu": 0.5, "mu_static": 0.2}, ["mu_static", ">= mu"]),
    ({"plane": "floor", "mu": 0.5, "bodies": ["ghost"]}, ["bodies[0]", "'ghost'"]),
    ({"plane": "floor", "mu": 0.5, "touch": 0.0}, ["touch", "0"]),
    ({"plane": "floor", "mu": 0.5, "footprints": {"plate": "square"}}, ["footprints['plate']", "part"]),
    ({"plane": "floor", "mu": [0.5, 0.2]}, ["mu", "one per body (1)", "(2,)"]),
])
def test_bad_arguments_are_named(kw: dict, words: list[str]) -> None:
    m, d = _model(PLATE)
    with pytest.raises(ValueError) as e:
        PlaneFriction(m, d, **{"mu": 0.5, **kw})
    assert all(w in str(e.value) for w in words), str(e.value)
    assert list(m.geom_condim) == [3, 3] and list(m.geom_priority) == [0, 0]  # the model is left as it was


def test_the_plane_must_be_a_plane_and_rk4_is_refused() -> None:
    m, d = _model(PLATE)
    with pytest.raises(ValueError, match="plane must be a geom of type plane"):
        PlaneFriction(m, d, plane=m.body("plate").geomadr[0].item(), mu=0.5)
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    with pytest.raises(ValueError, match="RK4"):
        PlaneFriction(m, d, plane="floor", mu=0.5)


@pytest.mark.parametrize("bad", [-1e-3, 0.0, math.nan, math.inf])
def test_a_timestep_that_is_not_finite_and_positive_is_refused_before_anything_changes(bad: float) -> None:
    """A negative step ran time back (the box sped up) and a NaN one was blamed on the body's angle: refused,
    naming model.opt.timestep, its value and the valid range, at construction and at a step after a change
    (the adapter reads it each step), with the model and the data as they were."""
    m, d = _model(PLATE)
    d.qvel[0] = 1.0
    m.opt.timestep = bad
    with pytest.raises(ValueError) as e:
        PlaneFriction(m, d, plane="floor", mu=MU)
    assert all(w in str(e.value) for w in ("model.opt.timestep", repr(bad), "(0, inf) s")), str(e.value)
    assert list(m.geom_condim) == [3, 3] and list(m.geom_priority) == [0, 0]
    m.opt.timestep = DT
    f = PlaneFriction(m, d, plane="floor", mu=MU)
    f.step(5)
    state = [a.copy() for a in (d.qpos, d.qvel, d.xfrc_applied)] + [d.time]
    m.opt.timestep = bad
    for call in (f.step, lambda: f.velocity("plate")):
        with pytest.raises(ValueError, match=r"model\.opt\.timestep must be a finite number in \(0, inf\) s"):
            call()
    assert all(np.array_equal(a, b) for a, b in zip(state[:3], (d.qpos, d.qvel, d.xfrc_applied))) and d.time == state[3]


# contact settings under which MuJoCo rests a body at another depth once the plane's contacts keep their normal
# row only (rrbody.mujoco_adapter.seat): a pyramidal cone's edges are regularised by 2 mu^2 R (mu != 1; more
# edges; impratio), or the plane's priority replaces the two geoms' mixed solref/solimp; each slid 83 to 255
# times the bound off before the bodies were moved with the switch. The last two change nothing (controls).
SETTLED = [
    ('friction="0.5 0.005 0.0001"', "", ""),  # docs/mujoco.md's example
    ('friction="0.2"', "", ""), ('friction="1.5"', "", ""),
    ('friction="0.5" condim="4"', "", ""), ('friction="0.5" condim="6"', "", ""),
    ('friction="0.5"', 'impratio="10"', ""),
    ("", "", 'solref="0.05 1"'), ("", "", 'solimp="0.8 0.99 0.002"'),  # the box's own, not the plane's
    ('friction="0.5"', 'cone="elliptic"', ""), ("", "", ""),
]


@pytest.mark.parametrize("default, option, box", SETTLED)
def test_built_after_the_body_settled_under_any_contact_settings(default: str, option: str, box: str) -> None:
    """Settled with mj_step as docs/mujoco.md's example does, launched, then the adapter built: the slide
    stops at v0^2 / (2 mu g) within the documented mu g dt^2 / 8 (measured 2e-8 to 6e-8 m), and the normal
    force stays m g to 1e-5 (MuJoCo's fluctuation on a resting box, the spin-down test's), where the switch of
    the plane's contacts used to swing it by 2 to 6 %. Building reads a copy: data's time, the in-plane
    position and the velocities stay as they were."""
    xml = f"""<mujoco><option timestep="{DT}" {option}/><default><geom {default} density="1000"/></default>
    <worldbody><geom name="floor" type="plane" size="5 5 .1"/>
    <body name="plate" pos="0 0 0.01"><freejoint/><geom type="box" size="0.1 0.1 0.01" {box}/></body>
    </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, nstep=300)  # settled on the plane
    v0 = (1.0, 0.7)
    d.qvel[0:2] = v0
    before = d.time, d.qpos[:2].copy(), d.qvel.copy()
    f = PlaneFriction(m, d, plane="floor", mu=MU)
    assert d.time == before[0] and np.array_equal(d.qpos[:2], before[1])
    assert np.allclose(d.qvel, before[2], rtol=0.0, atol=1e-15)
    x0 = d.qpos[:2].copy()
    weight = float(m.body_mass[1]) * G
    loads = []
    for _ in range(400):
        f.step()
        loads.append(f.normal_force("plate") / weight)
    exact = (v0[0] ** 2 + v0[1] ** 2) / (2 * MU * G)
    assert float(np.hypot(*(d.qpos[:2] - x0))) == pytest.approx(exact, abs=MU * G * DT ** 2 / 8)
    assert np.max(np.abs(np.array(loads) - 1.0)) < 1e-5


def _python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)


def test_import_rrbody_never_imports_mujoco() -> None:
    p = _python("import sys, rrbody; rrbody.planar.circle(0.1); import rrbody.plugin; "
                "assert 'mujoco' not in sys.modules, 'mujoco imported'")
    assert p.returncode == 0, p.stderr[-2000:]


def test_without_the_extra_the_import_names_it_in_one_line() -> None:
    p = _python("import sys; sys.modules['mujoco'] = None\n"
                "try:\n    import rrbody.mujoco\nexcept ImportError as e:\n    print(e)\nelse:\n    print('imported')")
    assert p.returncode == 0, p.stderr[-2000:]
    lines = p.stdout.strip().splitlines()
    assert len(lines) == 1 and "[mujoco]" in lines[0] and "pip install" in lines[0], p.stdout


@pytest.mark.parametrize("block", [0, 1])
def test_the_pages_examples_run(block: int, tmp_path: Path) -> None:
    """docs/mujoco.md's two programs, as a reader copies them, in an empty folder; the second prints
    what the page says it prints (MuJoCo 4.0.0's own friction, rrbody's exact one)."""
    import re

    code = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "mujoco.md").read_text(), re.S)[block]
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    if block == 1:
        shown = re.search(r"```text\n(.*?)```", (ROOT / "docs" / "mujoco.md").read_text(), re.S).group(1)
        ours = [ln for ln in shown.splitlines() if ln.startswith("rrbody")]
        assert ours and ours[0] in p.stdout  # rrbody's line is reproducible to the millisecond


@pytest.mark.parametrize("steps", [(1e-3, 2e-3), (1e-3, 2e-3, 0.5e-3, 1.5e-3)])
def test_a_step_that_changes_size_keeps_the_slide_exact(steps: tuple[float, ...]) -> None:
    """model.opt.timestep changed between every step (alternating 1 and 2 ms, and an irregular cycle): the
    slide still stops at v0^2 / (2 mu g) within the documented mu g dt^2 / 8 for the largest step (plus 1e-6
    m for MuJoCo's settling, as with a constant step); without the resynchronised kick it stopped 3.3e-4 m
    long."""
    v0 = (1.0, 0.0)
    f = _launched(PLATE, "plate", v0, 0.0)
    x0 = f.data.qpos[:2].copy()
    for k in range(600):
        f.model.opt.timestep = steps[k % len(steps)]
        f.step()
    d = float(np.hypot(*(f.data.qpos[:2] - x0)))
    exact = v0[0] ** 2 / (2 * MU * G)
    assert d == pytest.approx(exact, abs=MU * G * max(steps) ** 2 / 8 + 1e-6)
