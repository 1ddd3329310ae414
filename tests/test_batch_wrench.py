"""rrbody.planar: the batched friction wrench against an independent brute-force quadrature on random
convex polygons, against the disk's closed forms (4/3 and 0.653), frames, unions, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial import ConvexHull

from rrbody import planar
from rrbody.physics import contact as C
from rrbody.physics.footprint import combine


def _random_convex(rng: np.random.Generator) -> np.ndarray:
    """A random convex polygon (3 to 9 vertices, size ~0.1 to 0.3 m) around a random offset."""
    pts = rng.normal(size=(rng.integers(3, 12), 2)) * rng.uniform(0.05, 0.2, size=2)
    hull = pts[ConvexHull(pts).vertices]
    return hull + rng.uniform(-0.05, 0.05, size=2)


def _brute(vertices: np.ndarray, v: tuple[float, float], w: float, k: int) -> np.ndarray:
    """(fx, fy, tq) per unit load and mu of uniform pressure on the polygon, from its own centroid-rule
    sum: a fan of triangles from vertex 0, each cut into k^2 similar triangles, v_hat at each centroid.
    Independent of rrbody's kernels (no instantaneous centre, no closed form)."""
    i, j = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
    up = i + j < k  # the upward sub-triangles (i, j) and the downward ones (i + j < k - 1)
    down = i + j < k - 1
    bary = np.concatenate([np.stack([i[up] + 1 / 3, j[up] + 1 / 3], 1),
                           np.stack([i[down] + 2 / 3, j[down] + 2 / 3], 1)]) / k
    total = np.zeros(3)
    area = 0.0
    p0 = vertices[0]
    for a, b in zip(vertices[1:-1], vertices[2:]):
        tri = abs((a[0] - p0[0]) * (b[1] - p0[1]) - (a[1] - p0[1]) * (b[0] - p0[0])) / 2
        s = p0 + bary[:, :1] * (a - p0) + bary[:, 1:] * (b - p0)
        ux = v[0] - w * s[:, 1]
        uy = v[1] + w * s[:, 0]
        sp = np.hypot(ux, uy)
        hx, hy = -ux / sp, -uy / sp
        dA = tri / (k * k)  # every sub-triangle has the same area
        total += dA * np.array([hx.sum(), hy.sum(), (s[:, 0] * hy - s[:, 1] * hx).sum()])
        area += tri
    return total / area


def test_random_convex_polygons_match_a_brute_force_quadrature() -> None:
    """The centroid rule converges at second order (v_hat is smooth but at the instantaneous centre,
    whose cell adds O(h^2) of either sign): its error at 2k is about its change from k to 2k over 3.
    The cell holding the centre makes single components converge unevenly, so the tolerance is the
    largest component's change (max norm), measured per case: the ratio is 1/3 (second order) in 9
    of the 12 cases, 0.76 at worst."""
    rng = np.random.default_rng(27)
    polys, cases = [], []
    for _ in range(12):
        poly = _random_convex(rng)
        # the centre of gravity at the origin: the API's parts are given from it
        part = planar.polygon(poly)
        g = np.array(part[4])
        poly = poly - g
        v = rng.normal(size=2) * rng.choice([0.01, 0.3, 2.0])  # centre of rotation inside, near, outside
        w = rng.normal() * 5.0
        polys.append(planar.polygon(poly))
        cases.append((poly, v, w))
    feet = planar.Footprints(polys)
    vel = np.array([c[1] for c in cases])
    force, torque = feet.wrench(0.0, vel, [c[2] for c in cases])
    for n, (poly, v, w) in enumerate(cases):
        coarse = _brute(poly, tuple(v), w, 150)
        fine = _brute(poly, tuple(v), w, 300)
        tol = np.max(np.abs(fine - coarse)) + 1e-12  # + rounding of the sums (~1e-13 measured)
        got = np.array([*force[n], torque[n]])
        assert np.max(np.abs(got - fine)) <= tol, (n, got, fine, tol)


def test_angle_turns_the_footprint() -> None:
    """A body turned by angle a: the wrench equals the unturned body's at the velocity turned back, turned by a."""
    rng = np.random.default_rng(5)
    poly = _random_convex(rng)
    poly = poly - np.array(planar.polygon(poly)[4])
    a = 0.7
    c, s = math.cos(a), math.sin(a)
    turned = poly @ np.array([[c, s], [-s, c]])  # the vertices turned by a
    feet = planar.Footprints([planar.polygon(poly), planar.polygon(turned)])
    v = np.array([0.3, -0.2])
    vb = np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1]])
    f, t = feet.wrench([a, 0.0], [v, v], 2.0)
    f0, t0 = feet.wrench([0.0, 0.0], [vb, vb], 2.0)
    assert f[0] == pytest.approx([c * f0[0, 0] - s * f0[0, 1], s * f0[0, 0] + c * f0[0, 1]], abs=1e-14)
    assert t[0] == pytest.approx(t0[0], abs=1e-14)
    assert f[1] == pytest.approx(f[0], abs=1e-12) and t[1] == pytest.approx(t[0], abs=1e-12)  # near/far forms: ~1e-15


def test_disk_spins_down_at_four_thirds_mu_g_over_r() -> None:
    """A uniform disk in pure spin: torque (2/3) mu N R, so with I = m R^2/2 the spin falls at
    4 mu g / (3 R) (the instantaneous-centre quadrature: ~5e-12, contact.py)."""
    R, mu, m, g = 0.1, 0.5, 2.0, 9.81
    f, t = planar.Footprints([planar.circle(R)]).wrench(0.3, [[0.0, 0.0]], 7.0, mu=mu, load=m * g)
    assert np.all(np.abs(f) < 1e-12)
    assert -t[0] / (m * R * R / 2) == pytest.approx(4 * mu * g / (3 * R), rel=1e-10)


def test_disk_stop_ratio_is_farkas_0653() -> None:
    """Slide and spin end together at v/(R Omega) = eps* with F(eps) = 2 eps T(eps)/R (the ratio's rate
    vanishes; Farkas et al. 2003: 0.653, to its 3 figures)."""
    R = 0.1
    feet = planar.Footprints([planar.circle(R)])

    def rate(eps: float) -> float:
        f, t = feet.wrench(0.0, [[eps * R, 0.0]], 1.0)
        return -f[0, 0] - 2 * eps * (-t[0]) / R

    assert brentq(rate, 0.1, 2.0, xtol=1e-12) == pytest.approx(0.653, abs=5e-4)


def test_a_union_is_the_area_weighted_sum_of_its_parts() -> None:
    parts = [planar.box(0.2, 0.1, (0.05, 0.0)), planar.circle(0.05, (-0.1, 0.02))]
    areas = np.array([p[2] for p in parts])
    feet = planar.Footprints([parts, parts[0], parts[1]])
    f, t = feet.wrench(0.4, np.tile([0.2, -0.1], (3, 1)), 3.0, load=[1.0, areas[0], areas[1]])
    assert f[0] * areas.sum() == pytest.approx(f[1] + f[2], abs=1e-14)
    assert t[0] * areas.sum() == pytest.approx(t[1] + t[2], abs=1e-14)
    # the same rows as the plugin's own footprint of the union (one kernel)
    shapes, _, _, _, _ = combine(parts)
    assert np.array_equal(feet._shapes[feet._ranges[0, 0]:feet._ranges[0, 1], C.KIND], shapes[:, C.KIND])


def test_pressure_profiles_per_body() -> None:
    """A ring of radius R: the whole load at distance R, so pure spin gives torque mu N R exactly."""
    feet = planar.Footprints([planar.circle(0.1), planar.circle(0.1)], pressure=["uniform", "ring:0.08"])
    _, t = feet.wrench(0.0, np.zeros((2, 2)), -4.0, mu=0.5, load=2.0)
    assert t == pytest.approx([0.5 * 2.0 * 0.1 * 2 / 3, 0.5 * 2.0 * 0.08], rel=1e-10)


def test_no_slip_no_friction_and_scaling() -> None:
    feet = planar.Footprints([planar.box(0.1, 0.1), planar.point(0.01, 0.0)])
    f, t = feet.wrench([0.0, 1.0], np.zeros((2, 2)), [0.0, 0.0], mu=0.3, load=10.0)
    assert np.all(f == 0.0) and np.all(t == 0.0)
    f1, t1 = feet.wrench(0.2, [[1.0, 0.5], [0.0, 1.0]], 2.0)
    f2, t2 = feet.wrench(0.2, [[1.0, 0.5], [0.0, 1.0]], 2.0, mu=[0.5, 0.2], load=[3.0, 7.0])
    assert f2 == pytest.approx(f1 * np.array([[1.5], [1.4]]), rel=1e-14)
    assert t2 == pytest.approx(t1 * np.array([1.5, 1.4]), rel=1e-14)


@pytest.mark.parametrize("call, words", [
    (lambda f: f.wrench(0.0, [[1.0, 0.0]], 0.0), ["velocity", "(2, 2)", "(1, 2)"]),
    (lambda f: f.wrench(0.0, np.zeros((2, 2)), [0.0, math.nan]), ["spin[1]", "finite", "nan"]),
    (lambda f: f.wrench([0.0, math.inf], np.zeros((2, 2)), 0.0), ["angle[1]", "finite", "inf"]),
    (lambda f: f.wrench(0.0, np.zeros((2, 2)), 0.0, mu=-0.1), ["mu[0]", ">= 0", "-0.1"]),
    (lambda f: f.wrench(0.0, np.zeros((2, 2)), 0.0, load=[1.0, -2.0]), ["load[1]", ">= 0", "-2"]),
    (lambda f: f.wrench(0.0, np.zeros((2, 2)), 0.0, load=[1.0, 2.0, 3.0]), ["load", "(2,)", "(3,)"]),
    (lambda f: f.wrench(0.0, np.zeros((2, 2)), 0.0, v_eps=-1.0), ["v_eps", "-1"]),
])
def test_bad_arguments_are_named(call, words) -> None:  # noqa: ANN001
    feet = planar.Footprints([planar.circle(0.1), planar.box(0.1, 0.2)])
    with pytest.raises(ValueError) as e:
        call(feet)
    assert all(w in str(e.value) for w in words), str(e.value)


@pytest.mark.parametrize("make, words", [
    (lambda: planar.circle(0.0), ["radius", "0"]),
    (lambda: planar.circle(0.1, (0.0, math.nan)), ["centre[1]", "nan"]),
    (lambda: planar.box(0.1, -1.0), ["height", "-1"]),
    (lambda: planar.polygon([(0, 0), (1, 0), (0.2, 0.2), (0, 1)]), ["vertices", "convex"]),
    (lambda: planar.Footprints([]), ["bodies", "none"]),
    (lambda: planar.Footprints([planar.circle(0.1)], pressure=["uniform", "uniform"]), ["pressure", "1", "2"]),
    (lambda: planar.Footprints([[planar.circle(0.1), "disk"]]), ["bodies[0]", "part"]),
    (lambda: planar.Footprints([planar.circle(0.1)], pressure="ring:0.2"), ["bodies[0]", "ring", "0.2"]),
])
def test_bad_footprints_are_named(make, words) -> None:  # noqa: ANN001
    with pytest.raises(ValueError) as e:
        make()
    assert all(w in str(e.value) for w in words), str(e.value)
