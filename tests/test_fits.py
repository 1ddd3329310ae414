"""Fits recover known parameters within their stated errors; the exact small-omega flip-time limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody.analysis.fits import fit_power_law, fit_q_exponential, q_exponential
from rrbody.analysis.report import paper_small_omega_C, small_omega_C


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_q_exponential_recovers_parameters_within_errors(seed: int) -> None:
    rng = np.random.default_rng(seed)
    H0, lam, q = 0.79272623, 41.32, 1.936  # the paper's dry-friction values
    k = np.linspace(0.0, 1.0, 101)
    noise = 1e-3  # absolute noise in H, the size of our Hc fit residuals
    y = q_exponential(k, H0, lam, q) + noise * rng.standard_normal(k.size)
    f = fit_q_exponential(k, y, H0=H0, relative=False, p0=(30.0, 1.5))
    # 4 standard errors: a false failure has probability ~1e-4 per parameter for Gaussian noise
    assert abs(f.params["q"] - q) < 4 * f.stderr["q"]
    assert abs(f.params["lam"] - lam) < 4 * f.stderr["lam"]
    # the stated errors are honest: they are of the size the noise implies (not vanishing, not huge)
    assert 1e-4 < f.stderr["q"] < 0.05
    assert f.x_range == (0.0, 1.0) and f.n == 101
    assert abs(f.rms - noise) < 0.3 * noise  # residual rms estimates the injected noise (101 points: ~7% scatter)
    np.testing.assert_allclose(f.residuals, y - f(k), atol=1e-12)


def test_q_exponential_three_parameters_and_range() -> None:
    k = np.linspace(0.0, 2.0, 201)
    y = q_exponential(k, 0.8, 11.64, 1.724)  # exact data: the fit must return the parameters to ~solver precision
    f = fit_q_exponential(k, y, x_range=(0.0, 1.0))
    assert f.n == 101 and f.x_range == (0.0, 1.0)
    assert f.params["H0"] == pytest.approx(0.8, rel=1e-6)
    assert f.params["lam"] == pytest.approx(11.64, rel=1e-6)
    assert f.params["q"] == pytest.approx(1.724, rel=1e-6)


def test_q_exponential_reduces_to_exponential_at_q1() -> None:
    x = np.linspace(0, 3, 7)
    np.testing.assert_allclose(q_exponential(x, 2.0, 0.5, 1.0), 2.0 * np.exp(-0.5 * x), rtol=1e-14)
    # q -> 1 limit is continuous: (1 + lam eps x)^(-1/eps) -> exp(-lam x), error O(eps)
    np.testing.assert_allclose(q_exponential(x, 2.0, 0.5, 1.0 + 1e-7), 2.0 * np.exp(-0.5 * x), rtol=1e-6)


@pytest.mark.parametrize("seed", [0, 1])
def test_power_law_recovers_exponent_within_errors(seed: int) -> None:
    rng = np.random.default_rng(seed)
    x = np.geomspace(0.01, 300, 60)
    y = 0.53 * x ** -1.0 * np.exp(0.01 * rng.standard_normal(x.size))  # 1% multiplicative noise
    f = fit_power_law(x, y, x_range=(0.01, 0.3))
    assert abs(f.params["b"] + 1.0) < 4 * f.stderr["b"]  # 4 sigma, as above
    assert abs(f.params["A"] - 0.53) < 4 * f.stderr["A"]
    assert f.x_range[0] == pytest.approx(0.01) and f.x_range[1] <= 0.3


def test_fit_input_errors() -> None:
    with pytest.raises(ValueError, match="x_range"):
        fit_power_law([1, 2, 3, 4], [1, 2, 3, 4], x_range=(10, 20))
    with pytest.raises(ValueError, match="> 0"):
        fit_power_law([1, 2, 3, 4], [1, -2, 3, 4])
    with pytest.raises(ValueError, match="equal length"):
        fit_q_exponential([0, 1, 2], [1, 2])
    with pytest.raises(ValueError, match="H must be > 0"):
        small_omega_C(-1.0)


def test_small_omega_closed_form_matches_quadrature() -> None:
    from scipy.integrate import quad

    for H in (0.1, 0.25, 0.6, 1.0, 1.5, 3.0):
        ref = quad(lambda p: H / (H - math.cos(p)), math.pi / 2, math.pi, epsabs=1e-13, epsrel=1e-13)[0]
        assert small_omega_C(H) == pytest.approx(ref, rel=1e-10)  # quad converges to ~1e-13 here
    # the paper's estimate is the leading-order value, about 11.5% low at H = 0.25
    assert paper_small_omega_C(0.25) == pytest.approx(2 * math.sqrt(2) / 6)


def test_small_omega_limit_matches_the_ode() -> None:
    from rrbody.analysis.flip import flip_time
    from rrbody.model.scene import rod_mass_scene

    w, k, H = 0.03, 7.5, 0.25
    r = flip_time(rod_mass_scene(H, k, w))
    # The quasi-static limit neglects inertia, a correction of relative order omega^2/k = 1.2e-4
    # (measured: omega t_f = 0.532768 at omega = 0.01, 0.532699 at 0.03, against C = 0.532777).
    assert w * r.t_f == pytest.approx(small_omega_C(H), rel=1e-3)
    assert r.phi_min == pytest.approx(math.pi / 2 + small_omega_C(H), abs=1e-3)
