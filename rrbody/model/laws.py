"""The friction laws: one table, the single source that every path, every check and the command line read.

Each law is declared once, in :data:`LAW_TABLE` (REBOUNDx's effects, declared as data): its name, its code,
what its coefficient is, its further parameters with their units and ranges, the area methods that have a form
for it, what it does at rest, and the module of its compiled entry points, ``rrbody.physics.effects.<module>``
(the element force ``force`` and its one-axis component ``perp`` that the point and sampled methods and the
point-mass Jacobian call, plus any closed forms of its own; :mod:`rrbody.physics.effects.laws` builds the
compiled dispatch over the table). Everything else is derived from it:

- :data:`rrbody.model.friction.LAWS` and ``LAW_CODES``, and the validation of a
  :class:`~rrbody.model.friction.Friction` and its parameters;
- the effects registry (:data:`rrbody.physics.effects.LAWS`) and the compiled dispatch of
  :mod:`rrbody.physics.effects.laws`;
- the plugin's float codes (``rrbody.contact.columns.LAW_*``: numba reads them as compile-time constants);
- the command line's ``--friction`` choices and the options of the laws' parameters (:mod:`rrbody.cli.options`).

The composition checks itself: :func:`law_named` refuses an unknown law and :func:`check_area` a law on an area
method that has no form for it, each a ValueError naming both, raised where a scene is bound
(:func:`rrbody.physics.bind.area_model`) or a body enters the plugin (:mod:`rrbody.engine.plugin.admit`), never
inside a compiled kernel. Adding a law: its module in ``rrbody/physics/effects/`` and one entry here.

This module is plain data (no numpy, no numba): the model layer validates scenes with it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from rrbody.model.checks import LIMITS, Limit, MissingParameters, check_range

__all__ = ["AREA_METHODS", "AREA_CODES", "PLUGIN_AREA", "LawParam", "Law", "LAW_TABLE", "LAWS", "LAW_CODES",
           "LAW_PARAMS", "N_LAW_PARAMS", "law_named", "law_coded", "check_area", "check_law_params", "bound_params",
           "zero_speed_mu"]

#: the area-integration methods, in the order of their codes (AREA_CODES): friction at the
#: CM, summed over area elements, the instantaneous-centre quadrature, its table, the footprint kernel
AREA_METHODS: tuple[str, ...] = ("point", "sampled", "icr", "table", "contact")
#: area method -> code: its place in AREA_METHODS (the code a bound scene carries, rrbody.physics.params.BODY)
AREA_CODES: dict[str, int] = {name: code for code, name in enumerate(AREA_METHODS)}
#: the area method of the plugin path (the pymunk plugin, the MuJoCo adapter): the wrench of a footprint
PLUGIN_AREA = "contact"


@dataclass(frozen=True)
class LawParam:
    """A law's parameter beyond its coefficient, stored with the law (``Friction.params``).

    ``limit``: its valid range and unit; ``example``: a typical value, in the range (the prebuild's workload
    runs the law with it, :mod:`rrbody.cli.workload`); ``load``: a friction coefficient (dimensionless, like
    mu), which the kernels receive per unit mass as value * g * cos(tilt) (m/s^2), as the coefficient of a
    load-scaled law; otherwise they receive the value as it is."""

    name: str
    limit: Limit
    help: str
    example: float
    load: bool = False


@dataclass(frozen=True)
class Law:
    """One friction law (module docstring).

    ``code``: its integer in the system code (one decimal digit, rrbody.physics.effects.system_code) and in
    the plugin's LAW column; ``coeff_unit``: the unit of ``Friction.coeff``; ``load_scaled``: the coefficient
    is mu g, scaled by the normal load (times cos(tilt) on a tilted plane; the paper's k = coeff / d), else
    it is a rate (1/s, k = coeff); ``sticks``: the force stays finite as the speed goes to zero, so a body
    comes to rest in finite time: the rest rule, static friction (mu_static: a footprint at rest has dry
    friction's limit surface, the zero-speed limit of such a law) and the zero-speed dead band apply;
    ``smooth``: the right-hand side is smooth, so the variational equations hold (Lyapunov spectra);
    ``areas``: the area methods with a form for it; ``params``: its further parameters; ``module``: the
    module of its compiled entry points in rrbody.physics.effects ('' for a law that computes nothing);
    ``rest``: for a law that sticks, the parameter that is its coefficient at zero speed (static friction's
    default and floor, :func:`zero_speed_mu`), '' for the coefficient itself (dry friction)."""

    name: str
    code: int
    summary: str
    coeff_unit: str
    load_scaled: bool
    sticks: bool
    smooth: bool
    areas: tuple[str, ...]
    params: tuple[LawParam, ...] = ()
    module: str = ""
    rest: str = ""


#: every friction law, in the order the command line lists them
LAW_TABLE: tuple[Law, ...] = (
    Law("dry", 1, "Coulomb: f = -mu g v_hat on each mass element", "m/s^2", load_scaled=True, sticks=True,
        smooth=False, areas=AREA_METHODS, module="law_dry"),
    Law("viscous", 2, "linear: f = -gamma v on each mass element", "1/s", load_scaled=False, sticks=False,
        smooth=True, areas=AREA_METHODS, module="law_viscous"),
    Law("stribeck", 3, "Stribeck: f = -mu(v) g v_hat, mu(v) = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2), mu_k = mu",
        "m/s^2", load_scaled=True, sticks=True, smooth=False, areas=("point", "sampled", "contact"),
        params=(LawParam("mu_s", LIMITS["mu"],
                         "the friction coefficient at rest (mu(0); mu, the kinetic one, is mu(v >> v_s))", 0.5,
                         load=True),
                LawParam("v_s", Limit(1e-9, 1e9, "m/s"), "the Stribeck speed, over which mu falls from mu_s to mu",
                         0.01)),
        module="law_stribeck", rest="mu_s"),
    # no friction: no kernel runs (a scene binds it to the point method; every method has its form: zero)
    Law("none", 0, "no friction", "", load_scaled=False, sticks=False, smooth=True, areas=AREA_METHODS),
)

#: the laws' names (the command line's --friction choices) and codes
LAWS: tuple[str, ...] = tuple(law.name for law in LAW_TABLE)
LAW_CODES: dict[str, int] = {law.name: law.code for law in LAW_TABLE}
_BY_NAME: dict[str, Law] = {law.name: law for law in LAW_TABLE}
_BY_CODE: dict[int, Law] = {law.code: law for law in LAW_TABLE}
#: every law parameter by name (one name, one meaning: a name two laws share is declared alike)
LAW_PARAMS: dict[str, LawParam] = {q.name: q for law in LAW_TABLE for q in law.params}
#: the kernels' law-parameter slots (rrbody.physics.params, rrbody.contact.columns): the most any law has
N_LAW_PARAMS: int = max(len(law.params) for law in LAW_TABLE)


def _check_table() -> None:
    """The table's own consistency, at import: a broken declaration fails at once, not in a kernel."""
    if len(_BY_NAME) != len(LAW_TABLE) or len(_BY_CODE) != len(LAW_TABLE):
        pairs = [(law.name, law.code) for law in LAW_TABLE]
        raise ValueError(f"LAW_TABLE: names and codes must be unique, got {pairs}")
    for law in LAW_TABLE:
        if not 0 <= law.code <= 9:
            raise ValueError(f"LAW_TABLE: law {law.name!r} code must be in [0, 9] (a digit of the system code), "
                             f"got {law.code}")
        if law.rest and (not law.sticks or law.rest not in {q.name for q in law.params}):
            raise ValueError(f"LAW_TABLE: law {law.name!r} rest must name one of its parameters, and the law stick, "
                             f"got {law.rest!r}")
        bad = [a for a in law.areas if a not in AREA_METHODS]
        if bad or not law.areas:
            raise ValueError(f"LAW_TABLE: law {law.name!r} areas must be among {AREA_METHODS}, got {law.areas}")
    for law in LAW_TABLE:
        for q in law.params:
            if LAW_PARAMS[q.name] != q:
                raise ValueError(f"LAW_TABLE: parameter {q.name!r} is declared differently by two laws")
            lim = q.limit
            check_range(f"LAW_TABLE: {law.name!r} parameter {q.name!r} example", q.example, lim.lo, lim.hi,
                        lo_open=lim.lo_open, hi_open=lim.hi_open, unit=lim.unit)


_check_table()


def law_named(name: object, *, label: str = "friction") -> Law:
    """The law called ``name``; ValueError naming ``label`` and listing the laws otherwise."""
    law = _BY_NAME.get(name) if isinstance(name, str) else None
    if law is None:
        raise ValueError(f"{label} must be one of {', '.join(repr(n) for n in LAWS)}, got {name!r}")
    return law


def law_coded(code: object, *, label: str = "law") -> Law:
    """The law of code ``code`` (an int, or a float with an integral value: the plugin's column); ValueError
    naming ``label``, the code and the valid codes otherwise."""
    try:
        law = _BY_CODE.get(int(code)) if float(code) == int(code) else None  # type: ignore[call-overload]
    except (TypeError, ValueError, OverflowError):
        law = None
    if law is None:
        valid = ", ".join(f"{law.code} ({law.name})" for law in LAW_TABLE)
        raise ValueError(f"{label} must be one of the law codes {valid}, got {code!r}")
    return law


def check_area(law: str, area: str, *, where: str = "") -> None:
    """Raise ValueError naming the law and the area method if ``law`` has no form for ``area`` (and naming
    ``where`` it was asked for, e.g. the body); an unknown law or method is refused the same way."""
    spec = law_named(law)
    if area not in AREA_METHODS:
        raise ValueError(f"area method must be one of {', '.join(repr(a) for a in AREA_METHODS)}, got {area!r}")
    if area not in spec.areas:
        at = f" ({where})" if where else ""
        raise ValueError(f"friction {law!r} has no form for the area method {area!r}{at}; its methods: "
                         f"{', '.join(repr(a) for a in spec.areas)}")


def check_law_params(law: str, params: object) -> tuple[tuple[str, float], ...]:
    """``params`` (a mapping, or pairs (name, value)) validated for ``law``: exactly its declared parameters,
    each in its range, in the declared order. ValueError naming an unknown parameter (and the law's own),
    :class:`~rrbody.model.checks.MissingParameters` for those not given."""
    spec = law_named(law)
    try:
        given = dict(params.items() if isinstance(params, Mapping) else params)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"params must be a mapping of parameter names to numbers, got {params!r}") from None
    own = {q.name for q in spec.params}
    unknown = sorted(str(k) for k in given if k not in own)
    if unknown:
        names = ", ".join(repr(q.name) for q in spec.params) or "none"
        raise ValueError(f"friction {law!r} has no parameter {unknown[0]!r} (its parameters: {names})")
    missing = [q.name for q in spec.params if q.name not in given]
    if missing:
        raise MissingParameters(missing, prefix=f"friction {law!r}")
    out = []
    for q in spec.params:
        lim = q.limit
        out.append((q.name, check_range(q.name, given[q.name], lim.lo, lim.hi, lo_open=lim.lo_open,
                                        hi_open=lim.hi_open, unit=lim.unit)))
    return tuple(out)


def bound_params(law: str, params: tuple[tuple[str, float], ...], g_normal: float) -> tuple[float, ...]:
    """The kernels' law-parameter slots for ``law`` with validated ``params``: each value per unit mass
    (a :attr:`LawParam.load` coefficient times ``g_normal`` = g cos(tilt), m/s^2; others as they are), in the
    declared order, padded with zeros to :data:`N_LAW_PARAMS`."""
    spec = law_named(law)
    values = dict(params)
    out = [values[q.name] * g_normal if q.load else values[q.name] for q in spec.params]
    return tuple(out) + (0.0,) * (N_LAW_PARAMS - len(out))


def zero_speed_mu(law: str, mu: float, params: tuple[tuple[str, float], ...]) -> float:
    """The friction coefficient at zero speed of ``law`` with kinetic coefficient ``mu`` and validated ``params``
    (dimensionless): its :attr:`Law.rest` parameter (Stribeck's mu_s), else ``mu``. Static friction's default
    and its floor: a body the law holds at rest is held at least this hard (mu_static below it would let a body
    break away that the law, at the smallest speed, pushes straight back)."""
    spec = law_named(law)
    return float(dict(params)[spec.rest]) if spec.rest else float(mu)
