"""Parse numbers and angle expressions such as ``pi``, ``-pi/2``, ``3pi/4``, ``0.75*pi``, ``2.1`` or ``180deg``
without ``eval``.

Every value is finite at every step of parsing, not only at the end: a literal beyond the float range
(``1e400``), a product that overflows (``1e308pi``) or a quotient by one (``1/1e400``, which would be a
silent 0) is refused, and so is a nonzero literal or step that underflows to 0 (``1e-400``: as a
friction coefficient that would silently mean "no friction").
"""

from __future__ import annotations

import math
import re

__all__ = ["parse_angle", "parse_number", "maybe_degrees"]

_NUM = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_NUMBER = re.compile(rf"^\s*[+-]?{_NUM}\s*$", re.ASCII)  # ASCII digits: "٣" is no number here
_DEG = re.compile(rf"^\s*(?P<num>[+-]?\s*{_NUM})\s*(?:deg|°)\s*$")
_PATTERN = re.compile(
    rf"^\s*(?P<sign>[+-]?)\s*(?P<coef>{_NUM})?\s*(?P<star>\*)?\s*(?P<pi>pi|π)?\s*(?:/\s*(?P<den>{_NUM}))?\s*$"
)


def _nonzero_literal(text: str) -> bool:
    """True when a decimal literal has a nonzero digit before its exponent (it denotes a nonzero value)."""
    mantissa = re.split(r"[eE]", text, maxsplit=1)[0]
    return any(c in "123456789" for c in mantissa)


def parse_number(text: str, *, name: str, valid: str = "") -> float:
    """Return the float that the decimal literal ``text`` denotes (``2.5``, ``-1e-3``, ``.5``, ``1E6``).

    Raises ``ValueError`` naming ``name`` (followed by ``valid``, e.g. ``" in [1e-6, 1e6] rad/s"``) for
    anything else: words, ``inf`` and ``nan``, underscores, a literal beyond the float range
    (``1e400``, which ``float`` turns into inf) and a nonzero literal that underflows to 0 (``1e-400``).
    """
    if not isinstance(text, str):
        raise ValueError(f"{name} must be a finite number{valid}, got {text!r}")
    bad = f"{name} must be a finite number{valid}, got {text!r}"
    if _NUMBER.match(text) is None:
        raise ValueError(bad)
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"{bad}: beyond the float range (about 1.8e308)")
    if v == 0.0 and _nonzero_literal(text):
        raise ValueError(f"{bad}: too small, it underflows to 0")
    return v


def _step(value: float, operands: tuple[float, ...], name: str, text: str) -> float:
    """One arithmetic step of an expression: finite, and not a silent 0 from nonzero operands."""
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite at every step of {text!r}: it overflows the float range")
    if value == 0.0 and all(x != 0.0 for x in operands):
        raise ValueError(f"{name}: {text!r} underflows to 0 (a nonzero value too small for a float)")
    return value


def parse_angle(text: str | float | int, *, name: str = "phi0") -> float:
    """Return the angle in radians that ``text`` denotes.

    Accepted forms: a plain number (radians), ``[sign][coef][*]pi[/den]`` such as ``pi``,
    ``-pi/2``, ``3pi/4``, ``0.5*pi``, or a number of degrees with an explicit suffix, ``180deg``,
    ``-90 deg``, ``45°``. Each step (the literals, the product with pi, the quotient, degrees to
    radians) must be finite and must not underflow to 0. Raises ``ValueError`` naming ``name``
    otherwise.
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        try:
            value = float(text)
        except OverflowError:  # an int beyond the float range
            raise ValueError(f"{name} must be finite, got {text!r}") from None
        if not math.isfinite(value):
            raise ValueError(f"{name} must be finite, got {text!r}")
        return value
    if not isinstance(text, str):
        raise ValueError(f"{name} must be a number or an expression like 'pi/2', got {text!r}")
    low = text.lower()
    deg = _DEG.match(low)
    if deg is not None:
        d = parse_number(deg["num"].replace(" ", ""), name=name)
        return _step(math.radians(d), (d,), name, text)
    m = _PATTERN.match(low)
    if m is None or (m["coef"] is None and m["pi"] is None) or (m["star"] and not (m["coef"] and m["pi"])):
        raise ValueError(
            f"{name} must be a number (rad) or an expression like 'pi', '-pi/2', '3pi/4', '0.5*pi', '180deg'; "
            f"got {text!r}"
        )
    value = parse_number(m["coef"], name=name) if m["coef"] is not None else 1.0
    if m["pi"] is not None:
        value = _step(value * math.pi, (value,), name, text)
    if m["den"] is not None:
        den = parse_number(m["den"], name=name)
        if den == 0.0:
            raise ValueError(f"{name}: division by zero in {text!r}")
        value = _step(value / den, (value,), name, text)
    return -value if m["sign"] == "-" else value


def maybe_degrees(text: str, value: float) -> bool:
    """True when a bare number (no ``pi``, no ``deg``) beyond 2 pi is a whole number: most likely
    degrees typed without the ``deg`` suffix (``--phi0 180`` is 180 rad, 28.6 turns)."""
    bare = not any(c in text.lower() for c in ("pi", "π", "deg", "°"))
    return bare and abs(value) > 2.0 * math.pi and float(value).is_integer()
