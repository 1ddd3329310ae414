"""Argument helpers shared by every ``rrbody`` subcommand (parsers of numbers, angles, lists)."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

__all__ = ["CliError", "_angle", "_finite", "_float_list"]


class CliError(ValueError):
    """A bad option value (reported as `rrbody: error: ...`, exit 2)."""


def _float_list(name: str, n: int) -> Callable[[str], tuple[float, ...]]:
    def parse(text: str) -> tuple[float, ...]:
        parts = [s for s in text.replace(" ", "").split(",") if s]
        try:
            vals = tuple(float(s) for s in parts)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be {n} comma-separated numbers, got {text!r}") from None
        if len(vals) != n or not all(math.isfinite(v) for v in vals):
            raise argparse.ArgumentTypeError(f"{name} must be {n} finite comma-separated numbers, got {text!r}")
        return vals

    return parse


def _finite(name: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name} must be finite, got {text!r}")
        return v

    return parse


def _angle(text: str) -> float:
    from rrbody.model.angles import parse_angle

    try:
        return parse_angle(text, name="--phi0")
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
