"""The plugin against the ODE path: a body's end state at several dt, and the observed order."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np


def plugin_errors(make_shape: Callable[[Any], Any], want: Sequence[float], *, v0: tuple[float, float], w0: float,
                  T: float, dts: Sequence[float], plane: dict[str, Any], add: dict[str, Any]) -> tuple[list, list]:
    """(errors, orders): the largest deviation of (x, y, angle) at T (m, rad) from ``want`` for each dt
    (s), a body of shape ``make_shape(body)`` (density 1) launched at (v0, w0) in a fresh space with
    ``PlaneFriction(space, **plane)`` and ``pf.add(body, **add)``; orders log2(e_i / e_(i+1))."""
    import pymunk

    from rrbody.engine import PlaneFriction

    errs = []
    for dt in dts:
        space = pymunk.Space()
        pf = PlaneFriction(space, **plane)
        b = pymunk.Body()
        s = make_shape(b)
        s.density = 1.0
        space.add(b, s)
        b.velocity, b.angular_velocity = v0, w0
        pf.add(b, **add)
        for _ in range(round(T / dt)):
            pf.step(dt)
        errs.append(float(np.max(np.abs(np.array([b.position.x, b.position.y, b.angle]) - np.asarray(want)))))
    return errs, [math.log2(errs[i] / errs[i + 1]) for i in range(len(errs) - 1)]
