"""Effect ``icr``: friction on a homogeneous disk or ellipse by the instantaneous-centre quadrature.

Spectrally accurate 1-D Gauss quadrature about the instantaneous centre of rotation with exact
radial integrals (kernel and derivation: :mod:`rrbody.physics.icr`, docs/extended.md).
Parameters: semi-axes ra, rb (m), nodes per panel nq, icm = I_cm / m (m^2, for the viscous law).
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.icr import icr_wrench

__all__ = ["wrench"]

NAME = "icr"


@njit(cache=True, inline="always")
def wrench(law, S, ra, rb, nq, icm, alpha, vx, vy, spin, coeff, v_eps):  # noqa: ANN001 (numba)
    """(Fx, Fy, tau_cm) per unit mass (m/s^2 world frame, m^2/s^2)."""
    return icr_wrench(ra, rb, nq, alpha, vx, vy, spin, law, coeff, v_eps, icm)
