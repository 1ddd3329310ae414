"""The panels of the instantaneous-centre quadrature of :mod:`rrbody.physics.icr` (its sibling, which
holds the wrench itself, :func:`rrbody.physics.icr.icr_wrench_body`, and the method's derivation):
the Gauss-Legendre tables, one node's contribution (:func:`node_wrench`), a Gauss panel graded
toward a near-singularity (:func:`panel_wrench`) and the split-and-graded rule of a thin ellipse
(:func:`eccentric_wrench`), whose direction u(psi) has branch points near the real axis.

Coordinates: the scaled body frame (x/a, y/b), where the ellipse is the unit disk; phi in
[-pi/2, pi/2] is the integration variable (sin(sigma) = S sin(phi)), the ICR Q at distance r from the
centre, psi0 the direction from Q to the centre. What a node returns is the integrand of the body-frame
force and of the torque about the CM, before the common factor -(mu g / pi) sgn(Omega).
"""

from __future__ import annotations

import cmath
import math

from numba import njit

from rrbody.physics.quadrature import quadrature_tables

__all__ = ["node_wrench", "panel_wrench", "eccentric_wrench", "NODE_COUNTS", "KAPPA_SWITCH", "X_END", "ECC_FAR",
           "SIZES", "OFFS", "GX", "GW", "FULL_S", "FULL_C", "MID_S", "MID_C"]

#: allowed nodes per panel; the kernel rounds a request up to the next one
NODE_COUNTS: tuple[int, ...] = (8, 12, 16, 20, 24, 32, 40, 48, 64, 80, 96, 128, 160, 192, 256, 320, 384, 512)
#: below this kappa' (ICR near the boundary) the end panels are graded (see :mod:`rrbody.physics.icr`)
KAPPA_SWITCH: float = 0.3
#: the graded end panels cover |phi| in [pi/2 - X_END, pi/2]
X_END: float = math.pi / 8.0
#: thin ellipses: a branch point farther than this from [-pi/2, pi/2] (in phi) needs no panel split
ECC_FAR: float = 0.8

#: the Gauss-Legendre rules of every count of NODE_COUNTS, packed (:mod:`rrbody.physics.quadrature`):
#: the counts and their offsets into the packed arrays, nodes and weights on [-1, 1], and sin, cos of
#: the nodes scaled to the full panel [-pi/2, pi/2] and to the middle one [-(pi/2 - X_END), pi/2 - X_END]
SIZES, OFFS, GX, GW, FULL_S, FULL_C, MID_S, MID_C = quadrature_tables(NODE_COUNTS, X_END)


@njit(cache=True, inline="always")
def node_wrench(sphi, cphi, delta, wt, inside, r, S, cpsi0, spsi0, g0, a, b):  # noqa: ANN001
    """One node's contribution: (force x, force y) in the body frame and the torque."""
    if inside:
        ssig = sphi
        csig = cphi
        s = delta
    else:
        ssig = S * sphi
        csig = delta
        s = cphi
    cpsi = cpsi0 * csig - spsi0 * ssig
    spsi = spsi0 * csig + cpsi0 * ssig
    rs = r * S
    fw = wt * 2.0 * rs * s * cphi
    # line integral of rho^2 along the chord: (2/3) L s^3 dsigma, dsigma/dphi = S cos(phi)/cos(sigma)
    # (= 1 inside, where sigma = phi)
    s3 = (2.0 / 3.0) * s * s * s if inside else (2.0 / 3.0) * s * s * s * S * cphi / csig
    if a == b:
        # disk: u = (cos psi, sin psi), L = a, chord midpoints are the feet of the CM (h = 0)
        return -fw * spsi, fw * cpsi, wt * a * s3
    ux = a * cpsi
    uy = b * spsi
    L2 = ux * ux + uy * uy
    inv = 1.0 / math.sqrt(L2)
    # g0 = sin cos / L at psi0: its part integrates to zero (odd in phi) and is subtracted so that
    # the far-ICR torque, O(1/r), is not the small difference of O(1) terms
    h = r * ssig * (b * b - a * a) * (spsi * cpsi * inv - g0)
    return -fw * uy * inv, fw * ux * inv, wt * (L2 * inv * s3 + 2.0 * h * rs * s * cphi)


@njit(cache=True, inline="always")
def _sincos(x):  # noqa: ANN001
    """sin, cos with the panel ends +-pi/2 exact (cos = 0 there, not 6e-17)."""
    h = 0.5 * math.pi
    if x == h:
        return 1.0, 0.0
    if x == -h:
        return -1.0, 0.0
    return math.sin(x), math.cos(x)


@njit(cache=True)
def panel_wrench(A, B, toward, y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b):  # noqa: ANN001
    """Gauss rule on phi in [A, B]. ``toward`` 1 (A) or 2 (B): a near-singularity sits at distance
    y from that end, and the nodes are graded by phi = end +- y sinh(t), t uniform-Gauss, which
    maps its branch points to t = +-i pi/2 (plain Gauss if toward = 0 or y >= B - A). sin/cos of
    the nodes come from the end's and the offset's, so cos(phi) keeps full relative precision
    next to phi = +-pi/2."""
    ax = 0.0
    ay = 0.0
    at = 0.0
    length = B - A
    if length <= 0.0:
        return ax, ay, at
    if toward == 0 or y >= length:
        for i in range(nn):
            ph = A + 0.5 * length * (1.0 + GX[o + i])
            sp = math.sin(ph)
            cp = math.cos(ph)
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = node_wrench(sp, cp, dl, 0.5 * length * GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
        return ax, ay, at
    se, ce = _sincos(A if toward == 1 else B)
    sgn = 1.0 if toward == 1 else -1.0
    T = math.asinh(length / y)
    for i in range(nn):
        t = 0.5 * T * (1.0 + GX[o + i])
        et = math.exp(t)
        sh = 0.5 * (et - 1.0 / et)
        ch = 0.5 * (et + 1.0 / et)
        dx = sgn * y * sh
        sd = math.sin(dx)
        cd = math.cos(dx)
        sp = se * cd + ce * sd
        cp = ce * cd - se * sd
        if cp < 0.0:
            cp = 0.0
        dl = math.sqrt(kp2 + kap * kap * cp * cp)
        dfx, dfy, dtq = node_wrench(sp, cp, dl, 0.5 * T * GW[o + i] * y * ch, inside, r, S, cpsi0, spsi0, g0, a, b)
        ax += dfx
        ay += dfy
        at += dtq
    return ax, ay, at


@njit(cache=True, inline="always")
def _add_point(pts, ys, n, ph, y):  # noqa: ANN001
    """(pts, ys, n) with the point ph (rad, distance y) added to the n sorted points of the
    4-tuples pts, ys: a point already there keeps the smaller distance, a new one goes in order."""
    k = 0
    for q in range(n):
        if pts[q] == ph:
            return pts, (min(ys[0], y) if q == 0 else ys[0], min(ys[1], y) if q == 1 else ys[1],
                         min(ys[2], y) if q == 2 else ys[2], min(ys[3], y) if q == 3 else ys[3]), n
        if pts[q] < ph:
            k = q + 1
    p2 = (pts[0] if k > 0 else ph, pts[1] if k > 1 else (ph if k == 1 else pts[0]),
          pts[2] if k > 2 else (ph if k == 2 else pts[1]), pts[3] if k > 3 else (ph if k == 3 else pts[2]))
    y2 = (ys[0] if k > 0 else y, ys[1] if k > 1 else (y if k == 1 else ys[0]),
          ys[2] if k > 2 else (y if k == 2 else ys[1]), ys[3] if k > 3 else (y if k == 3 else ys[2]))
    return p2, y2, n + 1


@njit(cache=True)
def eccentric_wrench(eta, a, b, nn, o, inside, r, S, kap, kp, kp2, cpsi0, spsi0, g0):  # noqa: ANN001
    """Integrate phi in [-pi/2, pi/2] for a thin ellipse. Near-singular points: the branch points
    of u(psi) (psi_s +- i eta; psi_s = pi/2 if a > b, else 0, modulo pi) mapped to phi, and, when
    the ICR is near the boundary, those of Delta at phi = +-pi/2 +- i asinh(kappa'/kappa). Panels
    are split at their real parts and graded toward them (distance: imaginary part plus any
    clamping distance)."""
    ax = 0.0
    ay = 0.0
    at = 0.0
    half = 0.5 * math.pi
    # at most four near-singular points, kept sorted in tuples: no heap array, so the quadrature
    # also compiles inside callers built without reference counting (the composed right-hand side)
    inf = math.inf
    pts = (inf, inf, inf, inf)
    ys = (inf, inf, inf, inf)
    npts = 0
    if KAPPA_SWITCH > kp >= 1e-9:
        ye = math.asinh(kp / kap)
        pts = (-half, half, inf, inf)
        ys = (ye, ye, inf, inf)
        npts = 2
    psi_s = half if a > b else 0.0
    psi0 = math.atan2(spsi0, cpsi0)
    sig = psi_s - psi0
    sig = sig - math.pi * math.floor(sig / math.pi + 0.5)  # into [-pi/2, pi/2)
    for j in range(2):
        sj = sig if j == 0 else (sig - math.pi if sig > 0.0 else sig + math.pi)
        z = complex(sj, eta)
        if inside:
            w = z
        else:
            w = cmath.asin(cmath.sin(z) * r)
        ph = w.real
        y = abs(w.imag)
        if ph < -half:
            y = math.hypot(y, -half - ph)
            ph = -half
        elif ph > half:
            y = math.hypot(y, ph - half)
            ph = half
        if y < ECC_FAR:
            pts, ys, npts = _add_point(pts, ys, npts, ph, y)
    if npts == 0:
        # nothing near: one panel with the tabulated nodes (the common far-ICR case)
        for i in range(nn):
            cp = FULL_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = node_wrench(FULL_S[o + i], cp, dl, half * GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
        return ax, ay, at
    # walk the breakpoints -pi/2 .. pi/2; ends that are not near-singular get y = inf
    prev = -half
    prev_y = math.inf
    for q in range(npts + 1):
        if q < npts:
            cur = pts[q]
            cur_y = ys[q]
        else:
            cur = half
            cur_y = math.inf
        if cur > prev:
            if math.isfinite(prev_y) and math.isfinite(cur_y):
                m = 0.5 * (prev + cur)
                dfx, dfy, dtq = panel_wrench(prev, m, 1, prev_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
                dfx, dfy, dtq = panel_wrench(m, cur, 2, cur_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            elif math.isfinite(prev_y):
                dfx, dfy, dtq = panel_wrench(prev, cur, 1, prev_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a,
                                             b)
                ax += dfx
                ay += dfy
                at += dtq
            elif math.isfinite(cur_y):
                dfx, dfy, dtq = panel_wrench(prev, cur, 2, cur_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            else:
                dfx, dfy, dtq = panel_wrench(prev, cur, 0, math.inf, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0,
                                             a, b)
                ax += dfx
                ay += dfy
                at += dtq
            prev_y = cur_y
        else:
            prev_y = min(prev_y, cur_y)
        prev = cur
    return ax, ay, at
