"""Many bodies' footprints in one pair of arrays, and the compiled loop that evaluates
:func:`rrbody.physics.contact.footprint_wrench` for all of them in one call.

:func:`stack` lays the footprints of n bodies end to end (the rows of :mod:`rrbody.physics.contact`,
each polygon's and sample block's ranges shifted to where its geo rows land) and returns each
body's row range: the layout the pymunk plugin keeps for its bodies, built once. :func:`batch_wrench`
is the loop over bodies, the same kernel per body as the plugin and the ODE path (no copy of it):
it takes world-frame velocities and body angles, turns them into the body frame, and turns the
wrench back. The public, validated API is :mod:`rrbody.physics.planar`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench

__all__ = ["stack", "batch_wrench"]


def stack(footprints: Sequence[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(shapes, geo, ranges): the footprints' part rows and geo rows end to end, and each body's
    rows ``shapes[ranges[i, 0]:ranges[i, 1]]`` (int64, shape (n, 2)). Each footprint is (shapes,
    geo) as :func:`rrbody.physics.footprint.combine` makes them (ranges local to its geo block)."""
    rows, geos, ranges = [], [], np.zeros((len(footprints), 2), dtype=np.int64)
    n_rows = n_geo = 0
    for i, (sh, geo) in enumerate(footprints):
        sh = np.array(sh, dtype=float)
        kind = sh[:, C.KIND]
        # VERTEX_FIRST, VERTEX_END, QUAD_FIRST, QUAD_END: consecutive columns
        sh[kind == C.POLYGON, C.VERTEX_FIRST:C.QUAD_END + 1] += n_geo
        sh[kind == C.SAMPLED, C.QUAD_FIRST:C.QUAD_END + 1] += n_geo
        ranges[i] = n_rows, n_rows + sh.shape[0]
        n_rows += sh.shape[0]
        n_geo += geo.shape[0]
        rows.append(sh)
        geos.append(np.asarray(geo, dtype=float)[:, :3])
    shapes = np.ascontiguousarray(np.vstack(rows)) if rows else np.zeros((0, C.N_SHAPE))
    geo = np.ascontiguousarray(np.vstack(geos)) if geos else np.zeros((0, 3))
    return shapes, geo, ranges


@njit(cache=True)
def batch_wrench(shapes: np.ndarray, geo: np.ndarray, ranges: np.ndarray, angle: np.ndarray, vx: np.ndarray,
                 vy: np.ndarray, w: np.ndarray, v_eps: float, out: np.ndarray) -> None:
    """Per body i: the dry friction of its footprint per unit normal load and per unit mu, at the
    centre-of-gravity velocity (vx[i], vy[i]) (m/s, world frame) and spin w[i] (rad/s, counter-
    clockwise), its body frame turned by angle[i] (rad) from the world's. Writes out[i] = (fx, fy,
    tq): the force (dimensionless, world frame) and the torque about the centre of gravity (m)."""
    for i in range(angle.shape[0]):
        ca = math.cos(angle[i])
        sa = math.sin(angle[i])
        vbx = ca * vx[i] + sa * vy[i]  # the body frame
        vby = -sa * vx[i] + ca * vy[i]
        fx, fy, tq = footprint_wrench(shapes, geo, ranges[i, 0], ranges[i, 1], vbx, vby, w[i], v_eps)
        out[i, 0] = ca * fx - sa * fy
        out[i, 1] = sa * fx + ca * fy
        out[i, 2] = tq
