"""Area-integrated friction: ICR quadrature vs the disk closed form, vs sampled elements, limits.

Tolerances: the ICR rule is spectrally accurate (measured worst cases in docs/extended.md), so
its comparisons against exact references use a few hundred ulps; the sampled rule converges like
1/N (measured below), so its comparisons use the error it reaches at the N chosen.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rrbody.model.bodies import Disk, Ellipse, RodMass
from rrbody.physics import area
from rrbody.physics.wrench import sampled_wrench as sampled_kernel

LAW_DRY = 1


def _motion(body, r: float, ang: float, spin: float, alpha: float) -> tuple[float, float, float, float]:
    """(alpha, vx, vy, spin) whose ICR sits at scaled radius r (r < 1 inside the body), direction ang."""
    a, b = body.semi_axes
    q = np.array([r * math.cos(ang) * a, r * math.sin(ang) * b])
    ca, sa = math.cos(alpha), math.sin(alpha)
    qw = np.array([ca * q[0] - sa * q[1], sa * q[0] + ca * q[1]])
    v = -spin * np.array([-qw[1], qw[0]])  # v_cm = -Omega z x (c - cm)
    return alpha, float(v[0]), float(v[1]), spin


def _rel(w, ref, R: float, mu_g: float = 1.0) -> float:
    """Error of a wrench relative to its natural scale: mu g for the force, mu g R for the torque."""
    return max(math.hypot(w[0] - ref[0], w[1] - ref[1]) / mu_g, abs(w[2] - ref[2]) / (mu_g * R))


# ---- the closed form itself -------------------------------------------------------------------
@pytest.mark.parametrize("eps", [0.01, 0.3, 0.7, 0.99, 1.01, 1.5, 4.0, 100.0])
def test_disk_closed_form_matches_direct_quadrature(eps: float) -> None:
    # the J integrals by adaptive quadrature (scipy quad, epsrel 1e-13): an independent check of
    # the elliptic-integral expressions
    k = min(eps, 1.0 / eps)
    m = k * k
    D = lambda p: math.sqrt(1.0 - m * math.sin(p) ** 2)  # noqa: E731
    j1 = quad(lambda p: math.cos(p) ** 2 * D(p), 0.0, math.pi / 2, epsabs=0.0, epsrel=1e-13)[0]
    j2 = quad(lambda p: D(p) ** 3, 0.0, math.pi / 2, epsabs=0.0, epsrel=1e-13)[0]
    j3 = quad(lambda p: math.cos(p) ** 4 / D(p), 0.0, math.pi / 2, epsabs=0.0, epsrel=1e-13)[0]
    f, t = area.disk_closed_form_ratio(eps)
    if eps <= 1.0:
        fq, tq = 4 * eps / math.pi * j1, 4 / (3 * math.pi) * j2
    else:
        fq, tq = 4 / math.pi * j1, 4 / (3 * math.pi * eps) * j3
    assert f == pytest.approx(fq, rel=1e-12, abs=0)  # quad's requested 1e-13, with margin
    assert t == pytest.approx(tq, rel=1e-12, abs=0)


def test_disk_closed_form_limits() -> None:
    # pure spin about the centre: tau = (2/3) mu g R, F = 0; pure translation: |F| = mu g, tau = 0
    assert area.disk_closed_form_ratio(0.0) == (0.0, 2.0 / 3.0)
    f, t = area.disk_closed_form_ratio(1e9)
    assert f == pytest.approx(1.0, abs=1e-15) and t < 1e-9
    # continuous across the rim (eps = 1): both forms give 8/(3 pi) and 8/(9 pi) there
    for e in (1.0 - 1e-12, 1.0, 1.0 + 1e-12):
        f, t = area.disk_closed_form_ratio(e)
        assert f == pytest.approx(8 / (3 * math.pi), rel=1e-10)  # d/d eps is finite: 1e-12 shift
        assert t == pytest.approx(8 / (9 * math.pi), rel=1e-10)


# ---- ICR quadrature vs the closed form ----------------------------------------------------------
def test_icr_disk_machine_precision_against_closed_form() -> None:
    d = Disk(R=0.7)
    eps_grid = np.concatenate([np.linspace(0.0, 3.0, 61), 1.0 + np.geomspace(1e-13, 0.2, 25),
                               1.0 - np.geomspace(1e-13, 0.2, 25), np.geomspace(3.0, 1e10, 12), [1.0]])
    worst = 0.0
    for i, eps in enumerate(eps_grid):
        spin = (-1.0) ** i * 1.7
        ang = 0.37 * i
        speed = eps * abs(spin) * d.R
        vx, vy = speed * math.cos(ang), speed * math.sin(ang)
        w = area.icr_wrench(d, 0.3 * i, vx, vy, spin, coeff=2.0)
        ref = area.disk_closed_form(d.R, vx, vy, spin, mu_g=2.0)
        worst = max(worst, _rel(w, ref, d.R, 2.0))
    # measured worst case 5.5e-12 at eps = 1 + 1e-12 (the ICR on the rim; docs/extended.md)
    assert worst < 2e-11


def test_icr_nodes_reach_stated_accuracy() -> None:
    # self-convergence against 512 nodes per panel over random motions (ICR inside, outside, near the
    # rim): icr_nodes' counts meet the accuracies its docstring states (1e-11 of the wrench scale
    # for |delta| <= 0.9; the 0.99 needle 1e-9)
    rng = np.random.default_rng(3)
    for delta, tol in ((0.0, 2e-11), (0.2, 2e-11), (0.6, 2e-11), (-0.9, 5e-11), (0.99, 2e-9)):
        body = Ellipse(R0=1.0, delta=delta)
        n = area.icr_nodes(body)
        worst = 0.0
        for _ in range(60):
            r = float(np.exp(rng.uniform(math.log(1e-3), math.log(1e3))))
            if rng.random() < 0.4:
                r = 1.0 + float(rng.choice([-1.0, 1.0])) * 10 ** rng.uniform(-12, -1)
            m = _motion(body, r, rng.uniform(0, 2 * math.pi), float(rng.choice([-1.0, 1.0])) * rng.uniform(0.1, 3),
                        rng.uniform(0, 2 * math.pi))
            ref = area.icr_wrench(body, *m, nodes=512)
            worst = max(worst, _rel(area.icr_wrench(body, *m, nodes=n), ref, max(body.semi_axes)))
        assert worst < tol, (delta, n, worst)


def test_icr_continuous_across_the_boundary_and_translation_switch() -> None:
    # the rule changes at kappa' = 0.3, at the rim and at |Omega| R / |v| = 1e-8: the wrench must
    # be continuous there (jumps below 1e-11 of its scale)
    body = Ellipse(R0=0.5, delta=0.4)
    for r0 in (1.0, math.sqrt(1 - 0.3 ** 2), 1 / math.sqrt(1 - 0.3 ** 2)):
        w1 = area.icr_wrench(body, *_motion(body, r0 * (1 - 1e-12), 0.8, 1.3, 0.2))
        w2 = area.icr_wrench(body, *_motion(body, r0 * (1 + 1e-12), 0.8, 1.3, 0.2))
        assert _rel(w1, w2, 0.7) < 1e-11
    # far ICR: r = 0.99e8 / 1.01e8 on both sides of the translation switch (R_max/|q| = 1e-8)
    a = max(body.semi_axes)
    for scale in (0.99, 1.01):
        m = (0.2, 1.0, 0.5, 1e-8 * math.hypot(1.0, 0.5) / a * scale)
        m_lo = (0.2, 1.0, 0.5, m[3] * 0.98)
        w, w_lo = area.icr_wrench(body, *m), area.icr_wrench(body, *m_lo)
        # torque linear in Omega there: tau / Omega constant to 1e-9
        assert w[2] / m[3] == pytest.approx(w_lo[2] / m_lo[3], rel=1e-9)
        assert math.hypot(w[0], w[1]) == pytest.approx(1.0, abs=1e-14)


def test_translation_and_pure_spin_exact() -> None:
    e = Ellipse(R0=0.4, delta=0.5)
    a, b = e.semi_axes
    # pure translation: F = -mu g v_hat exactly, no torque
    fx, fy, t = area.icr_wrench(e, 0.7, 3.0, -4.0, 0.0, coeff=2.0)
    assert (fx, fy) == pytest.approx((-1.2, 1.6), abs=1e-15) and t == 0.0
    # pure spin about the CM: no force; torque -(mu g) <rho> over the ellipse (mean distance from
    # the centre, by adaptive quadrature in polar coordinates: int r^2 dr = rho_b^3 / 3)
    fx, fy, t = area.icr_wrench(e, 0.7, 0.0, 0.0, 2.0, coeff=1.0)
    mean_r = quad(lambda th: (1.0 / math.sqrt((math.cos(th) / a) ** 2 + (math.sin(th) / b) ** 2)) ** 3 / 3.0,
                  0.0, 2 * math.pi, epsabs=0.0, epsrel=1e-13, limit=200)[0] / (math.pi * a * b)
    assert abs(fx) < 1e-15 and abs(fy) < 1e-15
    assert t == pytest.approx(-mean_r, rel=1e-12)  # quad's requested accuracy, with margin


def test_viscous_closed_forms() -> None:
    e = Ellipse(R0=0.3, delta=-0.4)
    fx, fy, t = area.icr_wrench(e, 0.3, 0.5, -0.2, 1.5, law="viscous", coeff=0.8)
    assert (fx, fy, t) == pytest.approx((-0.4, 0.16, -0.8 * e.inertia_per_mass * 1.5), rel=1e-15)
    # the sampled rule integrates the linear law: exact up to the samples' second moment, which the
    # equal-area cells carry with error O(1/N) (measured 1e-4 relative at N = 4800); the force is a
    # 4800-term sum taken in the body frame and turned once into the world frame: its rounding is
    # ~sqrt(N) eps |F| ~ 1e-15 (measured 1.05e-15), at worst N eps |F| ~ 8e-14
    s = area.sampled_wrench(e, 0.3, 0.5, -0.2, 1.5, law="viscous", coeff=0.8, samples=4800)
    assert s[:2] == pytest.approx((fx, fy), abs=1e-14)
    assert s[2] == pytest.approx(t, rel=3e-4)


# ---- sampled elements -----------------------------------------------------------------------------
def test_area_samples_weights_and_moments() -> None:
    e = Ellipse(R0=0.5, delta=0.3)
    a, b = e.semi_axes
    S = area.area_samples(e, 30_000)
    assert S.shape[1] == 3 and abs(S.shape[0] - 30_000) < 0.05 * 30_000
    assert S[:, 2].sum() == pytest.approx(1.0, abs=1e-12)
    assert np.all(S[:, 2] > 0)
    # centred on the CM; all inside the ellipse
    assert abs(np.sum(S[:, 2] * S[:, 0])) < 1e-12 and abs(np.sum(S[:, 2] * S[:, 1])) < 1e-12
    assert np.all((S[:, 0] / a) ** 2 + (S[:, 1] / b) ** 2 < 1.0)
    # second moments converge to a^2/4, b^2/4 (midpoint rule in radius^2: error ~ 1/N)
    assert np.sum(S[:, 2] * S[:, 0] ** 2) == pytest.approx(a * a / 4, rel=1e-4)


def test_sampled_convergence_order() -> None:
    # ICR outside the body (smooth integrand): error ~ C / N; measured slope -1.00 (docs/extended.md)
    d = Disk(R=1.0)
    m = _motion(d, 3.0, 0.4, 1.3, 0.2)
    ref = area.icr_wrench(d, *m)
    ns, errs = [], []
    for n in (3 * 16 ** 2, 3 * 32 ** 2, 3 * 64 ** 2, 3 * 128 ** 2):
        S = area.area_samples(d, n)
        w = sampled_kernel(S, *m, LAW_DRY, 1.0, 0.0)
        ns.append(S.shape[0])
        errs.append(_rel(w, ref, 1.0))
    slope = np.polyfit(np.log(ns), np.log(errs), 1)[0]
    assert -1.15 < slope < -0.85


@pytest.mark.parametrize("body", [Disk(R=0.8), Ellipse(R0=0.5, delta=0.5)], ids=["disk", "ellipse"])
def test_sampled_and_icr_agree_1e6(body) -> None:
    # a grid of motions: spin-dominated (ICR near the centre), ICR inside near the rim, on the rim,
    # just outside, translation-dominated (far ICR); relative to the wrench scale. The sampled rule
    # at ~4.1e6 elements reaches ~2e-7 (measured: docs/extended.md), the ICR rule ~1e-12.
    S = area.area_samples(body, 4_100_000)
    R = max(body.semi_axes)
    worst = 0.0
    for r in (0.0, 0.05, 0.5, 0.9, 1.0, 1.1, 3.0, 50.0):
        for ang in (0.3, 2.0):
            m = _motion(body, r, ang, 1.3 if ang < 1 else -0.6, 0.5)
            w = sampled_kernel(S, *m, LAW_DRY, 1.0, 0.0)
            worst = max(worst, _rel(w, area.icr_wrench(body, *m), R))
    assert worst <= 1e-6


def test_small_n_and_bad_arguments() -> None:
    with pytest.raises(ValueError, match="samples"):
        area.area_samples(Disk(R=1.0), 0)
    with pytest.raises(ValueError, match="extended body"):
        area.area_samples(RodMass(l=1.0), 100)
    with pytest.raises(ValueError, match="extended body"):
        area.icr_nodes(RodMass(l=1.0))
    with pytest.raises(ValueError, match="eps"):
        area.disk_closed_form_ratio(-1.0)
    with pytest.raises(ValueError, match="vx"):
        area.icr_wrench(Disk(R=1.0), 0.0, float("nan"), 0.0, 1.0)
    with pytest.raises(ValueError, match="law"):
        area.icr_wrench(Disk(R=1.0), 0.0, 1.0, 0.0, 1.0, law="sticky")
    assert area.area_samples(Disk(R=1.0), 1).shape == (3, 3)
    assert area.icr_supported(Disk(R=1.0), "dry") and not area.icr_supported(RodMass(l=1.0), "dry")
    assert not area.icr_supported(Disk(R=1.0), "none")
