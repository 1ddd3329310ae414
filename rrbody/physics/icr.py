"""Area-integrated friction on a homogeneous ellipse by the instantaneous centre of rotation (ICR).

Pure numba kernels; the quadrature's Gauss tables and panels (one node, a graded panel, the thin
ellipse's split rule) are in the sibling :mod:`rrbody.physics.icr_panels`. Units per unit mass: force m/s^2, torque
about the CM m^2/s^2; inputs in SI. The core, :func:`icr_wrench_body`, works in the body frame (CM velocity in, force
out, no trigonometric call); :func:`icr_wrench` is its world-frame wrapper (one cos/sin of the body angle and two
rotations) for callers that hold world-frame velocities.

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
linear: F = -gamma v_cm, tau_cm = -gamma (I_cm/m) Omega exactly (:func:`rrbody.physics.effects.law_viscous.rigid`).
"""

from __future__ import annotations

import math

from numba import njit

from rrbody.physics.effects import law_viscous
from rrbody.physics.effects.laws import DRY, VISCOUS
from rrbody.physics.icr_panels import (
    FULL_C,
    FULL_S,
    GW,
    GX,
    KAPPA_SWITCH,
    MID_C,
    MID_S,
    OFFS,
    SIZES,
    X_END,
    eccentric_wrench,
    node_wrench,
)

__all__ = ["icr_wrench", "icr_wrench_body", "translation_wrench", "scaled_icr", "TRANSLATION_EPS", "ECC_ETA"]

#: |Omega| R / |v| below which the translation expansion is used (its error is O(ratio^2))
TRANSLATION_EPS: float = 1e-8
#: below this strip half-width atanh(b/a) (|delta| > ~0.25) the eccentric, split-and-graded rule is used
#: (:func:`rrbody.physics.icr_panels.eccentric_wrench`)
ECC_ETA: float = 0.7


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

    ``law`` (a code of the law table, rrbody.model.laws): dry (``coeff`` = mu g, m/s^2), viscous
    (``coeff`` = gamma, 1/s; ``icm`` = I_cm/m in m^2), none. ``n``: Gauss nodes per panel (rounded up to an
    allowed count). Dry friction with every element slower than ``v_eps`` (m/s) gives zero (the impulsive
    start, docs/physics.md).
    """
    if law == VISCOUS:
        return law_viscous.rigid(vbx, vby, spin, coeff, icm)
    if law != DRY:
        # the law "none": no other law has an icr or table form in the law table, and a scene or a call of
        # rrbody.physics.area with one is refused before any kernel runs (rrbody.model.laws.check_area)
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
    while k < SIZES.shape[0] - 1 and SIZES[k] < n:
        k += 1
    nn = SIZES[k]
    o = OFFS[k]
    ax = 0.0
    ay = 0.0
    at = 0.0
    half = 0.5 * math.pi
    graded_ends = KAPPA_SWITCH > kp >= 1e-9
    # eccentric ellipse: the direction u(psi) has branch points at psi_s +- i eta, eta = atanh(b/a)
    eta = math.atanh(min(a, b) / rmax) if a != b else math.inf
    if eta < ECC_ETA:
        dfx, dfy, dtq = eccentric_wrench(eta, a, b, nn, o, inside, r, S, kap, kp, kp2, cpsi0, spsi0, g0)
        ax += dfx
        ay += dfy
        at += dtq
    elif not graded_ends:
        # one panel over [-pi/2, pi/2]; at kappa' < 1e-9 the near-singularity's weight
        # (~kappa'^2 log kappa') is below rounding, so the plain rule is exact to machine precision
        for i in range(nn):
            sp = FULL_S[o + i]
            cp = FULL_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = node_wrench(sp, cp, dl, half * GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
    else:
        mid = half - X_END
        for i in range(nn):
            sp = MID_S[o + i]
            cp = MID_C[o + i]
            dl = math.sqrt(kp2 + kap * kap * cp * cp)
            dfx, dfy, dtq = node_wrench(sp, cp, dl, mid * GW[o + i], inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
        # graded end panels: x = pi/2 - |phi|, sin x = c sinh w, w in [0, W]: Delta = kappa' cosh w exactly
        c = kp / kap
        W = math.asinh(math.sin(X_END) / c)
        for i in range(nn):
            wv = 0.5 * W * (1.0 + GX[o + i])
            ew = math.exp(wv)
            sh = 0.5 * (ew - 1.0 / ew)
            ch = 0.5 * (ew + 1.0 / ew)
            sx = c * sh
            cx = math.sqrt((1.0 - sx) * (1.0 + sx))
            wt = 0.5 * W * GW[o + i] * c * ch / cx
            dl = kp * ch
            dfx, dfy, dtq = node_wrench(cx, sx, dl, wt, inside, r, S, cpsi0, spsi0, g0, a, b)
            ax += dfx
            ay += dfy
            at += dtq
            dfx, dfy, dtq = node_wrench(-cx, sx, dl, wt, inside, r, S, cpsi0, spsi0, g0, a, b)
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
    if law != DRY:
        # viscous (or none) is isotropic: the body-frame formula holds in any frame, no rotation needed
        return icr_wrench_body(a, b, n, vx, vy, spin, law, coeff, v_eps, icm)
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    fbx, fby, tau = icr_wrench_body(a, b, n, ca * vx + sa * vy, -sa * vx + ca * vy, spin, law, coeff, v_eps, icm)
    return ca * fbx - sa * fby, sa * fbx + ca * fby, tau
