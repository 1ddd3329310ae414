"""A footprint's dry-friction wrench as a precomputed table: piecewise polynomials in the
instantaneous centre of rotation (ICR), with the exact formula where the table does not reach.

Per unit load and mu g the dry wrench of a footprint (:func:`rrbody.physics.contact.footprint_wrench`)
depends on the twist (v, w) only through the ICR c = z x v / w and the sign of w, and it is odd,
W(-v, -w) = -W(v, w): for one footprint it is a fixed function on a 2-D domain, tabulated once
(:func:`build_footprint_table`) and evaluated with one Horner sum (:func:`footprint_table_wrench`).
Body frame, origin at the centre of gravity G; R is the footprint's reach (m, the largest distance of
a loaded point from G); forces are dimensionless, torques are stored divided by R.

Coordinates (the spin made >= 0 by the odd symmetry; P0 = RHO R):

- inner: the square |c|_inf <= P0, CELLS x CELLS square cells; a cell whose fit fails is split into
  SPLIT x SPLIT sub-cells, up to LEVELS times; a cell still failing is *exact*;
- outer: beyond the square, on side k (+x, -x, +y, -y: the coordinate of c of largest magnitude and
  its sign), s = P0 / |c|_inf = P0 w / max(|vx|, |vy|) in [0, 1] (pure translation is s = 0: no
  division by w) and u = the other coordinate / |c|_inf in [-1, 1]; S_PANELS equal panels in s, each
  cut into NU equal u-panels, NU doubled at build time until every fit passes (at most MAX_U_PANELS; a
  panel still failing is exact), one NU for the whole table so that a panel is found by arithmetic.

Each cell or panel holds a polynomial of total degree <= N - 1 in its local coordinates (zx, zy) in
[-1, 1]^2 (zx along x or s), fitted at N x N Chebyshev points. A fit passes when the Chebyshev terms it
drops sum to at most TAIL_TOL, its last kept terms are below TAIL_TOL, and it is within VALID_TOL of
the exact formula at VALID_PTS x VALID_PTS equally spaced points of the cell (edges and corners
included). A polygon's wrench is non-analytic where the ICR crosses the footprint's boundary (terms
h^2 log|h| at a distance h from an edge): a cell on or next to one edge fits the wrench less that
edge's terms (:func:`rrbody.physics.footprint_fit.singular_part`, on the line
:func:`rrbody.physics.footprint_fit.cell_line` gives it), which the kernel adds back with one
logarithm; the cells at and next to a vertex fail and stay exact: there the kernel calls
:func:`footprint_wrench` itself. It does too in the dead band, wherever
some part could be slower than v_eps (max(|v|, |w| R) <= K v_eps, K from
:func:`rrbody.physics.footprint_fit.deadband_factor`). An exact cell's block is all NaN: the kernel
sums it like any other and tests the result, so no test stands between the look-up and the sum.

Layout of a table ``T`` (rows of 3; row offsets are relative to its first row, so tables can be
concatenated): row 0 (N, CELLS, P0); row 1 (R, K, number of rows); row 2 (NF / (2 P0), NU, first row
of the outer blocks); from row HEAD an index of the inner square at its finest resolution, NF x NF
entries (NF = CELLS SPLIT^LEVELS, x-major), each (first row of its cell's line record or 0, first
row of its cell's block, q) with q = 1 / (the cell's side in finest cells), so that the block's local
coordinates follow from the finest-cell position without a branch; then the blocks: one NaN block
(every exact inner cell's), 4 x S_PANELS x NU outer blocks (side +x, -x, +y, -y, then s-panel, then
u-panel; an exact panel's is NaN), then the inner cells' blocks; then the line records, two rows
each: (nx, ny, d) and kappa (-ny, nx, 1 / R). A block is BLOCK rows
(:func:`rrbody.physics.footprint_fit.pack`): the coefficients of zx^i zy^j (three components each) for
i = 0 .. N - 1 and j = 0 .. N - 1 - i, those of total degree below F32_FROM as float64 (N64 rows, in
that order), then the others as float32 (in that order, two triples to a row; read through the
table's float32 view). The rounding is part of each fit's test
(:data:`rrbody.physics.footprint_fit.ROUND_TOL`): the table's stated accuracy, 1e-10, holds as stored.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody._private import no_refcount
from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.footprint_fit import (
    BLOCK,
    N64,
    ROWS,
    N,
    cell_line,
    deadband_factor,
    edge_lines,
    fit_cells,
    pack,
    table_reach,
)
from rrbody.physics.icr_table import HUGE, TINY, twist_scale

__all__ = ["build_footprint_table", "footprint_table_wrench", "table_covers", "table_reach",
           "RHO", "CELLS", "SPLIT", "LEVELS", "S_PANELS", "MAX_U_PANELS", "HEAD"]

#: half-width of the inner square in units of the reach R
RHO: float = 1.5
#: inner cells per side of the square
CELLS: int = 24
#: sub-cells per side of an inner cell whose fit fails
SPLIT: int = 2
#: times a failing inner cell is split (a cell still failing at the finest level is exact)
LEVELS: int = 2
#: panels in s of each outer side
S_PANELS: int = 8
#: most u-panels per outer s-panel
MAX_U_PANELS: int = 64
HEAD: int = 3
#: finest inner cells per side (the index's resolution)
_NF: int = CELLS * SPLIT**LEVELS
#: just below 1: clamps a coordinate below the end of its range (the cell index stays in range)
_BELOW1: float = 1.0 - 2.0**-52


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
    if not R > 0.0:
        head = np.zeros((HEAD, 3))
        head[0] = (N, 0, 0.0)
        head[1] = (0.0, 1e300, HEAD)
        return head
    h = 2.0 * p0 / CELLS
    edges = -p0 + h * np.arange(CELLS + 1)
    top: list = [None] * (CELLS * CELLS)  # per cell: ("poly", block), ("exact",) or ("split", children)
    pending = [((edges[i], edges[i + 1], edges[j], edges[j + 1]), top, i * CELLS + j)
               for i in range(CELLS) for j in range(CELLS)]
    covered = []
    lines = edge_lines(shapes, geo, s0, s1, R)
    for level in range(LEVELS + 1):
        rects = np.array([p[0] for p in pending])
        sing = np.array([cell_line(lines, p[0], R) for p in pending])
        mono, ok = fit_cells(shapes, geo, s0, s1, R, -1, rects, p0, sing)
        nxt = []
        for (rect, cont, idx), m, good, line in zip(pending, mono, ok, sing):
            if good:
                cont[idx] = ("poly", m, line)
                covered.append(rect)
            elif level < LEVELS:
                kids: list = [None] * (SPLIT * SPLIT)
                cont[idx] = ("split", kids)
                x0, x1, y0, y1 = rect
                hx, hy = (x1 - x0) / SPLIT, (y1 - y0) / SPLIT
                nxt += [((x0 + a * hx, x0 + (a + 1) * hx, y0 + b * hy, y0 + (b + 1) * hy), kids, a * SPLIT + b)
                        for a in range(SPLIT) for b in range(SPLIT)]
            else:
                cont[idx] = ("exact",)
        pending = nxt
        if not pending:
            break
    # outer sides: the u-panels of each s-panel doubled until all pass; then every s-panel gets the
    # largest count (the kernel then finds a panel by arithmetic alone, no look-up)
    fits: dict[tuple[int, int], tuple[int, np.ndarray, np.ndarray]] = {}
    for side in range(4):
        for sp in range(S_PANELS):
            nu = 1
            while True:
                fits[side, sp] = (nu, *fit_cells(shapes, geo, s0, s1, R, side, _panels(sp, nu), p0))
                if fits[side, sp][2].all() or nu >= MAX_U_PANELS:
                    break
                nu *= 2
    nu = max(f[0] for f in fits.values())
    outer = []
    for (side, sp), (n, m, ok) in fits.items():
        if n != nu:
            m, ok = fit_cells(shapes, geo, s0, s1, R, side, _panels(sp, nu), p0)
        outer += [m[k] if ok[k] else None for k in range(nu)]
    K = deadband_factor(shapes, geo, s0, s1, R, np.array(covered).reshape(-1, 4), p0)
    return _assemble(top, outer, nu, R, p0, K)


def _panels(sp: int, nu: int) -> np.ndarray:
    """The rectangles (s0, s1, u0, u1) of s-panel ``sp`` cut into ``nu`` equal u-panels."""
    ue = np.linspace(-1.0, 1.0, nu + 1)
    return np.array([(sp / S_PANELS, (sp + 1) / S_PANELS, ue[k], ue[k + 1]) for k in range(nu)])


def _assemble(top: list, outer: list, nu: int, R: float, p0: float, K: float) -> np.ndarray:
    """The table array from the inner cells' trees and the outer panels (layout: module docstring)."""
    fine = SPLIT**LEVELS
    index = np.zeros((_NF, _NF, 3))  # per finest cell: (0, block, q); block 0 is the NaN block
    blocks: list[np.ndarray] = [np.full((BLOCK, 3), np.nan)]
    blocks += [np.full((BLOCK, 3), np.nan) if m is None else pack(m) for m in outer]

    lines: list[np.ndarray] = []  # the line records, each two rows

    def fill(node: tuple, i0: int, j0: int, size: int) -> None:
        if node[0] == "poly":
            at = 0.0
            nx, ny, d, kap = node[2]
            if kap != 0.0:
                at = float(len(lines) + 1)  # (0: none)
                lines.append(np.array([(nx, ny, d), (-kap * ny, kap * nx, kap / R)]))
            index[i0:i0 + size, j0:j0 + size] = (at, len(blocks), 1.0 / size)
            blocks.append(pack(node[1]))
        elif node[0] == "split":
            h = size // SPLIT
            for k, kid in enumerate(node[1]):
                fill(kid, i0 + (k // SPLIT) * h, j0 + (k % SPLIT) * h, h)

    for k, node in enumerate(top):
        fill(node, (k // CELLS) * fine, (k % CELLS) * fine, fine)
    first_block = HEAD + _NF * _NF
    first_line = first_block + len(blocks) * BLOCK
    nrows = first_line + 2 * len(lines)
    T = np.zeros((nrows, 3))
    T[0] = (N, CELLS, p0)
    T[1] = (R, K if math.isfinite(K) else 1e300, nrows)
    T[2] = (_NF / (2.0 * p0), nu, first_block + BLOCK)
    index[:, :, 1] = first_block + index[:, :, 1] * BLOCK
    index[:, :, 0] = np.where(index[:, :, 0] > 0.0, first_line + 2.0 * (index[:, :, 0] - 1.0), 0.0)
    T[HEAD:first_block] = index.reshape(-1, 3)
    T[first_block:first_line] = np.stack(blocks).reshape(-1, 3)
    if lines:
        T[first_line:] = np.concatenate(lines)
    return T


@njit(cache=True, inline="always", fastmath={"contract"})
def _row(T, F, b, k64, n64, k32, n32, zy):  # noqa: ANN001 (numba)
    """Horner sum in zy of one power of zx's coefficients (three components) in the block at row ``b``:
    its n32 float32 triples from triple k32 (the higher powers of zy; ``F`` the table's float32 view,
    :func:`rrbody.physics.footprint_fit.pack`), then its n64 float64 triples from row b + k64. ``b``
    is unsigned: numba then drops its negative-index test from every load (measured 27 -> 23 ns a
    block); the counts are constants, so the loops unroll."""
    k = k32 + n32 - 1
    r = b + np.uint64(N64 + k // 2)
    c = 3 * (k % 2)
    g0 = np.float64(F[r, c])
    g1 = np.float64(F[r, c + 1])
    g2 = np.float64(F[r, c + 2])
    for m in range(n32 - 2, -1, -1):
        k = k32 + m
        r = b + np.uint64(N64 + k // 2)
        c = 3 * (k % 2)
        g0 = g0 * zy + F[r, c]
        g1 = g1 * zy + F[r, c + 1]
        g2 = g2 * zy + F[r, c + 2]
    for m in range(n64 - 1, -1, -1):
        r = b + np.uint64(k64 + m)
        g0 = g0 * zy + T[r, 0]
        g1 = g1 * zy + T[r, 1]
        g2 = g2 * zy + T[r, 2]
    return g0, g1, g2


@njit(cache=True, inline="always", fastmath={"contract"})
def _block(T, F, base, zx, zy):  # noqa: ANN001 (numba)
    """The three components of the packed triangular block at row ``base`` at (zx, zy): the sums in
    zy of zx^i (i = 7 .. 0) two at a time, then Horner in zx. Written out for N = 8 (the loops over
    the powers, with their varying lengths, are then unrolled: measured 31 -> 23 ns)."""
    b = np.uint64(base)
    a0, a1, a2 = _row(T, F, b, ROWS[7][0], ROWS[7][1], ROWS[7][2], ROWS[7][3], zy)
    c0, c1, c2 = _row(T, F, b, ROWS[6][0], ROWS[6][1], ROWS[6][2], ROWS[6][3], zy)
    f0 = a0 * zx + c0
    f1 = a1 * zx + c1
    f2 = a2 * zx + c2
    a0, a1, a2 = _row(T, F, b, ROWS[5][0], ROWS[5][1], ROWS[5][2], ROWS[5][3], zy)
    c0, c1, c2 = _row(T, F, b, ROWS[4][0], ROWS[4][1], ROWS[4][2], ROWS[4][3], zy)
    f0 = (f0 * zx + a0) * zx + c0
    f1 = (f1 * zx + a1) * zx + c1
    f2 = (f2 * zx + a2) * zx + c2
    a0, a1, a2 = _row(T, F, b, ROWS[3][0], ROWS[3][1], ROWS[3][2], ROWS[3][3], zy)
    c0, c1, c2 = _row(T, F, b, ROWS[2][0], ROWS[2][1], ROWS[2][2], ROWS[2][3], zy)
    f0 = (f0 * zx + a0) * zx + c0
    f1 = (f1 * zx + a1) * zx + c1
    f2 = (f2 * zx + a2) * zx + c2
    a0, a1, a2 = _row(T, F, b, ROWS[1][0], ROWS[1][1], ROWS[1][2], ROWS[1][3], zy)
    c0, c1, c2 = _row(T, F, b, ROWS[0][0], ROWS[0][1], ROWS[0][2], ROWS[0][3], zy)
    f0 = (f0 * zx + a0) * zx + c0
    f1 = (f1 * zx + a1) * zx + c1
    f2 = (f2 * zx + a2) * zx + c2
    return f0, f1, f2


@njit(cache=True, inline="always")
def _locate(T, t0, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """(first row of the block or -1 for the exact formula, zx, zy, sign of the spin) of a twist.

    Branch-light: the spin's sign and the outer side are selected without a branch (a random side
    mispredicted: 100 ns a call for the active benchmark's twists, against 72 for those near the body
    and 58 for the far ones alone, before); only inner against outer branches (84 % outer there)."""
    R = T[t0 + 1, 0]
    kv = T[t0 + 1, 1] * v_eps
    if not abs(vbx) + abs(vby) + abs(w) < math.inf or R == 0.0:  # NaN or inf: never an index from it
        return -1, 0.0, 0.0, 1.0, 0, 0.0, 0.0
    big = max(abs(vbx), abs(vby), abs(w) * R)
    if big < TINY or big > HUGE:
        # (a body left with a velocity of 1e-166 m/s): the dead band, or else, the wrench depending on
        # the twist's direction only, a scaling by a power of two (exact): no square or reciprocal
        # below underflows or overflows
        if 2.0 * big <= kv or big == 0.0:
            return -1, 0.0, 0.0, 1.0, 0, 0.0, 0.0
        k = twist_scale(big)
        vbx *= k
        vby *= k
        w *= k
    elif vbx * vbx + vby * vby <= kv * kv and abs(w) * R <= kv:
        return -1, 0.0, 0.0, 1.0, 0, 0.0, 0.0
    # spin >= 0 by the odd symmetry; (cxw, cyw) = c w
    sg = 1.0 if w >= 0.0 else -1.0
    cxw = -sg * vby
    cyw = sg * vbx
    ww = sg * w
    p0 = T[t0, 2]
    P = p0 * ww
    ax = abs(cxw)
    ay = abs(cyw)
    m = max(ax, ay)
    if m <= P:
        # inner: the finest cell (_NF per side) holding c; its record gives the block and the block
        # cell's size (q = 1 / its side in finest cells), hence the local coordinates
        inv = 1.0 / ww
        cx = cxw * inv
        cy = cyw * inv
        ih = T[t0 + 2, 0]
        gx = min(max((cx + p0) * ih, 0.0), _NF * _BELOW1)
        gy = min(max((cy + p0) * ih, 0.0), _NF * _BELOW1)
        rec = t0 + HEAD + int(gx) * _NF + int(gy)
        q = T[rec, 2]
        tx = gx * q
        ty = gy * q
        return t0 + int(T[rec, 1]), 2.0 * (tx - int(tx)) - 1.0, 2.0 * (ty - int(ty)) - 1.0, sg, int(T[rec, 0]), cx, cy
    # outer: side (+x, -x, +y, -y: no branch), s = P0 / |c|_inf and u; every s-panel has nu u-panels
    inv = 1.0 / m
    xs = ax >= ay
    u = (cyw if xs else cxw) * inv
    side = (0 if xs else 2) + (1 if (cxw if xs else cyw) < 0.0 else 0)
    hs = P * inv * S_PANELS
    sp = min(int(hs), S_PANELS - 1)
    nu = T[t0 + 2, 1]
    hu = min(max((u + 1.0) * (0.5 * nu), 0.0), nu * _BELOW1)
    k = int(hu)
    base = int(T[t0 + 2, 2]) + ((side * S_PANELS + sp) * int(nu) + k) * BLOCK
    return t0 + base, 2.0 * (hs - sp) - 1.0, 2.0 * (hu - k) - 1.0, sg, 0, 0.0, 0.0


@njit(cache=True)
def table_covers(T, t0, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """Whether :func:`footprint_table_wrench` evaluates this twist from the table (False: the exact formula)."""
    base = _locate(T, t0, vbx, vby, w, v_eps)[0]
    return base >= 0 and T[base, 0] == T[base, 0]  # an exact cell's block is NaN




@njit(cache=True, fastmath={"contract"}, **no_refcount())
def footprint_table_wrench(T, t0, shapes, geo, s0, s1, vbx, vby, w, v_eps):  # noqa: ANN001 (numba)
    """(fx, fy, tq): the dry wrench of the footprint ``shapes[s0:s1]`` per unit load and mu g, as
    :func:`footprint_wrench` gives it (force in the body frame, dimensionless; torque about the centre
    of gravity, m), at the centre-of-gravity velocity (vbx, vby) (m/s, body frame) and spin w (rad/s),
    from its table ``T[t0:]`` (:func:`build_footprint_table`), or from footprint_wrench itself where
    the table does not reach (cells on the footprint's boundary, the dead band below ``v_eps`` m/s).
    Allocates nothing."""
    base, zx, zy, sg, line, cx, cy = _locate(T, t0, vbx, vby, w, v_eps)
    if base < 0:
        return footprint_wrench(shapes, geo, s0, s1, vbx, vby, w, v_eps)
    # (the float32 view costs nothing here: no reference is counted, no_refcount)
    f0, f1, f2 = _block(T, T.view(np.float32), base, zx, zy)
    if f0 != f0:  # an exact cell (its block is NaN): no test before the sum, which then starts sooner
        return footprint_wrench(shapes, geo, s0, s1, vbx, vby, w, v_eps)
    if line > 0:  # a cell on an edge: its polynomial is the wrench less the edge's h^2 log|h| terms
        r = t0 + line
        d = T[r, 2]
        h = d - T[r, 0] * cx - T[r, 1] * cy
        if h != 0.0:
            L = h * h * math.log(abs(h))
            f0 += L * T[r + 1, 0]
            f1 += L * T[r + 1, 1]
            f2 += L * T[r + 1, 2] * (d - 2.0 * h / 3.0)
    return sg * f0, sg * f1, sg * T[t0 + 1, 0] * f2
