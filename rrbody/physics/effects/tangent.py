"""Effect ``tangent``: the variational equations of a driven body, carried in the state itself.

A driven state y = (phi, phi') may carry m tangent vectors after it, y = (phi, phi', dphi_1,
dphi'_1, ..., dphi_m, dphi'_m): their equations are the linearised flow,

    d/dt (dphi, dphi') = (dphi', a dphi + b dphi'),   a = d phi''/d phi,  b = d phi''/d phi'

at the base state. The effect is chosen by the state's size at run time (no compiled loop of its
own: the one stepping loop integrates the tangent vectors with the state, under the same error
control, and its events see the same phi); a run without tangent vectors pays one predictable
branch per evaluation.

a and b are analytic for a point mass on a level plane (the terms of the stiff methods' Jacobian,
:func:`rrbody.physics.dynamics.jacobian`: the drive's torque w^2 l d cos(psi), friction through
the law's derivatives ``element_perp``). Elsewhere (an extended body, a point mass on a tilt, which
is bound as one sampled element) they are central differences of phi'' in phi and phi' with steps
EPS times the variable's size: error about EPS^2 ~ 1e-12 relative from the truncation and 1e-10
from rounding, far below what a Lyapunov exponent is read to. For dry friction a and b exist only
while the contact slides (they jump where a slip speed crosses zero): use the two-trajectory estimate
there (:mod:`rrbody.analysis.chaos`).
"""

from __future__ import annotations

from numba import njit

__all__ = ["advance", "EPS"]

NAME = "tangent"
#: relative step of the central differences (cube root of the double precision epsilon, rounded)
EPS = 6e-6


@njit(cache=True, inline="always")
def advance(y, out, row, a, b):  # noqa: ANN001 (numba)
    """out[row, 2:] = the tangent vectors' derivatives, for coefficients a (1/s^2) and b (1/s)."""
    for i in range(2, y.shape[0], 2):
        out[row, i] = y[i + 1]
        out[row, i + 1] = a * y[i] + b * y[i + 1]
