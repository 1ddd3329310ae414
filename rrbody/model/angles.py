"""Parse angle expressions such as ``pi``, ``-pi/2``, ``3pi/4``, ``0.75*pi``, ``2.1`` or ``180deg`` without ``eval``."""

from __future__ import annotations

import math
import re

__all__ = ["parse_angle", "maybe_degrees"]

_DEG = re.compile(r"^\s*(?P<num>[+-]?\s*(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(?:deg|°)\s*$")

_NUM = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_PATTERN = re.compile(
    rf"^\s*(?P<sign>[+-]?)\s*(?P<coef>{_NUM})?\s*(?P<star>\*)?\s*(?P<pi>pi|π)?\s*(?:/\s*(?P<den>{_NUM}))?\s*$"
)


def parse_angle(text: str | float | int, *, name: str = "phi0") -> float:
    """Return the angle in radians that ``text`` denotes.

    Accepted forms: a plain number (radians), ``[sign][coef][*]pi[/den]`` such as ``pi``,
    ``-pi/2``, ``3pi/4``, ``0.5*pi``, or a number of degrees with an explicit suffix, ``180deg``,
    ``-90 deg``, ``45°``. Raises ``ValueError`` naming ``name`` otherwise.
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        value = float(text)
    else:
        if not isinstance(text, str):
            raise ValueError(f"{name} must be a number or an expression like 'pi/2', got {text!r}")
        deg = _DEG.match(text.lower())
        if deg is not None:
            value = math.radians(float(deg["num"].replace(" ", "")))
            if not math.isfinite(value):
                raise ValueError(f"{name} must be finite, got {text!r}")
            return value
        m = _PATTERN.match(text.lower())
        if m is None or (m["coef"] is None and m["pi"] is None) or (m["star"] and not (m["coef"] and m["pi"])):
            raise ValueError(
                f"{name} must be a number (rad) or an expression like 'pi', '-pi/2', '3pi/4', '0.5*pi', '180deg'; "
                f"got {text!r}"
            )
        value = float(m["coef"]) if m["coef"] is not None else 1.0
        if m["pi"] is not None:
            value *= math.pi
        if m["den"] is not None:
            den = float(m["den"])
            if den == 0.0:
                raise ValueError(f"{name}: division by zero in {text!r}")
            value /= den
        if m["sign"] == "-":
            value = -value
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {text!r}")
    return value


def maybe_degrees(text: str, value: float) -> bool:
    """True when a bare number (no ``pi``, no ``deg``) beyond 2 pi is a whole number: most likely
    degrees typed without the ``deg`` suffix (``--phi0 180`` is 180 rad, 28.6 turns)."""
    bare = not any(c in text.lower() for c in ("pi", "π", "deg", "°"))
    return bare and abs(value) > 2.0 * math.pi and float(value).is_integer()
