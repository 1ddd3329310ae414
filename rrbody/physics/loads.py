"""How a body's weight is shared by its parts under the default ("uniform") pressure, and the linear
pressure that puts the centre of pressure at a centre of gravity set off the parts' own centre of mass.

A rigid body resting on a level plane is pressed with its centre of pressure under its centre of
gravity (the plane's moments balance the weight's). Under the default pressure:

1. *Each part presses with its own weight, spread over its own area* (:func:`shares`): a part that
   carries a mass (kg, in its row's LOAD_SHARE column before :func:`rrbody.physics.footprint.combine`
   normalises it: a pymunk shape's ``mass``, ``rrbody.planar.box(..., mass=...)``) takes the share
   m_i / sum m of the load; parts without masses share it by area (one density). Mass shares within
   ``SHARE_TOL`` of the area shares *are* the area shares, so a body of one density is loaded bit for
   bit as by area.
2. *A centre of gravity set elsewhere* (:func:`centred`): when the parts' load centre P (from the
   centre of gravity, the origin) is farther than ``CENTRE_TOL`` x the footprint's reach from it (a
   pymunk ``body.center_of_gravity`` moved by hand, a mass set by hand on shapes of no mass, a
   MuJoCo body's centre of mass), each part's pressure is multiplied by one linear factor
   1 + k . (s - P). The load stays 1 and its centre moves to P + J k, J = sum_i w_i [(g_i - P)(g_i - P)^T
   + M_i] (g_i a part's centroid, M_i its second moment of area about it over its area; 0 for a point),
   so k = -J^-1 P: the 3 x 3 moment system (load, two moments) with the load already normalised. For a
   body of one density this is the linear pressure p = a + b . (s - c) that puts the centre of
   pressure at the centre of gravity (a rigid body on an evenly elastic plane presses so).

The factor must be >= 0 on the whole footprint (its minimum is at a polygon's vertex or a point):
otherwise no non-negative linear pressure holds the centre of gravity there (the body would tip) and
:func:`centred` raises ValueError saying so. A polygon under a linear pressure is exact
(:mod:`rrbody.physics.polygon_linear`) and a point only changes its share; the ellipse quadrature has
no linear form, so a body with a circle or an ellipse that would need one is refused, as is a body
whose load lies on a line (points in a row) when its centre of gravity is off that line.
"""

from __future__ import annotations

import math

import numpy as np

from rrbody.physics import contact as C

__all__ = ["shares", "centred", "SHARE_TOL", "CENTRE_TOL", "TIP_TOL"]

#: mass shares that differ from the area shares by at most this (relative) are the area shares: one density
#: (pymunk's mass = density x area, rounded in its own sums)
SHARE_TOL = 1e-12
#: |centre of the parts' load - centre of gravity| <= CENTRE_TOL x reach counts as at it: the rounding of
#: the sums that place the centre of gravity (pymunk's, MuJoCo's, ~1e-16 relative) with a wide margin
CENTRE_TOL = 1e-9
#: the linear factor may dip this far below 0 at a vertex (rounding of the moment solve, a body exactly on
#: the verge of tipping): the kernel integrates that linear pressure as it is
TIP_TOL = 1e-12

Part = tuple[np.ndarray, np.ndarray, float, float, tuple[float, float], float]


def shares(parts: list[Part]) -> np.ndarray:
    """Each part's share of the load (summing to 1): its mass over the parts' total where parts carry
    masses (their row's LOAD_SHARE > 0; a part of no mass carries none), else by area (parts of no area,
    points, share it equally)."""
    areas = np.array([p[2] for p in parts])
    by_area = areas / areas.sum() if areas.sum() > 0.0 else np.full(len(parts), 1.0 / len(parts))
    masses = np.array([p[0][C.LOAD_SHARE] for p in parts])
    if not masses.sum() > 0.0:
        return by_area
    by_mass = masses / masses.sum()
    if np.all(np.abs(by_mass - by_area) <= SHARE_TOL * by_area):
        return by_area  # one density: the area shares, bit for bit
    return by_mass


def _central(row: np.ndarray) -> np.ndarray:
    """A uniformly loaded part's second moment about its own centre, over its area (m^2; 2 x 2)."""
    if row[C.KIND] == C.POLYGON:
        gx, gy = row[C.CENTRE_X], row[C.CENTRE_Y]
        return np.array([[row[C.MOMENT_XX] - gx * gx, row[C.MOMENT_XY] - gx * gy],
                         [row[C.MOMENT_XY] - gx * gy, row[C.MOMENT_YY] - gy * gy]])
    return np.zeros((2, 2))


def _lowest(parts: list[Part], px: float, py: float, k: np.ndarray) -> tuple[float, float, float]:
    """The smallest 1 + k . (s - P) over the footprint's vertices and points, and where (m)."""
    best = (math.inf, 0.0, 0.0)
    for row, geo, *_ in parts:
        if row[C.KIND] == C.POLYGON:
            pts = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]
        else:
            pts = np.array([[row[C.CENTRE_X], row[C.CENTRE_Y]]])
        f = 1.0 + k[0] * (pts[:, 0] - px) + k[1] * (pts[:, 1] - py)
        i = int(np.argmin(f))
        if f[i] < best[0]:
            best = (float(f[i]), float(pts[i, 0]), float(pts[i, 1]))
    return best


def centred(parts: list[Part], weights: np.ndarray) -> tuple[list[Part], np.ndarray]:
    """``parts`` with ``weights`` (uniform pressure on each, summing to 1), their load centred on the
    origin (the centre of gravity): as given when it already is (to ``CENTRE_TOL`` x reach), else each
    part's pressure times 1 + k . (s - P) (module docstring): polygons get their pressure slope (row
    SLOPE_X, SLOPE_Y, 1/m), every part its new share. Raises ValueError (saying why, without the body's name: the
    caller adds it) where no non-negative linear pressure centres it, or it would need one on an
    ellipse or along a line of points."""
    px = float(sum(w * p[4][0] for p, w in zip(parts, weights)))
    py = float(sum(w * p[4][1] for p, w in zip(parts, weights)))
    reach = max(p[3] for p in parts)
    if math.hypot(px, py) <= CENTRE_TOL * reach:
        return parts, weights
    where = (f"its centre of gravity lies ({-px:.6g}, {-py:.6g}) m from the centre of its shapes' weight "
             f"(set by hand, or a mass not on the footprint)")
    if any(p[0][C.KIND] not in (C.POLYGON, C.POINT) and w != 0.0 for p, w in zip(parts, weights)):
        raise ValueError(f"{where}: the linear pressure that would press it there is exact on polygons and points, "
                         f"not on circles or ellipses; give the shapes masses that put their centre of mass at the "
                         f"centre of gravity, or pass a pressure profile (rrbody.pressure)")
    J = np.zeros((2, 2))
    for (row, _, _, _, (gx, gy), _), w in zip(parts, weights):
        d = np.array([gx - px, gy - py])
        J += w * (np.outer(d, d) + _central(row))
    if not abs(np.linalg.det(J)) > 1e-12 * np.trace(J) ** 2:
        raise ValueError(f"{where}, and its load lies on a line (points in a row): no pressure on it can hold "
                         f"a centre of gravity off that line")
    k = -np.linalg.solve(J, np.array([px, py]))
    low, lx, ly = _lowest([p for p, w in zip(parts, weights) if w != 0.0], px, py, k)  # (a part of no load: any)
    if low < -TIP_TOL:
        raise ValueError(f"{where}, farther than any non-negative linear pressure can carry it: the pressure "
                         f"would be {low:.3g} x its mean value at ({lx:.6g}, {ly:.6g}) m (the body would tip "
                         f"over that edge); place the centre of gravity nearer the footprint's middle")
    out, new = [], np.empty(len(parts))
    for i, ((row, geo, area, rch, (gx, gy), spread), w) in enumerate(zip(parts, weights)):
        f = 1.0 + k[0] * (gx - px) + k[1] * (gy - py)  # the factor's mean over the part: at its centroid
        new[i] = w * f
        if row[C.KIND] == C.POLYGON and f > 0.0:
            kp = k / f  # the part's own pressure, per its mean: 1 + kp . (s - g)
            row = row.copy()
            row[C.SLOPE_X], row[C.SLOPE_Y] = kp
            m = _central(row) @ kp
            rule = geo[int(row[C.QUAD_FIRST]):int(row[C.QUAD_END])]  # exact for the cubic moment (degree 12)
            third = float(rule[:, 2] @ ((kp[0] * (rule[:, 0] - gx) + kp[1] * (rule[:, 1] - gy))
                                        * (rule[:, 0] ** 2 + rule[:, 1] ** 2))) / area
            out.append((row, geo, area, rch, (gx + float(m[0]), gy + float(m[1])), spread + third))
        else:
            out.append((row, geo, area, rch, (gx, gy), spread))
    return out, new

