"""Static friction: the limit surface of a contact, the stick test and the break-away motion.

A body at rest on the plane can be held by any friction wrench phi * c, c = mu_s g cos(tilt) per
unit mass, with phi in the contact's *limit set* W: every wrench (force, torque about the centre of
gravity) a field of elemental forces |f(s)| <= p(s) can give, per unit load. W is convex and
symmetric, and its support function is the friction power of a motion: for a twist
xi = (vx, vy, omega) (centre-of-gravity velocity, spin), max_{phi in W} phi . xi = int p |v_xi| dA,
attained by the kinetic friction wrench of the opposite motion, -F(xi) = F(-xi)
(:func:`rrbody.physics.contact.footprint_wrench`). So W needs no other description: the kernel that
gives kinetic friction is W's support map.

The rule (maximum dissipation; derivation in docs/contacts.md). Let L be the in-plane load per unit
mass (force, and torque / 1 about the centre of gravity: everything but friction), M = diag(1, 1, j)
with j = I / m. Then

- the body sticks, exactly, while -L / c_s lies in W: friction supplies -L and nothing moves;
- otherwise it breaks away with the acceleration a = M^-1 (L + c_k phi*), where phi* is the point of
  W nearest to -L / c_k in the metric M^-1. This a maximises L . xi - c_k h(xi) - xi^T M xi / 2
  (a strictly concave problem), whose optimality condition M a = L + c_k F(a) says exactly that the
  body starts to slide along a with the kinetic friction of that same motion.

Both are one computation: the distance from a point to W, by the Gilbert-Johnson-Keerthi algorithm
(a simplex of support points grown toward the point; the nearest point of a simplex of up to four
points by enumeration of its faces), in coordinates scaled by M^-1/2. Units: forces per unit load
(dimensionless), torques in m; the twist's speed scale is irrelevant (the support map is homogeneous
of degree 0).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics.contact import footprint_wrench

__all__ = ["nearest_in_limit_set", "at_rest", "MAX_ITER", "TOL"]

#: GJK iterations at most (a smooth limit set: a few to a few tens; polytopes: finite)
MAX_ITER = 96
#: relative tolerance: distances below TOL (1 + |q|) count as zero (the point is in W), and the
#: search stops when a new support point brings the gap below TOL |d|^2
TOL = 1e-13


@njit(cache=True)
def _support(shapes, geo, s0, s1, dx, dy, dt, sj):  # noqa: ANN001 (numba)
    """The point of the scaled set W' = diag(1, 1, 1/sj) W furthest along (dx, dy, dt)."""
    # argmax over W of phi . e, e = (dx, dy, dt / sj), is the friction of the twist -e
    fx, fy, ft = footprint_wrench(shapes, geo, s0, s1, -dx, -dy, -dt / sj, 0.0)
    return fx, fy, ft / sj


@njit(cache=True)
def _solve_face(P, idx, k, qx, qy, qz):  # noqa: ANN001 (numba)
    """Nearest point to q of the affine hull of points P[idx[:k]]: (barycentric weights, ok)."""
    lam = np.zeros(4)
    if k == 1:
        lam[0] = 1.0
        return lam, True
    p0 = idx[0]
    G = np.zeros((3, 3))
    b = np.zeros(3)
    for i in range(1, k):
        ei = P[idx[i]] - P[p0]
        b[i - 1] = (qx - P[p0, 0]) * ei[0] + (qy - P[p0, 1]) * ei[1] + (qz - P[p0, 2]) * ei[2]
        for j2 in range(1, k):
            ej = P[idx[j2]] - P[p0]
            G[i - 1, j2 - 1] = ei[0] * ej[0] + ei[1] * ej[1] + ei[2] * ej[2]
    n = k - 1
    scale = 0.0
    for i in range(n):
        scale = max(scale, G[i, i])
    # Gaussian elimination with partial pivoting (n <= 3); a degenerate face is skipped
    A = np.zeros((3, 4))
    for i in range(n):
        for j2 in range(n):
            A[i, j2] = G[i, j2]
        A[i, 3] = b[i]
    for c in range(n):
        piv = c
        for r in range(c + 1, n):
            if abs(A[r, c]) > abs(A[piv, c]):
                piv = r
        if abs(A[piv, c]) <= 1e-14 * scale:
            return lam, False
        if piv != c:
            for c2 in range(4):
                A[c, c2], A[piv, c2] = A[piv, c2], A[c, c2]
        for r in range(c + 1, n):
            f = A[r, c] / A[c, c]
            for c2 in range(c, 4):
                A[r, c2] -= f * A[c, c2]
    mu = np.zeros(3)
    for r in range(n - 1, -1, -1):
        acc = A[r, 3]
        for c2 in range(r + 1, n):
            acc -= A[r, c2] * mu[c2]
        mu[r] = acc / A[r, r]
    s = 0.0
    for i in range(n):
        lam[i + 1] = mu[i]
        s += mu[i]
    lam[0] = 1.0 - s
    for i in range(k):
        if lam[i] < -1e-12:
            return lam, False
    return lam, True


@njit(cache=True)
def _nearest_on_simplex(P, m, qx, qy, qz):  # noqa: ANN001 (numba)
    """Nearest point to q of the convex hull of P[:m] (m <= 4): the point, and the simplex reduced to
    the smallest face that holds it (P rewritten in place; returns its new size)."""
    best = 1e300
    bx = by = bz = 0.0
    bmask = 0
    idx = np.zeros(4, dtype=np.int64)
    for mask in range(1, 1 << m):
        k = 0
        for i in range(m):
            if mask & (1 << i):
                idx[k] = i
                k += 1
        lam, ok = _solve_face(P, idx, k, qx, qy, qz)
        if not ok:
            continue
        x = 0.0
        y = 0.0
        z = 0.0
        for i in range(k):
            x += lam[i] * P[idx[i], 0]
            y += lam[i] * P[idx[i], 1]
            z += lam[i] * P[idx[i], 2]
        dist = (x - qx) ** 2 + (y - qy) ** 2 + (z - qz) ** 2
        if dist < best * (1.0 - 1e-12) or (dist <= best and k < _popcount(bmask)):
            best = dist
            bx, by, bz = x, y, z
            bmask = mask
    k = 0
    for i in range(m):
        if bmask & (1 << i):
            for c in range(3):
                P[k, c] = P[i, c]
            k += 1
    return bx, by, bz, k


@njit(cache=True, inline="always")
def _popcount(mask):  # noqa: ANN001 (numba)
    n = 0
    while mask:
        n += mask & 1
        mask >>= 1
    return n


@njit(cache=True)
def nearest_in_limit_set(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, qx: float, qy: float, qt: float,
                         j: float) -> tuple[float, float, float, bool]:
    """The point phi of the limit set W of the parts ``shapes[s0:s1]`` nearest to q = (qx, qy, qt)
    (force per unit load, torque in m; body frame) in the metric diag(1, 1, 1/j) (j = I/m, m^2), and
    whether q lies in W (then phi = q)."""
    sj = math.sqrt(j)
    qz = qt / sj
    tol = TOL * (1.0 + math.sqrt(qx * qx + qy * qy + qz * qz))
    P = np.zeros((4, 3))
    # start from the support point toward q (or any, if q = 0)
    if qx == 0.0 and qy == 0.0 and qz == 0.0:
        return 0.0, 0.0, 0.0, True
    P[0, 0], P[0, 1], P[0, 2] = _support(shapes, geo, s0, s1, qx, qy, qz, sj)
    m = 1
    x, y, z = P[0, 0], P[0, 1], P[0, 2]
    for _ in range(MAX_ITER):
        dx = qx - x
        dy = qy - y
        dz = qz - z
        dd = dx * dx + dy * dy + dz * dz
        if dd <= tol * tol:
            return qx, qy, qz * sj, True
        sx, sy, sz = _support(shapes, geo, s0, s1, dx, dy, dz, sj)
        # no support point beyond the current nearest one along d: it is the nearest point of W
        if (sx - x) * dx + (sy - y) * dy + (sz - z) * dz <= TOL * dd:
            return x, y, z * sj, False
        P[m, 0], P[m, 1], P[m, 2] = sx, sy, sz
        m += 1
        x, y, z, m = _nearest_on_simplex(P, m, qx, qy, qz)
        if m == 4:
            # q inside the tetrahedron of support points: inside W
            return qx, qy, qz * sj, True
    dx = qx - x
    dy = qy - y
    dz = qz - z
    return x, y, z * sj, dx * dx + dy * dy + dz * dz <= tol * tol


@njit(cache=True)
def at_rest(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, lx: float, ly: float, lt: float, j: float,
            c_static: float, c_kinetic: float) -> tuple[float, float, float, bool]:
    """A body at rest under the load (lx, ly) (m/s^2, body frame) and lt (torque per unit mass about
    the centre of gravity, m^2/s^2): (ax, ay, alpha_dot, stuck). Stuck (friction coefficients per unit
    mass c = mu g cos(tilt), m/s^2): zero acceleration. Else the break-away acceleration (m/s^2, body
    frame; rad/s^2) under kinetic friction, the maximum-dissipation start."""
    if lx == 0.0 and ly == 0.0 and lt == 0.0:
        return 0.0, 0.0, 0.0, True
    if c_static > 0.0 and lx * lx + ly * ly <= c_static * c_static:
        # |force| <= c_s is necessary for sticking (no wrench of W has a force above 1 per unit load)
        _, _, _, inside = nearest_in_limit_set(shapes, geo, s0, s1, -lx / c_static, -ly / c_static,
                                               -lt / c_static, j)
        if inside:
            return 0.0, 0.0, 0.0, True
    if c_kinetic <= 0.0:
        return lx, ly, lt / j, False
    px, py, pt, _ = nearest_in_limit_set(shapes, geo, s0, s1, -lx / c_kinetic, -ly / c_kinetic, -lt / c_kinetic, j)
    ax, ay, aw = _polish(shapes, geo, s0, s1, lx, ly, lt, j, c_kinetic, lx + c_kinetic * px, ly + c_kinetic * py,
                         (lt + c_kinetic * pt) / j)
    return ax, ay, aw, False


@njit(cache=True)
def _residual(shapes, geo, s0, s1, lx, ly, lt, j, c, ax, ay, aw):  # noqa: ANN001 (numba)
    """M a - L - c F(a): zero at the break-away acceleration (force per unit mass, m/s^2)."""
    fx, fy, ft = footprint_wrench(shapes, geo, s0, s1, ax, ay, aw, 0.0)
    return ax - lx - c * fx, ay - ly - c * fy, j * aw - lt - c * ft


@njit(cache=True)
def _solve3(J: np.ndarray, rx: float, ry: float, rt: float) -> tuple[float, float, float]:
    """J^-1 (rx, ry, rt) by Cramer's rule; NaNs where J is singular to rounding (its determinant below 1e-14
    of the product of its rows' sizes)."""
    a, b, c = J[0, 0], J[0, 1], J[0, 2]
    d, e, f = J[1, 0], J[1, 1], J[1, 2]
    g, h, i = J[2, 0], J[2, 1], J[2, 2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    size = (math.sqrt(a * a + b * b + c * c) * math.sqrt(d * d + e * e + f * f) * math.sqrt(g * g + h * h + i * i))
    if not abs(det) > 1e-14 * size:
        return math.nan, math.nan, math.nan
    x = (rx * (e * i - f * h) - b * (ry * i - f * rt) + c * (ry * h - e * rt)) / det
    y = (a * (ry * i - f * rt) - rx * (d * i - f * g) + c * (d * rt - ry * g)) / det
    z = (a * (e * rt - ry * h) - b * (d * rt - ry * g) + rx * (d * h - e * g)) / det
    return x, y, z


@njit(cache=True)
def _polish(shapes, geo, s0, s1, lx, ly, lt, j, c, ax, ay, aw):  # noqa: ANN001 (numba)
    """Newton's method on M a = L + c F(a) from GJK's answer (GJK converges only linearly on a smooth
    limit set): its Jacobian M - c dF/da is positive definite (dF/da is minus the Hessian of the
    convex dissipation), taken by central differences. A step is kept only if it lowers the
    residual, so a kink of F (the instantaneous centre on a foot) leaves GJK's answer."""
    rx, ry, rt = _residual(shapes, geo, s0, s1, lx, ly, lt, j, c, ax, ay, aw)
    r2 = rx * rx + ry * ry + rt * rt / j
    scale = math.sqrt(lx * lx + ly * ly + lt * lt / j) + c
    J = np.zeros((3, 3))
    for _ in range(8):
        if r2 <= (1e-15 * scale) ** 2:
            break
        h = 1e-7 * math.sqrt(ax * ax + ay * ay + j * aw * aw)
        if h == 0.0:  # GJK's answer is no acceleration: the load on the limit surface's edge, the start of a slide
            break
        for k in range(3):
            hk = h if k < 2 else h / math.sqrt(j)
            dx = hk if k == 0 else 0.0
            dy = hk if k == 1 else 0.0
            dw = hk if k == 2 else 0.0
            px, py, pt = _residual(shapes, geo, s0, s1, lx, ly, lt, j, c, ax + dx, ay + dy, aw + dw)
            mx, my, mt = _residual(shapes, geo, s0, s1, lx, ly, lt, j, c, ax - dx, ay - dy, aw - dw)
            J[0, k] = (px - mx) / (2.0 * hk)
            J[1, k] = (py - my) / (2.0 * hk)
            J[2, k] = (pt - mt) / (2.0 * hk)
        step = _solve3(J, rx, ry, rt)
        if step[0] != step[0]:  # a singular Jacobian (the twist on a kink of the wrench): GJK's answer stands
            break
        nx, ny, nw = ax - step[0], ay - step[1], aw - step[2]
        qx, qy, qt = _residual(shapes, geo, s0, s1, lx, ly, lt, j, c, nx, ny, nw)
        q2 = qx * qx + qy * qy + qt * qt / j
        if not q2 < r2:
            break
        ax, ay, aw, rx, ry, rt, r2 = nx, ny, nw, qx, qy, qt, q2
    return ax, ay, aw
