"""Precomputed dry-friction wrench of a homogeneous disk or ellipse: a piecewise polynomial table.

The dry wrench depends on the motion only through the instantaneous centre of rotation (ICR) and
the sign of the spin, so per unit ``mu g`` it is a function of the ICR alone, one function per
aspect ratio. This module tabulates it once per ratio (from :func:`rrbody.physics.icr.icr_wrench`
at high node count) and evaluates it with a few hundred multiply-adds and no transcendental call.

Coordinates (scaled body frame x/a, y/b, where the ellipse is the unit disk; Q the scaled ICR,
r = |Q|; lengths in units of L = max(a, b), so force is scale-free and torque scales with L):

- radial: t = r inside (r < 1), t = 1/r outside (translation, r -> inf, is the finite end t = 0),
  and x = 1 - t in (0, 1]. The wrench is non-analytic only at the boundary x -> 0, through terms
  like x log x; the panels are the octaves [2^-(o+1), 2^-o) of x (found from the float's exponent,
  ``math.frexp``), each split into k_o equal sub-panels, k_o chosen so the log-type term stays below
  ~1e-12 on a degree-(NT-1) polynomial and doubled at build time while the fit's radial tail exceeds
  ``TAIL_TOL`` (the far field of a thin ellipse); x below 2^-E is clamped (the term there is < 2e-12).
- angle (ellipse only): the reflections x -> -x, y -> -y map Q into the first quadrant
  (F_x changes sign with y, F_y with x, the torque keeps its sign), and the quadrant is split into
  the octants |Q_y| <= |Q_x| and |Q_y| > |Q_x| with coordinate m = min/max in [0, 1] (no atan2).
  Each octant of each radial panel has its own number of equal m-panels, doubled at build time until
  the Chebyshev tail of the fit is below ``TAIL_TOL`` (thin ellipses have near-singularities in the
  angle at distance ~atanh(b/a)).
- a disk is rotationally symmetric: its table is 1-D in t (force magnitude and torque), the force
  opposing v_cm.

Each panel holds NT x NM coefficient triples (F_x, F_y, tau per unit mu g and mu g L, body frame,
spin > 0) of a monomial in the local coordinates z_t, z_m in [-1, 1], evaluated by nested Horner.
Where the fit allows (the Chebyshev coefficients of total degree > NTRI sum to at most TAIL_TOL
in every panel of the octant), an octant's panels keep only the triangle i + j <= NTRI, 45 terms
instead of 100, which roughly halves the evaluation. Share of the m-panels that are triangles:
100 % at b/a = 0.82, 99 % at 0.54, 95 % at 1/3, 89 % at 1/4, 74 % at 1/9, 79 % at 1/19.
A negative spin flips the wrench (W(-v, -Omega) = -W(v, Omega), the ICR is unchanged).
:func:`table_wrench_body` works in the body frame (no trigonometric call); the area methods' one
world-frame wrapper is :func:`rrbody.physics.effects.areas.body_wrench`. Pure translation and the zero-speed dead band are handled exactly as
:func:`icr_wrench_body` does; the viscous law is linear and exact, so it never uses the table.

Layout of the table array ``S`` (rows of 3, what the kernels receive as the area-sample array):
row 0 (kind 1 disk / 2 ellipse, NT, NM; a disk: its radial profile's near-translation factor
<|s|^2 - (s . e)^2> / a^2 instead of NM); row 1 (b/a, E octaves, radial panels inside);
rows 2 .. 2+2E-1 per side (inside first) and octave o (k_o, index of its first radial panel, 0);
then one row per radial panel (base row of octant 0, m-panels of octant 0, m-panels of octant 1,
each count negative if that octant's panels are triangles; a disk: base row only); then the
coefficient rows, NT x NM per panel either way (octant 1's panels follow octant 0's).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import njit, prange

from rrbody.model.checks import check_positive
from rrbody.physics.icr import TRANSLATION_EPS, icr_wrench_body, translation_wrench
from rrbody.physics.radial import hertz_wrench, ring_wrench

__all__ = ["build_table", "build_radial_table", "PROFILES", "table_wrench_body", "cheb", "twist_scale", "TINY", "HUGE",
           "NT", "NM", "NTRI", "OCTAVES", "TAIL_TOL", "BUILD_NODES"]

#: coefficients per panel along t (degree NT - 1; even: the disk's sum takes them in pairs) and along m (degree NM - 1)
NT: int = 10
NM: int = 10
#: octaves of x = 1 - t that get panels; below 2^-OCTAVES (x log x < 2e-12) x is clamped
OCTAVES: int = 44
#: acceptance threshold on the last two Chebyshev coefficients of an angle fit (units mu g, mu g L)
TAIL_TOL: float = 1e-11
#: Gauss nodes per panel of the ICR quadrature that builds the table (self-converged to ~1e-14)
BUILD_NODES: int = 64
#: most m-panels per octant before the build gives up refining (the test reports the error)
MAX_M_PANELS: int = 128
#: total degree of the triangular blocks: a block whose Chebyshev coefficients of total degree
#: i + j > NTRI sum (in absolute value, a bound on what dropping them changes) to at most TAIL_TOL
#: keeps only i + j <= NTRI: 45 terms instead of NT x NM = 100. NTRI = 8 gave the fewest terms on
#: average over aspect ratios 0.1 - 0.9 among 8, 9 and 10 (measured when it was chosen).
NTRI: int = 8
_HEADER = 2
#: twists whose largest component (m/s) lies outside [TINY, HUGE] are scaled by a power of two first
#: (here and in :mod:`rrbody.physics.footprint_table`): the dry wrench depends on their direction only
TINY, HUGE = 2.0**-450, 2.0**450
_SCALE_UP, _SCALE_DOWN = 2.0**500, 2.0**-500


@njit(cache=True, inline="always")
def twist_scale(big):  # noqa: ANN001, ANN202 (numba)
    """A power of two k (exact to multiply by) with k big in [TINY, HUGE], for big > 0 finite
    (a subnormal takes up to three steps)."""
    k = 1.0
    while big < TINY:
        big *= _SCALE_UP
        k *= _SCALE_UP
    while big > HUGE:
        big *= _SCALE_DOWN
        k *= _SCALE_DOWN
    return k


def _sub_panels(o: int) -> int:
    """Sub-panels of octave o: the log term's size there, 2^-o (1 + o ln 2), times the Chebyshev
    decay rho^-NT of the sub-panel nearest x = 0 (rho = d + sqrt(d^2 - 1), d = 2 k + 1), kept < 1e-12."""
    amp = 2.0 ** -o * (1.0 + o * math.log(2.0))
    for k in (1, 2, 4, 8):
        d = 2.0 * k + 1.0
        if amp * (d + math.sqrt(d * d - 1.0)) ** -NT < 1e-12:
            return k
    return 16


@njit(cache=True, parallel=True)
def _values(a, b, rs, ms, octant):  # noqa: ANN001
    """Wrench (body frame, mu g = 1, spin = 1) at every scaled ICR (r, m) of the grid rs x ms."""
    out = np.empty((rs.shape[0], ms.shape[0], 3))
    for i in prange(rs.shape[0]):
        for j in range(ms.shape[0]):
            c = 1.0 / math.sqrt(1.0 + ms[j] * ms[j])
            qx = rs[i] * c
            qy = rs[i] * ms[j] * c
            if octant == 1:
                qx, qy = qy, qx
            # spin 1: v_b = (qy b, -qx a) puts the ICR at q = z x v_b / spin, i.e. Q = (qx, qy) scaled
            # np.int64: literal constants would compile the quadrature once more for the build alone
            fx, fy, tq = icr_wrench_body(a, b, np.int64(BUILD_NODES), qy * b, -qx * a, 1.0, np.int64(1), 1.0, 0.0, 0.0)
            out[i, j, 0] = fx
            out[i, j, 1] = fy
            out[i, j, 2] = tq
    return out


def cheb(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Chebyshev points of the first kind on [-1, 1], the values -> coefficients matrix, and the
    Chebyshev -> monomial matrix (degree n - 1 is small: the monomial form loses < 1e-15)."""
    k = np.arange(n)
    th = np.pi * (k + 0.5) / n
    z = np.cos(th)
    V = np.cos(np.outer(k, th)) * (2.0 / n)
    V[0] *= 0.5
    M = np.zeros((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0
        c = np.polynomial.chebyshev.cheb2poly(e)
        M[: c.size, j] = c
    return z, V, M


def _octave_edges(o: int, k: int) -> list[tuple[float, float]]:
    lo = 2.0 ** -(o + 1)
    return [(lo * (1.0 + s / k), lo * (1.0 + (s + 1) / k)) for s in range(k)]


def _fit_octant(a: float, b: float, rs: np.ndarray, octant: int, n: int, cheb: tuple) -> tuple[np.ndarray, int]:
    """Chebyshev coefficients (panel, NT, NM, 3) of one octant of one radial panel, the number of
    m-panels doubled from ``n`` (half the neighbour's, so it can also fall) until the angular tail
    is below TAIL_TOL."""
    zm, Vt, Vm = cheb
    while True:
        ms = ((np.arange(n)[:, None] + 0.5 + 0.5 * zm[None, :]) / n).ravel()
        w = _values(a, b, rs, ms, octant).reshape(NT, n, NM, 3)
        c = np.einsum("it,tpmk,jm->pijk", Vt, w, Vm)
        if np.abs(c[:, :, -2:, :]).max() < TAIL_TOL or n >= MAX_M_PANELS:
            return c, n
        n *= 2


#: the Chebyshev terms a triangular block drops (total degree above NTRI)
_HIGH = np.add.outer(np.arange(NT), np.arange(NM)) > NTRI


def _triangular(c: np.ndarray) -> bool:
    """Whether every m-panel of an octant's Chebyshev coefficients ``c`` (panel, NT, NM, 3) can drop
    its terms of total degree > NTRI: |T_i T_j| <= 1 on the panel, so the sum of the dropped
    coefficients' magnitudes bounds the change, and it must stay below TAIL_TOL (the accuracy the
    fit itself is accepted at). The monomial form of a truncated block stays triangular (T_i has
    degree i), so the kernel reads only its 45 terms."""
    return bool(np.abs(c[:, _HIGH, :]).sum(axis=1).max() <= TAIL_TOL)


#: radial profiles a disk table can hold (:func:`build_radial_table`): uniform pressure, the load on the rim
#: (a ring), Hertz's sqrt(1 - rho^2 / a^2); and each one's <|s|^2 - (s . e)^2> / a^2 for a unit e (the
#: near-translation torque's factor: 1/4, 1/2, 1/5), kept in the table's row 0
PROFILES = {"uniform": 0, "ring": 1, "hertz": 2}
_TRANSLATION_M2 = (0.25, 0.5, 0.2)


@njit(cache=True)
def _radial_values(hertz: bool, rs: np.ndarray) -> np.ndarray:
    """The ring's (or Hertz patch's) exact wrench (radius 1, spin 1) with the ICR at (r, 0), r in ``rs``."""
    out = np.empty((rs.shape[0], 3))
    for i in range(rs.shape[0]):
        # spin 1 about the ICR (r, 0): the centre moves at (0, -r)
        fx, fy, tq = hertz_wrench(1.0, 0.0, -rs[i], 1.0, 0.0) if hertz else ring_wrench(1.0, 0.0, -rs[i], 1.0, 0.0)
        out[i, 0] = fx
        out[i, 1] = fy
        out[i, 2] = tq
    return out


@functools.lru_cache(maxsize=16)
def _build(ratio: float, profile: int = 0) -> np.ndarray:
    a, b = (1.0, ratio) if ratio <= 1.0 else (1.0 / ratio, 1.0)
    disk = ratio == 1.0
    zt, Vt, Mt = cheb(NT)
    zm, Vm, Mm = cheb(NM)
    # per side and octave: the radial panels' Chebyshev coefficients (list over sub-panels of
    # [octant 0, octant 1] blocks), sub-panels doubled until the radial tail is below TAIL_TOL
    sides: list[list[list[list[np.ndarray]]]] = []
    for side in range(2):
        octs = []
        warm = [1, 1]
        for o in range(OCTAVES):
            k = _sub_panels(o)
            while True:
                panels = []
                rtail = 0.0
                for lo, hi in _octave_edges(o, k):
                    t = 1.0 - (0.5 * (lo + hi) + 0.5 * (hi - lo) * zt)
                    rs = t if side == 0 else 1.0 / t
                    if disk:
                        w = _values(a, b, rs, np.zeros(1), 0)[:, 0, :] if profile == 0 else \
                            _radial_values(profile == 2, rs)
                        c = (Vt @ w)[None, :, None, :]
                        panels.append([c])
                    else:
                        blocks = []
                        for octant in range(2):
                            c, warm[octant] = _fit_octant(a, b, rs, octant, max(1, warm[octant] // 2), (zm, Vt, Vm))
                            blocks.append(c)
                        panels.append(blocks)
                    rtail = max(rtail, max(float(np.abs(c[:, -2:]).max()) for c in panels[-1]))
                if rtail < TAIL_TOL or k >= 64:
                    break
                k *= 2
            octs.append(panels)
        sides.append(octs)
    nr = [sum(len(p) for p in octs) for octs in sides]
    head = np.zeros((_HEADER + 2 * OCTAVES + nr[0] + nr[1], 3))
    head[0] = (1.0 if disk else 2.0, NT, _TRANSLATION_M2[profile] if disk else NM)
    head[1] = (ratio, OCTAVES, nr[0])
    rows = []
    row = head.shape[0]
    ip = 0
    for side in range(2):
        for o, panels in enumerate(sides[side]):
            head[_HEADER + side * OCTAVES + o] = (len(panels), ip, 0.0)
            for blocks in panels:
                hrow = _HEADER + 2 * OCTAVES + ip
                head[hrow, 0] = row
                ip += 1
                if disk:
                    c = Mt @ blocks[0][0, :, 0, :]  # (NT, 3): force along z x e_Q (col 1), torque (col 2)
                    rows.append(np.column_stack([c[:, 1], c[:, 2], np.zeros(NT)]))
                    row += NT
                    continue
                for octant, c in enumerate(blocks):
                    tri = _triangular(c)
                    if tri:
                        c = np.where(_HIGH[None, :, :, None], 0.0, c)
                    mono = np.einsum("ai,pijk,bj->pabk", Mt, c, Mm)
                    rows.append(mono.reshape(-1, 3))
                    # a negative count marks the octant's blocks as triangles (kernel: _horner_tri)
                    head[hrow, 1 + octant] = -c.shape[0] if tri else c.shape[0]
                    row += c.shape[0] * NT * NM
    return np.ascontiguousarray(np.vstack([head, *rows]))


def build_radial_table(profile: str) -> np.ndarray:
    """The wrench table of a disk under the radial pressure ``profile`` (one of :data:`PROFILES`:
    "uniform", the same as ``build_table(r, r)``; "ring", the load on the rim; "hertz"), from its
    exact wrench (:mod:`rrbody.physics.radial` for the ring and Hertz's); dimensionless (any radius)."""
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {', '.join(map(repr, PROFILES))}, got {profile!r}")
    return _build(1.0, PROFILES[profile])


def build_table(ra: float, rb: float) -> np.ndarray:
    """The wrench table of an ellipse with semi-axes ``ra`` (body x) and ``rb`` (body y), both in m
    and > 0 (a disk if equal). Cached in memory per aspect ratio rb/ra: the table is dimensionless."""
    return _build(check_positive("rb", rb, unit="m") / check_positive("ra", ra, unit="m"))


@njit(cache=True, inline="always")
def _locate(S, x, side):  # noqa: ANN001
    """(radial panel index, local coordinate z_t) of x = 1 - t in [0, 1] on ``side`` (0 inside, 1 outside)."""
    # math.frexp(x) from the float's bits (a library call otherwise): x = mant 2^e, mant in [0.5, 1)
    bits = np.float64(x).view(np.int64)
    mant = np.int64((bits & 0x800FFFFFFFFFFFFF) | 0x3FE0000000000000).view(np.float64)
    o = 1022 - ((bits >> 52) & 0x7FF)
    E = OCTAVES  # compile-time constant (the table's header records it)
    if x >= 1.0 or o < 0:
        o = 0
        u = 1.0
    elif x <= 0.0 or o >= E:
        o = E - 1
        u = 0.0
    else:
        u = 2.0 * mant - 1.0
    h = _HEADER + side * E + o
    k = S[h, 0]
    uk = u * k
    s = int(uk)
    if s >= k:
        s = int(k) - 1
    return int(S[h, 1]) + s, 2.0 * (uk - s) - 1.0


@njit(cache=True, inline="always")
def _pair(S, row, low, n, zm, h0, h1, h2):  # noqa: ANN001
    """The inner (zm) Horner sums of the coefficient rows ``row`` and ``low`` over their n lowest
    terms, side by side: six independent chains, which the CPU overlaps (the nested Horner is
    latency-bound with three). The lower row's chains start from (h0, h1, h2): its extra top term
    in a triangular block, else zero."""
    g0 = 0.0
    g1 = 0.0
    g2 = 0.0
    for j in range(n - 1, -1, -1):
        g0 = g0 * zm + S[row + j, 0]
        g1 = g1 * zm + S[row + j, 1]
        g2 = g2 * zm + S[row + j, 2]
        h0 = h0 * zm + S[low + j, 0]
        h1 = h1 * zm + S[low + j, 1]
        h2 = h2 * zm + S[low + j, 2]
    return g0, g1, g2, h0, h1, h2


@njit(cache=True, inline="always")
def _horner2(S, base, nt, nm, zt, zm):  # noqa: ANN001
    """Sum_ij zt^i zm^j C_ij for the three components of the panel at row ``base``, two rows at a
    time (:func:`_pair`); nt is even."""
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    for i in range(nt - 1, 0, -2):
        row = base + i * nm
        g0, g1, g2, h0, h1, h2 = _pair(S, row, row - nm, nm, zm, 0.0, 0.0, 0.0)
        f0 = (f0 * zt + g0) * zt + h0
        f1 = (f1 * zt + g1) * zt + h1
        f2 = (f2 * zt + g2) * zt + h2
    return f0, f1, f2


@njit(cache=True, inline="always")
def _horner_tri(S, base, zt, zm):  # noqa: ANN001
    """Sum over i + j <= NTRI of zt^i zm^j C_ij (three components) for the triangular block at row
    ``base`` (stored with the tensor blocks' stride NM; row i holds NTRI - i + 1 terms). Rows run in
    pairs (i, i - 1) as in :func:`_horner2`, the lower row's one extra (top) term starting its chain;
    NTRI is a compile-time constant, so every loop has a constant trip count and unrolls."""
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    for i in range(NTRI, 0, -2):
        row = base + i * NM
        low = row - NM
        li = NTRI - i + 1
        g0, g1, g2, h0, h1, h2 = _pair(S, row, low, li, zm, S[low + li, 0], S[low + li, 1], S[low + li, 2])
        f0 = (f0 * zt + g0) * zt + h0
        f1 = (f1 * zt + g1) * zt + h1
        f2 = (f2 * zt + g2) * zt + h2
    if NTRI % 2 == 0:  # an even degree leaves row 0 (NTRI + 1 terms) unpaired
        g0 = 0.0
        g1 = 0.0
        g2 = 0.0
        for j in range(NTRI, -1, -1):
            g0 = g0 * zm + S[base + j, 0]
            g1 = g1 * zm + S[base + j, 1]
            g2 = g2 * zm + S[base + j, 2]
        f0 = f0 * zt + g0
        f1 = f1 * zt + g1
        f2 = f2 * zt + g2
    return f0, f1, f2


@njit(cache=True, fastmath={"contract"})
def table_wrench_body(S, ra, rb, vbx, vby, spin, coeff, v_eps):  # noqa: ANN001
    """Dry-friction force (m/s^2) and torque about the CM (m^2/s^2) per unit mass on the ellipse
    (ra, rb) (m) whose table is ``S`` (:func:`build_table`), in the BODY frame: CM velocity
    (vbx, vby) (m/s, body frame) in, force (body frame) out; spin (rad/s), ``coeff`` = mu g
    (m/s^2); zero below ``v_eps`` (m/s). No trigonometric call, two divisions (ellipse).

    Compiled with fused multiply-adds (``contract``): the Horner sum is 300 of them, and fusing
    halves its floating-point work (and rounds once per step instead of twice)."""
    rmax = max(ra, rb)
    wr = abs(spin) * rmax
    big = max(abs(vbx), abs(vby), wr)
    if big < TINY or big > HUGE:
        # (a body left with a velocity of 1e-166 m/s): every point slower than v_eps is the dead band;
        # else the wrench depends on the twist's direction only, so it is scaled by a power of two
        # (exact) and no square below underflows or overflows
        if big == 0.0 or 2.0 * big <= v_eps:
            return 0.0, 0.0, 0.0
        k = twist_scale(big)
        vbx *= k
        vby *= k
        spin *= k
        wr = abs(spin) * rmax  # (not wr * k: a subnormal product has lost its bits)
    sp2 = vbx * vbx + vby * vby
    if sp2 <= v_eps * v_eps and wr <= v_eps:
        return 0.0, 0.0, 0.0
    if wr * wr <= (TRANSLATION_EPS * TRANSLATION_EPS) * sp2:
        if S[0, 0] == 1.0:  # a disk, its profile's factor in row 0: the radial profiles' expansion
            speed = math.sqrt(sp2)
            return -coeff * vbx / speed, -coeff * vby / speed, -coeff * spin / speed * S[0, 2] * rmax * rmax
        return translation_wrench(ra, rb, vbx, vby, spin, math.sqrt(sp2), coeff)
    pre = coeff if spin > 0.0 else -coeff
    if S[0, 0] == 1.0:
        # disk: rotationally symmetric; r = |v| / (|Omega| R), force opposite v_cm (any frame)
        speed = math.sqrt(sp2)
        # x = 1 - r inside (r = speed / wr < 1), 1 - 1 / r outside: each one division from the
        # speeds (both computed, then one chosen: no division waits for another, no branch to mispredict)
        inside = speed < wr
        x_in = (wr - speed) / wr
        x_out = (speed - wr) / speed if speed > 0.0 else 0.0
        ip, zt = _locate(S, x_in if inside else x_out, 0 if inside else 1)
        inv = 1.0 / speed if speed > 0.0 else 0.0  # (off the critical path: the sum below takes longer)
        base = int(S[_HEADER + 2 * OCTAVES + ip, 0])
        # Estrin's scheme: pairs c_2k + c_2k+1 z (independent), then Horner in z^2: half the chain of
        # dependent multiply-adds of Horner's (NT is even)
        z2 = zt * zt
        g = S[base + NT - 2, 0] + S[base + NT - 1, 0] * zt
        h = S[base + NT - 2, 1] + S[base + NT - 1, 1] * zt
        for i in range(NT - 4, -1, -2):
            g = g * z2 + (S[base + i, 0] + S[base + i + 1, 0] * zt)
            h = h * z2 + (S[base + i, 1] + S[base + i + 1, 1] * zt)
        f = -coeff * g * inv
        return f * vbx, f * vby, pre * rmax * h
    # the scaled ICR (scaled_icr) times spin ra rb, which keeps the divisions out: Q = (ux, uy) / (spin ra rb)
    ux = -vby * rb
    uy = vbx * ra
    ax_ = abs(ux)
    ay_ = abs(uy)
    if ay_ <= ax_:
        m = ay_ / ax_ if ax_ > 0.0 else 0.0
        col = 1
    else:
        m = ax_ / ay_
        col = 2
    # r = |Q| = B / D; x = 1 - r inside, 1 - 1/r outside, one division either way. B from the
    # components, not from m: the square root then does not wait for m's division
    B = math.sqrt(ux * ux + uy * uy)
    D = abs(spin) * ra * rb
    if B < D:
        ip, zt = _locate(S, (D - B) / D, 0)
    else:
        ip, zt = _locate(S, (B - D) / B, 1)
    # NT, NM, OCTAVES are compile-time constants (the header records them): the Horner loops
    # below get constant trip counts, which the compiler unrolls and schedules
    hrow = _HEADER + 2 * OCTAVES + ip
    base = int(S[hrow, 0])
    if col == 2:
        base += int(abs(S[hrow, 1])) * (NT * NM)
    cnt = S[hrow, col]
    n = int(abs(cnt))
    mn = m * n
    j = int(mn)
    if j >= n:
        j = n - 1
    zm = 2.0 * (mn - j) - 1.0
    if cnt < 0.0:  # the octant's blocks are triangles of total degree NTRI
        f0, f1, f2 = _horner_tri(S, base + j * (NT * NM), zt, zm)
    else:
        f0, f1, f2 = _horner2(S, base + j * (NT * NM), NT, NM, zt, zm)
    # reflections back from the first quadrant: F_x flips with Q_y, F_y with Q_x (Q = u / spin)
    if spin < 0.0:
        ux = -ux
        uy = -uy
    fbx = pre * (f0 if uy >= 0.0 else -f0)
    fby = pre * (f1 if ux >= 0.0 else -f1)
    return fbx, fby, pre * rmax * f2

