"""Any friction law over a footprint by quadrature: the contact method of a law without a closed form of its own.

Dry friction has exact footprint kernels (:func:`rrbody.physics.contact.footprint_wrench`) and the viscous law a
closed form of the load's moments (:func:`rrbody.physics.effects.law_viscous.footprint`). A law whose module has
no ``footprint`` form (the law table, :mod:`rrbody.model.laws`: Stribeck friction) is integrated here: every
part of the footprint (:mod:`rrbody.physics.contact`'s rows) is replaced by quadrature nodes carrying its
load, and each node feels the law's element force (:func:`rrbody.physics.effects.laws.element_force`) at its
own velocity. :func:`footprint_law_wrench` is what both paths call for a law other than dry friction: the
ODE path's contact method (:mod:`rrbody.physics.areas.area_contact`) and the plugin's kernel
(:mod:`rrbody.contact.accel`).

The rules (nodes are computed on the fly from the part's row; nothing is stored):

- POINT and SAMPLED parts: their own points, exactly (no quadrature error);
- ELLIPSE (uniform pressure): :data:`N_RADIAL` Gauss-Legendre nodes in r on [0, 1] (the load 2 r dr)
  times :data:`N_ANGLE` equally spaced angles, in the ellipse's scaled frame;
- RING: :data:`N_ANGLE` equally spaced points on the circle;
- HERTZ (p ~ sqrt(1 - rho^2/R^2)): rho = R sin(t), where the load element is 3 sin(t) cos(t)^2 dt, with
  :data:`N_RADIAL` Gauss-Legendre nodes in t on [0, pi/2], times :data:`N_ANGLE` angles;
- POLYGON: a fan of triangles from its centroid, each the collapsed (Duffy) image of an
  :data:`N_TRIANGLE` x :data:`N_TRIANGLE` Gauss-Legendre product rule, the pressure weighted by its
  slope (1 + k . (s - centroid)).

Error: the integrand is smooth except where an element's velocity vanishes (the instantaneous centre of
a spinning footprint, where a law that sticks turns its direction discontinuously); there the rules
converge slowly. So :func:`quadrature_wrench` integrates the law's force at zero speed (c0 v_hat,
:func:`rrbody.physics.effects.laws.law_rest_coeff`: Stribeck's mu_s g) exactly, by dry friction's
footprint kernel, and only the rest, which vanishes where the velocity does, by the rules. Measured
(``tests/test_footprint_quad.py``, the rules alone on dry friction against its exact kernels): below
1e-14 of mu m g (force) and mu m g R (torque, R the footprint's reach) with the instantaneous centre
3-30 reaches away; with it inside, up to 2e-3 for an ellipse or a Hertz patch and 6e-3 for a box (and
1.3e-2 for a ring with the centre on the ring); exact for point and sampled parts. With the exact part
taken out, Stribeck friction on a box is within 5.3e-5 of mu_s m g (``tests/test_stribeck.py``), the
remainder's error scaling with (mu_s - mu_k) / mu_s: up to the rules' own error as v_s -> 0. Cost:
(N_RADIAL x N_ANGLE) = 1024 element forces per ellipse or Hertz patch, 144 per triangle of a polygon,
plus dry friction's kernel.

Units: per unit mass, the force in the body frame (m/s^2) and the torque about the centre of gravity
(m^2/s^2): the law's ``coeff`` (m/s^2 for a load-scaled law) is applied by the element force.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.effects import law_dry
from rrbody.physics.effects.laws import element_force, law_footprint, law_has_footprint, law_rest_coeff

__all__ = ["footprint_law_wrench", "quadrature_wrench", "element_quadrature", "N_RADIAL", "N_ANGLE", "N_TRIANGLE"]

#: Gauss-Legendre nodes in the radial variable of an ellipse or a Hertz patch
N_RADIAL: int = 16
#: equally spaced angles around an ellipse, a ring or a Hertz patch (the periodic trapezoid rule)
N_ANGLE: int = 64
#: Gauss-Legendre nodes per direction of each triangle of a polygon's fan
N_TRIANGLE: int = 12


def _gauss01(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1] (weights sum to 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return np.ascontiguousarray(0.5 * (x + 1.0)), np.ascontiguousarray(0.5 * w)


_XR, _WR = _gauss01(N_RADIAL)
_XT, _WT = _gauss01(N_TRIANGLE)
_CA = np.cos(2.0 * np.pi * (np.arange(N_ANGLE) + 0.5) / N_ANGLE)
_SA = np.sin(2.0 * np.pi * (np.arange(N_ANGLE) + 0.5) / N_ANGLE)
# the ellipse's radial rule: Gauss in r itself, the load 2 r dr on the unit disk (a smooth integrand in r:
# spectral convergence where the velocity does not vanish, e.g. a disk spinning about its centre)
_ER = _XR
_EW = 2.0 * _XR * _WR
# the Hertz patch's: rho = sin(t), t in [0, pi/2], the load 3 rho sqrt(1 - rho^2) drho = 3 sin(t) cos(t)^2 dt
# (smooth in t, where the square root's slope at the rim would slow a rule in rho)
_HT = 0.5 * np.pi * _XR
_HR = np.sin(_HT)
_HW = 1.5 * np.pi * np.sin(_HT) * np.cos(_HT) ** 2 * _WR


@njit(cache=True, inline="always")
def _node(law, x, y, wt, vbx, vby, w, coeff, v_eps, lp, c0):  # noqa: ANN001, ANN202 (numba)
    """(fx, fy, tq) of the load ``wt`` at (x, y) (m, body frame from the centre of gravity): the law's element
    force less ``c0`` times dry friction's unit force (the part integrated exactly)."""
    ux = vbx - w * y
    uy = vby + w * x
    gx, gy = element_force(law, ux, uy, coeff, v_eps, lp)
    if c0 != 0.0:
        dx, dy = law_dry.force(ux, uy, c0, v_eps)
        gx -= dx
        gy -= dy
    return wt * gx, wt * gy, wt * (x * gy - y * gx)


@njit(cache=True)
def quadrature_wrench(law, shapes, geo, s0, s1, vbx, vby, w, coeff, v_eps, lp):  # noqa: ANN001, ANN201 (numba)
    """(fx, fy, tq): law ``law`` (a code of the law table) with coefficient ``coeff`` and parameters ``lp``
    (per unit mass) over the parts ``shapes[s0:s1]``, per unit mass (force m/s^2, body frame; torque about
    the centre of gravity m^2/s^2) at the centre-of-gravity velocity (vbx, vby) (m/s, body frame) and spin
    ``w`` (rad/s): its force at zero speed, c0 = :func:`~rrbody.physics.effects.laws.law_rest_coeff`, as
    dry friction by the exact footprint kernel, and the rest by :func:`element_quadrature`."""
    c0 = law_rest_coeff(law, coeff, lp)
    fx, fy, tq = element_quadrature(law, shapes, geo, s0, s1, vbx, vby, w, coeff, v_eps, lp, c0)
    if c0 != 0.0:
        dx, dy, dt = footprint_wrench(shapes, geo, s0, s1, vbx, vby, w, v_eps)
        fx += c0 * dx
        fy += c0 * dy
        tq += c0 * dt
    return fx, fy, tq


@njit(cache=True)
def element_quadrature(law, shapes, geo, s0, s1, vbx, vby, w, coeff, v_eps, lp, c0):  # noqa: ANN001, ANN201
    """(fx, fy, tq): the element force of law ``law`` less ``c0`` (m/s^2 per unit mass) times dry friction's
    unit force, over the parts ``shapes[s0:s1]`` by the rules of the module docstring; units and frames as
    :func:`quadrature_wrench`."""
    fx = 0.0
    fy = 0.0
    tq = 0.0
    for k in range(s0, s1):
        kind = shapes[k, C.KIND]
        wk = shapes[k, C.LOAD_SHARE]
        ox = shapes[k, C.CENTRE_X]
        oy = shapes[k, C.CENTRE_Y]
        if kind == C.POINT:
            a, b, c = _node(law, ox, oy, wk, vbx, vby, w, coeff, v_eps, lp, c0)
            fx += a
            fy += b
            tq += c
        elif kind == C.SAMPLED:
            for q in range(int(shapes[k, C.QUAD_FIRST]), int(shapes[k, C.QUAD_END])):
                a, b, c = _node(law, geo[q, 0], geo[q, 1], wk * geo[q, 2], vbx, vby, w, coeff, v_eps, lp, c0)
                fx += a
                fy += b
                tq += c
        elif kind == C.POLYGON:
            v0 = int(shapes[k, C.VERTEX_FIRST])
            nv = int(shapes[k, C.VERTEX_END]) - v0
            kx = shapes[k, C.SLOPE_X]
            ky = shapes[k, C.SLOPE_Y]
            scale = wk / shapes[k, C.AREA]
            for e in range(nv):
                ax = geo[v0 + e, 0] - ox
                ay = geo[v0 + e, 1] - oy
                bx = geo[v0 + (e + 1) % nv, 0] - ox
                by = geo[v0 + (e + 1) % nv, 1] - oy
                jac = ax * by - ay * bx  # twice the triangle's area (counter-clockwise vertices: >= 0)
                for i in range(N_TRIANGLE):
                    xi = _XT[i]
                    for j in range(N_TRIANGLE):
                        eta = _XT[j]
                        dx = xi * (ax + eta * (bx - ax))
                        dy = xi * (ay + eta * (by - ay))
                        wt = scale * (1.0 + kx * dx + ky * dy) * _WT[i] * _WT[j] * xi * jac
                        a, b, c = _node(law, ox + dx, oy + dy, wt, vbx, vby, w, coeff, v_eps, lp, c0)
                        fx += a
                        fy += b
                        tq += c
        else:  # ELLIPSE, RING, HERTZ: polar rules about the part's centre
            ra = shapes[k, C.RADIUS_A]
            if kind == C.ELLIPSE:
                rb = shapes[k, C.RADIUS_B]
                co = math.cos(shapes[k, C.AXIS_ANGLE])
                so = math.sin(shapes[k, C.AXIS_ANGLE])
                nr = N_RADIAL
            else:
                rb = ra
                co = 1.0
                so = 0.0
                nr = 1 if kind == C.RING else N_RADIAL
            for i in range(nr):
                if kind == C.ELLIPSE:
                    r = _ER[i]
                    wr = _EW[i]
                elif kind == C.HERTZ:
                    r = _HR[i]
                    wr = _HW[i]
                else:
                    r = 1.0
                    wr = 1.0
                wt = wk * wr / N_ANGLE
                for j in range(N_ANGLE):
                    ex = ra * r * _CA[j]
                    ey = rb * r * _SA[j]
                    a, b, c = _node(law, ox + co * ex - so * ey, oy + so * ex + co * ey, wt, vbx, vby, w, coeff,
                                    v_eps, lp, c0)
                    fx += a
                    fy += b
                    tq += c
    return fx, fy, tq


@njit(cache=True, inline="always")
def footprint_law_wrench(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp):  # noqa: ANN001, ANN201
    """(fx, fy, tq) per unit mass of any law but dry friction over the parts ``shapes[s0:s1]``: the law's own
    footprint form where its module has one (:func:`rrbody.physics.effects.laws.law_footprint`: the viscous
    law's moments, from the load's mean position (gx, gy) and mean squared distance ``jj``), else
    :func:`quadrature_wrench`. Units and frames as there."""
    if law_has_footprint(law):
        return law_footprint(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp)
    return quadrature_wrench(law, shapes, geo, s0, s1, vbx, vby, w, coeff, v_eps, lp)
