"""Active bodies: a propulsion force fixed in the body frame, a medium's drag and Langevin noise.

:class:`Active` is validated plain data, read by both paths: the pymunk plugin
(``PlaneFriction.activate``, :mod:`rrbody.engine.plugin.active`) and, for one body, the ODE path (a free
scene's ``active``, :mod:`rrbody.physics.effects.active`; with noise, the fixed-step stochastic
Runge-Kutta scheme of :mod:`rrbody.integrate.sde`, seeded by the scene's ``seed``).

Model (per body, mass m, moment I about its centre of gravity G; world frame; body angle alpha):

    m dv = [R(alpha) F_b + F_plane + F_other - m gamma_t v] dt + m gamma_t sqrt(2 D_t) dW_2
    I dw = [p x F_b + tau_plane + tau_other - I gamma_r w] dt + I gamma_r sqrt(2 D_r) dW_1

with F_b = force (cos angle, sin angle) the propulsion (N, body frame), p = point (m, body frame
from G) where it acts, gamma_t, gamma_r the medium's linear and rotational drag rates (1/s) and
D_t (m^2/s), D_r (rad^2/s) the diffusion constants the noise gives a body with the drag alone:
its velocity and spin are Ornstein-Uhlenbeck processes, position and angle diffuse with D_t and
D_r at times >> 1/gamma (the fluctuation-dissipation relation with temperatures
k T_t = m gamma_t D_t and k T_r = I gamma_r D_r). Noise needs the drag that defines it: a
diffusion constant > 0 with its drag 0 is refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rrbody.model.checks import MAX_FRICTION, MAX_LENGTH, check_nonnegative, check_range, check_real

__all__ = ["Active", "MAX_FORCE", "MAX_DIFFUSION", "MAX_SEED"]

MAX_FORCE = 1e9       # N: a propulsion beyond this overflows nothing but is no physical body
MAX_DIFFUSION = 1e6   # m^2/s and rad^2/s
#: the largest seed of the noise (numpy's PCG64 takes any integer in [0, 2^63 - 1]): the plugin's
#: (PlaneFriction.seed), a Scene's, the box study's
MAX_SEED: int = 2**63 - 1


@dataclass(frozen=True)
class Active:
    """A body's self-propulsion and its medium (docstring of :mod:`rrbody.model.active`).

    Parameters
    ----------
    force : float
        Magnitude of the propulsion, N, in [0, 1e9].
    angle : float
        Its direction in the body frame, rad from the body's x axis (any finite value).
    point : (float, float)
        Where it acts, m, body frame from the centre of gravity (each component in [-1e6, 1e6]).
        Off the line of action through G it torques the body: tau = point x force (N m).
    drag, rot_drag : float
        The medium's translational and rotational drag rates gamma_t, gamma_r, 1/s, in [0, 1e9]
        (force -m gamma_t v at G, torque -I gamma_r w).
    diffusion, rot_diffusion : float
        D_t (m^2/s) and D_r (rad^2/s), in [0, 1e6]: the Langevin noise's strength (0: none). Each
        needs its drag > 0.
    """

    force: float
    angle: float = 0.0
    point: tuple[float, float] = (0.0, 0.0)
    drag: float = 0.0
    rot_drag: float = 0.0
    diffusion: float = 0.0
    rot_diffusion: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "force", check_nonnegative("force", self.force, unit="N", hi=MAX_FORCE))
        object.__setattr__(self, "angle", check_real("angle", self.angle))
        pt = tuple(self.point) if isinstance(self.point, (tuple, list)) else ()
        if len(pt) != 2:
            raise ValueError(f"point must be a pair (x, y) in m (body frame from the centre of gravity), "
                             f"got {self.point!r}")
        object.__setattr__(self, "point", tuple(check_range(f"point[{k}]", v, -MAX_LENGTH, MAX_LENGTH, unit="m")
                                                for k, v in enumerate(pt)))
        object.__setattr__(self, "drag", check_nonnegative("drag", self.drag, unit="1/s", hi=MAX_FRICTION))
        object.__setattr__(self, "rot_drag", check_nonnegative("rot_drag", self.rot_drag, unit="1/s",
                                                               hi=MAX_FRICTION))
        for name, drag in (("diffusion", "drag"), ("rot_diffusion", "rot_drag")):
            unit = "m^2/s" if name == "diffusion" else "rad^2/s"
            v = check_nonnegative(name, getattr(self, name), unit=unit, hi=MAX_DIFFUSION)
            object.__setattr__(self, name, v)
            if v > 0.0 and getattr(self, drag) == 0.0:
                raise ValueError(f"{name} > 0 needs {drag} > 0 (the noise's strength is {drag} times "
                                 f"sqrt(2 {name})), got {name} {v!r} with {drag} 0.0")

    @property
    def body_force(self) -> tuple[float, float]:
        """The propulsion in the body frame, N."""
        return self.force * math.cos(self.angle), self.force * math.sin(self.angle)

    @property
    def torque(self) -> float:
        """Its torque about the centre of gravity, N m: point x force."""
        fx, fy = self.body_force
        return self.point[0] * fy - self.point[1] * fx

    @property
    def noisy(self) -> bool:
        """Whether it has Langevin noise."""
        return self.diffusion > 0.0 or self.rot_diffusion > 0.0
