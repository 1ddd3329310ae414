"""Footprints: a body's parts on the plane and the load each carries (the rows of
:mod:`rrbody.physics.contact`), built from geometry and a pressure distribution.

The geometry comes from a pymunk body (:func:`rrbody.engine.plugin.shapes.body_footprint`) or from one of
rrbody's bodies (:func:`scene_parts`); :func:`apply_pressure` then spreads the load as the pressure
distribution (:mod:`rrbody.model.pressure`) says; under the default one each part presses with its
own weight and a centre of gravity off the parts' centre of mass gets a linear pressure
(:mod:`rrbody.physics.loads`). One description feeds both paths: the plugin
steps these rows, and the ODE path packs the same rows into its ``S`` (:func:`rrbody.physics.contact.pack`).
Geometry is in the body frame with the origin at the body's centre of gravity (m).
"""

from __future__ import annotations

import math

import numpy as np

from rrbody.model.bodies import Body
from rrbody.model.pressure import Pressure
from rrbody.physics import contact as C
from rrbody.physics.loads import centred, shares
from rrbody.physics.polygon import gauss_rule, polygon_geometry

__all__ = ["Footprint", "Part", "ellipse_part", "polygon_part", "point_part", "sampled_part", "ring_part",
           "hertz_part", "combine", "apply_pressure", "inside", "body_parts", "packed", "ICR_NODES"]

#: nodes per panel of the instantaneous-centre quadrature for a circle (~5e-12 against the closed form)
ICR_NODES = 24
#: points on a circle that must lie on the footprint for a ring, an annulus or a Hertz patch to fit
FIT_POINTS = 256
#: how far (m, relative to the footprint's size) a point may stick out and still count as on it (rounding)
FIT_SLACK = 1e-9

#: (shapes rows, geo rows, reach in m, load-weighted mean position (m, m), mean squared distance m^2)
Footprint = tuple[np.ndarray, np.ndarray, float, tuple[float, float], float]
#: one part: its row (ranges local to its geo block), geo block, area (m^2), reach (m), mean
#: position (m, m) and mean squared distance from the centre of gravity (m^2) of its load
Part = tuple[np.ndarray, np.ndarray, float, float, tuple[float, float], float]


def _row(kind: float, cx: float, cy: float) -> np.ndarray:
    row = np.zeros(C.N_SHAPE)
    row[[C.KIND, C.CENTRE_X, C.CENTRE_Y]] = kind, cx, cy
    return row


def ellipse_part(cx: float, cy: float, a: float, b: float, ori: float = 0.0, nodes: int = ICR_NODES) -> Part:
    """An ellipse (a circle if a = b) with semi-axes a (along ``ori``) and b (m) centred at (cx, cy),
    uniform pressure, integrated by the instantaneous-centre quadrature with ``nodes`` per panel."""
    row = _row(C.ELLIPSE, cx, cy)
    row[[C.RADIUS_A, C.RADIUS_B, C.AXIS_ANGLE, C.PANEL_NODES]] = a, b, ori, nodes
    return row, np.zeros((0, 3)), math.pi * a * b, math.hypot(cx, cy) + max(a, b), (cx, cy), \
        cx * cx + cy * cy + 0.25 * (a * a + b * b)


def polygon_part(vertices: np.ndarray) -> Part:
    """A convex polygon (vertices in either orientation, m), uniform pressure."""
    v, area, gx, gy, m2 = polygon_geometry(vertices)
    rule = gauss_rule(v)
    row = _row(C.POLYGON, gx, gy)
    row[C.VERTEX_RADIUS] = float(np.max(np.hypot(v[:, 0] - gx, v[:, 1] - gy)))
    row[[C.AREA, C.MOMENT_XX, C.MOMENT_XY, C.MOMENT_YY]] = area, *m2
    row[[C.VERTEX_FIRST, C.VERTEX_END, C.QUAD_FIRST, C.QUAD_END]] = (0, v.shape[0], v.shape[0],
                                                                     v.shape[0] + rule.shape[0])
    geo = np.vstack([np.column_stack([v, np.zeros(v.shape[0])]), rule])
    return row, geo, area, float(np.max(np.hypot(v[:, 0], v[:, 1]))), (gx, gy), float(m2[0] + m2[2])


def point_part(cx: float, cy: float) -> Part:
    """All of the part's load at one point (a point mass, a foot): area 0."""
    return _row(C.POINT, cx, cy), np.zeros((0, 3)), 0.0, math.hypot(cx, cy), (cx, cy), cx * cx + cy * cy


def sampled_part(samples: np.ndarray) -> Part:
    """Area elements: rows (x, y, weight) from the centre of gravity, weights summing to 1 (use alone)."""
    s = np.ascontiguousarray(samples, dtype=float)
    row = _row(C.SAMPLED, 0.0, 0.0)
    row[[C.QUAD_FIRST, C.QUAD_END]] = 0, s.shape[0]
    w = s[:, 2]
    return row, s, 0.0, float(np.max(np.hypot(s[:, 0], s[:, 1]))), (float(w @ s[:, 0]), float(w @ s[:, 1])), \
        float(w @ (s[:, 0] ** 2 + s[:, 1] ** 2))


def ring_part(cx: float, cy: float, radius: float) -> Part:
    """The part's load spread evenly on the circle of ``radius`` (m) about (cx, cy)."""
    row = _row(C.RING, cx, cy)
    row[C.RADIUS_A] = radius
    return row, np.zeros((0, 3)), 0.0, math.hypot(cx, cy) + radius, (cx, cy), cx * cx + cy * cy + radius * radius


def hertz_part(cx: float, cy: float, a: float) -> Part:
    """Hertz's pressure, proportional to sqrt(1 - r^2/a^2), on the disk of radius ``a`` (m) about (cx, cy)."""
    row = _row(C.HERTZ, cx, cy)
    row[C.RADIUS_A] = a
    # <r^2> under p ~ sqrt(1 - r^2/a^2): 2 a^2 / 5
    return row, np.zeros((0, 3)), 0.0, math.hypot(cx, cy) + a, (cx, cy), cx * cx + cy * cy + 0.4 * a * a


def combine(parts: list[Part], weights: np.ndarray | None = None) -> Footprint:
    """One body's footprint from its parts: load shares ``weights`` (summing to 1), by default each
    part's own weight where parts carry masses, else by area (:func:`rrbody.physics.loads.shares`;
    parts of no area, points or samples, share it equally), and the geo blocks concatenated."""
    if not parts:
        raise ValueError("body must have at least one shape with area (a Circle, a Poly or a Segment with a "
                         "radius) for plane friction, got none")
    if weights is None:
        weights = shares(parts)
    rows, geos, n = [], [], 0
    for (row, geo, *_), wt in zip(parts, weights):
        row = row.copy()
        row[C.LOAD_SHARE] = wt
        if row[C.KIND] == C.POLYGON:
            row[[C.VERTEX_FIRST, C.VERTEX_END]] += n
        if row[C.KIND] in (C.POLYGON, C.SAMPLED):
            row[[C.QUAD_FIRST, C.QUAD_END]] += n
        n += geo.shape[0]
        rows.append(row)
        geos.append(geo)
    g = (float(sum(wt * p[4][0] for p, wt in zip(parts, weights))),
         float(sum(wt * p[4][1] for p, wt in zip(parts, weights))))
    j = float(sum(wt * p[5] for p, wt in zip(parts, weights)))
    return np.array(rows), np.ascontiguousarray(np.concatenate(geos)), max(p[3] for p in parts), g, j


def inside(parts: list[Part], x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether each point (x, y) (m, body frame) lies on the union of the parts with area (ellipses
    and convex polygons), to a relative slack of FIT_SLACK."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    size = max((p[3] for p in parts), default=1.0)
    tol = FIT_SLACK * size
    ok = np.zeros(x.shape, dtype=bool)
    for row, geo, *_ in parts:
        if row[C.KIND] == C.ELLIPSE:
            c, s = math.cos(row[C.AXIS_ANGLE]), math.sin(row[C.AXIS_ANGLE])
            dx, dy = x - row[C.CENTRE_X], y - row[C.CENTRE_Y]
            u, v = c * dx + s * dy, -s * dx + c * dy
            ok |= np.hypot(u / (row[C.RADIUS_A] + tol), v / (row[C.RADIUS_B] + tol)) <= 1.0
        elif row[C.KIND] == C.POLYGON:
            v = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]  # counter-clockwise (polygon_geometry)
            e = np.roll(v, -1, axis=0) - v
            length = np.hypot(e[:, 0], e[:, 1])
            # signed distance inside every edge's line (>= -tol) for a convex polygon
            d = (e[:, 0, None] * (y[None] - v[:, 1, None]) - e[:, 1, None] * (x[None] - v[:, 0, None])) / length[:,
                                                                                                                 None]
            ok |= np.all(d >= -tol, axis=0)
    return ok


def _circle_fits(parts: list[Part], what: str, cx: float, cy: float, radius: float) -> None:
    t = np.linspace(0.0, 2.0 * math.pi, FIT_POINTS, endpoint=False)
    x, y = cx + radius * np.cos(t), cy + radius * np.sin(t)
    if not np.all(inside(parts, np.append(x, cx), np.append(y, cy))):
        raise ValueError(f"{what} must lie on the body's footprint (reach {max(p[3] for p in parts):g} m from its "
                         f"centre of gravity), got radius {radius:g} m about ({cx:g}, {cy:g}) m")


def _field_samples(parts: list[Part], pressure: Pressure) -> np.ndarray:
    """Area elements (x, y, weight) of the footprint weighted by the user's p(x, y), normalised."""
    areas = np.array([p[2] for p in parts])
    rows = []
    for (row, geo, area, *_), n in zip(parts, np.maximum(16, pressure.samples * areas / areas.sum()).astype(int)):
        if row[C.KIND] == C.POLYGON:
            v = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]
            q = gauss_rule(v, max(2, int(math.sqrt(n / max(1, v.shape[0] - 2)))))
            rows.append(np.column_stack([q[:, 0], q[:, 1], q[:, 2] * area / q[:, 2].sum()]))
        elif row[C.KIND] == C.ELLIPSE:
            # polar Gauss-Legendre in the scaled disk (spectrally accurate for a smooth p)
            nr = max(4, int(math.sqrt(n / 2)))
            nt = 2 * nr
            xr, wr = np.polynomial.legendre.leggauss(nr)
            rr = 0.5 * (xr + 1.0)
            th = 2.0 * math.pi * (np.arange(nt) + 0.5) / nt
            R, T = np.meshgrid(rr, th)
            W = np.meshgrid(0.5 * wr * rr, th)[0] * (2.0 * math.pi / nt) * row[C.RADIUS_A] * row[C.RADIUS_B]
            u, v = row[C.RADIUS_A] * R * np.cos(T), row[C.RADIUS_B] * R * np.sin(T)
            c, s = math.cos(row[C.AXIS_ANGLE]), math.sin(row[C.AXIS_ANGLE])
            rows.append(np.column_stack([row[C.CENTRE_X] + c * u.ravel() - s * v.ravel(),
                                         row[C.CENTRE_Y] + s * u.ravel() + c * v.ravel(), W.ravel()]))
    if not rows:
        raise ValueError("pressure field needs a footprint with area (circles, ellipses or polygons)")
    q = np.vstack(rows)
    try:
        p = np.broadcast_to(np.asarray(pressure.density(q[:, 0], q[:, 1]), dtype=float), q[:, 0].shape)  # type: ignore[misc]
    except Exception as e:  # the user's function: say what went wrong with it, in one line
        raise ValueError(f"pressure density p(x, y) failed on arrays of points (m): {type(e).__name__}: {e}") from None
    if not np.all(np.isfinite(p)) or np.any(p < 0.0):
        bad = float(p[~(np.isfinite(p) & (p >= 0.0))][0])
        raise ValueError(f"pressure density must be finite and >= 0 on the footprint, got {bad!r}")
    w = p * q[:, 2]
    if not w.sum() > 0.0:
        raise ValueError("pressure density must integrate to a positive load over the footprint, got 0")
    return np.column_stack([q[:, 0], q[:, 1], w / w.sum()])


def apply_pressure(parts: list[Part], pressure: Pressure, *, balance: bool = False) -> Footprint:
    """The footprint of a body whose geometry is ``parts`` (ellipses, polygons: its shapes with area)
    under ``pressure``. The default (uniform) presses each part with its own weight (its mass, else
    by area); with ``balance`` the origin is the body's centre of gravity and a load centred
    elsewhere is made linear to centre it there (:mod:`rrbody.physics.loads`). Other profiles are
    taken as given (they say where the load is). Raises ValueError naming the pressure's parameter
    when its load does not lie on the footprint (a ring wider than the body, a foot off it), or why
    no linear pressure centres the load (the body would tip)."""
    if pressure.is_uniform:
        weights = shares(parts)
        if balance:
            parts, weights = centred(parts, weights)
        return combine(parts, weights)
    if not any(p[2] > 0.0 for p in parts):
        raise ValueError(f"pressure {pressure.kind!r} needs a body with area (a point mass has no footprint)")
    reach = max(p[3] for p in parts)
    cx, cy = pressure.centre
    if pressure.kind == "ring":
        (r,) = pressure.radii
        _circle_fits(parts, "ring", cx, cy, r)
        new = [ring_part(cx, cy, r)]
        weights = np.array([1.0])
    elif pressure.kind == "hertz":
        (a,) = pressure.radii
        _circle_fits(parts, "hertz patch", cx, cy, a)
        new = [hertz_part(cx, cy, a)]
        weights = np.array([1.0])
    elif pressure.kind == "annulus":
        rin, rout = pressure.radii
        _circle_fits(parts, "annulus", cx, cy, rout)
        if rin == 0.0:
            new, weights = [ellipse_part(cx, cy, rout, rout)], np.array([1.0])
        else:
            # friction is linear in the pressure: the annulus is the outer disk minus the inner one
            a_out, a_in = rout * rout, rin * rin
            new = [ellipse_part(cx, cy, rout, rout), ellipse_part(cx, cy, rin, rin)]
            weights = np.array([a_out, -a_in]) / (a_out - a_in)
    elif pressure.kind == "points":
        feet = np.array(pressure.feet)
        off = ~inside(parts, feet[:, 0], feet[:, 1])
        if off.any():
            i = int(np.flatnonzero(off)[0])
            raise ValueError(f"feet[{i}] must lie on the body's footprint (reach {reach:g} m from its centre of "
                             f"gravity), got ({feet[i, 0]:g}, {feet[i, 1]:g}) m")
        new = [point_part(float(x), float(y)) for x, y, _ in feet]
        weights = feet[:, 2]
    else:  # field
        new, weights = [sampled_part(_field_samples(parts, pressure))], np.array([1.0])
    shapes, geo, _, g, j = combine(new, weights)
    # the reach stays the footprint's: the rest rule needs a bound on the speed of every loaded point
    return shapes, geo, reach, g, j


def body_parts(body: Body) -> list[Part]:
    """The footprint geometry of one of rrbody's bodies (body frame: R_A along x, origin at the CM):
    an ellipse (a disk), with the quadrature nodes the ODE path uses for it, or a convex polygon."""
    from rrbody.model.bodies import Polygon
    from rrbody.physics.area import icr_nodes

    if body.is_point:
        return [point_part(0.0, 0.0)]
    if isinstance(body, Polygon):
        return [polygon_part(np.array(body.vertices))]
    ra, rb = body.semi_axes
    return [ellipse_part(0.0, 0.0, ra, rb, 0.0, icr_nodes(body))]


def packed(body: Body, pressure: Pressure) -> np.ndarray:
    """The ODE path's ``S`` for the contact method: ``body`` under ``pressure``, packed
    (:func:`rrbody.physics.contact.pack`)."""
    return C.pack(*apply_pressure(body_parts(body), pressure))
