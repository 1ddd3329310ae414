"""Effect ``dry``: Coulomb friction on a mass element, F = -mu g v_hat (per unit mass, m/s^2).

Parameter: ``coeff`` = mu g (m/s^2). Below the zero-speed dead band ``v_eps`` (m/s) the direction
of the velocity is undefined and the force is zero: the self-consistent limit at the impulsive
start from phi0 = pi (the equation of motion (docs/physics.md); the band's width and its bounded effect are in
:mod:`rrbody.physics.bind`). Declared in the law table (:data:`rrbody.model.laws.LAW_TABLE`).

Entry points, both paths: the element force :func:`force` and its one-axis component :func:`perp` (the
point and sampled methods, the point-mass Jacobian: :mod:`rrbody.physics.effects.laws`; the plugin's point feet and
sampled parts). Its exact area integrals are kernels of their own, which call these: the instantaneous-centre
quadrature and its table (:mod:`rrbody.physics.icr`, :mod:`rrbody.physics.icr_table`) and the footprint kernel
(:func:`rrbody.physics.contact.footprint_wrench`), which the ODE path's contact method and the plugin both use.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["force", "perp"]

NAME = "dry"


@njit(cache=True, inline="always")
def force(vx: float, vy: float, coeff: float, v_eps: float) -> tuple[float, float]:
    """Force per unit mass (m/s^2) on an element moving with (vx, vy) m/s, any frame."""
    # squares cannot overflow here: scene speeds are bounded far below 1e150 m/s by validation
    sp2 = vx * vx + vy * vy
    if sp2 <= v_eps * v_eps:
        return 0.0, 0.0
    inv = coeff / math.sqrt(sp2)
    return -vx * inv, -vy * inv


@njit(cache=True, inline="always")
def perp(ve: float, vp: float, coeff: float, v_eps: float) -> tuple[float, float, float]:
    """The component of the force along the second axis, f_p = -c v_p / |v|, and its derivatives
    (df_p/dv_e, df_p/dv_p): what the point-mass right-hand side and its Jacobian need."""
    sp2 = ve * ve + vp * vp
    if sp2 <= v_eps * v_eps:
        return 0.0, 0.0, 0.0
    speed = math.sqrt(sp2)
    inv3 = coeff / (sp2 * speed)
    return -coeff * vp / speed, vp * ve * inv3, -ve * ve * inv3
