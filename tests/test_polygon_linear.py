"""The exact polygon friction kernel under a linear pressure (rrbody.physics.polygon_linear) against an
independent quadrature, the uniform kernel and its own limits.

The reference integrates in polar coordinates about the instantaneous centre c, as tests/test_polygon.py
does: along a ray from c in direction d the pressure is f_c + rho (k . d), so the radial integrals of
f rho and f rho^2 are exact polynomials, and scipy's adaptive quad does the angle between consecutive
vertex directions (~1e-14). It shares no code with the kernel's edge formulas. With c far out (more
than NEAR polygon radii, where the kernel uses its Gauss rule) the polar sums cancel (f_c grows with
|c|), so there the reference is a 40 x 40-point Gauss rule summed in extended precision (u is smooth
on the polygon: converged to rounding).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rrbody.physics.polygon import NEAR, TRANSLATION_EPS, gauss_rule, polygon_geometry, polygon_wrench
from rrbody.physics.polygon_linear import linear_polygon_wrench

TRIANGLE = np.array([[0.0, 0.0], [1.2, 0.1], [0.3, 0.9]]) + [0.2, -0.1]
BOX = np.array([[-0.5, -0.25], [0.5, -0.25], [0.5, 0.25], [-0.5, 0.25]]) + [0.1, 0.3]
# slopes (1/m) that keep 1 + k . (s - g) >= 0 on these polygons (largest |s - g| < 0.8 m)
SLOPES = [(0.0, 0.0), (0.9, 0.0), (-0.4, 0.7), (0.3, -1.1)]
MOTIONS = [(0.0, 0.0, 1.0), (0.3, 0.2, 1.0), (1.0, -0.5, 0.7), (5.0, 1.0, -0.3), (0.05, 0.9, -2.0),
           (3.0, -40.0, 1.0)]

pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")


def _geometry(p: np.ndarray) -> tuple:
    v, area, gx, gy, m2 = polygon_geometry(p)
    rg = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    return v, area, gx, gy, rg, m2, gauss_rule(v)


def kernel(p: np.ndarray, k: tuple[float, float], vx: float, vy: float, w: float, rg_scale: float = 1.0) -> np.ndarray:
    v, area, gx, gy, rg, _, rule = _geometry(p)
    return np.array(linear_polygon_wrench(v, 0, len(v), area, gx, gy, rg * rg_scale, k[0], k[1], rule, 0, len(rule),
                                          vx, vy, w, 0.0))


def reference(p: np.ndarray, k: tuple[float, float], vx: float, vy: float, w: float) -> np.ndarray:
    """Independent polar quadrature about c (module docstring); spin w != 0."""
    v, area, gx, gy, *_ = _geometry(p)
    cx, cy = -vy / w, vx / w
    fc = 1.0 + k[0] * (cx - gx) + k[1] * (cy - gy)

    def clip(dx: float, dy: float) -> tuple[float, float]:
        lo, hi = 0.0, math.inf
        for i in range(len(v)):
            a, b = v[i], v[(i + 1) % len(v)]
            nx, ny = b[1] - a[1], -(b[0] - a[0])
            den = nx * dx + ny * dy
            num = nx * (a[0] - cx) + ny * (a[1] - cy)
            if den > 0:
                hi = min(hi, num / den)
            elif den < 0:
                lo = max(lo, num / den)
            elif num < 0:
                return 0.0, 0.0
        return (lo, hi) if hi > lo else (0.0, 0.0)

    def radial(th: float, n: int) -> float:
        dx, dy = math.cos(th), math.sin(th)
        a, b = clip(dx, dy)
        kd = k[0] * dx + k[1] * dy
        return fc * (b ** (n + 1) - a ** (n + 1)) / (n + 1) + kd * (b ** (n + 2) - a ** (n + 2)) / (n + 2)

    cuts = sorted({math.atan2(y - cy, x - cx) % (2 * math.pi) for x, y in v} | {0.0, 2 * math.pi})
    U = np.zeros(2)
    R = 0.0
    kw = {"epsabs": 1e-16, "epsrel": 1e-14, "limit": 200}
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a < 1e-15:
            continue
        U[0] += quad(lambda t: math.cos(t) * radial(t, 1), a, b, **kw)[0]
        U[1] += quad(lambda t: math.sin(t) * radial(t, 1), a, b, **kw)[0]
        R += quad(lambda t: radial(t, 2), a, b, **kw)[0]
    T = R + cx * U[0] + cy * U[1]
    return -math.copysign(1.0, w) / area * np.array([-U[1], U[0], T])


def far_reference(p: np.ndarray, k: tuple[float, float], vx: float, vy: float, w: float) -> np.ndarray:
    """The integrals by a 40-point-per-direction Gauss rule in long double (c far outside the polygon)."""
    v, area, gx, gy, *_ = _geometry(p)
    q = gauss_rule(v, 40).astype(np.longdouble)
    cx, cy = np.longdouble(-vy) / w, np.longdouble(vx) / w
    f = 1 + k[0] * (q[:, 0] - gx) + k[1] * (q[:, 1] - gy)
    dx, dy = q[:, 0] - cx, q[:, 1] - cy
    wu = q[:, 2] * f / np.sqrt(dx * dx + dy * dy)
    U = np.array([(wu * dx).sum(), (wu * dy).sum()])
    T = (wu * (q[:, 0] * dx + q[:, 1] * dy)).sum()
    return (-math.copysign(1.0, w) / np.longdouble(area) * np.array([-U[1], U[0], T])).astype(float)


@pytest.mark.parametrize("poly", [TRIANGLE, BOX], ids=["triangle", "box"])
@pytest.mark.parametrize("k", SLOPES)
@pytest.mark.parametrize("motion", MOTIONS)
def test_wrench_matches_independent_quadrature(poly: np.ndarray, k: tuple, motion: tuple) -> None:
    got = kernel(poly, k, *motion)
    v, _, gx, gy, rg, *_ = _geometry(poly)
    far = math.hypot(gx + motion[1] / motion[2], gy - motion[0] / motion[2]) > NEAR * rg
    ref = (far_reference if far else reference)(poly, k, *motion)
    # the reference is good to ~1e-14 (adaptive quad at epsrel 1e-14 on smooth pieces), the kernel's closed
    # forms and rule to ~1e-15 (as the uniform kernel's): 1e-12 of the scale (force 1, torque ~ 1 m) has margin
    assert np.max(np.abs(got - ref)) < 1e-12, (got, ref)


@pytest.mark.parametrize("motion", MOTIONS + [(1.0, 0.3, 0.0)])
def test_zero_slope_is_the_uniform_kernel(motion: tuple) -> None:
    v, area, gx, gy, rg, m2, rule = _geometry(TRIANGLE)
    uni = np.array(polygon_wrench(v, 0, 3, area, gx, gy, rg, *m2, rule, 0, len(rule), *motion, 0.0))
    # the same integrals by other sums (the translation moments from the rule, not M): rounding only
    assert np.max(np.abs(kernel(TRIANGLE, (0.0, 0.0), *motion) - uni)) < 1e-14


def test_near_and_far_forms_agree_where_they_meet() -> None:
    """The closed forms (rg x 10 forces them) and the rule (rg / 10) at |c - g| = NEAR rg."""
    v, area, gx, gy, rg, _, _ = _geometry(TRIANGLE)
    worst = 0.0
    for th in np.linspace(0.0, 2 * math.pi, 17):
        cx, cy = gx + NEAR * rg * math.cos(th), gy + NEAR * rg * math.sin(th)
        a, b = (kernel(TRIANGLE, (0.6, -0.8), cy, -cx, 1.0, s) for s in (10.0, 0.1))
        worst = max(worst, float(np.max(np.abs(a - b))))
    # the closed forms cancel by ~NEAR^3 = 512 there (as the uniform kernel's: 6e-14 of the scale)
    assert worst < 1e-13


def test_translation_limit_is_exact_and_continuous() -> None:
    """Pure translation: F = -v_hat and tau = -(P x v_hat), P = g + M_g k the centre of pressure (closed form);
    just either side of the switch the expansion and the rule agree to the linear term."""
    k = (0.9, -0.3)
    v, area, gx, gy, rg, m2, _ = _geometry(TRIANGLE)
    mgxx, mgxy, mgyy = m2[0] - gx * gx, m2[1] - gx * gy, m2[2] - gy * gy  # second moment about g, over A
    px, py = gx + mgxx * k[0] + mgxy * k[1], gy + mgxy * k[0] + mgyy * k[1]
    speed = math.hypot(1.0, 0.3)
    f = kernel(TRIANGLE, k, 1.0, 0.3, 0.0)
    assert f[0] == pytest.approx(-1.0 / speed, rel=1e-15) and f[1] == pytest.approx(-0.3 / speed, rel=1e-15)
    assert f[2] == pytest.approx(-(px * 0.3 - py * 1.0) / speed, rel=1e-13)
    reach = math.hypot(gx, gy) + rg
    w0 = TRANSLATION_EPS * speed / reach
    a = kernel(TRIANGLE, k, 1.0, 0.3, 1.0001 * w0)
    b = kernel(TRIANGLE, k, 1.0, 0.3, 0.9999 * w0)
    slope = (kernel(TRIANGLE, k, 1.0, 0.3, 4 * w0) - kernel(TRIANGLE, k, 1.0, 0.3, 2 * w0)) / (2 * w0)
    assert np.max(np.abs(a - b - slope * 2e-4 * w0)) < 1e-14
