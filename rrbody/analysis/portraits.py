"""Rotating-frame phase portraits (theta, theta') and the line of valid initial conditions.

theta = phi - omega t + pi is the angle of the rod in the frame rotating with the drive
(docs/physics.md); theta' = phi' - omega (rad/s). The impulsive start phi'(0) = (omega/H) cos(phi0)
(the paper's Eq. 3) puts every start on one curve of the (theta, theta') plane, the paper's "line of
valid initial conditions": theta = phi0 + pi, theta' = (omega/H) cos(phi0) - omega, i.e.
theta' = -(omega/H) cos(theta) - omega.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.model.checks import check_positive

__all__ = ["valid_initial_line", "theta_series", "initial_point"]


def valid_initial_line(H: float, omega: float, theta: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """(theta, theta') of impulsive starts: theta' = -(omega/H) cos(theta) - omega (rad, rad/s).

    ``theta`` defaults to 400 points over [0, 2 pi].
    """
    H = check_positive("H", H)
    omega = check_positive("omega", omega, unit="rad/s")
    th = np.linspace(0.0, 2.0 * math.pi, 400) if theta is None else np.asarray(theta, dtype=float)
    return th, -(omega / H) * np.cos(th) - omega


def initial_point(H: float, omega: float, phi0: float) -> tuple[float, float]:
    """(theta(0), theta'(0)) of the impulsive start at phi0: (phi0 + pi, (omega/H) cos phi0 - omega)."""
    H = check_positive("H", H)
    omega = check_positive("omega", omega, unit="rad/s")
    return phi0 + math.pi, (omega / H) * math.cos(phi0) - omega


def theta_series(t: np.ndarray, phi: np.ndarray, phi_dot: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """theta(t) = phi - omega t + pi (unwrapped) and theta'(t) = phi' - omega."""
    omega = check_positive("omega", omega, unit="rad/s")
    t = np.asarray(t, dtype=float)
    return np.asarray(phi) - omega * t + math.pi, np.asarray(phi_dot) - omega
