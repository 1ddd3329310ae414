"""Effect ``stribeck``: velocity-weakening dry friction on a mass element (per unit mass, m/s^2),

    F = -mu(|v|) g v_hat,   mu(v) = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2),

the classic Stribeck curve of engineering friction: mu_s at rest (the breakaway coefficient), falling to
the kinetic mu_k over the Stribeck speed v_s. Parameters: ``coeff`` = mu_k g (m/s^2, times cos(tilt) on a
tilted plane, as dry friction's), and ``lp`` = (mu_s g, v_s) (m/s^2 and m/s: the law table's ``mu_s`` and
``v_s``, :mod:`rrbody.model.laws`, bound per unit mass by :func:`rrbody.model.laws.bound_params`). Below the
zero-speed dead band ``v_eps`` (m/s) the force is zero, as dry friction's (:mod:`.law_dry`). Limits: v_s -> 0
is Coulomb friction with mu_k, v_s -> infinity Coulomb friction with mu_s (``tests/test_stribeck.py``).

Entry points, both paths: the element force :func:`force` and its one-axis component :func:`perp` (the
point and sampled methods and the point-mass Jacobian, through :mod:`rrbody.physics.effects.laws`). It has no closed
form over an area: the contact method (the ODE path's, and the plugin's footprints) integrates :func:`force` by
quadrature (:mod:`rrbody.physics.footprint_quad`, with its stated error); the icr and table methods are dry friction's
own and have no form for it.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["force", "perp", "coefficient", "rest_coeff"]

NAME = "stribeck"


@njit(cache=True, inline="always")
def coefficient(speed: float, coeff: float, lp: tuple[float, ...]) -> tuple[float, float]:
    """(c, dc/dv): mu(v) g per unit mass at ``speed`` (m/s) and its derivative (1/s)."""
    x = speed / lp[1]
    drop = (lp[0] - coeff) * math.exp(-x * x)
    return coeff + drop, -2.0 * x / lp[1] * drop


@njit(cache=True, inline="always")
def rest_coeff(coeff: float, lp: tuple[float, ...]) -> float:
    """mu_s g per unit mass (m/s^2): the force's magnitude as the speed goes to zero (the footprint quadrature
    integrates this much exactly, as dry friction, :mod:`rrbody.physics.footprint_quad`)."""
    return lp[0]


@njit(cache=True, inline="always")
def force(vx: float, vy: float, coeff: float, v_eps: float, lp: tuple[float, ...]) -> tuple[float, float]:
    """Force per unit mass (m/s^2) on an element moving with (vx, vy) m/s, any frame."""
    sp2 = vx * vx + vy * vy  # (speeds are bounded far below 1e150 m/s by validation: no overflow)
    if sp2 <= v_eps * v_eps:
        return 0.0, 0.0
    speed = math.sqrt(sp2)
    c, _ = coefficient(speed, coeff, lp)
    inv = c / speed
    return -vx * inv, -vy * inv


@njit(cache=True, inline="always")
def perp(ve: float, vp: float, coeff: float, v_eps: float, lp: tuple[float, ...]) -> tuple[float, float, float]:
    """The force's component along the second axis, f_p = -c(v) v_p / v, and its derivatives
    (df_p/dv_e, df_p/dv_p) = (-c' v_e v_p / v^2 + c v_e v_p / v^3, -c' v_p^2 / v^2 - c v_e^2 / v^3)."""
    sp2 = ve * ve + vp * vp
    if sp2 <= v_eps * v_eps:
        return 0.0, 0.0, 0.0
    speed = math.sqrt(sp2)
    c, dc = coefficient(speed, coeff, lp)
    inv3 = c / (sp2 * speed)
    return -c * vp / speed, ve * vp * (inv3 - dc / sp2), -ve * ve * inv3 - dc * vp * vp / sp2
