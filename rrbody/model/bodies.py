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

__all__ = ["Body", "RodMass", "Disk", "Ellipse", "Polygon", "BODY_KINDS"]

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


def _polygon_props(v: np.ndarray) -> tuple[float, float, float, float]:
    """(signed area, centroid x, centroid y, polar second moment about the origin / area) of a polygon."""
    x, y = v[:, 0], v[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    a = 0.5 * float(cr.sum())
    if a == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    cx = float(((x + xn) * cr).sum()) / (6.0 * a)
    cy = float(((y + yn) * cr).sum()) / (6.0 * a)
    j = float(((x * x + x * xn + xn * xn + y * y + y * yn + yn * yn) * cr).sum()) / 12.0
    return a, cx, cy, j / a


@dataclass(frozen=True)
class Polygon(Body):
    """A homogeneous convex polygon: ``vertices`` (m, in order, either orientation). They are stored
    counter-clockwise in the body frame, shifted so that the centroid (the CM) is the origin; the body
    x axis is the vertices' x axis. Build common ones with :meth:`box` and :meth:`regular`."""

    kind: ClassVar[str] = "polygon"
    vertices: tuple[tuple[float, float], ...] = ((0.1, 0.0), (0.0, 0.1), (-0.1, 0.0), (0.0, -0.1))

    def __post_init__(self) -> None:
        super().__post_init__()
        try:
            v = np.array(self.vertices, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"vertices must be a list of (x, y) pairs in m, got {self.vertices!r}") from None
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3 or not np.all(np.isfinite(v)):
            raise ValueError(f"vertices must be at least 3 finite (x, y) pairs in m, got {self.vertices!r}")
        if np.max(np.abs(v)) > 1e6:
            raise ValueError(f"vertices must lie within 1e6 m of the origin, got {self.vertices!r}")
        a, cx, cy, _ = _polygon_props(v)
        if a < 0.0:
            v = v[::-1]
            a = -a
        size = float(np.max(np.hypot(v[:, 0] - cx, v[:, 1] - cy)))
        if not a > 1e-9 * size * size or size < 1e-9:
            raise ValueError(f"vertices must enclose a positive area (a convex polygon), got {self.vertices!r}")
        e = np.roll(v, -1, axis=0) - v
        turn = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        if np.any(turn < -1e-12 * size * size):
            # (the vertices were put counter-clockwise above: either orientation is accepted as given)
            raise ValueError(f"vertices must make a convex polygon (every turn the same way, all left or all "
                             f"right), got {self.vertices!r}")
        if math.hypot(cx, cy) <= 1e-13 * size:
            cx = cy = 0.0  # centred already (to rounding): kept as given, so a description round-trips
        object.__setattr__(self, "vertices", tuple((float(x - cx), float(y - cy)) for x, y in v))

    @classmethod
    def box(cls, width: float, height: float, **kw: object) -> Polygon:
        """A rectangle of ``width`` along the body x axis and ``height`` (m)."""
        w, h = 0.5 * check("width", width), 0.5 * check("height", height)
        return cls(vertices=((w, -h), (w, h), (-w, h), (-w, -h)), **kw)  # type: ignore[arg-type]

    @classmethod
    def regular(cls, sides: int, R: float, **kw: object) -> Polygon:
        """A regular polygon of ``sides`` (>= 3) inscribed in the circle of radius ``R`` (m), a vertex on +x."""
        n = int(check("sides", sides))
        r = check("R", R)
        return cls(vertices=tuple((r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n))
                                  for k in range(n)), **kw)  # type: ignore[arg-type]

    @property
    def _array(self) -> np.ndarray:
        return np.array(self.vertices)

    @property
    def area(self) -> float:
        return _polygon_props(self._array)[0]

    @property
    def inertia_per_mass(self) -> float:
        return _polygon_props(self._array)[3]

    @property
    def semi_axes(self) -> tuple[float, float]:
        """(largest |x|, largest |y|) of the vertices (m): the extents along the body axes."""
        v = self._array
        return float(np.max(np.abs(v[:, 0]))), float(np.max(np.abs(v[:, 1])))

    @property
    def pivot_inside(self) -> bool:
        """Whether P (at distance l from the CM, any direction) lies inside: l below the inradius."""
        v = self._array
        e = np.roll(v, -1, axis=0) - v
        dist = (e[:, 0] * v[:, 1] - e[:, 1] * v[:, 0]) / np.hypot(e[:, 0], e[:, 1])
        return self.l <= float(np.min(np.abs(dist)))

    def outline(self, n: int = 128) -> np.ndarray:
        """The vertices (counter-clockwise, body frame, m): the exact outline (``n`` is ignored)."""
        return self._array.copy()

    def describe(self) -> dict[str, object]:
        return {**super().describe(), "vertices": [list(v) for v in self.vertices]}


BODY_KINDS: dict[str, type[Body]] = {"rod": RodMass, "disk": Disk, "ellipse": Ellipse, "polygon": Polygon}
