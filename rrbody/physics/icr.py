"""Area-integrated friction on a homogeneous ellipse by the instantaneous centre of rotation (ICR).

Pure numba kernel (no imports from the rest of rrbody, so :mod:`rrbody.friction` can call it
without an import cycle). Units per unit mass: force m/s^2, torque about the CM m^2/s^2; inputs
in SI. The core, :func:`icr_wrench_body`, works in the body frame (CM velocity in, force out, no
trigonometric call); :func:`icr_wrench` is its world-frame wrapper (one cos/sin of the body angle
and two rotations) for callers that hold world-frame velocities.

Method (derivation in ``docs/extended.md``)
----------------------------------------------------------
With spin Omega != 0 the velocity field is v(s) = Omega z x (s - c), c = CM + z x v_cm / Omega, so
a dry element feels -mu g sgn(Omega) z x u, u the unit vector from c to the element. In the scaled
frame (x/a, y/b) the ellipse is the unit disk and c is Q, |Q| = r; a chord along the scaled
direction psi = psi0 + sigma (psi0: from Q to the centre) has midpoint parameter m = r cos(sigma)
and half-length s = sqrt(1 - r^2 sin^2 sigma). The radial integrals along each line through c are
exact, leaving

    F/m      = -(mu g / pi) sgn(Omega) Int z x u(psi) 2 m s dsigma
    tau_cm/m = -(mu g / pi) sgn(Omega) Int [ (2/3) L s^3 + 2 h m s ] dsigma

with L(psi) = |(a cos psi, b sin psi)|, u = (a cos psi, b sin psi)/L (body frame) and
h = r sin(sigma) (b^2 - a^2) sin(psi) cos(psi) / L (no difference of large numbers: the
near-translation limit does not cancel). sin(sigma) = S sin(phi), S = min(1, 1/r), maps c inside
and outside to phi in [-pi/2, pi/2], the integrands analytic except through the elliptic kernel
Delta = sqrt(1 - kappa^2 sin^2 phi), kappa = min(r, 1/r), whose branch points approach +-pi/2 as
c nears the boundary. Quadrature: one Gauss-Legendre panel of n nodes while
kappa' = sqrt(1 - kappa^2) >= ``KAPPA_SWITCH``; closer, a middle panel plus end panels in w with
sin(pi/2 - |phi|) = (kappa'/kappa) sinh(w), so that Delta = kappa' cosh(w) exactly.

Pure translation (|Omega| R < 1e-8 |v|) uses the expansion F = -mu g v_hat,
tau = -mu g (Omega/|v|) <(rho . v_hat)^2>, exact to O((Omega R/|v|)^2) < 1e-16. The viscous law is
linear: F = -gamma v_cm, tau_cm = -gamma (I_cm/m) Omega exactly.
"""

from __future__ import annotations

import cmath
import math

from numba import njit

from rrbody.physics.quadrature import quadrature_tables

__all__ = ["icr_wrench", "icr_wrench_body", "translation_wrench", "scaled_icr", "NODE_COUNTS", "KAPPA_SWITCH", "X_END", "TRANSLATION_EPS", "ECC_ETA", "ECC_FAR"]

#: allowed nodes per panel; the kernel rounds a request up to the next one
NODE_COUNTS: tuple[int, ...] = (8, 12, 16, 20, 24, 32, 40, 48, 64, 80, 96, 128, 160, 192, 256, 320, 384, 512)
#: below this kappa' (ICR near the boundary) the end panels are graded (see module docstring)
KAPPA_SWITCH: float = 0.3
#: the graded end panels cover |phi| in [pi/2 - X_END, pi/2]
X_END: float = math.pi / 8.0
#: |Omega| R / |v| below which the translation expansion is used (its error is O(ratio^2))
TRANSLATION_EPS: float = 1e-8
#: below this strip half-width atanh(b/a) (|delta| > ~0.25) the eccentric, split-and-graded rule is used
ECC_ETA: float = 0.7
#: thin ellipses: a branch point farther than this from [-pi/2, pi/2] (in phi) needs no panel split
ECC_FAR: float = 0.8


_SIZES, _OFFS, _GX, _GW, _FULL_S, _FULL_C, _MID_S, _MID_C = quadrature_tables(NODE_COUNTS, X_END)


@njit(cache=True, inline="always")
def _node(sphi, cphi, delta, wt, inside, r, S, cpsi0, spsi0, g0, a, b):  # noqa: ANN001
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
def _panel(A, B, toward, y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b):  # noqa: ANN001
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
            ph = A + 0.5 * length * (1.0 + _GX[o + i])
            sp = math.sin(ph)
            cp = math.cos(ph)
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = _node(sp, cp, dl, 0.5 * length * _GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
        return ax, ay, at
    se, ce = _sincos(A if toward == 1 else B)
    sgn = 1.0 if toward == 1 else -1.0
    T = math.asinh(length / y)
    for i in range(nn):
        t = 0.5 * T * (1.0 + _GX[o + i])
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
        dfx, dfy, dtq = _node(sp, cp, dl, 0.5 * T * _GW[o + i] * y * ch, inside, r, S, cpsi0, spsi0, g0, a, b)
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
def _eccentric(eta, a, b, nn, o, inside, r, S, kap, kp, kp2, cpsi0, spsi0, g0):  # noqa: ANN001
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
            cp = _FULL_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = _node(_FULL_S[o + i], cp, dl, half * _GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
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
                dfx, dfy, dtq = _panel(prev, m, 1, prev_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
                dfx, dfy, dtq = _panel(m, cur, 2, cur_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            elif math.isfinite(prev_y):
                dfx, dfy, dtq = _panel(prev, cur, 1, prev_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            elif math.isfinite(cur_y):
                dfx, dfy, dtq = _panel(prev, cur, 2, cur_y, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            else:
                dfx, dfy, dtq = _panel(prev, cur, 0, math.inf, nn, o, inside, r, S, kap, kp2, cpsi0, spsi0, g0, a, b)
                ax += dfx
                ay += dfy
                at += dtq
            prev_y = cur_y
        else:
            prev_y = min(prev_y, cur_y)
        prev = cur
    return ax, ay, at


@njit(cache=True, inline="always")
def translation_wrench(a, b, vbx, vby, spin, speed, coeff):  # noqa: ANN001
    """Dry wrench in near-pure translation (|Omega| R <= TRANSLATION_EPS |v|): v_hat is uniform to
    O(eps^2) and the torque is the linear response -mu g (Omega/|v|) <(rho . v_hat)^2>. CM velocity
    (vbx, vby) (m/s) and the returned force (m/s^2) in the body frame, torque about the CM (m^2/s^2)."""
    ebx = vbx / speed
    eby = vby / speed
    m2 = 0.25 * (a * a * ebx * ebx + b * b * eby * eby)
    return -coeff * ebx, -coeff * eby, -coeff * spin / speed * m2


@njit(cache=True, inline="always")
def scaled_icr(a, b, vbx, vby, spin):  # noqa: ANN001
    """The ICR in the scaled body frame (x/a, y/b): its offset from the CM in the body frame is
    q = z x v_b / Omega (m), v_b = (vbx, vby) the CM velocity (m/s) in the body frame."""
    return -vby / spin / a, vbx / spin / b


@njit(cache=True)
def icr_wrench_body(a: float, b: float, n: int, vbx: float, vby: float, spin: float, law: int,
                    coeff: float, v_eps: float, icm: float) -> tuple[float, float, float]:
    """Friction force (m/s^2) and torque about the CM (m^2/s^2) per unit mass on a homogeneous
    ellipse with semi-axes a (body x) and b (body y), all in the BODY frame: CM velocity
    (vbx, vby) (m/s, body frame), spin (rad/s), force returned in the body frame.

    ``law``: 1 dry (``coeff`` = mu g, m/s^2), 2 viscous (``coeff`` = gamma, 1/s; ``icm`` = I_cm/m
    in m^2), else no friction. ``n``: Gauss nodes per panel (rounded up to an allowed count).
    Dry friction with every element slower than ``v_eps`` (m/s) gives zero (the impulsive start, docs/physics.md).
    """
    if law == 2:
        return -coeff * vbx, -coeff * vby, -coeff * icm * spin
    if law != 1:
        return 0.0, 0.0, 0.0
    speed = math.hypot(vbx, vby)
    rmax = max(a, b)
    wr = abs(spin) * rmax
    if speed <= v_eps and wr <= v_eps:
        return 0.0, 0.0, 0.0
    if wr <= TRANSLATION_EPS * speed:
        return translation_wrench(a, b, vbx, vby, spin, speed, coeff)
    qx, qy = scaled_icr(a, b, vbx, vby, spin)
    r = math.hypot(qx, qy)
    if r > 0.0:
        cpsi0 = -qx / r
        spsi0 = -qy / r
    else:
        cpsi0 = 1.0
        spsi0 = 0.0
    g0 = spsi0 * cpsi0 / math.hypot(a * cpsi0, b * spsi0)
    inside = r < 1.0
    if inside:
        S = 1.0
        kap = r
    else:
        S = 1.0 / r
        kap = S
    kp2 = (1.0 - kap) * (1.0 + kap)
    kp = math.sqrt(kp2)
    # node table for n
    k = 0
    while k < _SIZES.shape[0] - 1 and _SIZES[k] < n:
        k += 1
    nn = _SIZES[k]
    o = _OFFS[k]
    ax = 0.0
    ay = 0.0
    at = 0.0
    half = 0.5 * math.pi
    graded_ends = KAPPA_SWITCH > kp >= 1e-9
    # eccentric ellipse: the direction u(psi) has branch points at psi_s +- i eta, eta = atanh(b/a)
    eta = math.atanh(min(a, b) / rmax) if a != b else math.inf
    if eta < ECC_ETA:
        dfx, dfy, dtq = _eccentric(eta, a, b, nn, o, inside, r, S, kap, kp, kp2, cpsi0, spsi0, g0)
        ax += dfx
        ay += dfy
        at += dtq
    elif not graded_ends:
        # one panel over [-pi/2, pi/2]; at kappa' < 1e-9 the near-singularity's weight
        # (~kappa'^2 log kappa') is below rounding, so the plain rule is exact to machine precision
        for i in range(nn):
            sp = _FULL_S[o + i]
            cp = _FULL_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = _node(sp, cp, dl, half * _GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
    else:
        mid = half - X_END
        for i in range(nn):
            sp = _MID_S[o + i]
            cp = _MID_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = _node(sp, cp, dl, mid * _GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
        # graded end panels: x = pi/2 - |phi|, sin x = c sinh w, w in [0, W]: Delta = kappa' cosh w exactly
        c = kp / kap
        W = math.asinh(math.sin(X_END) / c)
        for i in range(nn):
            wv = 0.5 * W * (1.0 + _GX[o + i])
            ew = math.exp(wv)
            sh = 0.5 * (ew - 1.0 / ew)
            ch = 0.5 * (ew + 1.0 / ew)
            sx = c * sh
            cx = math.sqrt((1.0 - sx) * (1.0 + sx))
            wt = 0.5 * W * _GW[o + i] * c * ch / cx
            dl = kp * ch
            dfx, dfy, dtq = _node(cx, sx, dl, wt, inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
            dfx, dfy, dtq = _node(-cx, sx, dl, wt, inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
    pre = -coeff / math.pi
    if spin < 0.0:
        pre = -pre
    return pre * ax, pre * ay, pre * at


@njit(cache=True)
def icr_wrench(a: float, b: float, n: int, alpha: float, vx: float, vy: float, spin: float, law: int,
               coeff: float, v_eps: float, icm: float) -> tuple[float, float, float]:
    """:func:`icr_wrench_body` in the world frame: body angle ``alpha`` (rad), CM velocity (vx, vy)
    (m/s, world) and spin (rad/s); force (m/s^2, world frame) and torque about the CM (m^2/s^2)
    per unit mass. Other arguments as there."""
    if law != 1:
        # viscous (or none) is isotropic: the body-frame formula holds in any frame, no rotation needed
        return icr_wrench_body(a, b, n, vx, vy, spin, law, coeff, v_eps, icm)
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    fbx, fby, tau = icr_wrench_body(a, b, n, ca * vx + sa * vy, -sa * vx + ca * vy, spin, law, coeff, v_eps, icm)
    return ca * fbx - sa * fby, sa * fbx + ca * fby, tau
