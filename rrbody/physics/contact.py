"""A body's contact with the plane, and the dry-friction wrench of the whole: the one kernel that the
pymunk plugin (:mod:`rrbody.contact.kernel`), the ODE path (the area method ``contact``,
:mod:`rrbody.physics.areas.area_contact`) and the batched API call.

A *footprint* is a list of parts, each a row of ``shapes`` carrying its share of the normal load
(LOAD_SHARE: the shares sum to 1; an annulus is a disk minus a disk, so a share may be negative):

- ELLIPSE (a circle if RADIUS_A = RADIUS_B): uniform pressure, the instantaneous-centre quadrature (PANEL_NODES nodes
  per panel; 24 give a circle to ~5e-12), semi-axes RADIUS_A, RADIUS_B (m), the RADIUS_A axis at angle AXIS_ANGLE (rad);
- POLYGON: uniform pressure on a convex polygon, exact (:mod:`rrbody.physics.polygon`): VERTEX_RADIUS, AREA,
  MOMENT_XX, MOMENT_XY, MOMENT_YY, its vertices ``geo[VERTEX_FIRST:VERTEX_END]`` and far-field rule
  ``geo[QUAD_FIRST:QUAD_END]``; a pressure slope (SLOPE_X, SLOPE_Y) != 0 (1/m) makes its pressure linear, proportional
  to 1 + k . (s - centroid), also exact (:mod:`rrbody.physics.polygon_linear`; the slope that puts a body's centre of
  pressure at its centre of gravity, :mod:`rrbody.physics.footprint`);
- POINT: the load at one point (a foot, a point mass);
- SAMPLED: area elements ``geo[QUAD_FIRST:QUAD_END]`` (rows x, y, weight; weights sum to 1): any pressure p(x, y);
- RING: the load spread evenly on a circle of radius RADIUS_A (a rim, a running band), exact
  (:mod:`rrbody.physics.radial`, complete elliptic integrals);
- HERTZ: p proportional to sqrt(1 - rho^2 / RADIUS_A^2) on a disk of radius RADIUS_A (a sphere or a rounded
  foot on the plane), exact (:mod:`rrbody.physics.radial`).

CENTRE_X, CENTRE_Y is the part's centre (ellipse, ring, Hertz patch, point) or centroid (polygon), in the body
frame from the body's centre of gravity (m). ``geo`` rows have at least three columns (x, y, w);
the ODE path packs parts and geo rows into one array (:func:`pack`).

Units: per unit normal load and per unit mu g, so the force is dimensionless and the torque about
the centre of gravity is in m (the caller multiplies by mu g, and by the mass for newtons).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.physics.effects import area_sampled, law_dry
from rrbody.physics.effects.laws import DRY, NO_PARAMS
from rrbody.physics.icr import icr_wrench
from rrbody.physics.polygon import polygon_wrench
from rrbody.physics.polygon_linear import linear_polygon_wrench
from rrbody.physics.radial import hertz_wrench, ring_wrench

__all__ = ["footprint_wrench", "pack", "KIND", "LOAD_SHARE", "CENTRE_X", "CENTRE_Y", "RADIUS_A", "RADIUS_B",
           "AXIS_ANGLE", "PANEL_NODES", "VERTEX_RADIUS", "AREA", "MOMENT_XX", "MOMENT_XY", "MOMENT_YY", "VERTEX_FIRST",
           "VERTEX_END", "QUAD_FIRST", "QUAD_END", "N_SHAPE", "ELLIPSE", "POLYGON", "POINT", "SAMPLED", "RING", "HERTZ",
           "SLOPE_X", "SLOPE_Y", "KIND_NAMES", "HEADER", "H_PARTS", "H_MEAN_X", "H_MEAN_Y", "H_SPREAD", "H_REACH"]

(KIND, LOAD_SHARE, CENTRE_X, CENTRE_Y, RADIUS_A, RADIUS_B, AXIS_ANGLE, PANEL_NODES, VERTEX_RADIUS, AREA, MOMENT_XX,
 MOMENT_XY, MOMENT_YY, VERTEX_FIRST, VERTEX_END, QUAD_FIRST, QUAD_END) = range(17)
N_SHAPE = 17
#: a polygon's pressure slope (1/m): columns an ellipse's semi-axes use, free in a polygon's row
SLOPE_X, SLOPE_Y = RADIUS_A, RADIUS_B
ELLIPSE, POLYGON, POINT, SAMPLED, RING, HERTZ = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0
KIND_NAMES = {ELLIPSE: "ellipse", POLYGON: "polygon", POINT: "point", SAMPLED: "sampled", RING: "ring",
              HERTZ: "hertz"}

#: the packed array's first row (:func:`pack`): the number of parts, the load-weighted mean position
#: (m) and mean squared distance (m^2) from the centre of gravity (all the viscous law needs), and
#: the footprint's reach (m: its largest distance from the centre of gravity)
HEADER = 1
H_PARTS, H_MEAN_X, H_MEAN_Y, H_SPREAD, H_REACH = range(5)


@njit(cache=True)
def footprint_wrench(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, vbx: float, vby: float, w: float,
                     v_eps: float) -> tuple[float, float, float]:
    """(fx, fy, tq): dry friction of the parts ``shapes[s0:s1]`` per unit load and mu g, at the
    centre-of-gravity velocity (vbx, vby) (m/s, body frame) and spin w (rad/s): the force in the
    body frame, the torque about the centre of gravity (m). Elements slower than ``v_eps`` (m/s)
    feel none."""
    fx = 0.0
    fy = 0.0
    tq = 0.0
    for k in range(s0, s1):
        ox = shapes[k, CENTRE_X]
        oy = shapes[k, CENTRE_Y]
        kind = shapes[k, KIND]
        # velocity of the part's own centre: v + w z x o
        ux = vbx - w * oy
        uy = vby + w * ox
        if kind == ELLIPSE:
            gx, gy, gt = icr_wrench(shapes[k, RADIUS_A], shapes[k, RADIUS_B], int(shapes[k, PANEL_NODES]),
                                    shapes[k, AXIS_ANGLE], ux, uy, w, DRY, 1.0, v_eps, 0.0)
            gt += ox * gy - oy * gx  # the kernels' torques are about the part's centre
        elif kind == POLYGON and shapes[k, SLOPE_X] == 0.0 and shapes[k, SLOPE_Y] == 0.0:
            gx, gy, gt = polygon_wrench(geo, int(shapes[k, VERTEX_FIRST]), int(shapes[k, VERTEX_END]), shapes[k, AREA],
                                        ox, oy, shapes[k, VERTEX_RADIUS], shapes[k, MOMENT_XX], shapes[k, MOMENT_XY],
                                        shapes[k, MOMENT_YY], geo, int(shapes[k, QUAD_FIRST]), int(shapes[k, QUAD_END]),
                                        vbx, vby, w, v_eps)
        elif kind == POLYGON:
            gx, gy, gt = linear_polygon_wrench(geo, int(shapes[k, VERTEX_FIRST]), int(shapes[k, VERTEX_END]),
                                               shapes[k, AREA], ox, oy, shapes[k, VERTEX_RADIUS], shapes[k, SLOPE_X],
                                               shapes[k, SLOPE_Y], geo, int(shapes[k, QUAD_FIRST]),
                                               int(shapes[k, QUAD_END]), vbx, vby, w, v_eps)
        elif kind == POINT:
            gx, gy = law_dry.force(ux, uy, 1.0, v_eps)
            gt = ox * gy - oy * gx
        elif kind == RING:
            gx, gy, gt = ring_wrench(shapes[k, RADIUS_A], ux, uy, w, v_eps)
            gt += ox * gy - oy * gx
        elif kind == HERTZ:
            gx, gy, gt = hertz_wrench(shapes[k, RADIUS_A], ux, uy, w, v_eps)
            gt += ox * gy - oy * gx
        else:  # SAMPLED: rows (x, y, weight) from the centre of gravity, the sampled area method's own sum
            # np.int64: literal constants would compile the sampled method's kernel once more
            gx, gy, gt = area_sampled.wrench(np.int64(DRY), geo[int(shapes[k, QUAD_FIRST]):int(shapes[k, QUAD_END])],
                                             0.0, 0.0, np.int64(0), 0.0, vbx, vby, w, 1.0, v_eps, NO_PARAMS)
        wt = shapes[k, LOAD_SHARE]
        fx += wt * gx
        fy += wt * gy
        tq += wt * gt
    return fx, fy, tq


def pack(shapes: np.ndarray, geo: np.ndarray, reach: float, mean: tuple[float, float], spread: float) -> np.ndarray:
    """One float array for the ODE path's kernels (their ``S``): a header row (:data:`HEADER`), the
    parts' rows, then the geo rows (x, y, w in the first columns), every range shifted to index this
    array; :func:`footprint_wrench` takes it as both ``shapes`` and ``geo``."""
    n = shapes.shape[0]
    S = np.zeros((HEADER + n + geo.shape[0], N_SHAPE))
    S[0, [H_PARTS, H_MEAN_X, H_MEAN_Y, H_SPREAD, H_REACH]] = n, mean[0], mean[1], spread, reach
    rows = shapes.copy()
    shift = HEADER + n
    # VERTEX_FIRST, VERTEX_END, QUAD_FIRST, QUAD_END: consecutive columns
    rows[rows[:, KIND] == POLYGON, VERTEX_FIRST:QUAD_END + 1] += shift
    rows[rows[:, KIND] == SAMPLED, QUAD_FIRST:QUAD_END + 1] += shift
    S[HEADER:shift] = rows
    S[shift:, :geo.shape[1]] = geo
    return S
