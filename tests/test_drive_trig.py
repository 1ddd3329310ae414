"""The drive phase's sine and cosine by angle addition (physics.effects.drive_circular.sincos_psi).

A DOP853 stage of a driven body evaluates sin and cos of psi = psi0 + d from the step's psi0 and a
short series in d. Tolerances:

- the series against sin and cos in extended precision (numpy's long double, 64-bit mantissa on
  x86-64; double precision where long double is double, which only loosens the reference by its
  own rounding, <= 1.1e-16): 2 ulp of 1 (4.4e-16). The series' fit error is 3e-19 (mpmath
  chebyfit at 40 digits) and the rest is double rounding in a polynomial whose terms are all
  below 1 in magnitude; measured 2.2e-16;
- the angle-added value against the library's sin and cos of psi = phi - omega t: that 4.4e-16,
  plus the roundings in forming psi and the base psi0 (each at most |x| 2^-53 for an operand or
  result x; the angle addition itself uses d exactly).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.model.scene import rod_mass_scene
from rrbody.physics import params as P
from rrbody.physics.bind import kernel_params
from rrbody.physics.effects.drive_circular import NEAR, sincos_psi, sincos_small

TWO_ULP = 2.0 * 2.0**-52


@njit(cache=True)
def _small(ds):  # noqa: ANN001
    out = np.empty((ds.shape[0], 2))
    for i in range(ds.shape[0]):
        out[i, 0], out[i, 1] = sincos_small(ds[i])
    return out


@njit(cache=True)
def _psi(t, phi, p, d, s0, c0):  # noqa: ANN001
    return sincos_psi(t, phi, p, d, s0, c0)


def test_series_matches_sine_and_cosine_to_two_ulp_on_its_interval() -> None:
    x = np.linspace(0.0, NEAR, 100_001)
    d = np.concatenate([-x[::-1], x, [1e-300, -1e-300, 5e-8]])
    got = _small(d)
    ref = d.astype(np.longdouble)
    err_s = np.abs(got[:, 0].astype(np.longdouble) - np.sin(ref)).max()
    err_c = np.abs(got[:, 1].astype(np.longdouble) - np.cos(ref)).max()
    assert float(err_s) <= TWO_ULP, err_s
    assert float(err_c) <= TWO_ULP, err_c
    # odd and even exactly (the grid is symmetric), and sin d = d for tiny d
    grid = got[:200_002]
    assert np.array_equal(grid[::-1, 0], -grid[:, 0])
    assert np.array_equal(grid[::-1, 1], grid[:, 1])
    assert _small(np.array([1e-300]))[0, 0] == 1e-300


def test_angle_addition_matches_the_library_within_the_argument_rounding() -> None:
    p, _ = kernel_params(rod_mass_scene(0.25, 7.5, 300.0))
    w = p[P.OMEGA]
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(20_000):
        t = rng.uniform(0.0, 40.0)
        phi0 = rng.uniform(-2e4, 2e4)
        d = rng.uniform(-NEAR, NEAR)
        psi0 = phi0 - w * t
        s, c = _psi(t, phi0 + d, p, d, math.sin(psi0), math.cos(psi0))
        psi = phi0 + d - w * t
        # both angles are rounded on the way: phi0 + d, w t and the difference for psi (what the
        # library sees), w t and the difference for the base psi0; each rounding of x is at most
        # |x| 2^-53, and sin, cos have slope <= 1. Plus the series' 2 ulp.
        tol = TWO_ULP + (abs(phi0 + d) + 2.0 * abs(w * t) + abs(psi) + abs(psi0)) * 2.0**-53
        dev = max(abs(s - math.sin(psi)), abs(c - math.cos(psi)))
        assert dev <= tol, (t, phi0, d, dev, tol)
        worst = max(worst, dev)
    assert worst > 0.0  # the two paths are distinct computations


def test_without_a_base_it_is_the_library_call_bitwise() -> None:
    p, _ = kernel_params(rod_mass_scene(0.25, 7.5, 300.0))
    for t, phi in ((0.0, math.pi), (12.3, -7909.79), (37.0, 1e4)):
        psi = phi - p[P.OMEGA] * t
        for d in (math.nan, NEAR * 1.0001, -2.0):
            assert _psi(t, phi, p, d, 0.3, 0.7) == (math.sin(psi), math.cos(psi))


def test_sincos_reduced_matches_the_library_at_any_angle() -> None:
    """sincos_reduced (the plugin's per-body angle): Cody-Waite reduction by pi/2 (products exact for
    |k| < 2^20) and sincos_small on |r| <= pi/4, so its error is the series' 2 ulp of 1 (TWO_ULP) plus
    the library's own rounding of its result (at most half an ulp of 1, 1.1e-16) and the reduction's
    last rounding (half an ulp of pi/4): 2 TWO_ULP bounds all three. Angles up to the reduction's
    limit, multiples of pi/4 and pi/2 (the quadrant edges), then the library's beyond it and for NaN."""
    from rrbody.physics.effects.drive_circular import REDUCED_MAX, sincos_reduced

    @njit
    def worst(xs):  # noqa: ANN001, ANN202
        e = 0.0
        for x in xs:
            s, c = sincos_reduced(x)
            e = max(e, abs(s - math.sin(x)), abs(c - math.cos(x)))
        return e

    rng = np.random.default_rng(4)
    xs = np.concatenate([rng.uniform(-s, s, 20000) for s in (1.0, 10.0, 1e3, 1e5, REDUCED_MAX)]
                        + [np.arange(-64, 64) * (math.pi / 4), np.arange(-64, 64) * (math.pi / 2) + 1e-13])
    assert worst(xs) <= 2 * TWO_ULP
    for x in (REDUCED_MAX * 1.5, -3e9, 1e300):  # beyond the reduction: the library itself
        assert sincos_reduced(x) == (math.sin(x), math.cos(x))
    s, c = sincos_reduced(math.nan)
    assert math.isnan(s) and math.isnan(c)
