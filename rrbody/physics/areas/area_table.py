"""Effect ``table``: friction on a homogeneous disk or ellipse from a precomputed wrench table.

The dry wrench as a piecewise polynomial of the instantaneous centre (kernel, layout and accuracy:
:mod:`rrbody.physics.icr_table`); ``S`` is the table of the body's aspect ratio
(:func:`rrbody.physics.icr_table.build_table`). The viscous law is linear, so it stays exact (the
closed form of :func:`rrbody.physics.icr.icr_wrench_body`, which returns before any quadrature).
Parameters: semi-axes ra, rb (m), icm = I_cm / m (m^2, for the viscous law).
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects.laws import DRY
from rrbody.physics.icr import icr_wrench_body
from rrbody.physics.icr_table import table_wrench_body

__all__ = ["wrench"]

NAME = "table"


@njit(cache=True, inline="always")
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm) per unit mass (m/s^2 body frame, m^2/s^2) at CM velocity (vbx, vby) (m/s, body frame)."""
    if law == DRY:
        return table_wrench_body(S, ra, rb, vbx, vby, spin, coeff, v_eps)
    # every other law with a table form (the law table) is exact in the quadrature's closed forms
    return icr_wrench_body(ra, rb, nq, vbx, vby, spin, law, coeff, v_eps, icm)
