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

from rrbody.model.active import MAX_SEED, Active
from rrbody.model.bodies import BODY_KINDS, Body, Polygon, RodMass
from rrbody.model.checks import LIMITS, MAX_TIME, MissingParameters, check, check_choice, check_int, check_range
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import LAWS, Friction, check_mu_static
from rrbody.model.laws import AREA_METHODS, LAW_PARAMS, LAW_TABLE, zero_speed_mu
from rrbody.model.pressure import Pressure, as_pressure, pressure_from_description, uniform

__all__ = ["Scene", "rod_mass_scene", "scene_from_params", "SCENE_PARAMS", "NUMERIC_SCENE_PARAMS", "FRICTION_METHODS",
           "NOISE_STEP_MAX", "MAX_SEED"]

FRICTION_METHODS: tuple[str, ...] = ("auto", *(m for m in AREA_METHODS if m != "point"))  # sampled, icr, table, contact
#: the largest noise_dt times the fastest linear rate (drag, rotational drag, viscous friction) a Scene takes:
#: the fixed-step scheme's stationary variance is then off by < 5 % (docs/active.md), and it is unstable beyond 2
NOISE_STEP_MAX: float = 0.5


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
        Initial phi' (rad/s). ``None`` (default) applies the impulsive start, the paper's Eq. 3:
        phi'(0) = (omega / H) cos(phi0).
    t_max : float or None
        Horizon (s). ``None``: analyses choose (the flip-time rule stops by itself).
    friction_method : {"auto", "sampled", "icr", "table", "contact"}
        Area integration for extended bodies ("auto": the instantaneous-centre method where it
        applies, its table for a disk under dry friction, else sampled elements; "table": a precomputed table of the
        instantaneous-centre wrench for disks and ellipses, built once per aspect ratio, <= 1e-10 from "icr" and
        several times cheaper per evaluation; docs/extended.md; "contact": the plugin's exact footprint kernel, which
        any pressure other than uniform uses).
    samples : int
        Resolution of the sampled-element quadrature (elements, approximately).
    v0, spin0 : free-body initial CM velocity (m/s, world frame) and spin (rad/s).
    pressure : Pressure or str
        How the weight presses on the plane (:mod:`rrbody.model.pressure`; default uniform over the
        body's area; a ring, an annulus, a Hertz patch, feet, a p(x, y); or the text form such as
        ``"ring:0.05"``). Anything but uniform is integrated exactly by the contact method
        (:mod:`rrbody.physics.contact`), the plugin's own kernel.
    tilt, downhill : float
        The plane's angle from the horizontal (rad, [0, pi/2)) and its direction of steepest descent
        (rad from the world x axis). On a tilt the normal load is m g cos(tilt) (dry friction's
        coefficient is scaled by it) and gravity's in-plane part m g sin(tilt) pulls at the CM; a
        thin flat body is assumed (nothing tips). For a driven rod-mass body this is the paper's
        circularly forced double pendulum.
    g : float
        Gravity (m/s^2) for the tilt's pull (dry friction's coefficient is already mu g).
    mu_static : float or None
        Static friction coefficient (>= mu = coeff / g; None: equal to mu). A free body that comes to
        rest stays at rest while static friction holds gravity's pull (docs: Contacts).
    active : rrbody.model.active.Active or None
        A free body's self-propulsion, its medium's drag and Langevin noise (:mod:`rrbody.model.active`).
    seed : int
        The active noise's seed on the ODE path, an integer in [0, 2^63 - 1] (numpy's PCG64; default 0):
        the same scene, seed, horizon and output interval give bit-identical runs. Non-zero only with a
        noisy ``active`` (diffusion or rot_diffusion > 0).
    noise_dt : float or None
        The fixed step (s) of the ODE path's stochastic scheme (:mod:`rrbody.integrate.sde`), in
        (0, 0.5 / r] with r the fastest of drag, rot_drag and a viscous friction's gamma (1/s); shortened
        to divide the output interval. None (default): 0.05 over the fastest rate of the motion
        (:func:`rrbody.integrate.sde.default_noise_dt`) for a noisy ``active``, the adaptive methods
        otherwise; given for an active body without noise, it runs the same fixed-step scheme (the
        deterministic limit).
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
    pressure: Pressure = field(default_factory=uniform)
    tilt: float = 0.0
    downhill: float = 0.0
    g: float = 9.81
    mu_static: float | None = None
    active: Active | None = None
    seed: int = 0
    noise_dt: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.body, Body):
            raise ValueError(f"body must be a rrbody body (RodMass, Disk, Ellipse), got {self.body!r}")
        if self.drive is not None and not isinstance(self.drive, CircularDrive):
            raise ValueError(f"drive must be a CircularDrive or None, got {self.drive!r}")
        if not isinstance(self.friction, Friction):
            raise ValueError(f"friction must be a Friction, got {self.friction!r}")
        object.__setattr__(self, "phi0", check("phi0", self.phi0))
        if self.phi_dot0 is not None:
            object.__setattr__(self, "phi_dot0", check("phi_dot0", self.phi_dot0))
        if self.t_max is not None:
            object.__setattr__(self, "t_max", check("t_max", self.t_max))
        check_choice("friction_method", self.friction_method, FRICTION_METHODS)
        object.__setattr__(self, "samples", check("samples", self.samples))
        v0 = tuple(self.v0) if isinstance(self.v0, (tuple, list)) else ()
        if len(v0) != 2:
            raise ValueError(f"v0 must be a pair (vx, vy) of numbers in {LIMITS['v0'].text()}, got {self.v0!r}")
        object.__setattr__(self, "v0", (check("v0", v0[0], label="v0[0]"), check("v0", v0[1], label="v0[1]")))
        object.__setattr__(self, "spin0", check("spin0", self.spin0))
        object.__setattr__(self, "pressure", as_pressure(self.pressure))
        object.__setattr__(self, "tilt", check("tilt", self.tilt))
        object.__setattr__(self, "downhill", check("downhill", self.downhill))
        object.__setattr__(self, "g", check("g", self.g))
        if self.mu_static is not None:
            if not self.friction.spec.sticks:  # (the laws under which a body comes to rest: rrbody.model.laws)
                sticky = ", ".join(repr(x.name) for x in LAW_TABLE if x.sticks)
                raise ValueError(f"mu_static applies to a law that sticks ({sticky}), got friction "
                                 f"{self.friction.law!r}")
            # (at least the law's coefficient at zero speed: dry's mu = (mu g) / g, Stribeck's mu_s)
            mu0 = zero_speed_mu(self.friction.law, self.friction.coeff / self.g, self.friction.params)
            object.__setattr__(self, "mu_static", check_mu_static(self.mu_static, mu0, rounding=1e-12,
                                                                       name=self.friction.spec.rest or "mu"))
        if self.active is not None:
            if not isinstance(self.active, Active):
                raise ValueError(f"active must be an rrbody.model.active.Active or None, got {self.active!r}")
            if self.drive is not None:
                raise ValueError("active applies to a free body (drive=None): a driven body's pivot holds it")
            if self.active.rot_diffusion > 0.0 and self.body.is_point:
                raise ValueError(f"rot_diffusion must be 0 for a {self.body.kind} body (a point mass: its spin is "
                                 f"kinematic, no torque turns it; use a disk, ellipse or polygon), got "
                                 f"{self.active.rot_diffusion!r} rad^2/s")
        self._check_noise()
        if not self.pressure.is_uniform and self.body.is_point:
            raise ValueError(f"pressure {self.pressure.kind!r} needs an extended body (disk or ellipse): a "
                             f"{self.body.kind} body is a point mass, got body {self.body.kind!r}")
        if not self.pressure.is_uniform and self.friction_method not in ("auto", "contact"):
            raise ValueError(f"friction_method must be 'auto' or 'contact' with pressure {self.pressure.kind!r} "
                             f"(the exact contact method), got {self.friction_method!r}")
        if self.drive is not None and isinstance(self.body, RodMass) and self.body.l == 0.0:
            raise ValueError(f"l must be {LIMITS['l'].text()[5:]} for a driven rod-mass body, got 0.0")
        if self.drive is not None and self.body.l > 0.0:
            # H enters every equation as omega/H and k/H: a derived H outside its range (a pivot a few
            # nanometres off a large body's centre) loses every digit; l = 0 is the legitimate limit
            check("H", self.H, label="H (derived from l, d and the body's size)")

    def _check_noise(self) -> None:
        """``seed`` and ``noise_dt``: each valid, and each with the active body it applies to."""
        object.__setattr__(self, "seed", check_int("seed", self.seed, 0, MAX_SEED))
        noisy = self.active is not None and self.active.noisy
        if self.seed != 0 and not noisy:
            raise ValueError(f"seed applies to an active body's noise (active=Active(..., diffusion or rot_diffusion "
                             f"> 0)), got seed {self.seed!r} with "
                             + ("no active body" if self.active is None else "an active body without noise"))
        if self.noise_dt is None:
            return
        if self.active is None:
            raise ValueError(f"noise_dt applies to an active body (active=Active(...)), got noise_dt "
                             f"{self.noise_dt!r} with no active body")
        rate = self.noise_rate
        hi = NOISE_STEP_MAX / rate if rate > 0.0 else MAX_TIME
        object.__setattr__(self, "noise_dt", check_range("noise_dt", self.noise_dt, 0.0, hi, lo_open=True, unit="s"))

    @property
    def noise_rate(self) -> float:
        """The fastest linear rate of an active body's medium and friction (1/s): drag, rot_drag (a body
        with a moment of inertia) and a viscous friction's gamma; 0 without an active body. The
        fixed-step scheme's stability (noise_dt * rate < 2) and accuracy depend on it."""
        if self.active is None:
            return 0.0
        rates = [self.active.drag, self.active.rot_drag if not self.body.is_point else 0.0]
        if self.friction.active and not self.friction.spec.load_scaled:  # a rate: viscous friction's gamma
            rates.append(self.friction.coeff)
        return max(rates)

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

    def with_(self, **changes: Any) -> Scene:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    def describe(self) -> dict[str, Any]:
        """Plain data (JSON-ready) for metadata, sidecars and sweep checkpoints."""
        return {
            **self.body.describe(),
            "drive": None if self.drive is None else {"omega": self.drive.omega, "d": self.drive.d},
            "friction": self.friction.describe(),
            "k": self.k if self.drive is not None else None,
            "H": self.H if self.drive is not None else None,
            "phi0": self.phi0,
            "phi_dot0": self.initial_phi_dot,
            "t_max": self.t_max,
            "friction_method": self.friction_method,
            "samples": self.samples,
            "v0": list(self.v0),
            "spin0": self.spin0,
            # only what differs from a level plane with uniform pressure is written: descriptions of
            # earlier runs stay the same
            **({} if self.pressure.is_uniform else {"pressure": self.pressure.describe()}),
            **({} if self.tilt == 0.0 else {"tilt": self.tilt, "downhill": self.downhill, "g": self.g}),
            **({} if self.mu_static is None else {"mu_static": self.mu_static, "g": self.g}),
            **({} if self.active is None else {"active": {**vars(self.active), "point": list(self.active.point)}}),
            **({} if self.seed == 0 else {"seed": self.seed}),
            **({} if self.noise_dt is None else {"noise_dt": self.noise_dt}),
        }

    @classmethod
    def from_description(cls, desc: dict[str, Any]) -> Scene:
        """Inverse of :meth:`describe` (used to reload trajectories and sweeps)."""
        kind = desc["body"]
        if kind not in BODY_KINDS:
            raise ValueError(f"body must be one of {', '.join(BODY_KINDS)}, got {kind!r}")
        common = {"l": desc["l"], "mass": desc.get("mass", 1.0), "orientation": desc.get("orientation", "x")}
        if kind == "rod":
            body: Body = RodMass(**common)
        elif kind == "polygon":
            body = Polygon(vertices=tuple(tuple(v) for v in desc["vertices"]), **common)  # type: ignore[arg-type]
        elif kind == "disk":
            body = BODY_KINDS["disk"](R=desc["R_A"], **common)  # type: ignore[call-arg]
        else:
            ra, rb = desc["R_A"], desc["R_B"]
            body = BODY_KINDS["ellipse"](R0=0.5 * (ra + rb), delta=(ra - rb) / (ra + rb), **common)  # type: ignore[call-arg]
        drive = None if desc["drive"] is None else CircularDrive(**desc["drive"])
        return cls(body=body, drive=drive, friction=Friction(**desc["friction"]), phi0=desc["phi0"],
                   phi_dot0=desc.get("phi_dot0"), t_max=desc.get("t_max"),
                   friction_method=desc.get("friction_method", "auto"), samples=desc.get("samples", 4096),
                   v0=tuple(desc.get("v0", (0.0, 0.0))), spin0=desc.get("spin0", 0.0),
                   pressure=pressure_from_description(desc.get("pressure")), tilt=desc.get("tilt", 0.0),
                   downhill=desc.get("downhill", 0.0), g=desc.get("g", 9.81), mu_static=desc.get("mu_static"),
                   active=None if desc.get("active") is None else Active(**{**desc["active"],
                                                                            "point": tuple(desc["active"]["point"])}),
                   seed=desc.get("seed", 0), noise_dt=desc.get("noise_dt"))


def rod_mass_scene(H: float, k: float, omega: float, phi0: float = math.pi, *, friction: str = "dry",
                   d: float = 1.0, t_max: float | None = None, phi_dot0: float | None = None) -> Scene:
    """The paper's rod-mass body: H = l/d, k = mu g/d (1/s^2; gamma for viscous), omega (rad/s)."""
    H = float(check("H", H))
    d = float(check("d", d))
    drive = CircularDrive(omega=omega, d=d)
    return Scene(body=RodMass(l=H * d), drive=drive, friction=Friction.from_k(friction, k, d), phi0=phi0,
                 t_max=t_max, phi_dot0=phi_dot0)


#: The flat parameters of :func:`scene_from_params` (the CLI's scene options and a sweep's base and
#: axes use these names; the law table's parameters last); the numeric ones can be sweep axes.
SCENE_PARAMS: tuple[str, ...] = ("body", "H", "l", "R0", "delta", "orientation", "omega", "d", "k", "mu", "g",
                                 "friction",
                                 "phi0", "phi_dot0", "t_max", "friction_method", "samples", "no_drive", "v0", "spin0",
                                 "pressure", "tilt", "downhill", "mu_static", "sides", "vertices", *LAW_PARAMS)
#: the body names scene_from_params takes (a box and a regular polygon are Polygon bodies)
BODY_CHOICES: tuple[str, ...] = ("rod", "disk", "ellipse", "box", "polygon")
NUMERIC_SCENE_PARAMS: tuple[str, ...] = ("H", "l", "R0", "delta", "omega", "d", "k", "mu", "g", "phi0", "phi_dot0",
                                         "t_max",
                                         "samples", "spin0", "tilt", "downhill", "mu_static", "sides", *LAW_PARAMS)


def scene_from_params(*, body: str = "rod", H: float | None = None, l: float | None = None,
                      R0: float | None = None, delta: float = 0.0, orientation: str = "x",
                      omega: float | None = None, d: float = 1.0, k: float | None = None, mu: float | None = None,
                      g: float = 9.81, friction: str = "dry", phi0: float = math.pi, phi_dot0: float | None = None,
                      t_max: float | None = None, friction_method: str = "auto", samples: int = 4096,
                      no_drive: bool = False, v0: tuple[float, float] = (0.0, 0.0), spin0: float = 0.0,
                      pressure: Pressure | str = "uniform", tilt: float = 0.0, downhill: float = 0.0,
                      mu_static: float | None = None, sides: int | None = None,
                      vertices: object = None, **law_params: float) -> Scene:
    """A Scene from flat parameters (the one mapping the CLI, batch mode and sweeps use).

    ``body``: ``rod`` (H = l/d, give ``H`` or ``l``), ``disk`` (radius ``R0``), ``ellipse``
    (``R0``, ``delta``), ``box`` (half-sides R0 (1 + delta) along x and R0 (1 - delta) along y, as
    an ellipse's semi-axes) or ``polygon`` (``sides`` of a regular polygon inscribed in a circle of
    radius ``R0``, or ``vertices`` [(x, y), ...] in m); ``l`` (m) is the CM -> P distance (default 0 for extended
    bodies). Friction: ``k`` (1/s^2; gamma in 1/s for viscous) or ``mu`` with ``g`` (m/s^2) and ``d`` (m), or
    ``friction="none"``. ``no_drive``: a free body launched with ``v0`` (m/s) and ``spin0`` (rad/s). ``pressure``: a
    :class:`rrbody.model.pressure.Pressure` or its text form (``"ring:0.05"``); ``tilt``, ``downhill`` (rad) and
    ``mu_static``: a tilted plane and static friction (``g`` is the tilt's gravity). ``law_params``: the friction
    law's further parameters by name (:data:`rrbody.model.laws.LAW_PARAMS`). Every parameter missing for the chosen
    body is named in one ValueError.
    """
    check_choice("body", body, BODY_CHOICES)
    if body == "polygon" and (sides is None) == (vertices is None):
        raise ValueError("polygon needs sides (with R0) or vertices, one of them: got "
                         + ("both" if sides is not None else "neither"))
    if body != "polygon" and (sides is not None or vertices is not None):
        raise ValueError(f"sides and vertices apply to body='polygon', got body={body!r}")
    check_choice("friction", friction, LAWS)
    missing = []
    if body == "rod" and H is None and l is None:
        missing.append("H")
    if body != "rod" and R0 is None and vertices is None:
        missing.append("R0")
    if not no_drive and omega is None:
        missing.append("omega")
    if friction != "none" and k is None and mu is None:
        missing.append("k")
    if missing:
        raise MissingParameters(missing)
    if k is not None and mu is not None:
        raise ValueError(f"k must be given alone: k and mu are alternatives, got k={k!r} and mu={mu!r}")
    # contradictions are named, never silently resolved (a k that would be ignored is an error)
    if friction == "none" and any(v not in (None, 0, 0.0) for v in (k, mu)):
        given = "k" if k not in (None, 0, 0.0) else "mu"
        raise ValueError(f"{given} must not be given with friction='none' (no friction has no coefficient), "
                         f"got {given}={k if given == 'k' else mu!r}")
    if body == "rod" and R0 is not None:
        raise ValueError(f"R0 must not be given for a rod-mass body (it has no area), got R0={R0!r}; "
                         "choose body='disk' or 'ellipse'")
    if not no_drive and (tuple(v0) != (0.0, 0.0) or spin0 != 0.0):
        raise ValueError(f"v0 and spin0 set the launch of a free body: give them with no_drive=True, got "
                         f"v0={tuple(v0)!r}, spin0={spin0!r}")
    d = float(check("d", d))
    if friction == "none":
        fric = Friction("none", params=law_params)  # type: ignore[arg-type]
    elif k is not None:
        fric = Friction.from_k(friction, k, d, law_params)
    else:
        fric = Friction.from_mu(friction, mu, g, d, law_params)  # type: ignore[arg-type]
    drive = None if no_drive else CircularDrive(omega=omega, d=d)  # type: ignore[arg-type]
    if body == "rod":
        if H is not None and l is not None:
            raise ValueError(f"H must be given alone for a rod-mass body: H and l are alternatives, got H={H!r}, "
                             f"l={l!r}")
        rod_l = float(check("H", H)) * d if H is not None else l
        b: Body = RodMass(l=rod_l, orientation=orientation)  # type: ignore[arg-type]
    else:
        if H is not None:
            raise ValueError(f"H must not be given for a {body} (it is derived from l, d and the body's size), "
                             f"got H={H!r}; give l (m) instead")
        ll = 0.0 if l is None else l
        if body == "box":
            r0 = float(check("R0", R0))
            dl = float(check("delta", delta))
            b = Polygon.box(2 * r0 * (1 + dl), 2 * r0 * (1 - dl), l=ll, orientation=orientation)
        elif body == "polygon":
            b = (Polygon.regular(sides, R0, l=ll, orientation=orientation) if vertices is None  # type: ignore[arg-type]
                 else Polygon(vertices=vertices, l=ll, orientation=orientation))  # type: ignore[arg-type]
        elif body == "disk":
            b = BODY_KINDS["disk"](R=R0, l=ll, orientation=orientation)  # type: ignore[call-arg,arg-type]
        else:
            b = BODY_KINDS["ellipse"](R0=R0, delta=delta, l=ll, orientation=orientation)  # type: ignore[call-arg,arg-type]
    return Scene(body=b, drive=drive, friction=fric, phi0=phi0, phi_dot0=phi_dot0, t_max=t_max,
                 friction_method=friction_method, samples=samples, v0=tuple(v0), spin0=spin0,  # type: ignore[arg-type]
                 pressure=as_pressure(pressure), tilt=tilt, downhill=downhill, g=g, mu_static=mu_static)
