"""Exact area-integrated dry (Coulomb) friction on a convex polygon under a *linear* pressure.

The pressure is p(s) = (1 + k . (s - g)) / A on the polygon (area A, centroid g, slope k in 1/m;
p >= 0 on it), so the load is 1 (Int (s - g) dA = 0) and its centre is g + M_g k, M_g the polygon's
second moment of area about g over A. This is the pressure that puts a body's centre of pressure at a
centre of gravity set off its shapes' centroid (:mod:`rrbody.physics.footprint`, "How the load is
spread" in docs/plugin.md). Everything else follows :mod:`rrbody.physics.polygon` (per unit normal
load, body frame with the origin at the point the torque is taken about; m, m/s, rad/s); k = 0 is its
uniform case, which the footprint kernel keeps on that module's own code path.

Method
------
With spin Omega the element at s feels -sgn(Omega) z x u, u = (s - c)/|s - c| (c the instantaneous
centre), so with f = 1 + k . (s - g)

    U = Int_S f u dA,   T = Int_S f s . u dA = c . U + Int_S f |s - c| dA,
    F = -(sgn Omega / A) z x U,   tau = -(sgn Omega / A) T.

*Near field*: a fan of triangles from c, one per edge; in the edge's frame (outward normal n, direction
e, signed distance h) a point is c + lam (h n + t e), dA = lam h dlam dt, and f = f_c + lam (h k_n +
t k_e) with f_c = f(c), k_n = k . n, k_e = k . e. The lam integrals are polynomial, leaving with
r = sqrt(h^2 + t^2) and [.] the difference between the edge's end points

    Int f u dA     = h^2 [(f_c/2 + h k_n/3) I0 + k_e I1 / 3] n + h [(f_c/2 + h k_n/3) I1 + k_e I2 / 3] e,
    Int f |s-c| dA = h [(f_c/3 + h k_n/4) J0 + k_e J1 / 4],

I0 = [asinh(t/|h|)], I1 = [r], I2 = [t r - h^2 asinh(t/|h|)] / 2, J0 = [t r + h^2 asinh(t/|h|)] / 2,
J1 = [r^3] / 3: closed forms (for k = 0 they are :func:`rrbody.physics.polygon._edge`'s).

*Far field* (c beyond ``NEAR`` polygon radii): the polygon's Gauss rule weighted by f, with the leading
terms of u taken out as in :mod:`rrbody.physics.polygon` (rho = s - g, Dv = g - c, q = |s - c| - D):
U = A Dv/D + Int f (rho - (Dv/D) q)/r dA, T = g . U + Int f [k . rho (rho . Dv/D) + (rho^2 - (rho . Dv/D) q)/r] dA
(the rule integrates the polynomial parts exactly: degree 12 >= 3).

*Pure translation* (|Omega| rmax <= TRANSLATION_EPS |v|): F = -v_hat - (Omega/|v|) (P . v_hat) z x v_hat,
tau = -(P x v_hat) - (Omega/|v|) Int p (s . v_hat)^2 dA with P = Int p s dA, the centre of pressure:
both moments from the Gauss rule, exact for these cubic integrands.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics.polygon import NEAR, TRANSLATION_EPS, triangle_frame

__all__ = ["linear_polygon_wrench"]


@njit(cache=True, inline="always")
def _edge_linear(p1x: float, p1y: float, p2x: float, p2y: float, cx: float, cy: float, fc: float, kx: float,
                 ky: float) -> tuple[float, float, float]:
    """(Ux, Uy, R): Int f u dA and Int f |s - c| dA over the signed triangle (c, p1, p2), f = fc + k . (s - c)
    (m^2, m^3)."""
    ex, ey, h, r1, r2, dr, da, dtr = triangle_frame(p1x, p1y, p2x, p2y, cx, cy)
    if h == 0.0:
        return 0.0, 0.0, 0.0
    nx = ey
    ny = -ex
    i2 = 0.5 * (dtr - h * h * da)
    j0 = 0.5 * (dtr + h * h * da)
    j1 = dr * (r1 * r1 + r1 * r2 + r2 * r2) / 3.0  # (r2^3 - r1^3) / 3
    kn = kx * nx + ky * ny
    ke = kx * ex + ky * ey
    a0 = 0.5 * fc + h * kn / 3.0
    un = h * h * (a0 * da + ke * dr / 3.0)
    ue = h * (a0 * dr + ke * i2 / 3.0)
    rr = h * ((fc / 3.0 + 0.25 * h * kn) * j0 + 0.25 * ke * j1)
    return un * nx + ue * ex, un * ny + ue * ey, rr


@njit(cache=True)
def linear_polygon_wrench(verts: np.ndarray, v0: int, v1: int, area: float, gx: float, gy: float, rg: float,
                          kx: float, ky: float, rule: np.ndarray, q0: int, q1: int, vx: float, vy: float,
                          spin: float, v_eps: float) -> tuple[float, float, float]:
    """Dry-friction force (body frame, per unit load) and torque about the origin (m, per unit load)
    on the convex polygon ``verts[v0:v1]`` (counter-clockwise, body frame, m) under the pressure
    (1 + k . (s - g)) / A, k = (kx, ky) (1/m), moving with velocity (vx, vy) at the origin (m/s, body
    frame) and spin (rad/s). ``area`` (m^2), centroid g = (gx, gy) and ``rg`` (largest vertex distance
    from g, m) as :func:`rrbody.physics.polygon.polygon_geometry` gives them, ``rule[q0:q1]`` its
    Gauss rule. Every point slower than ``v_eps`` (m/s): zero."""
    speed = math.hypot(vx, vy)
    reach = math.hypot(gx, gy) + rg
    wr = abs(spin) * reach
    if speed <= v_eps and wr <= v_eps:
        return 0.0, 0.0, 0.0
    if wr <= TRANSLATION_EPS * speed:
        ex = vx / speed
        ey = vy / speed
        px = 0.0
        py = 0.0
        m2 = 0.0
        for i in range(q0, q1):
            sx = rule[i, 0]
            sy = rule[i, 1]
            wf = rule[i, 2] * (1.0 + kx * (sx - gx) + ky * (sy - gy))
            px += wf * sx
            py += wf * sy
            se = sx * ex + sy * ey
            m2 += wf * se * se
        px /= area
        py /= area
        m2 /= area
        k = spin / speed * (px * ex + py * ey)
        return -ex + k * ey, -ey - k * ex, -(px * ey - py * ex) - spin / speed * m2
    cx = -vy / spin
    cy = vx / spin
    Dx = gx - cx
    Dy = gy - cy
    D = math.hypot(Dx, Dy)
    if D <= NEAR * rg:
        fc = 1.0 - kx * Dx - ky * Dy  # f at c
        ux = 0.0
        uy = 0.0
        rr = 0.0
        for i in range(v0, v1):
            j = i + 1 if i + 1 < v1 else v0
            dux, duy, dR = _edge_linear(verts[i, 0], verts[i, 1], verts[j, 0], verts[j, 1], cx, cy, fc, kx, ky)
            ux += dux
            uy += duy
            rr += dR
        tt = rr + cx * ux + cy * uy
    else:
        dhx = Dx / D
        dhy = Dy / D
        iux = 0.0
        iuy = 0.0
        it = 0.0
        for i in range(q0, q1):
            px = rule[i, 0] - gx
            py = rule[i, 1] - gy
            kr = kx * px + ky * py
            w = rule[i, 2]
            wf = w * (1.0 + kr)
            sx = px + Dx
            sy = py + Dy
            r = math.sqrt(sx * sx + sy * sy)
            q = (px * (px + 2.0 * Dx) + py * (py + 2.0 * Dy)) / (D + r)
            pd = px * dhx + py * dhy
            wr_ = wf / r
            iux += wr_ * (px - dhx * q)
            iuy += wr_ * (py - dhy * q)
            it += w * kr * pd + wr_ * (px * px + py * py - pd * q)
        ux = area * dhx + iux
        uy = area * dhy + iuy
        tt = it + gx * ux + gy * uy
    sg = 1.0 if spin > 0.0 else -1.0
    pre = -sg / area
    return -pre * uy, pre * ux, pre * tt
