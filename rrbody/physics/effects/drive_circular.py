"""Effect ``circular drive``: the pivot P moves on a circle of radius d at rate omega (the impulsive start, docs/physics.md).

Its term in the driven body's equation, per unit mass, is the torque about P of the inertial force
of the accelerating pivot: omega^2 l d sin(phi - omega t) (m^2/s^2), with the CM at
r = P - l (cos phi, sin phi). Parameters: p[OMEGA] (rad/s), p[D] (m), p[L] (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P

__all__ = ["torque", "rod_velocity", "frame", "kinematics"]

NAME = "circular"


@njit(cache=True, inline="always")
def torque(sin_psi: float, p: np.ndarray) -> float:
    """Drive torque about P per unit mass (m^2/s^2) given sin(phi - omega t)."""
    w = p[P.OMEGA]
    return w * w * p[P.L] * p[P.D] * sin_psi


@njit(cache=True, inline="always")
def rod_velocity(sin_psi: float, cos_psi: float, phid: float, p: np.ndarray) -> tuple[float, float]:
    """CM velocity (m/s) in the rod frame (e, e_perp) of CM -> P, e = (cos phi, sin phi):
    (d w sin psi, d w cos psi - l phi') with psi = phi - omega t (what the driven right-hand sides
    use: no world-frame angle, and the speed is a sum of squares that does not cancel)."""
    dw = p[P.D] * p[P.OMEGA]
    return dw * sin_psi, dw * cos_psi - p[P.L] * phid


@njit(cache=True, inline="always")
def frame(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """(cos wt, sin wt, cos phi, sin phi) and the CM velocity (vx, vy) (m/s, world frame):
    r = P - l e(phi), r' = P' - l phi' e_perp(phi), e_perp = (-sin, cos)."""
    w = p[P.OMEGA]
    d = p[P.D]
    l = p[P.L]
    cw = math.cos(w * t)
    sw = math.sin(w * t)
    cp = math.cos(phi)
    sp = math.sin(phi)
    return cw, sw, cp, sp, -d * w * sw + l * phid * sp, d * w * cw - l * phid * cp


@njit(cache=True, inline="always")
def kinematics(t: float, phi: float, phid: float, p: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """CM position (m) and velocity (m/s) and P position (m), world frame, for the driven body."""
    cw, sw, cp, sp, vx, vy = frame(t, phi, phid, p)
    px = p[P.D] * cw
    py = p[P.D] * sw
    return px - p[P.L] * cp, py - p[P.L] * sp, vx, vy, px, py
