"""Friction laws as validated data: the law (dry, viscous, none), its coefficient and its parameters.

Units: ``coeff`` is mu*g in m/s^2 for dry friction and gamma in 1/s for viscous friction.
The laws themselves are declared in :mod:`rrbody.model.laws` (the one table; :data:`LAWS` and
:data:`LAW_CODES` here are derived from it); the compiled kernels that evaluate a law live in
:mod:`rrbody.physics.effects`.

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
from rrbody.model.laws import LAW_CODES, LAWS, Law, check_law_params, law_named  # noqa: F401 (LAW_CODES: re-exported)

__all__ = ["Friction", "LAWS", "LAW_CODES", "check_mu_static"]


def check_mu_static(mu_static: object, mu: float, *, rounding: float = 0.0, name: str = "mu") -> float:
    """``mu_static`` validated (a friction coefficient, and >= ``mu``, the law's coefficient at zero speed:
    dry friction's kinetic mu, Stribeck's mu_s, :func:`rrbody.model.laws.zero_speed_mu`, called ``name``):
    static friction is never below kinetic. ``rounding``: the relative error ``mu`` carries (a mu recovered
    as mu g / g)."""
    mu_s = float(check("mu_static", mu_static))
    if mu_s < mu * (1.0 - rounding):
        raise ValueError(f"mu_static must be >= {name} ({mu:g}: static friction is never below kinetic), "
                         f"got {mu_static!r}")
    return mu_s


@dataclass(frozen=True)
class Friction:
    """A friction law, its coefficient and its further parameters.

    ``coeff`` is mu*g in m/s^2 for ``dry`` and gamma in 1/s for ``viscous`` (ignored for ``none``).
    ``params``: the law's further parameters (:attr:`rrbody.model.laws.Law.params`; a mapping or pairs
    (name, value), stored as pairs in the declared order; none for the laws above).
    Build it from the paper's ``k = mu g / d`` with :meth:`from_k`, or from ``mu`` and ``g`` with
    :meth:`from_mu`.
    """

    law: str = "dry"
    coeff: float = 0.0
    params: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        check_choice("friction", self.law, LAWS)
        object.__setattr__(self, "coeff", check("friction coefficient", self.coeff))
        object.__setattr__(self, "params", check_law_params(self.law, self.params))
        if self.law == "none":
            object.__setattr__(self, "coeff", 0.0)

    @classmethod
    def from_k(cls, law: str, k: float, d: float, params: object = ()) -> Friction:
        """From k = mu g / d (1/s^2) and the drive radius d (m). Viscous: gamma = k (paper convention)."""
        spec = law_named(law)
        k = check("k", k)
        d = check("d", d)
        return cls(law, k * d if spec.load_scaled else k, params)  # type: ignore[arg-type]

    @classmethod
    def from_mu(cls, law: str, mu: float, g: float = 9.81, d: float = 1.0, params: object = ()) -> Friction:
        """From the friction coefficient mu, gravity g (m/s^2) and, for the viscous convention, d (m)."""
        mu = check("mu", mu)
        g = check("g", g)
        d = check("d", d)
        return cls.from_k(law, mu * g / d, d, params)

    @property
    def spec(self) -> Law:
        """The law's declaration (:mod:`rrbody.model.laws`)."""
        return law_named(self.law)

    @property
    def code(self) -> int:
        """The law's code (the law table's)."""
        return self.spec.code

    @property
    def active(self) -> bool:
        """False when no friction kernel needs to run."""
        return self.law != "none" and self.coeff > 0.0

    def describe(self) -> dict[str, object]:
        """Plain data (JSON-ready): law and coeff, and the law's parameters if it has any (a law without
        writes none: the descriptions of earlier runs stay the same). ``Friction(**describe())`` rebuilds it."""
        return {"law": self.law, "coeff": self.coeff, **({"params": dict(self.params)} if self.params else {})}

    def k(self, d: float) -> float:
        """The paper's friction parameter for drive radius d: mu g / d (dry) or gamma (viscous)."""
        return self.coeff / d if self.spec.load_scaled else self.coeff
