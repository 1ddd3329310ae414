"""Effect ``tilt``: a plane tilted by an angle from the horizontal (the paper's first outlook).

Gravity's in-plane part, g sin(tilt) toward the downhill direction, acts at the centre of mass:
``p[GTX], p[GTY]`` (m/s^2, world frame; both 0 on a level plane). The normal load becomes
m g cos(tilt): :mod:`rrbody.physics.bind` scales the dry friction coefficient by cos(tilt). A thin
flat body is assumed: the pull tips nothing and leaves the pressure distribution as it is.

For a driven body its torque about P enters phi'': with phi the angle of CM -> P, the CM sits at
P - l (cos phi, sin phi), so tau_P / m = (CM - P) x g_t = l (sin phi g_x - cos phi g_y); for a
rod-mass body this is the paper's "circularly forced double pendulum". A point mass on a tilt is
bound as one sampled element at its CM (exactly its point friction: :func:`rrbody.physics.bind.area_model`),
so it takes the extended bodies' call and the numerical Jacobian, and the inline point mass of
every level run pays nothing for the tilt (its terms there cost a level run's step ~8 %, measured).
"""

from __future__ import annotations

import math

from numba import njit

from rrbody.physics import params as P

__all__ = ["pull", "pivot_torque"]

NAME = "tilt"


@njit(cache=True, inline="always")
def pull(p):  # noqa: ANN001 (numba)
    """Gravity's in-plane acceleration (m/s^2, world frame)."""
    return p[P.GTX], p[P.GTY]


@njit(cache=True, inline="always")
def pivot_torque(phi, p):  # noqa: ANN001 (numba)
    """The pull's torque about P per unit mass (m^2/s^2) at phi (rad, the angle of CM -> P)."""
    return p[P.L] * (math.sin(phi) * p[P.GTX] - math.cos(phi) * p[P.GTY])
