"""Dry friction on a uniformly loaded disk in closed form, compiled (the plugin's kernel for circles).

The same formulas as :func:`rrbody.physics.area.disk_closed_form_ratio` (complete elliptic integrals,
Farkas et al., PRL 90, 248302 (2003); derivation in docs/extended.md), evaluated without scipy:
K(m) and E(m) by the arithmetic-geometric mean (quadratic convergence: machine precision in ~6
iterations) and, for k = min(eps, 1/eps) < 0.5 where the elliptic forms of J1 and J3 cancel, their
hypergeometric series (ratio m <= 1/4 per term). About ten times cheaper than the 24-node
instantaneous-centre quadrature for a disk; ``tests/test_plugin.py`` checks both against scipy.

Units: per unit load (mu g = 1); the force is dimensionless, the torque about the centre in m.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["disk_wrench", "disk_ratio"]


@njit(cache=True)
def _ellipke(m: float) -> tuple[float, float]:
    """(K(m), E(m)) for 0 <= m < 1 by the arithmetic-geometric mean."""
    a = 1.0
    b = math.sqrt(1.0 - m)
    c2sum = 0.5 * m  # sum of 2^(n-1) c_n^2, c_0^2 = m
    p = 0.5
    for _ in range(40):
        c = 0.5 * (a - b)
        an = 0.5 * (a + b)
        b = math.sqrt(a * b)
        a = an
        p *= 2.0
        c2sum += p * c * c
        if abs(c) <= 1e-17 * a:
            break
    K = 0.5 * math.pi / a
    return K, K * (1.0 - c2sum)


@njit(cache=True)
def _hyp2f1(a: float, b: float, c: float, z: float) -> float:
    """Gauss's series 2F1(a, b; c; z) for |z| <= 1/4 (terms shrink at least 4x each)."""
    s = 1.0
    term = 1.0
    for n in range(200):
        term *= (a + n) * (b + n) / ((c + n) * (n + 1.0)) * z
        s += term
        if abs(term) <= 1e-17 * abs(s):
            break
    return s


@njit(cache=True)
def disk_ratio(eps: float) -> tuple[float, float]:
    """(f, t) with |F| = mu g f (opposing the centre's velocity) and |tau| = mu g R t (opposing the
    spin) for eps = |v| / (|Omega| R); eps = inf is pure translation."""
    if eps == 0.0:
        return 0.0, 2.0 / 3.0
    if math.isinf(eps):
        return 1.0, 0.0
    k = min(eps, 1.0 / eps)
    m = k * k
    if k < 0.5:
        j1 = 0.25 * math.pi * _hyp2f1(-0.5, 0.5, 2.0, m)
        j3 = 3.0 * math.pi / 16.0 * _hyp2f1(0.5, 0.5, 3.0, m)
        K, E = _ellipke(m)
    elif m < 1.0:
        K, E = _ellipke(m)
        j1 = ((1.0 + m) * E - (1.0 - m) * K) / (3.0 * m)
        j3 = ((1.0 - m) * (2.0 - 3.0 * m) * K - 2.0 * (1.0 - 2.0 * m) * E) / (3.0 * m * m)
    else:  # the instantaneous centre on the rim: (1 - m) K -> 0, E -> 1
        K, E = 0.0, 1.0
        j1 = 2.0 / 3.0
        j3 = 2.0 / 3.0
    j2 = (2.0 * (2.0 - m) * E - (1.0 - m) * K) / 3.0
    if eps <= 1.0:
        return 4.0 * eps / math.pi * j1, 4.0 / (3.0 * math.pi) * j2
    return 4.0 / math.pi * j1, 4.0 / (3.0 * math.pi * eps) * j3


@njit(cache=True)
def disk_wrench(R: float, vx: float, vy: float, spin: float, v_eps: float) -> tuple[float, float, float]:
    """(Fx, Fy, tau) per unit load on a disk of radius R (m) whose centre moves at (vx, vy) (m/s)
    with spin (rad/s); zero when every point is slower than ``v_eps`` (m/s)."""
    speed = math.sqrt(vx * vx + vy * vy)
    wr = abs(spin) * R
    if speed <= v_eps and wr <= v_eps:
        return 0.0, 0.0, 0.0
    eps = math.inf if spin == 0.0 else speed / wr
    f, t = disk_ratio(eps)
    fx = -f * vx / speed if speed > 0.0 else 0.0
    fy = -f * vy / speed if speed > 0.0 else 0.0
    tq = 0.0
    if spin > 0.0:
        tq = -R * t
    elif spin < 0.0:
        tq = R * t
    return fx, fy, tq
