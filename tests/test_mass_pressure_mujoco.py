"""Pressure follows the mass on the MuJoCo adapter: a compiled model keeps each body's mass and centre
of mass (not its geoms' masses), so the footprint's load is centred on the centre of mass, by a linear
pressure where spreading it by area would not (or per-part masses given by hand); a centre of mass no
non-negative pressure holds is refused naming the body.

Exact reference (tests/test_mass_pressure.py): in pure translation the friction force is -mu m g v_hat
and the torque about the centre of gravity -mu m g (P x v_hat), zero when the centre of pressure P is
the centre of gravity.
"""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from rrbody import planar  # noqa: E402
from rrbody.model.pressure import uniform  # noqa: E402
from rrbody.mujoco import PlaneFriction  # noqa: E402
from rrbody.physics import contact as C  # noqa: E402
from rrbody.physics.footprint import apply_pressure  # noqa: E402

MU = 0.5
# gym-pusht's T in metres: a 0.12 x 0.03 bar and a 0.03 x 0.09 stem, 1 kg each, 1 cm thick
TEE = ('<body name="tee" pos="0 0 0.005"><freejoint/>'
       '<geom type="box" size="0.06 0.015 0.005" pos="0 0.015 0" mass="1"/>'
       '<geom type="box" size="0.015 0.045 0.005" pos="0 0.075 0" mass="1"/></body>')


def _model(body: str) -> tuple:
    xml = f'<mujoco><worldbody><geom name="floor" type="plane" size="5 5 .1"/>{body}</worldbody></mujoco>'
    m = mujoco.MjModel.from_xml_string(xml)
    return m, mujoco.MjData(m)


def _torque(f: PlaneFriction, v: tuple[float, float]) -> float:
    """Friction torque per unit load and mu g of the adapter's first body in pure translation v (m/s)."""
    return C.footprint_wrench(f._shapes, f._geo, 0, f._shapes.shape[0], v[0], v[1], 0.0, 0.0)[2]


def test_the_tee_is_pressed_under_its_centre_of_mass() -> None:
    m, d = _model(TEE)
    f = PlaneFriction(m, d, plane="floor", mu=MU)
    com = d.xipos[1][:2]
    assert com == pytest.approx([0.0, 0.045], abs=1e-15)  # MuJoCo's: midway between the two 1 kg boxes
    # the shapes are loaded by area and tilted (a compiled model has no per-geom masses): slopes on both
    assert np.all(f._shapes[:, C.SLOPE_Y] != 0.0)
    for v in ((1.0, 0.3), (0.0, -2.0)):
        # 1e-15 of the T's 0.12 m size: the rounding of the moment solve
        assert abs(_torque(f, v)) < 1e-15 * 0.12
    # spread by area the centre of pressure would be 30/7 mm below the centre of mass (the area centroid, at
    # (3.6 x 15 + 2.7 x 75) / 6.3 mm): torque P_y per unit load
    parts = [planar.box(0.12, 0.03, (0.0, 0.015 - com[1])), planar.box(0.03, 0.09, (0.0, 0.075 - com[1]))]
    sh, geo, *_ = apply_pressure(parts, uniform())
    assert C.footprint_wrench(sh, geo, 0, 2, 1.0, 0.0, 0.0, 0.0)[2] == pytest.approx(-0.03 / 7, rel=1e-12)


def test_per_part_masses_given_by_hand() -> None:
    """footprints= with per-part masses: each box presses with its own weight (shares 1/2), no tilt."""
    m, d = _model(TEE)
    mujoco.mj_forward(m, d)
    cy = d.xipos[1][1]
    feet = [planar.box(0.12, 0.03, (0.0, 0.015 - cy), mass=1.0), planar.box(0.03, 0.09, (0.0, 0.075 - cy), mass=1.0)]
    f = PlaneFriction(m, d, plane="floor", mu=MU, footprints={"tee": feet})
    assert f._shapes[:, C.LOAD_SHARE] == pytest.approx([0.5, 0.5], rel=1e-15)
    assert not np.any(f._shapes[:, [C.SLOPE_X, C.SLOPE_Y]])
    assert abs(_torque(f, (0.6, -0.8))) < 1e-15 * 0.12


@pytest.mark.parametrize("extra, words", [
    # a 10 kg ball on a rod 0.3 m out, above a 0.1 m plate: its centre of mass lies off the plate
    ('<geom type="sphere" size="0.02" pos="0.3 0 0.1" mass="10" contype="0" conaffinity="0"/>', ["body 'b'", "tip"]),
    # a cylinder's disk under a centre of mass 2 cm off its axis: no exact linear pressure on a disk
    (None, ["body 'b'", "circles"]),
])
def test_a_centre_of_mass_no_pressure_holds_is_refused(extra: str | None, words: list[str]) -> None:
    if extra is None:
        body = ('<body name="b" pos="0 0 0.01"><freejoint/><geom type="cylinder" size="0.05 0.01" mass="1"/>'
                '<geom type="sphere" size="0.01" pos="0.04 0 0.05" mass="1" contype="0" conaffinity="0"/></body>')
    else:
        body = (f'<body name="b" pos="0 0 0.01"><freejoint/><geom type="box" size="0.05 0.05 0.01" mass="1"/>'
                f'{extra}</body>')
    m, d = _model(body)
    condim = m.geom_condim.copy()
    with pytest.raises(ValueError) as err:
        PlaneFriction(m, d, plane="floor", mu=MU)
    for w in words:
        assert w in str(err.value), (w, str(err.value))
    assert np.array_equal(m.geom_condim, condim)  # nothing changed in the model
