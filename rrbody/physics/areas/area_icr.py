"""Effect ``icr``: friction on a homogeneous disk or ellipse by the instantaneous-centre quadrature.

Spectrally accurate 1-D Gauss quadrature about the instantaneous centre of rotation with exact
radial integrals (kernel and derivation: :mod:`rrbody.physics.icr`, docs/extended.md).
Parameters: semi-axes ra, rb (m), nodes per panel nq, icm = I_cm / m (m^2, for the viscous law).
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.icr import icr_wrench_body

__all__ = ["wrench"]

NAME = "icr"


@njit(cache=True, inline="always")
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm) per unit mass (m/s^2 body frame, m^2/s^2) at CM velocity (vbx, vby) (m/s, body frame)."""
    return icr_wrench_body(ra, rb, nq, vbx, vby, spin, law, coeff, v_eps, icm)
