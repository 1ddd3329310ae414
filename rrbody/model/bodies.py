"""Rigid bodies: geometry and mass properties, nothing else.

Frames: the *body frame* has its origin at the centre of mass (CM) and its x axis along the
``R_A`` semi-axis (for a rod-mass or a disk, along the body's reference direction). The body
angle ``alpha`` is the angle of that x axis from the world x axis. Lengths are in metres, the
mass in kilograms; the mass cancels from every result (friction and drive both scale with it).

The pivot point P sits at distance ``l`` from the CM. Its direction in the body frame is fixed by
the scene's initial state (``phi0`` minus the initial body angle), see :mod:`rrbody.scene`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np

from rrbody.model.checks import LIMITS, check, check_choice

__all__ = ["Body", "RodMass", "Disk", "Ellipse", "BODY_KINDS"]

Orientation = Literal["x", "y"]


@dataclass(frozen=True)
class Body:
    """Base class: a homogeneous planar body (or a point mass) with a pivot offset ``l``.

    Subclasses are data only: they provide ``inertia_per_mass`` (I_cm / m, m^2), ``area`` (m^2),
    ``semi_axes`` (R_A, R_B in m; zero for a point) and ``outline``.
    """

    kind: ClassVar[str] = "body"
    l: float = 0.0
    mass: float = 1.0
    orientation: Orientation = "x"

    def __post_init__(self) -> None:
        object.__setattr__(self, "l", check("l", self.l))
        object.__setattr__(self, "mass", check("mass", self.mass))
        check_choice("orientation", self.orientation, ("x", "y"))

    # ---- mass properties -------------------------------------------------------------------
    @property
    def inertia_per_mass(self) -> float:
        """I_cm / m in m^2."""
        raise NotImplementedError

    @property
    def area(self) -> float:
        """Contact area in m^2 (0 for a point mass)."""
        return 0.0

    @property
    def semi_axes(self) -> tuple[float, float]:
        """(R_A, R_B) in m: R_A along the body x axis."""
        return (0.0, 0.0)

    @property
    def alpha0(self) -> float:
        """Initial body angle (rad): 0 if R_A starts along world x, pi/2 if along world y."""
        return 0.0 if self.orientation == "x" else 0.5 * math.pi

    @property
    def is_point(self) -> bool:
        return self.area == 0.0

    @property
    def pivot_inside(self) -> bool:
        """Whether P (at distance l from the CM along the R_A axis direction or any other) can lie
        inside the body: true when l is below the smaller semi-axis (sufficient, not necessary)."""
        return self.l <= min(self.semi_axes)

    def outline(self, n: int = 128) -> np.ndarray:
        """Closed outline in the body frame, shape (n, 2), metres. A point mass gives one point."""
        ra, rb = self.semi_axes
        if ra == 0.0:
            return np.zeros((1, 2))
        s = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
        return np.column_stack([ra * np.cos(s), rb * np.sin(s)])

    def describe(self) -> dict[str, object]:
        """Plain-data description for metadata and JSON."""
        ra, rb = self.semi_axes
        return {"body": self.kind, "l": self.l, "mass": self.mass, "orientation": self.orientation,
                "R_A": ra, "R_B": rb, "I_cm_per_mass": self.inertia_per_mass, "area": self.area}


@dataclass(frozen=True)
class RodMass(Body):
    """A point mass on a massless rod of length ``l`` (m) pivoted at P: I_cm = 0, H = l/d."""

    kind: ClassVar[str] = "rod"

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.l == 0.0:
            raise ValueError(f"l must be {LIMITS['l'].text()[5:]} for a rod-mass body (the rod length), got 0.0")

    @property
    def inertia_per_mass(self) -> float:
        return 0.0


@dataclass(frozen=True)
class Disk(Body):
    """A homogeneous disk of radius ``R`` (m); P at distance ``l`` from its centre (inside if l <= R)."""

    kind: ClassVar[str] = "disk"
    R: float = 0.1

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "R", check("R", self.R))

    @property
    def inertia_per_mass(self) -> float:
        return 0.5 * self.R**2

    @property
    def area(self) -> float:
        return math.pi * self.R**2

    @property
    def semi_axes(self) -> tuple[float, float]:
        return (self.R, self.R)


@dataclass(frozen=True)
class Ellipse(Body):
    """A homogeneous ellipse, R_A = R0 (1 + delta) along body x, R_B = R0 (1 - delta); -1 < delta < 1."""

    kind: ClassVar[str] = "ellipse"
    R0: float = 0.1
    delta: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "R0", check("R0", self.R0))
        object.__setattr__(self, "delta", check("delta", self.delta))

    @property
    def semi_axes(self) -> tuple[float, float]:
        return (self.R0 * (1.0 + self.delta), self.R0 * (1.0 - self.delta))

    @property
    def inertia_per_mass(self) -> float:
        ra, rb = self.semi_axes
        return 0.25 * (ra**2 + rb**2)

    @property
    def area(self) -> float:
        ra, rb = self.semi_axes
        return math.pi * ra * rb


BODY_KINDS: dict[str, type[Body]] = {"rod": RodMass, "disk": Disk, "ellipse": Ellipse}
