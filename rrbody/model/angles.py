"""Parse angle expressions such as ``pi``, ``-pi/2``, ``3pi/4``, ``0.75*pi`` or ``2.1`` without ``eval``."""

from __future__ import annotations

import math
import re

__all__ = ["parse_angle"]

_NUM = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_PATTERN = re.compile(
    rf"^\s*(?P<sign>[+-]?)\s*(?P<coef>{_NUM})?\s*(?P<star>\*)?\s*(?P<pi>pi|π)?\s*(?:/\s*(?P<den>{_NUM}))?\s*$"
)


def parse_angle(text: str | float | int, *, name: str = "phi0") -> float:
    """Return the angle in radians that ``text`` denotes.

    Accepted forms: a plain number (radians), or ``[sign][coef][*]pi[/den]`` such as ``pi``,
    ``-pi/2``, ``3pi/4``, ``0.5*pi``. Raises ``ValueError`` naming ``name`` otherwise.
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        value = float(text)
    else:
        if not isinstance(text, str):
            raise ValueError(f"{name} must be a number or an expression like 'pi/2', got {text!r}")
        m = _PATTERN.match(text.lower())
        if m is None or (m["coef"] is None and m["pi"] is None) or (m["star"] and not (m["coef"] and m["pi"])):
            raise ValueError(
                f"{name} must be a number or an expression like 'pi', '-pi/2', '3pi/4', '0.5*pi'; got {text!r}"
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
