"""The scene: one validated, plain-data description of a run, read by every integrator and output.

A scene says *what* is simulated: the body, the drive (or none), the friction law, the initial
state and the horizon. Effects are composed: a frictionless scene never calls a friction kernel,
a point mass never touches an area quadrature.

Angles in rad, lengths in m, times in s. ``phi`` is the world angle of the vector CM -> P.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from rrbody.model.checks import MAX_LENGTH, MAX_RATE, MAX_TIME, check_choice, check_int, check_positive, check_range
from rrbody.model.bodies import BODY_KINDS, Body, RodMass
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction

__all__ = ["Scene", "rod_mass_scene", "FRICTION_METHODS"]

FRICTION_METHODS: tuple[str, ...] = ("auto", "sampled", "icr")


@dataclass(frozen=True)
class Scene:
    """A run: ``body`` driven by ``drive`` (None: a free body) under ``friction``.

    Parameters
    ----------
    body : Body
        Geometry, mass properties and the pivot offset ``l`` (m).
    drive : CircularDrive or None
        P(t) = d (cos wt, sin wt). ``None`` makes a free body (issue: free bodies).
    friction : Friction
        Law and coefficient; ``Friction("none")`` switches friction off.
    phi0 : float
        Initial angle of CM -> P (rad). The body starts with its R_A axis along x or y
        (``body.orientation``), so P's direction in the body frame is ``phi0 - body.alpha0``.
    phi_dot0 : float or None
        Initial phi' (rad/s). ``None`` (default) applies the impulsive start, SPEC Eq. 3:
        phi'(0) = (omega / H) cos(phi0).
    t_max : float or None
        Horizon (s). ``None``: analyses choose (the flip-time rule stops by itself).
    friction_method : {"auto", "sampled", "icr"}
        Area integration for extended bodies ("auto": the instantaneous-centre method where it
        applies, else sampled elements).
    samples : int
        Resolution of the sampled-element quadrature (elements, approximately).
    v0, spin0 : free-body initial CM velocity (m/s, world frame) and spin (rad/s).
    """

    body: Body
    drive: CircularDrive | None
    friction: Friction = field(default_factory=lambda: Friction("none"))
    phi0: float = math.pi
    phi_dot0: float | None = None
    t_max: float | None = None
    friction_method: str = "auto"
    samples: int = 4096
    v0: tuple[float, float] = (0.0, 0.0)
    spin0: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.body, Body):
            raise ValueError(f"body must be a rrbody body (RodMass, Disk, Ellipse), got {self.body!r}")
        if self.drive is not None and not isinstance(self.drive, CircularDrive):
            raise ValueError(f"drive must be a CircularDrive or None, got {self.drive!r}")
        if not isinstance(self.friction, Friction):
            raise ValueError(f"friction must be a Friction, got {self.friction!r}")
        object.__setattr__(self, "phi0", check_range("phi0", self.phi0, -1e6, 1e6))
        if self.phi_dot0 is not None:
            object.__setattr__(self, "phi_dot0", check_range("phi_dot0", self.phi_dot0, -MAX_RATE, MAX_RATE))
        if self.t_max is not None:
            object.__setattr__(self, "t_max", check_positive("t_max", self.t_max, unit="s", hi=MAX_TIME))
        check_choice("friction_method", self.friction_method, FRICTION_METHODS)
        object.__setattr__(self, "samples", check_int("samples", self.samples, 1, 10_000_000))
        v0 = tuple(self.v0)
        if len(v0) != 2:
            raise ValueError(f"v0 must be a pair (vx, vy) in m/s, got {self.v0!r}")
        object.__setattr__(self, "v0", (check_range("v0[0]", v0[0], -MAX_LENGTH, MAX_LENGTH),
                                        check_range("v0[1]", v0[1], -MAX_LENGTH, MAX_LENGTH)))
        object.__setattr__(self, "spin0", check_range("spin0", self.spin0, -MAX_RATE, MAX_RATE))
        if self.drive is not None and isinstance(self.body, RodMass) and self.body.l == 0.0:
            raise ValueError("l must be > 0 for a driven rod-mass body")

    # ---- derived quantities ------------------------------------------------------------------
    @property
    def driven(self) -> bool:
        return self.drive is not None

    @property
    def omega(self) -> float:
        return self.drive.omega if self.drive is not None else 0.0

    @property
    def d(self) -> float:
        return self.drive.d if self.drive is not None else 1.0

    @property
    def H(self) -> float:
        """Geometric parameter (I_cm + m l^2) / (m d l); inf when l = 0 (P at the CM)."""
        l = self.body.l
        if l == 0.0:
            return math.inf
        return (self.body.inertia_per_mass + l * l) / (self.d * l)

    @property
    def k(self) -> float:
        """The paper's friction parameter: mu g / d (dry, 1/s^2) or gamma (viscous, 1/s)."""
        return self.friction.k(self.d)

    @property
    def inertia_about_pivot(self) -> float:
        """I_P / m = I_cm/m + l^2 (m^2)."""
        return self.body.inertia_per_mass + self.body.l ** 2

    @property
    def initial_phi_dot(self) -> float:
        """phi'(0) (rad/s): given, or the impulsive start omega l d cos(phi0) / (I_P/m) = (w/H) cos phi0."""
        if self.phi_dot0 is not None:
            return self.phi_dot0
        if self.drive is None:
            return self.spin0
        return self.omega * self.body.l * self.d * math.cos(self.phi0) / self.inertia_about_pivot

    def velocity_scale(self) -> float:
        """A characteristic speed (m/s) for tolerances: drive speed plus spin times size."""
        ra, rb = self.body.semi_axes
        spin = abs(self.initial_phi_dot)
        return self.omega * self.d + (self.body.l + max(ra, rb)) * max(spin, self.omega) + math.hypot(*self.v0)

    def with_(self, **changes: Any) -> "Scene":
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    def describe(self) -> dict[str, Any]:
        """Plain data (JSON-ready) for metadata, sidecars and sweep checkpoints."""
        return {
            **self.body.describe(),
            "drive": None if self.drive is None else {"omega": self.drive.omega, "d": self.drive.d},
            "friction": {"law": self.friction.law, "coeff": self.friction.coeff},
            "k": self.k if self.drive is not None else None,
            "H": self.H if self.drive is not None else None,
            "phi0": self.phi0,
            "phi_dot0": self.initial_phi_dot,
            "t_max": self.t_max,
            "friction_method": self.friction_method,
            "samples": self.samples,
            "v0": list(self.v0),
            "spin0": self.spin0,
        }

    @classmethod
    def from_description(cls, desc: dict[str, Any]) -> "Scene":
        """Inverse of :meth:`describe` (used to reload trajectories and sweeps)."""
        kind = desc["body"]
        if kind not in BODY_KINDS:
            raise ValueError(f"body must be one of {', '.join(BODY_KINDS)}, got {kind!r}")
        common = {"l": desc["l"], "mass": desc.get("mass", 1.0), "orientation": desc.get("orientation", "x")}
        if kind == "rod":
            body: Body = RodMass(**common)
        elif kind == "disk":
            body = BODY_KINDS["disk"](R=desc["R_A"], **common)  # type: ignore[call-arg]
        else:
            ra, rb = desc["R_A"], desc["R_B"]
            body = BODY_KINDS["ellipse"](R0=0.5 * (ra + rb), delta=(ra - rb) / (ra + rb), **common)  # type: ignore[call-arg]
        drive = None if desc["drive"] is None else CircularDrive(**desc["drive"])
        return cls(body=body, drive=drive, friction=Friction(**desc["friction"]), phi0=desc["phi0"],
                   phi_dot0=desc.get("phi_dot0"), t_max=desc.get("t_max"),
                   friction_method=desc.get("friction_method", "auto"), samples=desc.get("samples", 4096),
                   v0=tuple(desc.get("v0", (0.0, 0.0))), spin0=desc.get("spin0", 0.0))


def rod_mass_scene(H: float, k: float, omega: float, phi0: float = math.pi, *, friction: str = "dry",
                   d: float = 1.0, t_max: float | None = None, phi_dot0: float | None = None) -> Scene:
    """The paper's rod-mass body: H = l/d, k = mu g/d (1/s^2; gamma for viscous), omega (rad/s)."""
    H = check_positive("H", H, hi=MAX_LENGTH)
    d = check_positive("d", d, unit="m", hi=MAX_LENGTH)
    drive = CircularDrive(omega=omega, d=d)
    return Scene(body=RodMass(l=H * d), drive=drive, friction=Friction.from_k(friction, k, d), phi0=phi0,
                 t_max=t_max, phi_dot0=phi_dot0)


