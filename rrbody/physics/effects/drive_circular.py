"""Effect ``circular drive``: the pivot P moves on a circle of radius d at rate omega (SPEC section 2).

Its term in the driven body's equation, per unit mass, is the torque about P of the inertial force
of the accelerating pivot: omega^2 l d sin(phi - omega t) (m^2/s^2), with the CM at
r = P - l (cos phi, sin phi). Parameters: p[OMEGA] (rad/s), p[D] (m), p[L] (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P

__all__ = ["torque", "kinematics"]

NAME = "circular"


@njit(cache=True, inline="always")
def torque(sin_psi: float, p: np.ndarray) -> float:
    """Drive torque about P per unit mass (m^2/s^2) given sin(phi - omega t)."""
    w = p[P.OMEGA]
    return w * w * p[P.L] * p[P.D] * sin_psi


@njit(cache=True, inline="always")
def kinematics(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """CM position (m) and velocity (m/s) and P position (m), world frame, for the driven body."""
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    cw = math.cos(w * t)
    sw = math.sin(w * t)
    cp = math.cos(phi)
    sp = math.sin(phi)
    px = d * cw
    py = d * sw
    # r = P - l e(phi); r' = P' - l phi' e_perp(phi), e_perp = (-sin, cos)
    return px - l * cp, py - l * sp, -d * w * sw + l * phid * sp, d * w * cw - l * phid * cp, px, py
