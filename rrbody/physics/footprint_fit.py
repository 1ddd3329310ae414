"""The fitting half of :mod:`rrbody.physics.footprint_table`: exact wrench values of a footprint at
many twists, their Chebyshev fits on rectangles of the ICR plane (or of the outer coordinates) and
the tests a fit must pass, the footprint's reach and the dead-band bound.

Units: per unit load and mu g; force dimensionless, torque divided by the reach R (dimensionless).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.icr_fit import cheb

__all__ = ["fit_cells", "table_reach", "deadband_factor", "edge_lines", "cell_line", "singular_part", "pack", "N",
           "BLOCK", "N64", "ROWS", "F32_FROM", "TAIL_TOL", "VALID_TOL", "ROUND_TOL", "VALID_PTS"]

#: Chebyshev points per direction of every cell; its polynomial keeps total degree <= N - 1 (the
#: table's kernel, rrbody.physics.footprint_table._block, is written out for N = 8)
N: int = 8
#: bound on the Chebyshev terms a fit drops and on its last kept ones, in the force and in the torque
#: divided by R (both dimensionless); half the accuracy target 1e-10
TAIL_TOL: float = 5e-11
#: largest difference from the exact formula at the validation points, force and torque / R; half the target
VALID_TOL: float = 5e-11
#: validation points per direction of a cell (equally spaced, edges and corners included)
VALID_PTS: int = N + 3
#: total degree from which a coefficient is stored as float32 (those below as float64): a block then
#: takes 504 bytes instead of 864 (8-9 cache lines instead of 14, a smaller fetch ahead; alone it did
#: not measurably speed up the plugin's step, docs/active.md); the degree-3 coefficients are
#: small enough there (below 2e-5 outside the square, a few 1e-4 inside) for the rounding to stay
#: near 1e-12 (the L and the box: at most 3.9e-12 and 5.7e-12), while degree 2 reaches 1.1e-10
F32_FROM: int = 3
#: bound on what storing the coefficients of degree >= F32_FROM as float32 changes anywhere in a cell
#: (the sum of the roundings, |zx^i zy^j| <= 1), force and torque / R; a fifth of VALID_TOL (the
#: validation points see the stored coefficients too)
ROUND_TOL: float = 1e-11


@njit(cache=True)
def _values(shapes, geo, s0, s1, V):  # noqa: ANN001 (numba)
    """footprint_wrench (no dead band) at every twist row (vbx, vby, w) of ``V``."""
    out = np.empty((V.shape[0], 3))
    for k in range(V.shape[0]):
        fx, fy, tq = footprint_wrench(shapes, geo, s0, s1, V[k, 0], V[k, 1], V[k, 2], 0.0)
        out[k, 0] = fx
        out[k, 1] = fy
        out[k, 2] = tq
    return out


_Z, _V, _M = cheb(N)  # (icr_fit's: points, values -> Chebyshev, Chebyshev -> monomials)
_ZV = np.linspace(-1.0, 1.0, VALID_PTS)
_XV = _ZV[:, None] ** np.arange(N)[None, :]  # (VALID_PTS, N) monomials at the validation points
#: total degree i + j of the term zx^i zy^j; the kept terms (total degree <= N - 1, row-major: the
#: packed block's order) and the last kept ones
_DEG = np.add.outer(np.arange(N), np.arange(N))
_KEEP = _DEG <= N - 1
_LAST = _DEG == N - 1
#: the stored (float32) terms among all N x N, and, in the packed order (row-major: zx^i zy^j for i =
#: 0 .. N - 1, j = 0 .. N - 1 - i), the kept terms that are float64 and float32
_F32 = _KEEP & (_DEG >= F32_FROM)
_LOW = _DEG[_KEEP] < F32_FROM
#: float64 coefficient triples of a block (one row each), then float32 ones (two to a row)
N64: int = int(_LOW.sum())
_N32: int = int((~_LOW).sum())
#: rows of 3 float64 of a packed block: its float64 triples, then its float32 triples two to a row
BLOCK: int = N64 + (_N32 + 1) // 2
#: per power i of zx: (first float64 triple, how many, first float32 triple, how many) of its
#: coefficients of zy^j (j = 0 .. N - 1 - i: the float64 ones are the lowest powers of zy)
ROWS = tuple((sum(max(0, F32_FROM - a) for a in range(i)), max(0, F32_FROM - i),
              sum(N - a - max(0, F32_FROM - a) for a in range(i)), N - i - max(0, F32_FROM - i)) for i in range(N))


def pack(mono: np.ndarray) -> np.ndarray:
    """A table block (BLOCK rows of 3 float64) from a cell's kept coefficients (N (N + 1) / 2 x 3, the
    packed order, :func:`fit_cells`): the float64 triples, then the float32 ones as float32 pairs of bits
    in each float64 slot (read back through the table's float32 view, ``T.view(np.float32)``: rows
    of 6, a triple k at row N64 + k // 2, columns 3 (k % 2) .. + 2)."""
    out = np.zeros((BLOCK, 3))
    out[:N64] = mono[_LOW]
    hi = np.zeros(2 * (BLOCK - N64) * 3, dtype=np.float32)
    hi[:3 * _N32] = mono[~_LOW].astype(np.float32).ravel()
    out[N64:] = hi.view(np.float64).reshape(-1, 3)
    return out


def _grid(rects: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The tensor grid z x z mapped onto every rectangle (a0, a1, b0, b1): (a, b), rows (rect, ia, ib)."""
    a = rects[:, 0, None] + (rects[:, 1] - rects[:, 0])[:, None] * 0.5 * (z[None, :] + 1.0)
    b = rects[:, 2, None] + (rects[:, 3] - rects[:, 2])[:, None] * 0.5 * (z[None, :] + 1.0)
    shape = (rects.shape[0], z.size, z.size)
    return np.broadcast_to(a[:, :, None], shape).ravel(), np.broadcast_to(b[:, None, :], shape).ravel()


def twists(side: int, rects: np.ndarray, z: np.ndarray, p0: float) -> np.ndarray:
    """Twists (vbx, vby, w) at the grid z x z of each rectangle: inner (side -1, rectangles
    (x0, x1, y0, y1) of the ICR, w = 1) or on an outer side 0-3 (+x, -x, +y, -y; rectangles
    (s0, s1, u0, u1): c w = (+-1, u) or (u, +-1) and w = s / p0)."""
    a, b = _grid(rects, z)
    if side < 0:
        cxw, cyw, w = a, b, np.ones(a.size)
    else:
        one = np.full(a.size, 1.0 if side in (0, 2) else -1.0)
        cxw, cyw = (one, b) if side < 2 else (b, one)
        w = a / p0
    return np.column_stack([cyw, -cxw, w])  # c w = (-vby, vbx)


#: a line of :func:`edge_lines`: (nx, ny, d, pieces (t0, t1, kappa))
Line = tuple[float, float, float, list[tuple[float, float, float]]]


def edge_lines(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, R: float) -> list[Line]:
    """The lines the uniformly loaded polygons of ``shapes[s0:s1]`` have edges on: (nx, ny, d, pieces),
    n the unit normal (nx > 0, or nx = 0 and ny > 0), d = n . p for p on the line (m, body frame from
    the centre of gravity), pieces (t0, t1, kappa) the edges on it, t along (-ny, nx) (m), kappa the
    polygon's load share over its area (1/m^2), negative where the polygon lies on the +n side
    (its outward normal is -n). Collinear edges (to 1e-12 R) share one line."""
    lines: list[Line] = []
    for k in range(s0, s1):
        if shapes[k, C.KIND] != C.POLYGON:
            continue
        v = geo[int(shapes[k, C.VERTEX_FIRST]):int(shapes[k, C.VERTEX_END]), :2]  # counter-clockwise
        kap = shapes[k, C.LOAD_SHARE] / shapes[k, C.AREA]
        for a, b in zip(v, np.roll(v, -1, axis=0)):
            L = math.hypot(b[0] - a[0], b[1] - a[1])
            if L == 0.0:
                continue
            nx, ny = (b[1] - a[1]) / L, -(b[0] - a[0]) / L  # outward
            sg = 1.0 if nx > 0.0 or (nx == 0.0 and ny > 0.0) else -1.0
            nx, ny = sg * nx, sg * ny
            d = nx * a[0] + ny * a[1]
            ta, tb = -ny * a[0] + nx * a[1], -ny * b[0] + nx * b[1]
            piece = (min(ta, tb), max(ta, tb), sg * kap)
            for ln in lines:
                if abs(ln[0] - nx) <= 1e-12 and abs(ln[1] - ny) <= 1e-12 and abs(ln[2] - d) <= 1e-12 * R:
                    ln[3].append(piece)
                    break
            else:
                lines.append((nx, ny, d, [piece]))
    return lines


def cell_line(lines: list[Line], rect: tuple[float, float, float, float],
              R: float) -> tuple[float, float, float, float]:
    """(nx, ny, d, kappa) of the one line of ``lines`` (:func:`edge_lines`) whose edges cross the ICR
    rectangle ``rect`` (x0, x1, y0, y1; m), widened by its own size on every side (a line just
    outside a cell slows its fit's convergence as much as one through it), with a net kappa (the
    sum over the pieces there) that is the same all along the widened rectangle's stretch of it and
    not zero; kappa = 0 if none, or if a vertex of the net outline lies in the widened rectangle
    (the subtracted term would then add a singularity the wrench does not have), or if two lines
    qualify."""
    x0, x1, y0, y1 = rect
    grow = max(x1 - x0, y1 - y0)
    x0, x1, y0, y1 = x0 - grow, x1 + grow, y0 - grow, y1 + grow
    eps = 1e-9 * R
    found = (0.0, 0.0, 0.0, 0.0)
    for nx, ny, d, pieces in lines:
        # the line's stretch in the closed rectangle: t along (-ny, nx) from the foot point d n
        lo, hi = -math.inf, math.inf
        for p, dp, a0, a1 in ((d * nx, -ny, x0, x1), (d * ny, nx, y0, y1)):
            if abs(dp) < 1e-15:
                if not a0 - eps <= p <= a1 + eps:
                    lo, hi = 1.0, -1.0
                continue
            ta, tb = sorted(((a0 - eps - p) / dp, (a1 + eps - p) / dp))
            lo, hi = max(lo, ta), min(hi, tb)
        if lo > hi:
            continue
        ends = sorted({t for t0, t1, _ in pieces for t in (t0, t1)})

        def net(t: float, pieces: list = pieces) -> float:
            return sum(kp for t0, t1, kp in pieces if t0 < t < t1)
        tol = 1e-9 * max(abs(kp) for _, _, kp in pieces)
        # a vertex of the net outline (the net kappa jumps there) in the rectangle: no single line
        jumps = [t for t in ends if abs(net(t - 1e-9 * R) - net(t + 1e-9 * R)) > tol]
        if any(lo - eps <= t <= hi + eps for t in jumps):
            return 0.0, 0.0, 0.0, 0.0
        # (the net at a point of the stretch that is no piece's end: at an end a piece does not count)
        cuts = sorted([lo, hi] + [t for t in ends if lo < t < hi])
        k = int(np.argmax(np.diff(cuts)))
        kap = net(0.5 * (cuts[k] + cuts[k + 1]))
        if abs(kap) <= tol:
            continue
        if found[3] != 0.0:
            return 0.0, 0.0, 0.0, 0.0
        found = (nx, ny, d, kap)
    return found


def singular_part(line: np.ndarray, cx: np.ndarray, cy: np.ndarray, R: float) -> np.ndarray:
    """The part of the wrench (force, torque / R; per unit load and mu g; spin > 0) that is not smooth
    across the line (nx, ny, d, kappa) (:func:`cell_line`), at the ICRs (cx, cy) (m): an edge of a
    uniformly loaded polygon contributes kappa h^2 log|h| (-ny, nx, (d - 2 h / 3) / R), h = d - n . c
    (from the closed forms of :mod:`rrbody.physics.polygon`: the fan triangle on the edge gives
    Int u dA a term -h^2 log|h| n, and Int |s - c| dA one -(h^3 / 3) log|h|). Rows (force x, force y,
    torque / R)."""
    nx, ny, d, kap = line
    h = d - nx * cx - ny * cy
    L = np.where(h == 0.0, 0.0, kap * h * h * np.log(np.where(h == 0.0, 1.0, np.abs(h))))
    return np.stack([-ny * L, nx * L, L * (d - 2.0 * h / 3.0) / R], axis=-1)


def fit_cells(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, R: float, side: int, rects: np.ndarray,
              p0: float, lines: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Fits of the footprint ``shapes[s0:s1]`` (reach R, m) on the rectangles ``rects`` of the inner
    ICR plane (side -1) or of an outer side (:func:`twists`): the packed triangular monomial
    coefficients (n, N (N + 1) / 2, 3; :func:`pack` makes a table block of each) from the exact values
    at their N x N Chebyshev points (torque divided by R), and whether each passes: the Chebyshev terms
    it drops (total degree > N - 1) sum to at most TAIL_TOL (|T_i T_j| <= 1: a bound on what dropping
    them changes), its last kept ones (total degree N - 1) are below TAIL_TOL (the series has
    converged), storing its terms of degree >= F32_FROM as float32 changes it by at most ROUND_TOL (the
    coefficients returned are so rounded), and it is within VALID_TOL of the exact values at the
    validation points. ``lines`` (inner rectangles only; a row (nx, ny, d, kappa) per rectangle, kappa
    = 0 for none, :func:`cell_line`): the polynomial fits the wrench less the line's
    :func:`singular_part` (smooth across the edge), and is validated with it added back."""
    n = rects.shape[0]
    scale = np.array([1.0, 1.0, 1.0 / R])
    tw = twists(side, rects, _Z, p0)
    F = _values(shapes, geo, s0, s1, tw).reshape(n, N, N, 3) * scale
    if lines is not None:
        F -= singular_part(lines.T[:, :, None, None], -tw[:, 1].reshape(n, N, N), tw[:, 0].reshape(n, N, N), R)
    c = np.einsum("ia,jb,nabk->nijk", _V, _V, F)
    dropped = np.abs(c[:, ~_KEEP, :]).sum(axis=1).max(axis=1)
    last = np.abs(c[:, _LAST, :]).max(axis=(1, 2))
    exact = np.einsum("pi,nijk,qj->npqk", _M, np.where(_KEEP[None, :, :, None], c, 0.0), _M)
    # the coefficients as the table stores them (pack): the validation below sees them
    mono = np.where(_F32[None, :, :, None], exact.astype(np.float32).astype(np.float64), exact)
    rounding = np.abs(mono - exact).sum(axis=(1, 2)).max(axis=1)
    ok = (dropped <= TAIL_TOL) & (last <= TAIL_TOL) & (rounding <= ROUND_TOL)
    idx = np.flatnonzero(ok)  # only these are validated (the build's largest cost is exact evaluations)
    if idx.size:
        tw = twists(side, rects[idx], _ZV, p0)
        G = _values(shapes, geo, s0, s1, tw).reshape(idx.size, VALID_PTS, VALID_PTS, 3) * scale
        if lines is not None:  # (c w = (-vby, vbx), w = 1)
            G -= singular_part(lines[idx].T[:, :, None, None], -tw[:, 1].reshape(G.shape[:3]),
                               tw[:, 0].reshape(G.shape[:3]), R)
        P = np.einsum("ap,npqk,bq->nabk", _XV, mono[idx], _XV)
        err = np.abs(P - G).max(axis=(1, 2, 3))
        ok[idx] = (err <= VALID_TOL) & np.isfinite(err)
    return mono[:, _KEEP, :], ok


def table_reach(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int) -> float:
    """R (m): the largest distance from the centre of gravity of a loaded point of ``shapes[s0:s1]``."""
    r = 0.0
    for k in range(s0, s1):
        row = shapes[k]
        kind = row[C.KIND]
        o = math.hypot(row[C.CENTRE_X], row[C.CENTRE_Y])
        if kind == C.POLYGON:
            v = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]
            r = max(r, float(np.max(np.hypot(v[:, 0], v[:, 1]))))
        elif kind == C.SAMPLED:
            q = geo[int(row[C.QUAD_FIRST]):int(row[C.QUAD_END]), :2]
            r = max(r, float(np.max(np.hypot(q[:, 0], q[:, 1]))))
        elif kind == C.ELLIPSE:
            r = max(r, o + max(row[C.RADIUS_A], row[C.RADIUS_B]))
        elif kind in (C.RING, C.HERTZ):
            r = max(r, o + row[C.RADIUS_A])
        else:
            r = max(r, o)
    return r


def deadband_factor(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, R: float, covered: np.ndarray,
                     p0: float) -> float:
    """K >= 1 such that whenever some part of the footprint is in its own dead band (footprint_wrench
    gives it zero) while the ICR lies where the table is used, max(|v|, |w| R) <= K v_eps.

    A polygon is at rest when |v| <= v_eps and |w| (|g| + r_g) <= v_eps: K >= R / (|g| + r_g). An
    ellipse, ring or Hertz patch (centre o, largest radius a) when its centre's speed and |w| a are
    <= v_eps: then |v| <= v_eps (1 + |o| / a) and |w| R <= v_eps R / a. A point (or a sample) p when
    its speed |w| |c - p| <= v_eps: with the ICR at least d from p (``covered``: the rectangles the
    table is used on, and the outer region |c|_inf >= p0), |w| <= v_eps / d, so K >= 1 + R / d."""
    K = 1.0
    pts = []
    for k in range(s0, s1):
        row = shapes[k]
        kind = row[C.KIND]
        ox, oy = row[C.CENTRE_X], row[C.CENTRE_Y]
        o = math.hypot(ox, oy)
        if kind == C.POLYGON:
            K = max(K, R / (o + row[C.VERTEX_RADIUS]))
        elif kind == C.ELLIPSE:
            a = max(row[C.RADIUS_A], row[C.RADIUS_B])
            K = max(K, 1.0 + o / a, R / a)
        elif kind in (C.RING, C.HERTZ):
            K = max(K, 1.0 + o / row[C.RADIUS_A], R / row[C.RADIUS_A])
        elif kind == C.POINT:
            pts.append((ox, oy))
        else:
            pts.extend(map(tuple, geo[int(row[C.QUAD_FIRST]):int(row[C.QUAD_END]), :2]))
    if pts:
        p = np.array(pts)
        d = p0 - np.max(np.abs(p), axis=1)
        if covered.size:
            dx = np.maximum(0.0, np.maximum(covered[None, :, 0] - p[:, 0, None], p[:, 0, None] - covered[None, :, 1]))
            dy = np.maximum(0.0, np.maximum(covered[None, :, 2] - p[:, 1, None], p[:, 1, None] - covered[None, :, 3]))
            d = np.minimum(d, np.hypot(dx, dy).min(axis=1))
        dmin = float(d.min())
        if not dmin > 0.0:
            return math.inf
        K = max(K, 1.0 + R / dmin)
    return K * (1.0 + 1e-9)  # rounding of the kernel's comparisons
