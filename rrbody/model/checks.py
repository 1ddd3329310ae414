"""Argument checks shared by every public constructor and the CLI.

Each check raises ``ValueError`` naming the parameter, the bad value and the valid range
(never ``assert``, which vanishes under ``python -O``).
"""

from __future__ import annotations

import math
from numbers import Real

#: Upper bounds on physical inputs. They exclude values that overflow the kernels (omega * t or
#: spin * size beyond ~1e15 loses every digit of an angle) rather than any physical regime studied.
MAX_RATE = 1e6        # rad/s (omega, spins) and 1/s
MAX_LENGTH = 1e6      # m (d, l, R0)
MAX_FRICTION = 1e9    # mu g in m/s^2, gamma in 1/s, k in 1/s^2
MAX_TIME = 1e9        # s (horizons)

__all__ = ["MAX_RATE", "MAX_LENGTH", "MAX_FRICTION", "MAX_TIME", "check_real", "check_positive", "check_nonnegative", "check_range", "check_int", "check_choice"]


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a finite float, or raise ``ValueError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ValueError(f"{name} must be a finite real number, got {value!r} ({type(value).__name__})")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite real number, got {v!r}")
    return v


def check_positive(name: str, value: object, *, unit: str = "", hi: float = math.inf) -> float:
    """Finite, > 0 and <= hi."""
    v = check_real(name, value)
    if not (v > 0.0 and v <= hi):
        u = f" {unit}" if unit else ""
        raise ValueError(f"{name} must be > 0{u} and <= {hi:g}, got {v!r} (valid range: (0, {hi:g}])")
    return v


def check_nonnegative(name: str, value: object, *, unit: str = "", hi: float = math.inf) -> float:
    """Finite, >= 0 and <= hi."""
    v = check_real(name, value)
    if not (v >= 0.0 and v <= hi):
        u = f" {unit}" if unit else ""
        raise ValueError(f"{name} must be >= 0{u} and <= {hi:g}, got {v!r} (valid range: [0, {hi:g}])")
    return v


def check_range(name: str, value: object, lo: float, hi: float, *, lo_open: bool = False,
                hi_open: bool = False) -> float:
    """Finite and inside the interval [lo, hi] (ends open where asked)."""
    v = check_real(name, value)
    ok_lo = v > lo if lo_open else v >= lo
    ok_hi = v < hi if hi_open else v <= hi
    if not (ok_lo and ok_hi):
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise ValueError(f"{name} must lie in {interval}, got {v!r}")
    return v


def check_int(name: str, value: object, lo: int, hi: int | None = None) -> int:
    """An integer (not bool) in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, int):
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < lo or (hi is not None and value > hi):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi if hi is not None else 'inf'}], got {value!r}")
    return int(value)


def check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    """One of ``choices``; the error lists the valid names."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(repr(c) for c in choices)}, got {value!r}")
    return str(value)
