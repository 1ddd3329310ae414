"""Friction laws as validated data: the law (dry, viscous, none) and its coefficient.

Units: ``coeff`` is mu*g in m/s^2 for dry friction and gamma in 1/s for viscous friction.
The compiled kernels that evaluate a law live in :mod:`rrbody.physics.wrench`.

Laws
----
- ``dry`` (Coulomb): f = -mu g v_hat for each mass element; the direction of a zero velocity is
  taken as zero force (the self-consistent limit at an impulsive start).
- ``viscous``: f = -gamma v, gamma in 1/s. The paper's "viscous" curve (Eq. 2 without the square
  root) is gamma numerically equal to k = mu g / d.
- ``none``: no friction; no kernel is called at all.
"""

from __future__ import annotations

from dataclasses import dataclass

from rrbody.model.checks import check, check_choice

__all__ = ["Friction", "LAWS", "LAW_CODES", "check_mu_static"]

LAWS: tuple[str, ...] = ("dry", "viscous", "none")
LAW_CODES: dict[str, int] = {"none": 0, "dry": 1, "viscous": 2}


def check_mu_static(mu_static: object, mu: float, *, rounding: float = 0.0) -> float:
    """``mu_static`` validated (a friction coefficient, and >= the kinetic ``mu``): static friction is
    never below kinetic. ``rounding``: the relative error ``mu`` carries (a mu recovered as mu g / g)."""
    mu_s = float(check("mu_static", mu_static))
    if mu_s < mu * (1.0 - rounding):
        raise ValueError(f"mu_static must be >= mu ({mu:g}: static friction is never below kinetic), got {mu_static!r}")
    return mu_s


@dataclass(frozen=True)
class Friction:
    """A friction law and its coefficient.

    ``coeff`` is mu*g in m/s^2 for ``dry`` and gamma in 1/s for ``viscous`` (ignored for ``none``).
    Build it from the paper's ``k = mu g / d`` with :meth:`from_k`, or from ``mu`` and ``g`` with
    :meth:`from_mu`.
    """

    law: str = "dry"
    coeff: float = 0.0

    def __post_init__(self) -> None:
        check_choice("friction", self.law, LAWS)
        object.__setattr__(self, "coeff", check("friction coefficient", self.coeff))
        if self.law == "none":
            object.__setattr__(self, "coeff", 0.0)

    @classmethod
    def from_k(cls, law: str, k: float, d: float) -> "Friction":
        """From k = mu g / d (1/s^2) and the drive radius d (m). Viscous: gamma = k (paper convention)."""
        check_choice("friction", law, LAWS)
        k = check("k", k)
        d = check("d", d)
        return cls(law, k * d if law == "dry" else k)

    @classmethod
    def from_mu(cls, law: str, mu: float, g: float = 9.81, d: float = 1.0) -> "Friction":
        """From the friction coefficient mu, gravity g (m/s^2) and, for the viscous convention, d (m)."""
        mu = check("mu", mu)
        g = check("g", g)
        d = check("d", d)
        return cls.from_k(law, mu * g / d, d)

    @property
    def code(self) -> int:
        return LAW_CODES[self.law]

    @property
    def active(self) -> bool:
        """False when no friction kernel needs to run."""
        return self.law != "none" and self.coeff > 0.0

    def k(self, d: float) -> float:
        """The paper's friction parameter for drive radius d: mu g / d (dry) or gamma (viscous)."""
        return self.coeff / d if self.law == "dry" else self.coeff
