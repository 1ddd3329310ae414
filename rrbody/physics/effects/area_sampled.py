"""Effect ``sampled``: friction summed over equal-weight area elements (any body; the general method).

``S`` has rows (x_b, y_b, w): body-frame offsets from the CM (m) and mass fractions summing to 1
(:func:`rrbody.physics.area.area_samples`). Element velocity: v_cm + spin z x rho, all in the body
frame, where the samples are fixed: no rotation of the samples.
"""

from __future__ import annotations

from numba import njit

from rrbody.physics.effects.laws import element_force

__all__ = ["wrench"]

NAME = "sampled"


@njit(cache=True)
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm) per unit mass (m/s^2 body frame, m^2/s^2) from the area samples ``S`` at
    CM velocity (vbx, vby) (m/s, body frame)."""
    fx_t = 0.0
    fy_t = 0.0
    tau = 0.0
    for i in range(S.shape[0]):
        rx = S[i, 0]
        ry = S[i, 1]
        w = S[i, 2]
        fx, fy = element_force(law, vbx - spin * ry, vby + spin * rx, coeff, v_eps, lp)
        fx_t += w * fx
        fy_t += w * fy
        tau += w * (rx * fy - ry * fx)
    return fx_t, fy_t, tau
