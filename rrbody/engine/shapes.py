"""A body's footprint on the plane: its parts as the kernel's rows (see :mod:`rrbody.engine.kernel`).

From a pymunk body (:func:`body_footprint`): circles keep their exact geometry (the instantaneous-centre
quadrature with 24 nodes, ~5e-12); convex polygons (``pymunk.Poly``) are exact, their rounding radius
(``Poly(..., radius=r)``) is not part of the footprint; a ``pymunk.Segment`` with radius r is a stadium
and enters as one convex polygon with ``SEGMENT_CAP_EDGES`` edges on each round end (its caps' area
0.6 % short at 16); a segment of radius 0 has no area and no friction. rrbody's own scenes build
their footprint from the scene instead (:func:`ellipse_part`, :func:`point_part`,
:func:`sampled_part`). Geometry is in the body frame with the origin at the body's centre of
gravity (m); every part carries its share of the load (uniform pressure: its share of the area).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.engine import kernel as K
from rrbody.physics.polygon import gauss_rule, polygon_geometry

__all__ = ["Footprint", "body_footprint", "ellipse_part", "polygon_part", "point_part", "sampled_part",
           "combine", "SEGMENT_CAP_EDGES"]

#: edges of the polygon standing in for each half-disk end of a thick segment
SEGMENT_CAP_EDGES = 16

#: (shapes rows, geo rows, reach in m, load-weighted mean position (m, m), mean squared distance m^2)
Footprint = tuple[np.ndarray, np.ndarray, float, tuple[float, float], float]
#: one part: its kernel row (ranges local to its geo block), geo block, area (m^2), reach (m),
#: mean position (m, m) and mean squared distance from the centre of gravity (m^2)
Part = tuple[np.ndarray, np.ndarray, float, float, tuple[float, float], float]


def ellipse_part(cx: float, cy: float, a: float, b: float, ori: float = 0.0, nodes: int = 24) -> Part:
    """An ellipse (a circle if a = b) with semi-axes a (along ``ori``) and b (m) centred at (cx, cy),
    integrated by the instantaneous-centre quadrature with ``nodes`` per panel (24: a disk to ~5e-12)."""
    row = np.zeros(K.N_SHAPE)
    row[[K.KIND, K.CX, K.CY, K.RA, K.RB, K.ORI, K.NQ]] = K.ELLIPSE, cx, cy, a, b, ori, nodes
    return row, np.zeros((0, 3)), math.pi * a * b, math.hypot(cx, cy) + max(a, b), (cx, cy), \
        cx * cx + cy * cy + 0.25 * (a * a + b * b)


def polygon_part(vertices: np.ndarray) -> Part:
    """A convex polygon (vertices in either orientation, m)."""
    v, area, gx, gy, m2 = polygon_geometry(vertices)
    rule = gauss_rule(v)
    row = np.zeros(K.N_SHAPE)
    row[[K.KIND, K.CX, K.CY]] = K.POLYGON, gx, gy
    row[K.RAD] = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    row[[K.AREA, K.MXX, K.MXY, K.MYY]] = area, *m2
    row[[K.V0, K.V1, K.Q0, K.Q1]] = 0, v.shape[0], v.shape[0], v.shape[0] + rule.shape[0]
    geo = np.vstack([np.column_stack([v, np.zeros(v.shape[0])]), rule])
    return row, geo, area, float(np.max(np.hypot(v[:, 0], v[:, 1]))), (gx, gy), float(m2[0] + m2[2])


def point_part(cx: float, cy: float) -> Part:
    """All of the load at one point (a point mass): area 0, so use it alone."""
    row = np.zeros(K.N_SHAPE)
    row[[K.KIND, K.CX, K.CY]] = K.POINT, cx, cy
    return row, np.zeros((0, 3)), 0.0, math.hypot(cx, cy), (cx, cy), cx * cx + cy * cy


def sampled_part(samples: np.ndarray) -> Part:
    """Area elements: rows (x, y, weight) from the centre of gravity, weights summing to 1 (use alone)."""
    s = np.ascontiguousarray(samples, dtype=float)
    row = np.zeros(K.N_SHAPE)
    row[[K.KIND, K.Q0, K.Q1]] = K.SAMPLED, 0, s.shape[0]
    w = s[:, 2]
    return row, s, 0.0, float(np.max(np.hypot(s[:, 0], s[:, 1]))), (float(w @ s[:, 0]), float(w @ s[:, 1])), \
        float(w @ (s[:, 0] ** 2 + s[:, 1] ** 2))


def combine(parts: list[Part]) -> Footprint:
    """One body's footprint from its parts: load shares by area (uniform pressure; a lone part of no
    area, a point or samples, carries it all) and the geo blocks concatenated."""
    if not parts:
        raise ValueError("body must have at least one shape with area (a Circle, a Poly or a Segment with a "
                         "radius) for plane friction, got none")
    areas = np.array([p[2] for p in parts])
    weights = areas / areas.sum() if areas.sum() > 0.0 else np.full(len(parts), 1.0 / len(parts))
    rows, geos, n = [], [], 0
    for (row, geo, *_), wt in zip(parts, weights):
        row = row.copy()
        row[K.WEIGHT] = wt
        if row[K.KIND] == K.POLYGON:
            row[[K.V0, K.V1]] += n
        if row[K.KIND] in (K.POLYGON, K.SAMPLED):
            row[[K.Q0, K.Q1]] += n
        n += geo.shape[0]
        rows.append(row)
        geos.append(geo)
    g = (float(sum(wt * p[4][0] for p, wt in zip(parts, weights))),
         float(sum(wt * p[4][1] for p, wt in zip(parts, weights))))
    j = float(sum(wt * p[5] for p, wt in zip(parts, weights)))
    return np.array(rows), np.ascontiguousarray(np.concatenate(geos)), max(p[3] for p in parts), g, j


def _stadium(a: tuple[float, float], b: tuple[float, float], r: float) -> np.ndarray:
    """Convex polygon (counter-clockwise) of a segment a-b of radius r with polygonal round ends."""
    ang = math.atan2(b[1] - a[1], b[0] - a[0])
    pts = []
    for centre, start in ((b, ang - 0.5 * math.pi), (a, ang + 0.5 * math.pi)):
        for i in range(SEGMENT_CAP_EDGES + 1):
            t = start + math.pi * i / SEGMENT_CAP_EDGES
            pts.append((centre[0] + r * math.cos(t), centre[1] + r * math.sin(t)))
    return np.array(pts)


def body_footprint(body: Any) -> Footprint:
    """The footprint of a pymunk ``body``'s own shapes. Raises ValueError for a body without area or
    with a shape kind pymunk added after 7.x."""
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
    return combine(parts)
