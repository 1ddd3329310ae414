"""Effect ``viscous``: linear friction on a mass element, F = -gamma v (per unit mass, m/s^2).

Parameter: ``coeff`` = gamma (1/s). Smooth everywhere; ``v_eps`` is unused.
"""

from __future__ import annotations

from numba import njit

__all__ = ["force", "perp"]

NAME = "viscous"


@njit(cache=True, inline="always")
def force(vx: float, vy: float, coeff: float, v_eps: float) -> tuple[float, float]:
    """Force per unit mass (m/s^2) on an element moving with (vx, vy) m/s, any frame."""
    return -coeff * vx, -coeff * vy


@njit(cache=True, inline="always")
def perp(ve: float, vp: float, coeff: float, v_eps: float) -> tuple[float, float, float]:
    """f_p = -gamma v_p and its derivatives (df_p/dv_e, df_p/dv_p)."""
    return -coeff * vp, 0.0, -coeff
