"""A pymunk body's footprint on the plane: its shapes as parts (:mod:`rrbody.physics.footprint`).

From a pymunk body (:func:`body_parts`, :func:`body_footprint`): circles keep their exact geometry (the
instantaneous-centre quadrature with 24 nodes, ~5e-12); convex polygons (``pymunk.Poly``) are exact, their rounding
radius (``Poly(..., radius=r)``) is not part of the footprint; a ``pymunk.Segment`` with radius r is a stadium and
enters as one convex polygon with ``SEGMENT_CAP_EDGES`` edges on each round end (its caps' area 0.6 % short at 16); a
segment of radius 0 has no area and no friction. rrbody's own scenes build their footprint from the scene instead
(:func:`rrbody.physics.footprint.body_parts`). Geometry is in the body frame with the origin at the body's centre of
gravity (m); the pressure distribution (:mod:`rrbody.model.pressure`) says what load each part carries. Under the
default one each shape presses with its own weight (``shape.mass``, as pymunk has it from a mass or a density) over
its own area, or by area when no shape has a mass (a body whose mass you set); a centre of gravity off the shapes'
centre of mass (``body.center_of_gravity`` set by hand) gets the linear pressure that centres the load on it
(:mod:`rrbody.physics.loads`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from rrbody.model.pressure import Pressure, uniform
from rrbody.physics import contact as C
from rrbody.physics.footprint import Footprint, Part, apply_pressure, ellipse_part, polygon_part

__all__ = ["body_parts", "body_footprint", "SEGMENT_CAP_EDGES"]

#: edges of the polygon standing in for each half-disk end of a thick segment
SEGMENT_CAP_EDGES = 16

def _stadium(a: tuple[float, float], b: tuple[float, float], r: float) -> np.ndarray:
    """Convex polygon (counter-clockwise) of a segment a-b of radius r with polygonal round ends."""
    ang = math.atan2(b[1] - a[1], b[0] - a[0])
    pts = []
    for centre, start in ((b, ang - 0.5 * math.pi), (a, ang + 0.5 * math.pi)):
        for i in range(SEGMENT_CAP_EDGES + 1):
            t = start + math.pi * i / SEGMENT_CAP_EDGES
            pts.append((centre[0] + r * math.cos(t), centre[1] + r * math.sin(t)))
    return np.array(pts)


def body_footprint(body: Any, pressure: Pressure | None = None, *, name: Callable[[Any], str] = repr,
                   table: bool = False) -> Footprint:
    """The footprint of a pymunk ``body``'s own shapes under ``pressure`` (default uniform: each shape's
    weight over its area, centred on the centre of gravity). Raises ValueError for a body without area,
    a shape kind pymunk added after 7.x, or a pressure whose load does not lie on the shapes, and,
    naming the body (``name(body)``), where no linear pressure centres the load on a centre of gravity
    set by hand (the body would tip), or where ``table`` (a wrench table, which needs each polygon
    uniformly loaded) meets such a linear pressure."""
    try:
        foot = apply_pressure(body_parts(body), uniform() if pressure is None else pressure, balance=True)
    except ValueError as e:
        raise ValueError(f"body {name(body)}: {e}") from None
    if table and np.any((foot[0][:, C.KIND] == C.POLYGON)
                        & ((foot[0][:, C.SLOPE_X] != 0.0) | (foot[0][:, C.SLOPE_Y] != 0.0))):
        raise ValueError(f"body {name(body)}: friction_method 'table' needs each polygon uniformly loaded, but its "
                         f"centre of gravity, off its shapes' centre of mass, tilts the pressure: use 'auto' (exact)")
    return foot


def body_parts(body: Any) -> list[Part]:
    """The parts of a pymunk ``body``'s own shapes with area (body frame from its centre of gravity),
    each carrying its shape's mass (kg, row LOAD_SHARE: :func:`rrbody.physics.loads.shares`)."""
    import pymunk

    cog = body.center_of_gravity
    ox, oy = float(cog.x), float(cog.y)

    def keyf(s: Any) -> tuple:
        # a stable order (body.shapes is a set): the sums then round the same way in every run
        if isinstance(s, pymunk.Circle):
            return (0, s.radius, *s.offset)
        if isinstance(s, pymunk.Segment):
            return (1, s.radius, *s.a, *s.b)
        if isinstance(s, pymunk.Poly):
            return (2, *[c for v in s.get_vertices() for c in v])
        return (3,)

    parts: list[Part] = []
    for s in sorted(body.shapes, key=keyf):
        n = len(parts)
        if isinstance(s, pymunk.Circle):
            if s.radius > 0.0:
                parts.append(ellipse_part(s.offset.x - ox, s.offset.y - oy, s.radius, s.radius))
        elif isinstance(s, pymunk.Segment):
            if not s.radius > 0.0:
                continue  # a line has no area: no friction
            if s.a == s.b:
                parts.append(ellipse_part(s.a.x - ox, s.a.y - oy, s.radius, s.radius))
            else:
                parts.append(polygon_part(_stadium((s.a.x - ox, s.a.y - oy), (s.b.x - ox, s.b.y - oy),
                                                   float(s.radius))))
        elif isinstance(s, pymunk.Poly):
            parts.append(polygon_part(np.array([(v.x - ox, v.y - oy) for v in s.get_vertices()])))
        else:
            raise ValueError(f"shape must be a pymunk Circle, Poly or Segment, got {type(s).__name__}")
        if len(parts) > n:
            parts[-1][0][C.LOAD_SHARE] = float(s.mass)
    if not parts:
        raise ValueError("body must have at least one shape with area (a Circle, a Poly or a Segment with a "
                         "radius) for plane friction, got none")
    return parts
