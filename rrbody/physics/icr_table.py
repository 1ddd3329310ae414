"""Precomputed dry-friction wrench of a homogeneous disk or ellipse: a piecewise polynomial table.

The dry wrench depends on the motion only through the instantaneous centre of rotation (ICR) and
the sign of the spin, so per unit ``mu g`` it is a function of the ICR alone, one function per
aspect ratio. It is tabulated once per ratio (from :func:`rrbody.physics.icr.icr_wrench` at high
node count); this module packs the table (:func:`build_table`) and evaluates it with a few hundred
multiply-adds and no transcendental call (:func:`table_wrench_body`). The fits themselves, their
degrees and tolerances (``NT``, ``NM``, ``NTRI``, ``OCTAVES``, ``TAIL_TOL``) are in its sibling
:mod:`rrbody.physics.icr_fit`.

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
world-frame wrapper is :func:`rrbody.physics.areas.body_wrench`. Pure translation and the zero-speed dead band are
handled exactly as
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
from numba import njit

from rrbody.model.checks import check_positive
from rrbody.physics.icr import TRANSLATION_EPS, translation_wrench
from rrbody.physics.icr_fit import HIGH, NM, NT, NTRI, OCTAVES, PROFILES, TRANSLATION_M2, cheb, fit_panels, triangular

__all__ = ["build_table", "build_radial_table", "table_wrench_body", "twist_scale", "TINY", "HUGE"]

#: rows before the octave index: (kind, NT, NM or the disk's factor) and (b/a, OCTAVES, radial panels inside)
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


@functools.lru_cache(maxsize=16)
def _build(ratio: float, profile: int = 0) -> np.ndarray:
    """The table (layout: module docstring) of aspect ratio b/a = ``ratio`` under the radial profile
    ``profile`` (a disk's; a value of :data:`rrbody.physics.icr_fit.PROFILES`): the fits of
    :func:`rrbody.physics.icr_fit.fit_panels` in monomial form, a triangular octant's blocks cut to
    total degree NTRI."""
    disk = ratio == 1.0
    _, _, Mt = cheb(NT)
    _, _, Mm = cheb(NM)
    sides = fit_panels(ratio, profile)
    nr = [sum(len(p) for p in octs) for octs in sides]
    head = np.zeros((_HEADER + 2 * OCTAVES + nr[0] + nr[1], 3))
    head[0] = (1.0 if disk else 2.0, NT, TRANSLATION_M2[profile] if disk else NM)
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
                    tri = triangular(c)
                    if tri:
                        c = np.where(HIGH[None, :, :, None], 0.0, c)
                    mono = np.einsum("ai,pijk,bj->pabk", Mt, c, Mm)
                    rows.append(mono.reshape(-1, 3))
                    # a negative count marks the octant's blocks as triangles (kernel: _horner_tri)
                    head[hrow, 1 + octant] = -c.shape[0] if tri else c.shape[0]
                    row += c.shape[0] * NT * NM
    return np.ascontiguousarray(np.vstack([head, *rows]))


def build_radial_table(profile: str) -> np.ndarray:
    """The wrench table of a disk under the radial pressure ``profile`` (one of :data:`rrbody.physics.icr_fit.PROFILES`:
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

