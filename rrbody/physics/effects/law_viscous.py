"""Effect ``viscous``: linear friction on a mass element, F = -gamma v (per unit mass, m/s^2).

Parameter: ``coeff`` = gamma (1/s). Smooth everywhere; ``v_eps`` is unused. Declared in the law table
(:data:`rrbody.model.laws.LAW_TABLE`).

Entry points, both paths: the element force :func:`force` and its one-axis component :func:`perp` (the
point and sampled methods, the point-mass Jacobian: :mod:`rrbody.physics.effects.laws`); the law is linear, so its
integral over
any area is a closed form of the load's moments: :func:`rigid` for a homogeneous disk or ellipse (the icr
and table methods) and :func:`moments` for any footprint: :func:`footprint`, the law's contact form,
which the contact method on the ODE path (:mod:`rrbody.physics.areas.area_contact`) and the plugin's kernel
(:mod:`rrbody.contact.accel`) both call (through :func:`rrbody.physics.effects.laws.law_footprint`).
"""

from __future__ import annotations

from numba import njit

__all__ = ["force", "perp", "rigid", "moments", "footprint"]

NAME = "viscous"


@njit(cache=True, inline="always")
def force(vx: float, vy: float, coeff: float, v_eps: float) -> tuple[float, float]:
    """Force per unit mass (m/s^2) on an element moving with (vx, vy) m/s, any frame."""
    return -coeff * vx, -coeff * vy


@njit(cache=True, inline="always")
def perp(ve: float, vp: float, coeff: float, v_eps: float) -> tuple[float, float, float]:
    """f_p = -gamma v_p and its derivatives (df_p/dv_e, df_p/dv_p)."""
    return -coeff * vp, 0.0, -coeff


@njit(cache=True, inline="always")
def rigid(vbx: float, vby: float, spin: float, coeff: float, icm: float) -> tuple[float, float, float]:
    """(F_x, F_y, tau_cm) per unit mass of a body whose load's mean position is its CM: -gamma v_cm
    (m/s^2, the frame of (vbx, vby) m/s) and -gamma (I_cm/m) spin (m^2/s^2), ``icm`` = I_cm/m (m^2)."""
    return -coeff * vbx, -coeff * vby, -coeff * icm * spin


@njit(cache=True, inline="always")
def moments(vbx: float, vby: float, spin: float, coeff: float, gx: float, gy: float,
            jj: float) -> tuple[float, float, float]:
    """(F_x, F_y, tau_cm) per unit mass (m/s^2, body frame; m^2/s^2) of -gamma v(s) weighted by the load:
    linear, so the load's mean position (gx, gy) (m, body frame from the centre of gravity) and its mean
    squared distance ``jj`` (m^2) suffice. CM velocity (vbx, vby) (m/s, body frame), spin (rad/s)."""
    return (-coeff * (vbx - spin * gy), -coeff * (vby + spin * gx),
            -coeff * (gx * vby - gy * vbx + spin * jj))


@njit(cache=True, inline="always")
def footprint(shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps):  # noqa: ANN001 (numba)
    """The contact form (:func:`rrbody.physics.effects.laws.law_footprint`): :func:`moments` of the footprint's
    load (the parts shapes[s0:s1] themselves are not needed: the law is linear)."""
    return moments(vbx, vby, w, coeff, gx, gy, jj)
