"""Polygon bodies in rrbody's scenes: a box or any convex polygon, driven or free, on the
ODE path with the same exact polygon wrench the plugin uses, so t_f and H_c can be asked of squares
and triangles."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from rrbody.analysis.simulate import simulate
from rrbody.model.bodies import Polygon
from rrbody.model.scene import Scene, scene_from_params
from rrbody.physics.polygon import box_spin_torque

G = 9.81


def test_polygon_mass_properties_are_exact() -> None:
    """Area and I_cm / m against the closed forms: a w x h box (w^2 + h^2) / 12, an equilateral
    triangle of circumradius R: R^2 / 4 (rounding)."""
    b = Polygon.box(0.2, 0.1)
    assert b.area == pytest.approx(0.02, rel=1e-14)
    assert b.inertia_per_mass == pytest.approx((0.04 + 0.01) / 12, rel=1e-14)
    t = Polygon.regular(3, 0.1)
    assert t.area == pytest.approx(3 * math.sqrt(3) / 4 * 0.01, rel=1e-14)
    assert t.inertia_per_mass == pytest.approx(0.0025, rel=1e-14)
    # the centroid becomes the CM, the order counter-clockwise
    off = Polygon(vertices=((1.0, 1.0), (1.0, 1.2), (1.4, 1.2), (1.4, 1.0)))
    assert np.allclose(np.mean(off.outline(), axis=0), 0.0, atol=1e-15) and off.area > 0


def test_free_box_spins_down_at_the_exact_rate_on_the_ode_path() -> None:
    """Pure spin: mu g (sqrt 2 + ln(1 + sqrt 2)) / a, exactly (the integrator's tolerance; measured 7e-16 rad)."""
    a, mu, w0 = 0.2, 0.5, 10.0
    alpha = mu * G * box_spin_torque(a) / (a * a / 6)
    tr = simulate(scene_from_params(body="box", R0=a / 2, no_drive=True, spin0=w0, mu=mu, g=G, t_max=0.9 * w0 / alpha))
    assert np.max(np.abs(tr.body_angle - (w0 * tr.t - 0.5 * alpha * tr.t ** 2))) < 1e-10


def test_free_box_on_both_paths_agrees_at_second_order() -> None:
    """Sliding and spinning: pymunk's Poly.create_box in the plugin approaches the ODE path's box 4x
    closer per halving of dt."""
    a, mu, v0, w0, T = 0.2, 0.3, (1.0, 0.4), 6.0, 0.25
    ode = simulate(scene_from_params(body="box", R0=a / 2, no_drive=True, v0=v0, spin0=w0, mu=mu, g=G, t_max=T))
    want = np.array([ode.x_cm[-1], ode.y_cm[-1], ode.body_angle[-1]])
    from tests.plugin_orders import plugin_errors

    errs, rates = plugin_errors(lambda b: pymunk.Poly.create_box(b, (a, a)), want, v0=v0, w0=w0, T=T,
                                dts=(2e-3, 1e-3, 5e-4), plane={"g": G}, add={"mu": mu})
    assert all(1.7 < r < 2.3 for r in rates), (errs, rates)


def test_driven_box_on_the_engine_path_converges_to_the_ode_path() -> None:
    """A driven box (P off the centre) over 40 s: the engine path's phi approaches the ODE path's at
    second order in dt (one description of the scene feeds both)."""
    sc = scene_from_params(body="box", R0=0.1, delta=0.2, l=0.05, omega=1.0, k=0.05, t_max=40.0)
    ode = simulate(sc).phi[-1]
    errs = [abs(simulate(sc, method="engine", dt=dt).phi[-1] - ode) for dt in (2e-3, 1e-3)]
    assert 3.0 < errs[0] / errs[1] < 5.0, errs


def test_flip_times_of_a_square_and_a_triangle() -> None:
    """The paper's question asked of polygons: a flip exists, and the description round-trips."""
    from rrbody.analysis.flip import flip_time

    for body, kw in (("box", {"R0": 0.1}), ("polygon", {"sides": 3, "R0": 0.1})):
        sc = scene_from_params(body=body, l=0.05, omega=1.0, k=0.05, **kw)
        assert Scene.from_description(sc.describe()).body == sc.body
        r = flip_time(sc)
        assert r.reverse_rotation and 0.0 < r.t_f < 100.0


@pytest.mark.parametrize(("kw", "match"), [
    ({"body": "polygon", "R0": 0.1}, r"polygon needs sides \(with R0\) or vertices, one of them: got neither"),
    ({"body": "polygon", "sides": 2, "R0": 0.1}, r"sides must be an integer in \[3, 1000\] \(dimensionless\), got 2"),
    ({"body": "polygon", "vertices": ((0, 0), (1, 0), (0, 1), (1, 1))}, r"vertices must enclose a positive area"),
    ({"body": "polygon", "vertices": ((0, 0), (2, 0), (1, 0.1), (1, 1))}, r"vertices must make a convex polygon"),
    ({"body": "disk", "R0": 0.1, "sides": 4}, r"sides and vertices apply to body='polygon'"),
    ({"body": "box", "R0": 0.1, "friction_method": "icr"},
     r"friction_method must be 'auto' or 'contact' for a polygon"),
])
def test_bad_polygons_name_the_parameter(kw: dict, match: str) -> None:
    from rrbody.physics.bind import kernel_params

    with pytest.raises(ValueError, match=match):
        kernel_params(scene_from_params(no_drive=True, mu=0.3, **kw))


def test_cli_polygons() -> None:
    from tests.clirun import run_many

    ok, tri, bad = run_many([
        ["flip-time", "--body", "box", "--R0", "0.1", "--l", "0.05", "--omega", "1", "--k", "0.05", "--json"],
        ["simulate", "--body", "polygon", "--vertices", "0,0;0.2,0;0.1,0.15", "--no-drive", "--spin0", "3", "--mu",
         "0.3", "--t-max", "0.2", "--json"],
        ["simulate", "--body", "polygon", "--vertices", "0,0;a,b", "--no-drive", "--mu", "0.3", "--json"],
    ])
    assert ok.code == 0 and '"t_f"' in ok.out, ok.err
    assert tri.code == 0, tri.err
    assert bad.code == 2 and bad.err.count("\n") == 1 and "--vertices must be X,Y;X,Y" in bad.err
