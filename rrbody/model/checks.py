"""Argument checks: the one place where rrbody's parameters get their valid ranges and units.

Every check raises ``ValueError`` with one message format,

    ``<name> must be in <valid range> <unit>, got <value>``

(never ``assert``, which vanishes under ``python -O``). :data:`LIMITS` is the table of every named
parameter of the model and of the solver options; the model's constructors, the analyses and the
command line all check through it, so a range is written down once. The CLI maps its option names
onto these parameter names (``--t-max`` -> ``t_max``) and rewrites the name at the head of a message.

Subnormal numbers (0 < abs(v) < 2.2e-308) and absurd magnitudes are refused like negatives: they
lose every digit in the kernels (``H = l^2 / (d l)`` of ``l = 1e-320`` is 0, a division by zero).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from numbers import Integral, Real

#: Bounds on physical inputs. The upper ones exclude values that overflow the kernels (omega * t or
#: spin * size beyond ~1e15 loses every digit of an angle); the lower ones exclude magnitudes whose
#: squares underflow or whose periods exceed any horizon (MAX_TIME), not any regime studied.
MAX_RATE = 1e6        # rad/s (omega, spins) and 1/s
MIN_RATE = 1e-6       # rad/s (omega): a driving period of 6e6 s
MAX_LENGTH = 1e6      # m (d, l, R0)
MIN_LENGTH = 1e-9     # m (d, l, R0): squares stay far above the smallest normal float
MAX_FRICTION = 1e9    # mu g in m/s^2, gamma in 1/s, k in 1/s^2
MIN_FRICTION = 1e-12  # smallest nonzero k (t_f grows like omega/k; below this no horizon ends)
MAX_TIME = 1e9        # s (horizons)
TINY = sys.float_info.min  # smallest positive normal float (2.2e-308)
DIMENSIONLESS = "(dimensionless)"

__all__ = ["MAX_RATE", "MIN_RATE", "MAX_LENGTH", "MIN_LENGTH", "MAX_FRICTION", "MIN_FRICTION", "MAX_TIME",
           "Limit", "LIMITS", "MissingParameters", "check", "check_real", "check_positive", "check_nonnegative",
           "check_range",
           "check_int", "check_choice", "range_text", "number_rows"]


@dataclass(frozen=True)
class Limit:
    """The valid range of one parameter: [lo, hi] (ends open where asked), its unit, and whether
    exactly 0 is also allowed below ``lo`` (``zero_ok``: e.g. k = 0, no friction) and whether the
    value must be an integer."""

    lo: float
    hi: float
    unit: str = ""
    lo_open: bool = False
    hi_open: bool = False
    zero_ok: bool = False
    integer: bool = False
    help: str = ""

    def text(self) -> str:
        """The valid range as the messages and the CLI help show it, e.g. ``in [1e-6, 1e6] rad/s``."""
        return range_text(self.lo, self.hi, self.lo_open, self.hi_open, self.zero_ok, self.unit)


def range_text(lo: float, hi: float, lo_open: bool = False, hi_open: bool = False, zero_ok: bool = False,
               unit: str = "") -> str:
    """``in [lo, hi] unit`` with open ends as parentheses, and ``0 or`` in front when 0 is allowed."""
    iv = f"{'(' if lo_open else '['}{_num(lo)}, {_num(hi)}{')' if hi_open else ']'}"
    return f"{'0 or ' if zero_ok else ''}in {iv}{' ' + unit if unit else ''}"


def _num(x: float) -> str:
    """A bound as people write it: 1e6, 1e-12, 0.5, 256."""
    return f"{x:g}".replace("e+0", "e").replace("e-0", "e-").replace("e+", "e")


#: Every named parameter: model (bodies, drive, friction, scene), solver options, sweep and movie options.
LIMITS: dict[str, Limit] = {
    # bodies (m, kg)
    "l": Limit(MIN_LENGTH, MAX_LENGTH, "m", zero_ok=True, help="distance CM -> P"),
    "R": Limit(MIN_LENGTH, MAX_LENGTH, "m", help="disk radius"),
    "width": Limit(MIN_LENGTH, MAX_LENGTH, "m", help="box width"),
    "height": Limit(MIN_LENGTH, MAX_LENGTH, "m", help="box height"),
    "sides": Limit(3, 1000, DIMENSIONLESS, integer=True, help="sides of a regular polygon"),
    "R0": Limit(MIN_LENGTH, MAX_LENGTH, "m", help="ellipse mean semi-axis (disk radius)"),
    "delta": Limit(-1.0, 1.0, DIMENSIONLESS, lo_open=True, hi_open=True, help="ellipse eccentricity parameter"),
    "mass": Limit(1e-12, 1e12, "kg", help="mass (cancels from every result)"),
    # drive and friction
    "omega": Limit(MIN_RATE, MAX_RATE, "rad/s", help="driving rate"),
    "d": Limit(MIN_LENGTH, MAX_LENGTH, "m", help="driving radius"),
    "H": Limit(1e-6, 1e6, DIMENSIONLESS, help="geometry H = (I_cm + m l^2)/(m d l)"),
    "k": Limit(MIN_FRICTION, MAX_FRICTION, "1/s^2", zero_ok=True, help="friction k = mu g / d"),
    "mu": Limit(MIN_FRICTION, 1e3, DIMENSIONLESS, zero_ok=True, help="friction coefficient"),
    "g": Limit(1e-6, 1e6, "m/s^2", help="gravity"),
    "mu_static": Limit(MIN_FRICTION, 1e3, DIMENSIONLESS, zero_ok=True, help="static friction coefficient (>= mu)"),
    "tilt": Limit(0.0, 0.5 * math.pi, "rad", hi_open=True, help="angle of the plane from the horizontal"),
    "downhill": Limit(-1e6, 1e6, "rad", help="direction of steepest descent in the plane, from the x axis"),
    "friction coefficient": Limit(MIN_FRICTION, MAX_FRICTION, "m/s^2 (dry) or 1/s (viscous)", zero_ok=True),
    # initial state
    "phi0": Limit(-1e6, 1e6, "rad", help="initial angle of CM -> P"),
    "phi_dot0": Limit(-MAX_RATE, MAX_RATE, "rad/s", help="initial phi'"),
    "v0": Limit(-MAX_LENGTH, MAX_LENGTH, "m/s", help="free body: initial CM velocity component"),
    "spin0": Limit(-MAX_RATE, MAX_RATE, "rad/s", help="free body: initial spin"),
    "samples": Limit(1, 10_000_000, "area elements", integer=True),
    # solver options
    "t_max": Limit(0.0, MAX_TIME, "s", lo_open=True, help="horizon"),
    "dt_out": Limit(0.0, MAX_TIME, "s", lo_open=True, help="output interval"),
    "rtol": Limit(1e-15, 1e-2, DIMENSIONLESS, help="ODE relative tolerance"),
    "max_steps": Limit(1, 10**12, "steps", integer=True, help="cap on integration steps"),
    "tol": Limit(1e-14, 0.1, DIMENSIONLESS, help="absolute tolerance on H_c"),
    "dt": Limit(0.0, 10.0, "s", lo_open=True, help="engine time step"),
    "iterations": Limit(1, 100_000, "iterations per step", integer=True, help="engine constraint-solver iterations"),
    "settle_turns": Limit(0.5, 100.0, "turns"),
    "settle_periods": Limit(0.0, 1e6, "driving periods"),
    # Lyapunov exponents (rrbody.analysis.chaos)
    "renorm": Limit(0.0, MAX_TIME, "s", lo_open=True, help="time between renormalisations"),
    "d0": Limit(1e-14, 1e-3, DIMENSIONLESS, help="separation of the two trajectories (rad, rad/s)"),
    "points": Limit(1, 10_000_000, "points", integer=True, help="points of a Poincare section"),
    "theta_s": Limit(-1e6, 1e6, "rad", help="the Poincare section's surface theta = theta_s (mod 2 pi)"),
    # movie
    "fps": Limit(1.0, 240.0, "frames/s", help="movie frame rate"),
    "movie_speed": Limit(0.0, 1e6, "simulated s per movie s", lo_open=True),
    # sweeps
    "workers": Limit(0, 256, "processes", integer=True, help="local processes (0: in this process)"),
    "batch_size": Limit(1, 1_000_000, "points per task", integer=True),
}


class MissingParameters(ValueError):
    """Parameters that must be given and were not (all of them, named at once in ``names``)."""

    def __init__(self, names: list[str], prefix: str = "") -> None:
        self.names = list(names)
        super().__init__(f"{prefix + ': ' if prefix else ''}missing parameters {', '.join(names)}")


def _fail(name: str, value: object, valid: str) -> ValueError:
    return ValueError(f"{name} must be {valid}, got {value!r}")


def _float(value: object) -> float:
    """``float(value)``, with an int or fraction beyond the float range as inf (``float(10**400)`` raises
    OverflowError, which is not the ValueError every check promises)."""
    try:
        return float(value)  # type: ignore[arg-type]
    except OverflowError:
        return math.inf if value > 0 else -math.inf  # type: ignore[operator]


def _plain_number(value: object) -> bool:
    """A real number that is not a bool (float and int first: the ABC check costs a microsecond)."""
    tp = type(value)
    return tp is float or tp is int or (tp is not bool and isinstance(value, Real))


def check(name: str, value: object, *, label: str | None = None) -> float | int:
    """Validate ``value`` against ``LIMITS[name]``; the message names ``label`` (default ``name``).

    Refuses non-numbers, NaN, inf, subnormals, values outside the range and (for integer
    parameters) fractional values, each with the same one-line message."""
    lim = LIMITS[name]
    label = label or name
    if lim.integer:
        return check_int(label, value, int(lim.lo), int(lim.hi), unit=lim.unit)
    if not _plain_number(value):
        raise _fail(label, value, lim.text())
    v = _float(value)
    if v == 0.0 and lim.zero_ok:
        return 0.0
    ok_lo = v > lim.lo if lim.lo_open else v >= lim.lo
    ok_hi = v < lim.hi if lim.hi_open else v <= lim.hi
    if not (math.isfinite(v) and ok_lo and ok_hi) or (v != 0.0 and abs(v) < TINY):
        raise _fail(label, v, lim.text())
    return v


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a finite float, or raise ``ValueError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ValueError(f"{name} must be a finite real number, got {value!r} ({type(value).__name__})")
    v = _float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite real number, got {v!r}")
    return v


def check_range(name: str, value: object, lo: float, hi: float, *, lo_open: bool = False,
                hi_open: bool = False, unit: str = "") -> float:
    """Finite, not subnormal, and inside the interval [lo, hi] (ends open where asked)."""
    # the message is built only on failure: validation runs on every call of the fast paths
    if not _plain_number(value):
        raise _fail(name, value, range_text(lo, hi, lo_open, hi_open, False, unit))
    v = _float(value)
    ok_lo = v > lo if lo_open else v >= lo
    ok_hi = v < hi if hi_open else v <= hi
    if not (math.isfinite(v) and ok_lo and ok_hi) or (v != 0.0 and abs(v) < TINY):
        raise _fail(name, v, range_text(lo, hi, lo_open, hi_open, False, unit))
    return v


def check_positive(name: str, value: object, *, unit: str = "", hi: float = math.inf) -> float:
    """Finite, > 0 (and not subnormal) and <= hi."""
    return check_range(name, value, 0.0, hi, lo_open=True, unit=unit)


def check_nonnegative(name: str, value: object, *, unit: str = "", hi: float = math.inf) -> float:
    """Finite, >= 0 (not subnormal) and <= hi."""
    return check_range(name, value, 0.0, hi, unit=unit)


def check_int(name: str, value: object, lo: int, hi: int | None = None, *, unit: str = "") -> int:
    """An integer (not bool, not NaN, not fractional) in [lo, hi]; a float with an integral value counts."""
    def valid() -> str:
        return f"an integer in [{lo}, {hi if hi is not None else 'inf'}]{' ' + unit if unit else ''}"

    if type(value) is int:  # the common case first: it skips the ABC checks below, the costly part of a check
        iv = value
    elif isinstance(value, bool):
        raise _fail(name, value, valid())
    elif isinstance(value, Integral):
        iv = int(value)
    elif isinstance(value, Real) and math.isfinite(f := _float(value)) and f.is_integer():
        iv = int(f)
    else:
        raise _fail(name, value, valid())
    if iv < lo or (hi is not None and iv > hi):
        raise _fail(name, iv, valid())
    return iv


def check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    """One of ``choices``; the error lists the valid names."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(repr(c) for c in choices)}, got {value!r}")
    return str(value)


def number_rows(text: str) -> list[tuple[float, ...]]:
    """Rows of numbers in the command line's form ``A,B;C,D;...`` (empty rows skipped); ValueError
    (unnamed: the caller names its option) if a field is not a number."""
    return [tuple(float(v) for v in row.split(",")) for row in str(text).split(";") if row.strip()]
