"""Exact area-integrated dry (Coulomb) friction on a convex polygon under uniform pressure.

Everything is per unit normal load (mu g = 1): the force is dimensionless (multiply by mu m g),
the torque is in m (multiply by mu m g). Geometry and velocities are in the **body frame**, whose
origin is the point the torque is taken about (the body's centre of gravity); vertices are
counter-clockwise. Units: m, m/s, rad/s.

Method
------
With spin every point moves about the instantaneous centre c (docs/extended.md).
The body moves with velocity v at the origin and spin Omega; with Omega != 0 every point s moves
with v(s) = Omega z x (s - c), c = z x v / Omega, so a dry element feels -sgn(Omega) z x u(s),
u = (s - c)/|s - c|. The wrench needs two area integrals over the polygon S (area A):

    U = Int_S u dA,        T = Int_S s . u dA,
    F = -(sgn Omega / A) z x U,     tau = -(sgn Omega / A) T        (since s x (z x u) = s . u).

*Near field* (c within ``NEAR`` polygon radii of the centroid): a fan of triangles from c, one per
edge. In the edge's frame (outward normal n, direction e) a point is c + h n + t e, and with
r = sqrt(h^2 + t^2) the triangle's integrals are closed forms (signed, so c may lie anywhere):

    Int u dA     = (h^2 / 2) [asinh(t/|h|)] n + (h / 2) [r] e,
    Int |s-c| dA = (h / 6) [t r + h^2 asinh(t/|h|)],          T = Int |s-c| dA + c . U,

each difference [.] between the edge's end points written without cancellation
(``_edge``). The sums over edges cancel by about (|c - g| / rg)^3 in T, hence the switch.

*Far field* (c farther out): u is smooth over the polygon, and a fixed Gauss rule in the body frame
(``gauss_rule``: a fan of triangles from the first vertex, each a collapsed n x n Gauss-Legendre
product) integrates it. The leading terms, exact by construction (Int (s - g) dA = 0), are taken
out first so that nothing cancels: with rho = s - g, Dv = g - c, D = |Dv|, r = |s - c| and
q = rho . (rho + 2 Dv) / (D + r) = r - D,

    U = A Dv/D + Int (rho - (Dv/D) q) / r dA,      T = g . U + Int (rho^2 - (rho . Dv/D) q) / r dA.

*Pure translation* (|Omega| rmax <= TRANSLATION_EPS |v|): F = -v_hat - (Omega/|v|) (g . v_hat) z x v_hat
and tau = -(g x v_hat) - (Omega/|v|) v_hat^T M v_hat with M = Int s s^T dA / A, exact to
O((Omega rmax/|v|)^2) < 1e-16.

The accuracy of the switch and of the rule is measured in ``tests/test_polygon.py`` (near and far
forms agree to ~1e-15 where they meet; a box in pure spin matches its closed form to 1e-14).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["polygon_wrench", "polygon_geometry", "gauss_rule", "NEAR", "GAUSS_N", "TRANSLATION_EPS",
           "box_spin_torque"]

#: near-field closed forms while |c - g| <= NEAR * (largest vertex distance from the centroid g); their
#: cancellation grows like (|c - g| / rg)^3: measured 4e-14 relative in the torque at 3, 1.4e-13 at 10
NEAR: float = 8.0
#: Gauss-Legendre points per direction of each far-field triangle: beyond NEAR radii the nearest
#: singularity is ~7 triangle sizes away (error ~ 14^(-2n), measured below 1e-14 at 7)
GAUSS_N: int = 7
#: |Omega| rmax / |v| below which the translation expansion is used (its error is O(ratio^2))
TRANSLATION_EPS: float = 1e-8


def _check_vertices(vertices: np.ndarray) -> np.ndarray:
    v = np.ascontiguousarray(np.asarray(vertices, dtype=float))
    if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
        raise ValueError(f"vertices must be an (n, 2) array with n >= 3, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices must be finite (m)")
    return v


def polygon_geometry(vertices: np.ndarray) -> tuple[np.ndarray, float, float, float, np.ndarray]:
    """Counter-clockwise vertices, area (m^2), centroid (gx, gy) (m) and the second moment
    M = (Mxx, Mxy, Myy) = Int s s^T dA / A about the frame origin (m^2) of a simple polygon.

    Clockwise input is reversed; a polygon of zero area raises ValueError.
    """
    v = _check_vertices(vertices)
    x, y = v[:, 0], v[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    a2 = float(cr.sum())
    if not abs(a2) > 1e-300:
        raise ValueError("vertices must enclose a positive area (got a degenerate polygon)")
    if a2 < 0.0:
        return polygon_geometry(v[::-1])
    area = 0.5 * a2
    gx = float(((x + xn) * cr).sum() / (3.0 * a2))
    gy = float(((y + yn) * cr).sum() / (3.0 * a2))
    mxx = float(((x * x + x * xn + xn * xn) * cr).sum() / 12.0) / area
    myy = float(((y * y + y * yn + yn * yn) * cr).sum() / 12.0) / area
    mxy = float(((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * cr).sum() / 24.0) / area
    return v, area, gx, gy, np.array([mxx, mxy, myy])


def gauss_rule(vertices: np.ndarray, n: int = GAUSS_N) -> np.ndarray:
    """Far-field quadrature nodes of a convex polygon: rows (x, y, w) in its frame, weights summing
    to its area (m^2). A fan of triangles from the first vertex, each the collapsed (Duffy) image of
    an n x n Gauss-Legendre product rule, exact for polynomials of degree 2 n - 2."""
    v, _, _, _, _ = polygon_geometry(vertices)
    xg, wg = np.polynomial.legendre.leggauss(int(n))
    xg = 0.5 * (xg + 1.0)
    wg = 0.5 * wg
    rows = []
    gx, gy = v[0]
    for i in range(1, v.shape[0] - 1):
        ax, ay = v[i, 0] - gx, v[i, 1] - gy
        bx, by = v[i + 1, 0] - gx, v[i + 1, 1] - gy
        jac = abs(ax * by - ay * bx)  # twice the triangle's area
        xi, eta = np.meshgrid(xg, xg, indexing="ij")
        wxi, weta = np.meshgrid(wg, wg, indexing="ij")
        px = gx + xi * (ax + eta * (bx - ax))
        py = gy + xi * (ay + eta * (by - ay))
        rows.append(np.column_stack([px.ravel(), py.ravel(), (wxi * weta * xi * jac).ravel()]))
    return np.ascontiguousarray(np.concatenate(rows))


@njit(cache=True, inline="always")
def triangle_frame(p1x: float, p1y: float, p2x: float, p2y: float, cx: float, cy: float
                   ) -> tuple[float, float, float, float, float, float, float, float]:
    """The frame of the signed triangle (c, p1, p2) that the edge integrals are written in:
    (ex, ey, h, r1, r2, dr, da, dtr): the edge's direction e (its outward normal is n = (ey, -ex)), the
    signed distance h of c from the edge (m), r1 = |p1 - c| and r2 = |p2 - c| (m), and the
    differences between the edge's end points, each without cancellation: dr = [r] (m), da =
    [asinh(t/|h|)] and dtr = [t r] (m^2). h = 0 (nothing else set) where the triangle is flat."""
    dx = p2x - p1x
    dy = p2y - p1y
    L = math.sqrt(dx * dx + dy * dy)  # (no overflow at physical sizes; hypot is slower)
    if L == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    ex = dx / L
    ey = dy / L
    nx = ey
    ny = -ex
    ax = p1x - cx
    ay = p1y - cy
    bx = p2x - cx
    by = p2y - cy
    h = 0.5 * ((ax + bx) * nx + (ay + by) * ny)
    if h == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    t1 = ax * ex + ay * ey
    t2 = bx * ex + by * ey
    r1 = math.sqrt(ax * ax + ay * ay)
    r2 = math.sqrt(bx * bx + by * by)
    sr = r1 + r2
    dr = L * (t1 + t2) / sr  # r2 - r1 without cancellation (t2^2 - t1^2 = r2^2 - r1^2)
    # asinh(t2/|h|) - asinh(t1/|h|) = log((t2 + r2)/(t1 + r1)), written as log1p of a small ratio
    if t1 >= 0.0:
        da = math.log1p((L + dr) / (t1 + r1))
    elif t2 <= 0.0:
        da = math.log1p((L - dr) / (r2 - t2))
    else:
        ah = abs(h)
        da = math.asinh(t2 / ah) - math.asinh(t1 / ah)
    dtr = 0.5 * (L * sr + (t1 + t2) * dr)  # t2 r2 - t1 r1
    return ex, ey, h, r1, r2, dr, da, dtr


@njit(cache=True, inline="always")
def _edge(p1x: float, p1y: float, p2x: float, p2y: float, cx: float, cy: float) -> tuple[float, float, float]:
    """(Ux, Uy, R): Int u dA and Int |s - c| dA over the signed triangle (c, p1, p2) (m^2, m^3)."""
    ex, ey, h, _, _, dr, da, dtr = triangle_frame(p1x, p1y, p2x, p2y, cx, cy)
    if h == 0.0:
        return 0.0, 0.0, 0.0
    nx = ey
    ny = -ex
    un = 0.5 * h * h * da
    ue = 0.5 * h * dr
    return un * nx + ue * ex, un * ny + ue * ey, h / 6.0 * (dtr + h * h * da)


@njit(cache=True)
def polygon_wrench(verts: np.ndarray, v0: int, v1: int, area: float, gx: float, gy: float, rg: float,
                   mxx: float, mxy: float, myy: float, rule: np.ndarray, q0: int, q1: int, vx: float, vy: float,
                   spin: float, v_eps: float) -> tuple[float, float, float]:
    """Dry-friction force (body frame, per unit load) and torque about the origin (m, per unit load)
    on the convex polygon ``verts[v0:v1]`` (counter-clockwise, body frame, m) moving with velocity
    (vx, vy) at the origin (m/s, body frame) and spin (rad/s).

    ``area`` (m^2), centroid (gx, gy) and ``rg`` (largest vertex distance from it, m) and the second
    moment (mxx, mxy, myy) about the origin (m^2) come from :func:`polygon_geometry`;
    ``rule[q0:q1]`` is its :func:`gauss_rule`. Every point slower than ``v_eps`` (m/s): zero.
    """
    speed = math.hypot(vx, vy)
    reach = math.hypot(gx, gy) + rg  # bound on |s| over the polygon
    wr = abs(spin) * reach
    if speed <= v_eps and wr <= v_eps:
        return 0.0, 0.0, 0.0
    if wr <= TRANSLATION_EPS * speed:
        ex = vx / speed
        ey = vy / speed
        m2 = mxx * ex * ex + 2.0 * mxy * ex * ey + myy * ey * ey
        k = spin / speed * (gx * ex + gy * ey)  # first-order turn of the mean direction (zero if g = 0)
        return -ex + k * ey, -ey - k * ex, -(gx * ey - gy * ex) - spin / speed * m2
    cx = -vy / spin
    cy = vx / spin
    Dx = gx - cx
    Dy = gy - cy
    D = math.hypot(Dx, Dy)
    if D <= NEAR * rg:
        ux = 0.0
        uy = 0.0
        rr = 0.0
        for i in range(v0, v1):
            j = i + 1 if i + 1 < v1 else v0
            dux, duy, dR = _edge(verts[i, 0], verts[i, 1], verts[j, 0], verts[j, 1], cx, cy)
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
        for k in range(q0, q1):
            px = rule[k, 0] - gx
            py = rule[k, 1] - gy
            w = rule[k, 2]
            sx = px + Dx
            sy = py + Dy
            r = math.sqrt(sx * sx + sy * sy)
            q = (px * (px + 2.0 * Dx) + py * (py + 2.0 * Dy)) / (D + r)
            wr_ = w / r
            iux += wr_ * (px - dhx * q)
            iuy += wr_ * (py - dhy * q)
            it += wr_ * (px * px + py * py - (px * dhx + py * dhy) * q)
        ux = area * dhx + iux
        uy = area * dhy + iuy
        tt = it + gx * ux + gy * uy
    sg = 1.0 if spin > 0.0 else -1.0
    pre = -sg / area
    return -pre * uy, pre * ux, pre * tt


def box_spin_torque(a: float) -> float:
    """|tau| / (mu m g) (m) of a square of side a (m) spinning about its centre: the mean distance of
    its points from the centre, a (sqrt 2 + ln(1 + sqrt 2)) / 6."""
    return a * (math.sqrt(2.0) + math.log1p(math.sqrt(2.0))) / 6.0
