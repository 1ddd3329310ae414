"""Area-integrated friction for extended bodies: sampled elements, the ICR quadrature, the disk closed form.

Everything here is per unit mass: forces in m/s^2 (world frame), torques about the CM in
m^2/s^2. A body moves with CM velocity (vx, vy) (m/s, world frame), spin Omega (rad/s) and body
angle alpha (rad); an element at body-frame offset rho from the CM moves with v_cm + Omega z x R(alpha) rho.

Three ways to the same wrench, cross-checked in ``tests/test_area.py``:

- :func:`area_samples`: equal-weight area elements (the general method; the pymunk path uses
  it). Equal-area polar cells in the scaled frame; midpoint rule. Observed convergence (the test
  measures it): error ~ N^-1 (second order in the element size) when the ICR is outside the body,
  and ~ N^-1 up to a log when it is inside.
- :func:`icr_wrench` (kernel in :mod:`rrbody._icr`): 1-D Gauss quadrature about the
  instantaneous centre of rotation with exact radial integrals, spectrally accurate.
- :func:`disk_closed_form`: the uniformly loaded disk in complete elliptic integrals.
"""

from __future__ import annotations

import math

import numpy as np

from rrbody.model.bodies import Body, Disk, Ellipse
from rrbody.model.checks import check_int, check_positive, check_real
from rrbody.model.laws import LAW_CODES, check_area, law_named
from rrbody.physics.icr import ECC_ETA
from rrbody.physics.icr import icr_wrench as _icr_kernel
from rrbody.physics.icr_panels import NODE_COUNTS

__all__ = ["icr_supported", "icr_nodes", "area_samples", "icr_wrench", "sampled_wrench", "disk_closed_form",
           "disk_closed_form_ratio"]

def icr_supported(body: Body, law: str) -> bool:
    """Whether the instantaneous-centre quadrature applies: disks and ellipses, under a law that exerts a force
    and has an icr form (the law table: dry, viscous)."""
    spec = law_named(law)
    return isinstance(body, (Disk, Ellipse)) and bool(spec.module) and "icr" in spec.areas


def icr_nodes(body: Body) -> int:
    """Gauss nodes per panel of the ICR quadrature for ``body`` (<= ~1e-11 relative error).

    From the convergence study in docs/extended.md (reproduced by ``tests/test_area.py``): the
    disk needs 24 (worst case over eps = |v|/(|Omega| R) in [0, 1e9], ICR on the rim included:
    5.5e-12 against the closed form); an ellipse with strip half-width atanh(b/a) >= 0.7
    (|delta| < 0.25) needs 32 (worst 3e-13 over 300 random motions); thinner ellipses use the
    split-and-graded rule with 40 per panel (delta = 0.9: 6e-12, delta = 0.99: 3e-10).
    """
    ra, rb = body.semi_axes
    if ra <= 0.0 or rb <= 0.0:
        raise ValueError(f"icr_nodes needs an extended body (semi-axes > 0), got {body!r}")
    if ra == rb:
        return 24
    if math.atanh(min(ra, rb) / max(ra, rb)) >= ECC_ETA:
        return 32
    return 40


def area_samples(body: Body, n: int) -> np.ndarray:
    """About ``n`` equal-weight area elements of ``body``: rows (x_b, y_b, w) with body-frame offsets
    from the CM (m) and mass fractions w summing to 1.

    Equal-area polar cells of the unit disk (``nr`` rings, ring j split into 3 (2 j + 1) cells,
    N = 3 nr^2), each sampled at its centre in (radius^2, angle), then scaled by the semi-axes:
    the affine map keeps the cells equal in area. Successive rings are staggered by half a cell.
    """
    n = check_int("samples", n, 1, 10_000_000)
    ra, rb = body.semi_axes
    if ra <= 0.0 or rb <= 0.0:
        raise ValueError(f"area_samples needs an extended body (semi-axes > 0), got {body!r}")
    nr = max(1, int(round(math.sqrt(n / 3.0))))
    rows = []
    for j in range(nr):
        m = 3 * (2 * j + 1)
        rad = math.sqrt(((j * j) + (j + 1) ** 2) / 2.0) / nr
        ang = (np.arange(m) + 0.5 + 0.5 * (j % 2)) * (2.0 * math.pi / m)
        rows.append(np.column_stack([ra * rad * np.cos(ang), rb * rad * np.sin(ang)]))
    xy = np.concatenate(rows)
    w = np.full((xy.shape[0], 1), 1.0 / xy.shape[0])
    return np.ascontiguousarray(np.hstack([xy, w]))


def _law_code(law: str, area: str) -> int:
    """The code of ``law`` for the area method ``area``: ValueError naming both where it has no form there."""
    law_named(law, label="law")
    check_area(law, area)
    return LAW_CODES[law]


def _motion(alpha: float, vx: float, vy: float, spin: float) -> tuple[float, float, float, float]:
    return (check_real("alpha", alpha), check_real("vx", vx), check_real("vy", vy), check_real("spin", spin))


def icr_wrench(body: Body, alpha: float, vx: float, vy: float, spin: float, *, law: str = "dry",
               coeff: float = 1.0, nodes: int | None = None) -> tuple[float, float, float]:
    """(Fx, Fy, tau_cm) per unit mass by the ICR quadrature (see :mod:`rrbody._icr`).

    ``coeff`` is mu g (m/s^2) for ``dry`` and gamma (1/s) for ``viscous``; ``nodes`` defaults to
    :func:`icr_nodes`. Units: m/s^2 (world frame) and m^2/s^2.
    """
    alpha, vx, vy, spin = _motion(alpha, vx, vy, spin)
    ra, rb = body.semi_axes
    n = icr_nodes(body) if nodes is None else check_int("nodes", nodes, 1, NODE_COUNTS[-1])
    return tuple(float(v) for v in _icr_kernel(ra, rb, n, alpha, vx, vy, spin, _law_code(law, "icr"), float(coeff), 0.0,
                                               body.inertia_per_mass))  # type: ignore[return-value]


def sampled_wrench(body: Body, alpha: float, vx: float, vy: float, spin: float, *, law: str = "dry",
                   coeff: float = 1.0, samples: int = 4096) -> tuple[float, float, float]:
    """(Fx, Fy, tau_cm) per unit mass from :func:`area_samples` (m/s^2 world frame, m^2/s^2)."""
    from rrbody.physics.wrench import sampled_wrench as _kernel

    alpha, vx, vy, spin = _motion(alpha, vx, vy, spin)
    S = area_samples(body, samples)
    return tuple(float(v) for v in _kernel(S, alpha, vx, vy, spin, _law_code(law, "sampled"), float(coeff), 0.0))  # type: ignore[return-value]


def disk_closed_form_ratio(eps: float) -> tuple[float, float]:
    """Dimensionless dry-friction wrench of a uniformly loaded disk (independent of the quadrature).

    ``eps = |v_cm| / (|Omega| R)`` (the ICR sits at distance eps R from the centre). Returns
    (f, t) with |F| = mu g f (F opposite to v_cm) and |tau_cm| = mu g R t (opposing the spin).
    With m = k^2, k = min(eps, 1/eps), K = K(m), E = E(m) (scipy's parameter convention):

        eps <= 1:  f = (4 eps / pi) J1(k),       t = (4 / (3 pi)) J2(k)
        eps >= 1:  f = (4 / pi) J1(k),           t = (4 / (3 pi eps)) J3(k)
        J1 = int_0^{pi/2} cos^2 Delta      = [(1 + m) E - (1 - m) K] / (3 m)
        J2 = int_0^{pi/2} Delta^3          = [2 (2 - m) E - (1 - m) K] / 3
        J3 = int_0^{pi/2} cos^4 / Delta    = [(1 - m)(2 - 3 m) K - 2 (1 - 2 m) E] / (3 m^2)

    (Delta = sqrt(1 - m sin^2).) These agree with Farkas, Bartels, Unger and Wolf, PRL 90, 248302
    (2003); the derivation is in docs/extended.md. The J1 and J3 forms cancel for small k, where
    the hypergeometric forms J1 = (pi/4) 2F1(-1/2, 1/2; 2; m), J3 = (3 pi/16) 2F1(1/2, 1/2; 3; m)
    are used instead (k < 0.5).
    """
    from scipy.special import ellipe, ellipk, hyp2f1

    eps = check_real("eps", eps)
    if eps < 0.0:
        raise ValueError(f"eps must be >= 0, got {eps!r} (valid range: [0, inf))")
    if eps == 0.0:
        return 0.0, 2.0 / 3.0
    if math.isinf(eps):
        return 1.0, 0.0
    k = min(eps, 1.0 / eps)
    m = k * k
    if k < 0.5:
        # J1 and J3 by their hypergeometric series (the elliptic forms cancel like 1/m, 1/m^2)
        j1 = math.pi / 4.0 * float(hyp2f1(-0.5, 0.5, 2.0, m))
        j3 = 3.0 * math.pi / 16.0 * float(hyp2f1(0.5, 0.5, 3.0, m))
    else:
        K = float(ellipk(m)) if m < 1.0 else 0.0  # (1 - m) K -> 0 as m -> 1
        E = float(ellipe(m))
        j1 = ((1.0 + m) * E - (1.0 - m) * K) / (3.0 * m)
        j3 = ((1.0 - m) * (2.0 - 3.0 * m) * K - 2.0 * (1.0 - 2.0 * m) * E) / (3.0 * m * m)
    K = float(ellipk(m)) if m < 1.0 else 0.0
    E = float(ellipe(m))
    j2 = (2.0 * (2.0 - m) * E - (1.0 - m) * K) / 3.0
    if eps <= 1.0:
        return 4.0 * eps / math.pi * j1, 4.0 / (3.0 * math.pi) * j2
    return 4.0 / math.pi * j1, 4.0 / (3.0 * math.pi * eps) * j3


def disk_closed_form(R: float, vx: float, vy: float, spin: float, *, mu_g: float = 1.0) -> tuple[float, float, float]:
    """(Fx, Fy, tau_cm) per unit mass of a uniformly loaded disk of radius R (m) under dry friction
    mu g (m/s^2), from :func:`disk_closed_form_ratio`. World frame; m/s^2 and m^2/s^2."""
    R = check_positive("R", R, unit="m")
    vx, vy, spin = check_real("vx", vx), check_real("vy", vy), check_real("spin", spin)
    speed = math.hypot(vx, vy)
    if speed == 0.0 and spin == 0.0:
        return 0.0, 0.0, 0.0
    eps = math.inf if spin == 0.0 else speed / (abs(spin) * R)
    f, t = disk_closed_form_ratio(eps)
    fx = -mu_g * f * vx / speed if speed > 0.0 else 0.0
    fy = -mu_g * f * vy / speed if speed > 0.0 else 0.0
    return fx, fy, -math.copysign(mu_g * R * t, spin) if spin != 0.0 else 0.0
