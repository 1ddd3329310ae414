"""A footprint's dry-friction wrench as a precomputed table: piecewise polynomials in the
instantaneous centre of rotation (ICR), with the exact formula where the table does not reach.

Per unit load and mu g the dry wrench of a footprint (:func:`rrbody.physics.contact.footprint_wrench`)
depends on the twist (v, w) only through the ICR c = z x v / w and the sign of w, and it is odd:
W(-v, -w) = -W(v, w). So for one footprint it is one fixed function on a 2-D domain, tabulated once
(:func:`build_footprint_table`) and evaluated with one nested Horner sum (:func:`footprint_table_wrench`).
The body frame is the footprint's (origin at the centre of gravity G); R is its reach (largest
distance of a loaded point from G, m); forces are dimensionless, torques are stored divided by R.

Coordinates (spin made >= 0 by the odd symmetry; P0 = RHO R):

- inner: the square |c|_inf <= P0, a uniform grid of CELLS x CELLS square cells, each a tensor
  polynomial of degree N - 1 in the cell's local coordinates (zx, zy) in [-1, 1]^2; a cell whose fit
  fails is split once into SPLIT x SPLIT sub-cells, and a sub-cell whose fit fails is *exact*;
- outer: beyond the square, on side k (+x, -x, +y, -y: the coordinate of largest magnitude and its
  sign), s = P0 / |c|_inf = P0 w / max(|vx|, |vy|) in [0, 1] (pure translation is s = 0, no division
  by w) and u = the other coordinate / |c|_inf in [-1, 1]: S_PANELS equal panels in s, each with its
  own number of equal u-panels (doubled at build time until every fit passes, at most MAX_U_PANELS;
  a panel still failing is exact).

A fit passes when its Chebyshev tail (every coefficient of degree N - 2 or N - 1 in either variable)
is below TAIL_TOL and the polynomial agrees with the exact formula to VALID_TOL at a grid of
VALID_PTS x VALID_PTS equally spaced points of the cell, its edges and corners included. A polygon's
wrench is non-analytic where the ICR crosses the footprint's boundary (h^2 log|h| at a distance h from
an edge), so the cells on and next to the boundary fail and stay exact: there the kernel calls
:func:`footprint_wrench` itself. It does too in the dead band: wherever a part could be slower than
v_eps (a bound K v_eps on max(|v|, |w| R) computed at build time, see :func:`_deadband_factor`).

Layout of a table ``T`` (rows of 3, offsets relative to its first row, so tables can be concatenated):
row 0 (N, CELLS, P0); row 1 (R, K, number of rows); row 2 (CELLS / (2 P0), S_PANELS, SPLIT);
HEAD.. : CELLS x CELLS inner records (row-major in x then y); then 4 x S_PANELS outer rows
(u-panels, first record row, 0); then the other records; then the coefficient blocks (N x N rows,
row i N + j holding the three components' coefficients of zx^i zy^j). A record is
(status, offset, 0): status 0 exact, 1 a polynomial whose block starts at ``offset``, 2 split into
SPLIT x SPLIT sub-records starting at ``offset``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench

__all__ = ["build_footprint_table", "footprint_table_wrench", "table_covers", "table_reach", "N", "RHO", "CELLS", "SPLIT",
           "S_PANELS", "MAX_U_PANELS", "TAIL_TOL", "VALID_TOL", "VALID_PTS"]

#: Chebyshev points per direction of every cell (polynomial degree N - 1); a compile-time constant of the kernel
N: int = 8
#: half-width of the inner square in units of the reach R
RHO: float = 1.5
#: inner cells per side of the square
CELLS: int = 24
#: sub-cells per side of an inner cell whose fit fails
SPLIT: int = 2
#: panels in s of each outer side
S_PANELS: int = 8
#: most u-panels per outer s-panel
MAX_U_PANELS: int = 64
#: largest Chebyshev tail coefficient a fit may have (force, and torque / R: dimensionless); half the
#: accuracy target 1e-10 (the coefficients beyond the fit decay geometrically below the tail's)
TAIL_TOL: float = 5e-11
#: largest difference from the exact formula at the validation points (force, torque / R); half the target
VALID_TOL: float = 5e-11
#: validation points per direction of a cell (equally spaced, edges and corners included)
VALID_PTS: int = N + 3
HEAD: int = 3
_EXACT, _POLY, _SPLIT = 0.0, 1.0, 2.0


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


def _cheb() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Chebyshev points of the first kind on [-1, 1], the values -> coefficients matrix and the
    Chebyshev -> monomial matrix (M[p, i]: the coefficient of z^p in T_i)."""
    k = np.arange(N)
    th = np.pi * (k + 0.5) / N
    z = np.cos(th)
    V = np.cos(np.outer(k, th)) * (2.0 / N)
    V[0] *= 0.5
    M = np.zeros((N, N))
    for j in range(N):
        e = np.zeros(N)
        e[j] = 1.0
        c = np.polynomial.chebyshev.cheb2poly(e)
        M[: c.size, j] = c
    return z, V, M


_Z, _V, _M = _cheb()
_ZV = np.linspace(-1.0, 1.0, VALID_PTS)
_XV = _ZV[:, None] ** np.arange(N)[None, :]  # (VALID_PTS, N) monomials at the validation points
#: the tail: every Chebyshev coefficient of degree N - 2 or N - 1 in either variable
_TAIL = np.maximum.outer(np.arange(N), np.arange(N)) >= N - 2


def _twists_inner(rects: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Twists (vbx, vby, w = 1) putting the ICR at the tensor grid z x z of every rectangle
    (x0, x1, y0, y1) of ``rects``: rows ordered (rect, ix, iy)."""
    x = rects[:, 0, None] + (rects[:, 1] - rects[:, 0])[:, None] * 0.5 * (z[None, :] + 1.0)
    y = rects[:, 2, None] + (rects[:, 3] - rects[:, 2])[:, None] * 0.5 * (z[None, :] + 1.0)
    cx = np.broadcast_to(x[:, :, None], (rects.shape[0], z.size, z.size)).ravel()
    cy = np.broadcast_to(y[:, None, :], (rects.shape[0], z.size, z.size)).ravel()
    # spin 1: c = (-vby, vbx)
    return np.column_stack([cy, -cx, np.ones(cx.size)])


def _twists_outer(side: int, rects: np.ndarray, z: np.ndarray, p0: float) -> np.ndarray:
    """Twists on outer ``side`` at the grid z x z of every (s0, s1, u0, u1) rectangle: with
    m = max(|c_x|, |c_y|) w = 1, the ICR direction (1, u) (side +x) and so on, and w = s / p0."""
    s = rects[:, 0, None] + (rects[:, 1] - rects[:, 0])[:, None] * 0.5 * (z[None, :] + 1.0)
    u = rects[:, 2, None] + (rects[:, 3] - rects[:, 2])[:, None] * 0.5 * (z[None, :] + 1.0)
    ss = np.broadcast_to(s[:, :, None], (rects.shape[0], z.size, z.size)).ravel()
    uu = np.broadcast_to(u[:, None, :], (rects.shape[0], z.size, z.size)).ravel()
    sgn = 1.0 if side in (0, 2) else -1.0
    if side < 2:
        cxw, cyw = np.full(ss.size, sgn), uu
    else:
        cxw, cyw = uu, np.full(ss.size, sgn)
    return np.column_stack([cyw, -cxw, ss / p0])


def _fit(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, R: float, tw_nodes: np.ndarray,
         tw_valid: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Monomial coefficients (n, N, N, 3) of n cells from the exact values at their Chebyshev
    nodes, and whether each passes (tail and validation)."""
    scale = np.array([1.0, 1.0, 1.0 / R])
    F = _values(shapes, geo, s0, s1, tw_nodes).reshape(n, N, N, 3) * scale
    c = np.einsum("ia,jb,nabk->nijk", _V, _V, F)
    tail = np.abs(c[:, _TAIL, :]).max(axis=(1, 2))
    mono = np.einsum("pi,nijk,qj->npqk", _M, c, _M)
    G = _values(shapes, geo, s0, s1, tw_valid).reshape(n, VALID_PTS, VALID_PTS, 3) * scale
    P = np.einsum("ap,npqk,bq->nabk", _XV, mono, _XV)
    err = np.abs(P - G).max(axis=(1, 2, 3))
    ok = (tail <= TAIL_TOL) & (err <= VALID_TOL) & np.isfinite(err)
    return mono, ok


def table_reach(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int) -> float:
    """R (m): the largest distance from the centre of gravity of a loaded point of ``shapes[s0:s1]``."""
    r = 0.0
    for k in range(s0, s1):
        row = shapes[k]
        kind = row[C.KIND]
        o = math.hypot(row[C.CX], row[C.CY])
        if kind == C.POLYGON:
            v = geo[int(row[C.V0]):int(row[C.V1]), :2]
            r = max(r, float(np.max(np.hypot(v[:, 0], v[:, 1]))))
        elif kind == C.SAMPLED:
            q = geo[int(row[C.Q0]):int(row[C.Q1]), :2]
            r = max(r, float(np.max(np.hypot(q[:, 0], q[:, 1]))))
        elif kind == C.ELLIPSE:
            r = max(r, o + max(row[C.RA], row[C.RB]))
        elif kind in (C.RING, C.HERTZ):
            r = max(r, o + row[C.RA])
        else:
            r = max(r, o)
    return r


def _deadband_factor(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int, R: float, covered: np.ndarray,
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
        ox, oy = row[C.CX], row[C.CY]
        o = math.hypot(ox, oy)
        if kind == C.POLYGON:
            K = max(K, R / (o + row[C.RAD]))
        elif kind == C.ELLIPSE:
            a = max(row[C.RA], row[C.RB])
            K = max(K, 1.0 + o / a, R / a)
        elif kind in (C.RING, C.HERTZ):
            K = max(K, 1.0 + o / row[C.RA], R / row[C.RA])
        elif kind == C.POINT:
            pts.append((ox, oy))
        else:
            pts.extend(map(tuple, geo[int(row[C.Q0]):int(row[C.Q1]), :2]))
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


def build_footprint_table(shapes: np.ndarray, geo: np.ndarray, s0: int, s1: int) -> np.ndarray:
    """The wrench table (rows of 3, float64) of the footprint ``shapes[s0:s1]`` (rows of
    :mod:`rrbody.physics.contact`, geometry ``geo``, body frame from the centre of gravity, m),
    built from exact :func:`footprint_wrench` values; deterministic. Evaluate it with
    :func:`footprint_table_wrench`. A footprint of reach 0 (one point at G) gets a table that always
    defers to the exact formula."""
    shapes = np.ascontiguousarray(shapes, dtype=np.float64)
    geo = np.ascontiguousarray(geo, dtype=np.float64)
    if shapes.ndim != 2 or shapes.shape[1] < C.N_SHAPE:
        raise ValueError(f"shapes must be a 2-D array of rows with {C.N_SHAPE} columns, got shape {shapes.shape}")
    if not 0 <= s0 < s1 <= shapes.shape[0]:
        raise ValueError(f"s0, s1 must satisfy 0 <= s0 < s1 <= {shapes.shape[0]} (rows of shapes), got {s0}, {s1}")
    s0, s1 = int(s0), int(s1)
    R = table_reach(shapes, geo, s0, s1)
    p0 = RHO * R
    records: list[tuple[float, float]] = []  # (status, block index or record index); resolved below
    blocks: list[np.ndarray] = []
    if not R > 0.0:
        head = np.zeros((HEAD, 3))
        head[0] = (N, 0, 0.0)
        head[1] = (0.0, 1e300, HEAD)
        return head
    h = 2.0 * p0 / CELLS
    edges = -p0 + h * np.arange(CELLS + 1)
    rects = np.array([(edges[i], edges[i + 1], edges[j], edges[j + 1]) for i in range(CELLS) for j in range(CELLS)])
    n = rects.shape[0]
    mono, ok = _fit(shapes, geo, s0, s1, R, _twists_inner(rects, _Z), _twists_inner(rects, _ZV), n)
    inner = [None] * n  # per cell: block index, or list of sub-cell block indices (None: exact)
    covered = [rects[ok]]
    bad = np.flatnonzero(~ok)
    if bad.size:
        sub = []
        for i in bad:
            x0, x1, y0, y1 = rects[i]
            hx, hy = (x1 - x0) / SPLIT, (y1 - y0) / SPLIT
            sub += [(x0 + a * hx, x0 + (a + 1) * hx, y0 + b * hy, y0 + (b + 1) * hy)
                    for a in range(SPLIT) for b in range(SPLIT)]
        sub = np.array(sub)
        smono, sok = _fit(shapes, geo, s0, s1, R, _twists_inner(sub, _Z), _twists_inner(sub, _ZV), sub.shape[0])
        covered.append(sub[sok])
    for i in range(n):
        if ok[i]:
            inner[i] = len(blocks)
            blocks.append(mono[i])
    if bad.size:
        q = SPLIT * SPLIT
        for t, i in enumerate(bad):
            kids = []
            for r in range(q):
                if sok[t * q + r]:
                    kids.append(len(blocks))
                    blocks.append(smono[t * q + r])
                else:
                    kids.append(None)
            inner[i] = kids if any(k is not None for k in kids) else None
    # outer sides: u-panels doubled until all pass
    outer = []  # per (side, s-panel): list of block indices (None: exact)
    for side in range(4):
        for sp in range(S_PANELS):
            sa, sb = sp / S_PANELS, (sp + 1) / S_PANELS
            nu = 1
            while True:
                ue = np.linspace(-1.0, 1.0, nu + 1)
                pr = np.array([(sa, sb, ue[k], ue[k + 1]) for k in range(nu)])
                m, pok = _fit(shapes, geo, s0, s1, R, _twists_outer(side, pr, _Z, p0), _twists_outer(side, pr, _ZV, p0), nu)
                if pok.all() or nu >= MAX_U_PANELS:
                    break
                nu *= 2
            ids = []
            for k in range(nu):
                if pok[k]:
                    ids.append(len(blocks))
                    blocks.append(m[k])
                else:
                    ids.append(None)
            outer.append(ids)
    # assemble: header, inner records, outer rows, other records, blocks
    n_inner = CELLS * CELLS
    n_outer = 4 * S_PANELS
    extra = sum(len(x) for x in inner if isinstance(x, list)) + sum(len(x) for x in outer)
    first_block = HEAD + n_inner + n_outer + extra
    nrows = first_block + len(blocks) * N * N
    T = np.zeros((nrows, 3))
    K = _deadband_factor(shapes, geo, s0, s1, R, np.concatenate(covered), p0)
    T[0] = (N, CELLS, p0)
    T[1] = (R, K if math.isfinite(K) else 1e300, nrows)
    T[2] = (CELLS / (2.0 * p0), S_PANELS, SPLIT)

    def rec(b: int | None) -> tuple[float, float, float]:
        return (_EXACT, 0.0, 0.0) if b is None else (_POLY, first_block + b * N * N, 0.0)

    nxt = HEAD + n_inner + n_outer
    for i, x in enumerate(inner):
        if isinstance(x, list):
            T[HEAD + i] = (_SPLIT, nxt, 0.0)
            for b in x:
                T[nxt] = rec(b)
                nxt += 1
        else:
            T[HEAD + i] = rec(x)
    for k, ids in enumerate(outer):
        T[HEAD + n_inner + k] = (len(ids), nxt, 0.0)
        for b in ids:
            T[nxt] = rec(b)
            nxt += 1
    if blocks:
        T[first_block:] = np.stack(blocks).reshape(-1, 3)
    return T


@njit(cache=True, inline="always")
def _locate(T, t0, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """(record row or -1 for the exact formula, zx, zy, sign of the spin) of a twist."""
    R = T[t0 + 1, 0]
    kv = T[t0 + 1, 1] * v_eps
    if (vbx * vbx + vby * vby <= kv * kv and abs(w) * R <= kv) or R == 0.0:
        return -1, 0.0, 0.0, 1.0
    # spin >= 0 by the odd symmetry; (cxw, cyw) = c w
    if w < 0.0:
        sg = -1.0
        cxw = vby
        cyw = -vbx
        ww = -w
    else:
        sg = 1.0
        cxw = -vby
        cyw = vbx
        ww = w
    p0 = T[t0, 2]
    P = p0 * ww
    ax = abs(cxw)
    ay = abs(cyw)
    m = max(ax, ay)
    if m <= P:
        inv = 1.0 / ww
        ih = T[t0 + 2, 0]
        gx = (cxw * inv + p0) * ih
        gy = (cyw * inv + p0) * ih
        i = min(max(int(gx), 0), CELLS - 1)
        j = min(max(int(gy), 0), CELLS - 1)
        zx = 2.0 * (gx - i) - 1.0
        zy = 2.0 * (gy - j) - 1.0
        rec = t0 + HEAD + i * CELLS + j
        while T[rec, 0] == _SPLIT:
            hx = (zx + 1.0) * (0.5 * SPLIT)
            hy = (zy + 1.0) * (0.5 * SPLIT)
            a = min(int(hx), SPLIT - 1)
            b = min(int(hy), SPLIT - 1)
            zx = 2.0 * (hx - a) - 1.0
            zy = 2.0 * (hy - b) - 1.0
            rec = t0 + int(T[rec, 1]) + a * SPLIT + b
    else:
        inv = 1.0 / m
        s = P * inv
        if ax >= ay:
            side = 0 if cxw > 0.0 else 1
            u = cyw * inv
        else:
            side = 2 if cyw > 0.0 else 3
            u = cxw * inv
        hs = s * S_PANELS
        sp = min(int(hs), S_PANELS - 1)
        zx = 2.0 * (hs - sp) - 1.0
        orow = t0 + HEAD + CELLS * CELLS + side * S_PANELS + sp
        nu = T[orow, 0]
        hu = (u + 1.0) * (0.5 * nu)
        k = min(int(hu), int(nu) - 1)
        zy = 2.0 * (hu - k) - 1.0
        rec = t0 + int(T[orow, 1]) + k
    if T[rec, 0] != _POLY:
        return -1, zx, zy, sg
    return t0 + int(T[rec, 1]), zx, zy, sg


@njit(cache=True)
def table_covers(T, t0, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """Whether :func:`footprint_table_wrench` evaluates this twist from the table (False: the exact formula)."""
    return _locate(T, t0, vbx, vby, w, v_eps)[0] >= 0


@njit(cache=True, fastmath={"contract"})
def footprint_table_wrench(T, t0, shapes, geo, s0, s1, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """(fx, fy, tq): the dry wrench of the footprint ``shapes[s0:s1]`` per unit load and mu g, as
    :func:`footprint_wrench` gives it (force in the body frame, dimensionless; torque about the centre
    of gravity, m), at the centre-of-gravity velocity (vbx, vby) (m/s, body frame) and spin w (rad/s),
    from its table ``T[t0:]`` (:func:`build_footprint_table`), or from footprint_wrench itself where
    the table does not reach (cells on the footprint's boundary, the dead band below ``v_eps`` m/s).
    Allocates nothing."""
    base, zx, zy, sg = _locate(T, t0, vbx, vby, w, v_eps)
    if base < 0:
        return footprint_wrench(shapes, geo, s0, s1, vbx, vby, w, v_eps)
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    for i in range(N - 1, -1, -1):
        r = base + i * N
        g0 = 0.0
        g1 = 0.0
        g2 = 0.0
        for j in range(N - 1, -1, -1):
            g0 = g0 * zy + T[r + j, 0]
            g1 = g1 * zy + T[r + j, 1]
            g2 = g2 * zy + T[r + j, 2]
        f0 = f0 * zx + g0
        f1 = f1 * zx + g1
        f2 = f2 * zx + g2
    return sg * f0, sg * f1, sg * T[t0 + 1, 0] * f2
