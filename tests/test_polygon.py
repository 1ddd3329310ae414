"""The exact polygon friction kernel (rrbody.physics.polygon) against closed forms and an independent
quadrature.

The reference integrates in polar coordinates about the instantaneous centre c: for each direction
the ray from c is clipped against every convex polygon (Cyrus-Beck), the radial integrals of rho and
rho^2 are exact, and scipy's adaptive quad does the angle between consecutive vertex directions
(where the integrand is smooth), to ~1e-14. It shares no code with the kernel's edge formulas.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rrbody.physics.polygon import NEAR, TRANSLATION_EPS, box_spin_torque, gauss_rule, polygon_geometry, polygon_wrench

BOX = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
TRIANGLE = np.array([[0.0, 0.0], [1.2, 0.1], [0.3, 0.9]]) + [0.2, -0.1]
# an L of two boxes sharing an edge (a non-convex body as two convex polygons)
L_PARTS = [np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]),
           np.array([[0.0, 1.0], [1.0, 1.0], [1.0, 3.0], [0.0, 3.0]])]


def kernel(parts: list[np.ndarray], vx: float, vy: float, w: float) -> np.ndarray:
    """Area-weighted sum of polygon_wrench over convex parts (uniform pressure): (Fx, Fy, tau) per unit load."""
    areas = [polygon_geometry(p)[1] for p in parts]
    out = np.zeros(3)
    for p, a in zip(parts, areas):
        v, area, gx, gy, m2 = polygon_geometry(p)
        rg = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
        rule = gauss_rule(v)
        out += a / sum(areas) * np.array(polygon_wrench(v, 0, len(v), area, gx, gy, rg, *m2, rule, 0, len(rule),
                                                        vx, vy, w, 0.0))
    return out


def reference(parts: list[np.ndarray], vx: float, vy: float, w: float) -> np.ndarray:
    """Independent polar quadrature about c (see module docstring); spin w != 0."""
    cx, cy = -vy / w, vx / w
    polys = [polygon_geometry(p)[0] for p in parts]
    area = sum(polygon_geometry(p)[1] for p in parts)

    def clip(p: np.ndarray, dx: float, dy: float) -> tuple[float, float]:
        lo, hi = 0.0, math.inf
        for i in range(len(p)):
            a, b = p[i], p[(i + 1) % len(p)]
            nx, ny = b[1] - a[1], -(b[0] - a[0])  # outward normal (counter-clockwise polygon)
            den = nx * dx + ny * dy
            num = nx * (a[0] - cx) + ny * (a[1] - cy)
            if den > 0:
                hi = min(hi, num / den)
            elif den < 0:
                lo = max(lo, num / den)
            elif num < 0:
                return 0.0, 0.0
        return (lo, hi) if hi > lo else (0.0, 0.0)

    def radial(th: float, k: int) -> float:
        dx, dy = math.cos(th), math.sin(th)
        s = 0.0
        for p in polys:
            a, b = clip(p, dx, dy)
            s += (b ** (k + 1) - a ** (k + 1)) / (k + 1)
        return s

    cuts = sorted({math.atan2(y - cy, x - cx) % (2 * math.pi) for p in polys for x, y in p} | {0.0, 2 * math.pi})
    U = np.zeros(2)
    R = 0.0
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a < 1e-15:
            continue
        kw = {"epsabs": 1e-16, "epsrel": 1e-14, "limit": 200}
        U[0] += quad(lambda t: math.cos(t) * radial(t, 1), a, b, **kw)[0]
        U[1] += quad(lambda t: math.sin(t) * radial(t, 1), a, b, **kw)[0]
        R += quad(lambda t: radial(t, 2), a, b, **kw)[0]
    sg = math.copysign(1.0, w)
    T = R + cx * U[0] + cy * U[1]
    return -sg / area * np.array([-U[1], U[0], T])


# the reference's adaptive quad at epsrel 1e-14 reports roundoff (it reaches rounding level): expected
pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")

MOTIONS = [(0.0, 0.0, 1.0), (0.3, 0.2, 1.0), (1.0, -0.5, 0.7), (5.0, 1.0, -0.3), (0.05, 0.9, -2.0),
           (0.5, 0.5, 1.0), (3.0, -40.0, 1.0)]


@pytest.mark.parametrize("name,parts", [("box", [BOX]), ("triangle", [TRIANGLE]), ("L", L_PARTS)])
@pytest.mark.parametrize("motion", MOTIONS)
def test_wrench_matches_independent_quadrature(name: str, parts: list, motion: tuple) -> None:
    got = kernel(parts, *motion)
    ref = reference(parts, *motion)
    # the reference is good to ~1e-14 (adaptive quad at epsrel 1e-14 on smooth pieces); the
    # kernel's closed forms and rule to ~1e-15: 1e-12 of the scale (force 1, torque ~ size) has margin
    assert np.max(np.abs(got - ref)) < 1e-12, (got, ref)


def test_box_in_pure_spin_is_the_closed_form() -> None:
    """Pure spin about the centre: torque = mean distance of the points from it, a (sqrt2 + ln(1+sqrt2))/6."""
    for a, w in ((1.0, 1.0), (0.3, -7.0), (2.5, 1e-3)):
        f = kernel([BOX * a], 0.0, 0.0, w)
        assert abs(f[0]) < 1e-15 and abs(f[1]) < 1e-15
        assert f[2] == pytest.approx(-math.copysign(box_spin_torque(a), w), rel=1e-14)


def test_near_and_far_forms_agree_where_they_meet() -> None:
    """Closed forms inside NEAR polygon radii, the Gauss rule outside: equal to rounding at the switch.
    (The switch compares |c - g| with NEAR * rg, so passing rg x 10 forces the closed forms and
    rg / 10 the rule, for the same motion.)"""
    v, area, gx, gy, m2 = polygon_geometry(TRIANGLE)
    rg = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    rule = gauss_rule(v)
    worst = 0.0
    for th in np.linspace(0.0, 2 * math.pi, 17):
        cx, cy = gx + NEAR * rg * math.cos(th), gy + NEAR * rg * math.sin(th)
        a, b = (np.array(polygon_wrench(v, 0, 3, area, gx, gy, r, *m2, rule, 0, len(rule), cy, -cx, 1.0, 0.0))
                for r in (10.0 * rg, 0.1 * rg))
        worst = max(worst, float(np.max(np.abs(a - b))))
    # the closed forms cancel by ~(NEAR)^3 = 512 there (512 x 1.1e-16 = 6e-14 of the scale); measured 1.3e-14
    assert worst < 1e-13


def test_translation_limit_is_continuous() -> None:
    """|w| rmax just above and below TRANSLATION_EPS |v|: the expansion and the far-field rule agree."""
    v, area, gx, gy, _ = polygon_geometry(TRIANGLE)
    reach = math.hypot(gx, gy) + float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    speed = math.hypot(1.0, 0.3)
    w0 = TRANSLATION_EPS * speed / reach  # the switch
    a = kernel([TRIANGLE], 1.0, 0.3, 1.0001 * w0)
    b = kernel([TRIANGLE], 1.0, 0.3, 0.9999 * w0)
    # the wrench is linear in w here (next term O(eps^2) ~ 1e-16): slope from the rule side alone
    slope = (kernel([TRIANGLE], 1.0, 0.3, 4 * w0) - kernel([TRIANGLE], 1.0, 0.3, 2 * w0)) / (2 * w0)
    assert np.max(np.abs(a - b - slope * 2e-4 * w0)) < 1e-14
    # pure translation: F = -v_hat exactly; the torque is the lever arm of the centroid
    f = kernel([TRIANGLE], 1.0, 0.3, 0.0)
    assert f[0] == pytest.approx(-1.0 / speed, rel=1e-15) and f[1] == pytest.approx(-0.3 / speed, rel=1e-15)
    assert f[2] == pytest.approx(-(gx * 0.3 - gy * 1.0) / speed, rel=1e-14)


def test_geometry_and_rule() -> None:
    v, area, gx, gy, m2 = polygon_geometry(BOX[::-1] * 2.0 + [1.0, 0.0])  # clockwise input
    assert area == pytest.approx(4.0) and (gx, gy) == pytest.approx((1.0, 0.0))
    assert m2 == pytest.approx([1.0 + 4.0 / 12.0 * 1.0, 0.0, 4.0 / 12.0])  # parallel axes: gx^2 + a^2/12
    rule = gauss_rule(TRIANGLE)
    _, a_t, gxt, gyt, m2t = polygon_geometry(TRIANGLE)
    assert rule[:, 2].sum() == pytest.approx(a_t, rel=1e-14)
    assert (rule[:, 2] @ rule[:, 0]) / a_t == pytest.approx(gxt, rel=1e-14)
    assert (rule[:, 2] @ (rule[:, 0] * rule[:, 1])) / a_t == pytest.approx(m2t[1], rel=1e-13)
    assert len(rule) == 49  # one triangle, 7 x 7 nodes


@pytest.mark.parametrize("bad", [np.zeros((2, 2)), np.zeros((3, 3)), np.array([[0, 0], [1, 1], [2, 2.0]]),
                                 np.array([[0, 0], [1, 0], [math.nan, 1.0]])])
def test_bad_polygons_raise(bad: np.ndarray) -> None:
    with pytest.raises(ValueError, match="vertices must"):
        polygon_geometry(bad)
