"""The circular drive of the pivot P (world frame, metres, seconds)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rrbody.model.checks import check

__all__ = ["CircularDrive"]


@dataclass(frozen=True)
class CircularDrive:
    """P(t) = d (cos wt, sin wt): radius ``d`` (m), angular rate ``omega`` (rad/s, > 0: counter-clockwise)."""

    omega: float
    d: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "omega", check("omega", self.omega))
        object.__setattr__(self, "d", check("d", self.d))

    @property
    def period(self) -> float:
        """Driving period 2 pi / omega in s."""
        return 2.0 * math.pi / self.omega

    def position(self, t: np.ndarray | float) -> np.ndarray:
        """P(t), shape (..., 2), m."""
        wt = self.omega * np.asarray(t, dtype=float)
        return self.d * np.stack([np.cos(wt), np.sin(wt)], axis=-1)

    def velocity(self, t: np.ndarray | float) -> np.ndarray:
        """P'(t), shape (..., 2), m/s."""
        wt = self.omega * np.asarray(t, dtype=float)
        return self.d * self.omega * np.stack([-np.sin(wt), np.cos(wt)], axis=-1)
