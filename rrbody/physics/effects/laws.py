"""Registration of the friction laws: the one place that maps a law's code to its module.

The code is a compile-time constant in every composed right-hand side (part of its compiled code,
:mod:`rrbody.physics.effects`), so the branches below are resolved when the kernel is compiled; the
plugin's kernel and :mod:`rrbody.physics.wrench` pass it at run time.
Adding a law: a module with ``force`` and ``perp`` (see :mod:`.law_dry`), a code in
:data:`rrbody.physics.effects.LAWS` and one branch in each function here.
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects import law_dry, law_viscous

__all__ = ["element_force", "element_perp", "NONE", "DRY", "VISCOUS"]

NONE, DRY, VISCOUS = 0, 1, 2


@njit(cache=True, inline="always")
def element_force(law, vx, vy, coeff, v_eps):  # noqa: ANN001 (numba)
    """Force per unit mass (m/s^2) of law ``law`` on an element moving with (vx, vy) m/s."""
    if law == DRY:
        return law_dry.force(vx, vy, coeff, v_eps)
    if law == VISCOUS:
        return law_viscous.force(vx, vy, coeff, v_eps)
    return 0.0, 0.0


@njit(cache=True, inline="always")
def element_perp(law, ve, vp, coeff, v_eps):  # noqa: ANN001 (numba)
    """(f_p, df_p/dv_e, df_p/dv_p) of law ``law``: the force component along the second axis."""
    if law == DRY:
        return law_dry.perp(ve, vp, coeff, v_eps)
    if law == VISCOUS:
        return law_viscous.perp(ve, vp, coeff, v_eps)
    return 0.0, 0.0, 0.0
