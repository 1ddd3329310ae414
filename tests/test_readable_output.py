"""Human-readable output reads well: numbers in sentences are rounded and never ``None``, values are
echoed as they were typed, an angle expression out of range is reported as typed with its value in
rad, the scene list is one column, and the MuJoCo adapter's and the polygon's messages say what holds."""

from __future__ import annotations

import json
import math

import pytest

from rrbody.cli.main import main

ROD = ["--H", "0.2", "--k", "0.05", "--omega", "0.6"]
DISK = ["--body", "disk", "--R0", "0.1", "--no-drive", "--v0", "1,0", "--spin0", "5", "--mu", "0.2"]


def test_a_free_body_says_when_it_came_to_rest(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["simulate", *DISK, "--t-max", "5"]) == 0
    text = capsys.readouterr().out
    assert "stop time 0.571705 s" in text, text  # 6 digits, not 0.5717050384572355
    assert main(["simulate", *DISK, "--t-max", "0.1"]) == 0
    text = capsys.readouterr().out
    assert "still moving at t = 0.1 s (no stop time)" in text and "None" not in text, text


def test_a_driven_run_rounds_its_numbers_in_the_sentence(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["simulate", *ROD, "--t-max", "1"]) == 0
    text = capsys.readouterr().out
    assert "H=0.2," in text and "lowest phi in this span 3.141592654 rad at t=0 s" in text, text


@pytest.mark.parametrize("command", [["flip-time"], ["simulate", "--t-max", "1"], ["lyapunov", "--t-max", "20"]])
def test_H_and_k_are_echoed_as_typed(command: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    """--H 0.2 --k 0.05 --d 0.7 come back 0.2 and 0.05, not the 0.19999999999999998 and
    0.049999999999999996 that the scene derives from l = H d and the friction's coefficient."""
    from rrbody.model.scene import scene_from_params

    derived = scene_from_params(H=0.2, k=0.05, omega=0.6, d=0.7)
    assert (derived.H, derived.k) != (0.2, 0.05)  # what this test is about: the scene's values differ
    assert main([*command, *ROD, "--d", "0.7", "--json"]) == 0
    raw = capsys.readouterr().out
    out = json.loads(raw)
    echo = out["scene"] if command[0] == "simulate" else out
    assert (echo["H"], echo["k"]) == (0.2, 0.05)
    assert repr(derived.H) not in raw and repr(derived.k) not in raw


def test_a_derived_H_is_the_scenes(capsys: pytest.CaptureFixture[str]) -> None:
    """A disk's H is not typed: it is derived from l, R0 and d, and echoed as computed."""
    from rrbody.model.scene import scene_from_params

    argv = ["--body", "disk", "--R0", "0.4036", "--l", "0.2", "--omega", "0.6", "--k", "0.0033"]
    assert main(["flip-time", *argv, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["H"] == scene_from_params(body="disk", R0=0.4036, l=0.2, omega=0.6, k=0.0033).H


@pytest.mark.parametrize("typed,rad", [("100deg", "1.74533"), ("-pi/4", "-0.785398"), ("3pi/4", "2.35619")])
def test_an_angle_out_of_range_is_reported_as_typed(typed: str, rad: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["flip-time", *ROD, f"--tilt={typed}"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"rrbody flip-time: error: --tilt must be in [0, 1.5708) rad, got {typed} ({rad} rad)"


def test_an_angle_in_range_typed_as_an_expression_passes() -> None:
    from rrbody.cli.args import parse
    from rrbody.cli.main import build_parser

    args = parse(build_parser(), ["flip-time", *ROD, "--tilt", "10deg"])
    assert args.tilt == math.radians(10)


def test_the_scene_list_is_one_column(capsys: pytest.CaptureFixture[str]) -> None:
    from rrbody.cli.scenes import list_scenes

    assert main(["scene", "--list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(list_scenes())
    starts = {len(ln) - len(ln[len(ln.split()[0]):].lstrip()) for ln in lines}  # where each description begins
    assert len(starts) == 1, starts
    assert min(len(ln) - len(ln.lstrip()) for ln in lines) == 0


def test_a_polygon_of_either_orientation_and_the_message_says_so() -> None:
    from rrbody.model.bodies import Polygon

    square = ((0.1, 0.1), (-0.1, 0.1), (-0.1, -0.1), (0.1, -0.1))
    assert set(Polygon(vertices=square).vertices) == set(Polygon(vertices=square[::-1]).vertices)  # either way
    with pytest.raises(ValueError, match=r"convex polygon \(every turn the same way, all left or all right\)") as e:
        Polygon(vertices=((0, 0), (2, 0), (1, 0.1), (1, 1)))
    assert "counter-clockwise" not in str(e.value)


# ---- the MuJoCo adapter ----------------------------------------------------------------------------
PLATE = ('<mujoco><option timestep="0.001"/><worldbody><geom name="floor" type="plane" size="5 5 .1"/>'
         '<body name="plate" pos="0 0 0.01"><freejoint/><geom type="box" size="0.1 0.1 0.01" density="1000"/>'
         '</body></worldbody></mujoco>')


def _plate() -> object:
    mujoco = pytest.importorskip("mujoco")
    from rrbody.mujoco import PlaneFriction

    m = mujoco.MjModel.from_xml_string(PLATE)
    d = mujoco.MjData(m)
    return PlaneFriction(m, d, plane="floor", mu=0.5)


@pytest.mark.parametrize("n", [-1, 1.5, True, "2", math.nan])
def test_mujoco_step_names_a_bad_n(n: object) -> None:
    f = _plate()
    t0 = f.data.time  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match=r"^n must be an integer in \[0, inf\], got "):
        f.step(n)  # type: ignore[attr-defined]
    assert f.data.time == t0  # type: ignore[attr-defined]


def test_mujoco_step_counts_whole_steps() -> None:
    f = _plate()
    f.step(0)  # type: ignore[attr-defined]
    assert f.data.time == 0.0  # type: ignore[attr-defined]
    f.step(3.0)  # type: ignore[attr-defined]  # an integral float counts, as everywhere in rrbody
    assert f.data.time == pytest.approx(0.003)  # type: ignore[attr-defined]


def test_mujoco_nan_message_names_the_body_once() -> None:
    f = _plate()
    f.data.qvel[5] = math.nan  # type: ignore[attr-defined]
    with pytest.raises(ValueError) as e:
        f.step()  # type: ignore[attr-defined]
    assert str(e.value).startswith("body 'plate': angle, velocity and spin must be finite"), str(e.value)
    assert "body body" not in str(e.value)
