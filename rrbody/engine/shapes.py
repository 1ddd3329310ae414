"""A pymunk body's footprint on the plane: its shapes as the kernel's rows (see :mod:`rrbody.engine.kernel`).

Circles keep their exact geometry (the instantaneous-centre quadrature integrates a disk to ~1e-11).
Convex polygons (``pymunk.Poly``) are exact; their rounding radius (``Poly(..., radius=r)``) is not
part of the footprint. A ``pymunk.Segment`` with radius r is a stadium: it enters as one convex
polygon with ``SEGMENT_CAP_EDGES`` edges on each round end (its area 0.6 % short of the stadium's
caps at 16); a segment of radius 0 has no area and no friction. Geometry is in the body frame with
the origin at the body's centre of gravity (m).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.engine import kernel as K
from rrbody.physics.polygon import gauss_rule, polygon_geometry

__all__ = ["body_footprint", "SEGMENT_CAP_EDGES"]

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


def _polygon_row(verts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    v, area, gx, gy, m2 = polygon_geometry(verts)
    row = np.zeros(K.N_SHAPE)
    row[K.KIND] = K.KIND_POLYGON
    row[K.CX], row[K.CY] = gx, gy
    row[K.RAD] = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    row[K.AREA] = area
    row[K.MXX], row[K.MXY], row[K.MYY] = m2
    rule = gauss_rule(v)
    row[K.V1] = v.shape[0]
    row[K.Q1] = rule.shape[0]
    return row, v, rule, float(np.max(np.hypot(v[:, 0], v[:, 1])))


def body_footprint(body: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(shapes, verts, rule, reach) of ``body``'s shapes: kernel rows with vertex and rule ranges
    local to the returned ``verts`` and ``rule`` arrays, and the largest distance of the footprint
    from the centre of gravity (m). Raises ValueError for a body without area or an unknown shape."""
    import pymunk

    cog = body.center_of_gravity
    ox, oy = float(cog.x), float(cog.y)
    rows, verts, rules = [], [], []
    reach = 0.0
    nv = nq = 0

    def keyf(s: Any) -> tuple:
        # a stable order (body.shapes is a set): the sums then round the same way in every run
        if isinstance(s, pymunk.Circle):
            return (0, s.radius, *s.offset)
        if isinstance(s, pymunk.Segment):
            return (1, s.radius, *s.a, *s.b)
        if isinstance(s, pymunk.Poly):
            return (2, *[c for v in s.get_vertices() for c in v])
        return (3,)

    for s in sorted(body.shapes, key=keyf):
        if isinstance(s, pymunk.Circle) or (isinstance(s, pymunk.Segment) and s.a == s.b and s.radius > 0):
            r = float(s.radius)
            c = s.offset if isinstance(s, pymunk.Circle) else s.a
            if not r > 0.0:
                continue
            row = np.zeros(K.N_SHAPE)
            row[K.KIND] = K.KIND_CIRCLE
            row[K.CX], row[K.CY] = float(c[0]) - ox, float(c[1]) - oy
            row[K.RAD] = r
            row[K.AREA] = math.pi * r * r
            rows.append(row)
            reach = max(reach, math.hypot(row[K.CX], row[K.CY]) + r)
            continue
        if isinstance(s, pymunk.Segment):
            if not s.radius > 0.0:
                continue  # a line has no area: no friction
            pv = _stadium((s.a.x - ox, s.a.y - oy), (s.b.x - ox, s.b.y - oy), float(s.radius))
        elif isinstance(s, pymunk.Poly):
            pv = np.array([(v.x - ox, v.y - oy) for v in s.get_vertices()])
        else:
            raise ValueError(f"shape must be a pymunk Circle, Poly or Segment, got {type(s).__name__}")
        row, v, rule, rch = _polygon_row(pv)
        row[K.V0] += nv
        row[K.V1] += nv
        row[K.Q0] += nq
        row[K.Q1] += nq
        nv += v.shape[0]
        nq += rule.shape[0]
        rows.append(row)
        verts.append(v)
        rules.append(rule)
        reach = max(reach, rch)
    if not rows:
        raise ValueError("body must have at least one shape with area (a Circle, a Poly or a Segment with a "
                         "radius) for plane friction, got none")
    shapes = np.array(rows)
    shapes[:, K.WEIGHT] = shapes[:, K.AREA] / shapes[:, K.AREA].sum()  # uniform pressure: load ~ area
    v_all = np.concatenate(verts) if verts else np.zeros((0, 2))
    r_all = np.concatenate(rules) if rules else np.zeros((0, 3))
    return shapes, np.ascontiguousarray(v_all), np.ascontiguousarray(r_all), reach
