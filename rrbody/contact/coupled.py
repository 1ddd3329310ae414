"""The coupled step: the plane's friction solved together with the contacts of the bodies it acts on.

A body on the plane that touches something gets its velocity from one implicit (backward Euler) step
of its friction and its contacts at once, instead of friction first and contacts after (the split
step, which is exact only where no step's friction can stop a body). For the bodies of one island
(bodies on the plane joined by contacts, with the static and kinematic bodies they touch), with
generalised mass M_i = diag(m, m, I), the velocity before any impulse v*_i (the engine's velocity
update of the user's forces and loads) and the friction dissipation D_i (the friction power of the
footprint, convex, positively homogeneous of degree one), the step solves

    min  sum_i 1/2 (v_i - v*_i)^T M_i (v_i - v*_i) + dt D_i(v_i)

under the contacts' conditions at the end of the step: every contact point's normal velocity at
least minus its bounce, with a normal impulse >= 0 that vanishes where it separates (Signorini), and
the contact's own Coulomb friction, bounded by its coefficient times the normal impulse (Chipmunk's
contact model, the same numbers the engine's solver uses). Its optimality conditions say that a
body either sticks, its friction wrench (the reaction that keeps it at rest) inside the limit set of
its footprint (:mod:`rrbody.physics.limit`), or slides with the friction of the twist it ends with:
M (v - v*) = dt w(v) + contact impulses.

How it is solved (:func:`couple`, one call per step for every island):

- the velocities are scaled to q = (vx, vy, r_g w), r_g = sqrt(I / m), where kinetic energy is m |q|^2 / 2
  and the friction per unit mass a(q) is minus the gradient of D / m (symmetric Jacobian);
- Newton's method on the sliding bodies: the friction linearised at the current q, a(q) + G (q' - q)
  with G its Jacobian by forward differences of the exact wrench (symmetrised), turns the step into a
  quadratic programme in q' whose per-body mass is I - dt G: solved by projected Gauss-Seidel over the
  contact points to a relative tolerance (exact for one contact, converged for several), then a
  backtracking line search on the objective above for dry friction (D / m = -a(q) . q by Euler's
  theorem for a function homogeneous of degree one);
- sticking: a body whose Newton step passes through rest, or that was at rest, is tested at rest with
  the contacts' current impulses: the load it would need friction to cancel is tested against its
  limit set (:func:`rrbody.physics.limit.at_rest`, the static coefficient for a body at rest at the
  step's start, the kinetic one otherwise: the proximal map's own test); held, its velocity is pinned to
  zero and friction takes the reaction; not held, it starts from the break-away twist of
  the maximum-dissipation rule (the proximal map of its friction alone under those impulses);
- the island converges when no body's velocity moves by more than ``tol`` of its scale (its free
  velocity's size plus mu g dt) and no body sticks or lets go.

Units: SI; arrays are flat float64 rows with the named columns below (``IB_*`` for an island body,
``CN_*`` for a contact point), body rows of ``bodies`` are :mod:`rrbody.contact.columns`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact import rest as R
from rrbody.contact.accel import accel_at
from rrbody.contact.columns import (
    FRICTION_COEFF,
    INERTIA_PER_MASS,
    LAW,
    LAW_DRY,
    LOAD_MEAN_X,
    LOAD_MEAN_Y,
    REACH,
    REST_RULE,
    SHAPE_END,
    SHAPE_FIRST,
    STATIC_COEFF,
)
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.limit import at_rest

__all__ = ["IB_ROW", "IB_MASS", "IB_GYRATION", "IB_COS", "IB_SIN", "IB_FREE_QX", "IB_FREE_QY", "IB_FREE_QW",
           "IB_START_QX", "IB_START_QY", "IB_START_QW", "IB_REST", "IB_ISLAND", "IB_ENGINE_QX", "IB_ENGINE_QY",
           "IB_ENGINE_QW", "N_IB", "CN_A", "CN_B", "CN_NX", "CN_NY", "CN_ARM_AX", "CN_ARM_AY", "CN_ARM_BX", "CN_ARM_BY",
           "CN_FRICTION", "CN_BOUNCE", "CN_FIXED_VN", "CN_FIXED_VT", "N_CN", "OUT_ITER", "OUT_SWEEPS", "OUT_RESIDUAL",
           "OUT_WORST", "OUT_LEFT", "N_OUT", "MEMO_SET", "MEMO_QX", "MEMO_QY", "MEMO_QW", "MEMO_GXX", "MEMO_GXY",
           "MEMO_GXW", "MEMO_GYY", "MEMO_GYW", "MEMO_GWW", "MEMO_MOVED", "MEMO_DX", "MEMO_DY", "MEMO_DW", "N_MEMO",
           "couple"]

#: island-body columns (one row per body on the plane in an island): its row in ``bodies``, mass (kg),
#: radius of gyration r_g = sqrt(I / m) (m), cosine and sine of its angle after the engine's position
#: update (the angle its friction is evaluated at), its free velocity q* (velocity after the step's loads,
#: before friction and contacts; q coordinates: m/s, m/s, r_g rad/s), its velocity at the step's start
#: (the same coordinates), 1.0 if it was exactly at rest then (static friction holds it), its island, and
#: the velocity the engine's own contact solve gave it (q coordinates: where Newton starts a body that its
#: contacts push out of rest)
(IB_ROW, IB_MASS, IB_GYRATION, IB_COS, IB_SIN, IB_FREE_QX, IB_FREE_QY, IB_FREE_QW, IB_START_QX, IB_START_QY,
 IB_START_QW, IB_REST, IB_ISLAND, IB_ENGINE_QX, IB_ENGINE_QY, IB_ENGINE_QW) = range(16)
N_IB = 16
#: contact-point columns: the island bodies a and b (row of the island array; -1: a static or kinematic
#: body, whose velocity is in CN_FIXED_VN, CN_FIXED_VT), the unit normal from a to b, the point's offsets from a's
#: and b's centres of gravity (m, world), the contact's own friction coefficient, its bounce (the
#: restitution times the normal relative velocity at the step's start, m/s: the separation speed asked
#: is minus it), and the normal and tangential (t = z x n) relative velocity the fixed bodies and the
#: surface velocity give (m/s)
(CN_A, CN_B, CN_NX, CN_NY, CN_ARM_AX, CN_ARM_AY, CN_ARM_BX, CN_ARM_BY, CN_FRICTION, CN_BOUNCE, CN_FIXED_VN,
 CN_FIXED_VT) = range(12)
N_CN = 12
#: the per-island report: Newton iterations, contact sweeps in all, the last relative change, the island
#: body whose change it was (-1: none), and where the island was left to the engine: 1.0 squeezed (SQUEEZE),
#: 2.0 too large (MAX_ISLAND); 0.0 solved
OUT_ITER, OUT_SWEEPS, OUT_RESIDUAL, OUT_WORST, OUT_LEFT = range(5)
N_OUT = 5
#: the Jacobian memo (a row per plane row, kept by the caller from step to step): 1.0 where the row holds a
#: Jacobian, the twist it was taken at and the Jacobian itself, both in the body frame (q coordinates: the
#: friction of a footprint as a function of its body-frame twist does not change as the body turns), its
#: symmetric entries xx, xy, xw, yy, yw, ww (1/s); then 1.0 where the row holds the velocity change the
#: coupled step gave the body in the last step (a slide it solved), and that change (q coordinates, world frame)
(MEMO_SET, MEMO_QX, MEMO_QY, MEMO_QW, MEMO_GXX, MEMO_GXY, MEMO_GXW, MEMO_GYY, MEMO_GYW, MEMO_GWW, MEMO_MOVED,
 MEMO_DX, MEMO_DY, MEMO_DW) = range(14)
N_MEMO = 14

#: forward-difference step of the friction's Jacobian, relative to the twist (the wrench is homogeneous of
#: degree zero: its curvature scale is the twist itself, so the Jacobian is good to about this)
FD_STEP = 1e-7
#: a Newton iteration whose step moved a body by more than this fraction of its scale is followed by one with
#: a fresh Jacobian; closer to the answer the last one serves (the chord method)
CHORD = 1e-2
#: the first Newton iteration of a step takes a body's Jacobian from the last steps' (the memo) where the memo's
#: was taken within this fraction of its scale of its twist now: close enough that the second iteration's
#: step is within about a thousandth of the first's and the third lands (a Jacobian costs three evaluations
#: of the friction, an iteration one)
MEMO_REUSE = 2e-3
#: a Newton step that brings a body below this fraction of its scale passes through rest: test sticking
PASS_REST = 1e-9
#: a contact programme that, its sweeps spent, still has a contact closing faster than this fraction of the
#: island's velocity scale has no answer: a body squeezed between bodies that cannot give way (a kinematic
#: pusher driving it into a wall). The engine's own answer (its penetration correction) stands there
SQUEEZE = 1e-3
#: a Newton step smaller than this fraction of every body's scale is taken whole where the line search finds
#: no decrease (after a first step: the iteration is then in its last, fast stage)
SMALL_STEP = 1e-3
#: a proximal map's slide slower than this fraction of the body's scale is checked against the limit-set
#: test (held there, its answer is exactly rest)
NEAR_REST = 1e-3
#: how often a body may stick or let go in one step's solve (the active set's cycles end there)
MAX_FLIPS = 6
#: the Gauss-Seidel sweeps of a programme or of the nonsmooth iteration at most this many contact points and
#: bodies over the island's count (and at least MIN_SWEEPS): a jammed cluster of hundreds of bodies is one
#: island whose sweeps would otherwise cost seconds a step; an island that does not settle within them is
#: left to the engine (its squeeze test) or warns
ISLAND_WORK = 20000
MIN_SWEEPS = 20
#: an island of more bodies on the plane than this is left to the engine (the split step's answer): a jammed
#: cluster's solve costs seconds a step (benchmarks/active.py) where its bodies mostly push one another
MAX_ISLAND = 8
#: the nonsmooth Gauss-Seidel iteration's sweeps at most, per Newton iteration allowed (``max_iter``)
NSGS_PER_ITER = 50
#: the nonsmooth Gauss-Seidel iteration hands back to Newton, to polish, once no body's velocity moves by more
#: than this fraction of its scale in a sweep (which bodies stick is settled well before)
SETTLED = 1e-6


@njit(cache=True, inline="always")
def _accel(j, ca, sa, qx, qy, qw, rg, bodies, shapes, geo, tables):  # noqa: ANN001, ANN202
    """Friction per unit mass of plugin row j at q (q coordinates: m/s^2, m/s^2, r_g rad/s^2)."""
    ax, ay, aw = accel_at(j, ca, sa, qx, qy, qw / rg, bodies, shapes, geo, tables)
    return ax, ay, aw * rg


@njit(cache=True)
def _sticky(j: int, bodies: np.ndarray) -> bool:
    """Whether body row j can stick: a law that sticks, dry friction acting, the rest rule governing it."""
    return bodies[j, FRICTION_COEFF] > 0.0 and bodies[j, REST_RULE] > 0.0 and R.law_sticks(bodies[j, LAW])


@njit(cache=True)
def _at_rest(i, isl, s, dt, bodies, shapes, geo):  # noqa: ANN001, ANN202
    """Island body i at rest under its free velocity and the contact impulses per unit mass ``s`` (q
    coordinates): (held, and the break-away velocity in q coordinates if not). The load friction must
    cancel is (q* + s) / dt; static friction's coefficient for a body at rest at the step's start, the
    kinetic one otherwise (the proximal map of the friction alone)."""
    j = int(isl[i, IB_ROW])
    rg = isl[i, IB_GYRATION]
    ca = isl[i, IB_COS]
    sa = isl[i, IB_SIN]
    lx = (isl[i, IB_FREE_QX] + s[0]) / dt
    ly = (isl[i, IB_FREE_QY] + s[1]) / dt
    lt = (isl[i, IB_FREE_QW] + s[2]) / dt * rg  # torque per unit mass (m^2/s^2)
    ck = bodies[j, FRICTION_COEFF]
    cs = bodies[j, STATIC_COEFF] if (isl[i, IB_REST] > 0.0 and bodies[j, STATIC_COEFF] > 0.0) else ck
    # where the load is centred on the centre of gravity, a load inside the double cone spanned by the unit
    # force disk (the pure translations' wrenches) and the pure spins' torques is inside the limit set
    # (convex): held, no search
    if abs(bodies[j, LOAD_MEAN_X]) + abs(bodies[j, LOAD_MEAN_Y]) <= 1e-12 * bodies[j, REACH]:
        tmax = abs(footprint_wrench(shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), 0.0, 0.0, 1.0,
                                    0.0)[2])
        if tmax > 0.0 and math.sqrt(lx * lx + ly * ly) / cs + abs(lt) / (cs * tmax) <= 1.0 - 1e-12:
            return True, 0.0, 0.0, 0.0
    ax, ay, aw, held = at_rest(shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), ca * lx + sa * ly,
                               -sa * lx + ca * ly, lt, bodies[j, INERTIA_PER_MASS], cs, ck)
    if held:
        return True, 0.0, 0.0, 0.0
    return False, dt * (ca * ax - sa * ay), dt * (sa * ax + ca * ay), dt * aw * rg


@njit(cache=True)
def _inv3(A: np.ndarray, out: np.ndarray) -> bool:
    """out = A^-1 for a symmetric 3 x 3 A; False if A is not safely positive definite."""
    a, b, c = A[0, 0], A[0, 1], A[0, 2]
    d, e = A[1, 1], A[1, 2]
    f = A[2, 2]
    c00 = d * f - e * e
    c01 = c * e - b * f
    c02 = b * e - c * d
    det = a * c00 + b * c01 + c * c02
    if not (a > 0.0 and a * d - b * b > 0.0 and det > 1e-14 * a * d * f):
        return False
    out[0, 0] = c00 / det
    out[0, 1] = out[1, 0] = c01 / det
    out[0, 2] = out[2, 0] = c02 / det
    out[1, 1] = (a * f - c * c) / det
    out[1, 2] = out[2, 1] = (b * c - a * e) / det
    out[2, 2] = (a * d - b * b) / det
    return True


@njit(cache=True)
def _rows(con: np.ndarray, k: int, isl: np.ndarray, jac: np.ndarray) -> None:
    """The contact point k's rows in q coordinates: jac[0] normal, jac[1] tangent; [., 0:3] for body a,
    [., 3:6] for body b (zero for a fixed body): the relative velocity along n (t) is jac . (q_a, q_b)."""
    nx = con[k, CN_NX]
    ny = con[k, CN_NY]
    tx = -ny
    ty = nx
    a = int(con[k, CN_A])
    b = int(con[k, CN_B])
    jac[:, :] = 0.0
    if a >= 0:
        rg = isl[a, IB_GYRATION]
        rx = con[k, CN_ARM_AX]
        ry = con[k, CN_ARM_AY]
        jac[0, 0], jac[0, 1], jac[0, 2] = -nx, -ny, -(rx * ny - ry * nx) / rg
        jac[1, 0], jac[1, 1], jac[1, 2] = -tx, -ty, -(rx * ty - ry * tx) / rg
    if b >= 0:
        rg = isl[b, IB_GYRATION]
        rx = con[k, CN_ARM_BX]
        ry = con[k, CN_ARM_BY]
        jac[0, 3], jac[0, 4], jac[0, 5] = nx, ny, (rx * ny - ry * nx) / rg
        jac[1, 3], jac[1, 4], jac[1, 5] = tx, ty, (rx * ty - ry * tx) / rg


@njit(cache=True)
def _merit(i, isl, q, dt, bodies, shapes, geo, tables):  # noqa: ANN001, ANN202
    """Island body i's part of the objective per unit mass at q: |q - q*|^2 / 2 + dt D(q) / m (dry
    friction: D / m = -a(q) . q)."""
    j = int(isl[i, IB_ROW])
    dx = q[0] - isl[i, IB_FREE_QX]
    dy = q[1] - isl[i, IB_FREE_QY]
    dw = q[2] - isl[i, IB_FREE_QW]
    ax, ay, aw = _accel(j, isl[i, IB_COS], isl[i, IB_SIN], q[0], q[1], q[2], isl[i, IB_GYRATION], bodies, shapes, geo,
                        tables)
    return 0.5 * (dx * dx + dy * dy + dw * dw) - dt * (ax * q[0] + ay * q[1] + aw * q[2])


@njit(cache=True)
def _objective(b0, nb, k0, k1, isl, con, lam, q, qn, step, mode, dt, bodies, shapes, geo, tables, qt, jac,
               a0s):  # noqa: ANN001, ANN202
    """The island's objective at q + step (qn - q) (J): each body's mass times its part per unit mass (a held
    body is at rest: its part constant), and the contacts' own friction as the dissipation of a friction
    bounded by the current normal impulses (the Coulomb bound of this iteration, held fixed: Tresca). At
    step 0 the friction at q is the linearisation's (``a0s``)."""
    total = 0.0
    for k in range(k0, k1):
        u = con[k, CN_FRICTION]
        if u <= 0.0 or lam[k, 0] <= 0.0:
            continue
        _rows(con, k, isl, jac)
        v = con[k, CN_FIXED_VT]
        for side in range(2):
            bi = int(con[k, CN_A]) if side == 0 else int(con[k, CN_B])
            if bi < 0:
                continue
            for c1 in range(3):
                v += jac[1, 3 * side + c1] * (q[bi, c1] + step * (qn[bi - b0, c1] - q[bi, c1]))
        total += u * lam[k, 0] * abs(v)
    for ii in range(nb):
        if mode[ii] == 2:
            continue
        i = b0 + ii
        for r in range(3):
            qt[r] = q[i, r] + step * (qn[ii, r] - q[i, r])
        if mode[ii] == 1 and step == 0.0:
            total += isl[i, IB_MASS] * (0.5 * ((qt[0] - isl[i, IB_FREE_QX]) ** 2 + (qt[1] - isl[i, IB_FREE_QY]) ** 2
                                            + (qt[2] - isl[i, IB_FREE_QW]) ** 2)
                                     - dt * (a0s[ii, 0] * qt[0] + a0s[ii, 1] * qt[1] + a0s[ii, 2] * qt[2]))
        elif mode[ii] == 1:
            total += isl[i, IB_MASS] * _merit(i, isl, qt, dt, bodies, shapes, geo, tables)
        else:
            total += 0.5 * isl[i, IB_MASS] * ((qt[0] - isl[i, IB_FREE_QX]) ** 2 + (qt[1] - isl[i, IB_FREE_QY]) ** 2
                                          + (qt[2] - isl[i, IB_FREE_QW]) ** 2)
    return total


@njit(cache=True)
def _largest(b0, nb, q, qn, scale):  # noqa: ANN001, ANN202
    """The largest relative size of a body's step from q to qn (over its scale)."""
    big = 0.0
    for ii in range(nb):
        d = 0.0
        for r in range(3):
            d += (qn[ii, r] - q[b0 + ii, r]) ** 2
        big = max(big, math.sqrt(d) / scale[ii])
    return big


@njit(cache=True)
def _newtons(b0, nb, q, qn, mode):  # noqa: ANN001, ANN202
    """Whether the step from q to qn moves every sliding body by at most SMALL_STEP of its own velocity: near
    the answer, away from rest (where the friction's kink is), where Newton's full step is the one to take."""
    for ii in range(nb):
        if mode[ii] != 1:
            continue
        d = 0.0
        v = 0.0
        for r in range(3):
            d += (qn[ii, r] - q[b0 + ii, r]) ** 2
            v += q[b0 + ii, r] ** 2
        if d > (SMALL_STEP * SMALL_STEP) * v:
            return False
    return True


@njit(cache=True)
def _pushed(i, b0, k0, k1, con, isl, qn, mode, jac, slack):  # noqa: ANN001, ANN202
    """Whether a contact of island body i, at rest, with a body that cannot give way either (a static or
    kinematic body, or another held body, at rest) closes faster than its bounce allows: no impulse can hold
    it there."""
    for k in range(k0, k1):
        a = int(con[k, CN_A])
        b = int(con[k, CN_B])
        if a != i and b != i:
            continue
        other = b if a == i else a
        if other >= 0 and mode[other - b0] != 2:
            continue
        v = con[k, CN_FIXED_VN] + con[k, CN_BOUNCE]  # both bodies at rest: what the fixed one and the bounce ask
        if v < -slack:
            return True
    return False


@njit(cache=True)
def _start(b0, b1, isl, bodies, shapes, geo, dt, q, s, mode, scale):  # noqa: ANN001, ANN202
    """Each body's mode (0 free: no friction; 1 sliding; 2 held at rest) and starting velocity, and its
    velocity scale (its free velocity's size plus mu g dt: what the tolerance is relative to)."""
    vscale = 0.0
    for ii in range(b1 - b0):
        i = b0 + ii
        j = int(isl[i, IB_ROW])
        c = bodies[j, FRICTION_COEFF]
        scale[ii] = math.sqrt(isl[i, IB_FREE_QX] ** 2 + isl[i, IB_FREE_QY] ** 2
                              + isl[i, IB_FREE_QW] ** 2) + c * dt + 1e-300
        vscale = max(vscale, scale[ii])
        if c == 0.0:
            mode[ii] = 0
        elif _sticky(j, bodies) and isl[i, IB_REST] > 0.0:
            mode[ii] = 2  # at rest: held until its contacts break it
            q[i, :] = 0.0
        else:
            mode[ii] = 1
            if math.sqrt(q[i, 0] ** 2 + q[i, 1] ** 2 + q[i, 2] ** 2) <= PASS_REST * scale[ii]:
                # no direction to start from: the friction alone decides (held, or its break-away twist)
                if _sticky(j, bodies):
                    held, vx, vy, vw = _at_rest(i, isl, s[ii], dt, bodies, shapes, geo)
                    if held:
                        mode[ii] = 2
                        q[i, :] = 0.0
                    else:
                        q[i, 0], q[i, 1], q[i, 2] = vx, vy, vw
                else:
                    q[i, 0], q[i, 1], q[i, 2] = isl[i, IB_FREE_QX], isl[i, IB_FREE_QY], isl[i, IB_FREE_QW]
    return vscale


@njit(cache=True, inline="always")
def _turn(ca: float, sa: float, r: int, k: int) -> float:
    """Entry (r, k) of the rotation from the body frame to the world frame in q coordinates (the third
    coordinate, the spin, does not turn)."""
    if r == 2 or k == 2:
        return 1.0 if r == k else 0.0
    if r == k:
        return ca
    return -sa if r == 0 else sa


@njit(cache=True)
def _recall(i, isl, q, scale, memo, G):  # noqa: ANN001, ANN202
    """Island body i's Jacobian from the memo (world frame, into G) if the memo holds one taken at a twist
    within MEMO_REUSE of its scale of q (the chord method across steps: a body pushed steadily turns its
    twist little from one step to the next); False if not."""
    j = int(isl[i, IB_ROW])
    if memo[j, MEMO_SET] == 0.0:
        return False
    ca = isl[i, IB_COS]
    sa = isl[i, IB_SIN]
    dx = ca * q[i, 0] + sa * q[i, 1] - memo[j, MEMO_QX]
    dy = -sa * q[i, 0] + ca * q[i, 1] - memo[j, MEMO_QY]
    dw = q[i, 2] - memo[j, MEMO_QW]
    if math.sqrt(dx * dx + dy * dy + dw * dw) > MEMO_REUSE * scale:
        return False
    for r in range(3):
        for c in range(3):
            v = 0.0
            for k in range(3):
                for m in range(3):
                    v += _turn(ca, sa, r, k) * memo[j, _memo_column(k, m)] * _turn(ca, sa, c, m)
            G[r, c] = v
    return True


@njit(cache=True, inline="always")
def _memo_column(k: int, m: int) -> int:
    """The memo's column of the body-frame Jacobian's entry (k, m) (symmetric)."""
    lo = min(k, m)
    hi = max(k, m)
    if lo == 0:
        return MEMO_GXX + hi
    return MEMO_GYY + hi - 1 if lo == 1 else MEMO_GWW


@njit(cache=True)
def _remember(i, isl, q, G, memo):  # noqa: ANN001, ANN202
    """Keep island body i's Jacobian G (world frame), taken at q, in the memo (body frame)."""
    j = int(isl[i, IB_ROW])
    ca = isl[i, IB_COS]
    sa = isl[i, IB_SIN]
    memo[j, MEMO_QX] = ca * q[i, 0] + sa * q[i, 1]
    memo[j, MEMO_QY] = -sa * q[i, 0] + ca * q[i, 1]
    memo[j, MEMO_QW] = q[i, 2]
    for k in range(3):
        for m in range(k, 3):
            v = 0.0
            for r in range(3):
                for c in range(3):
                    v += _turn(ca, sa, r, k) * G[r, c] * _turn(ca, sa, c, m)
            memo[j, _memo_column(k, m)] = v
    memo[j, MEMO_SET] = 1.0


@njit(cache=True)
def _linearise(b0, b1, isl, bodies, shapes, geo, tables, dt, q, s, mode, scale, W, f, frozen, Gs, a0s,
               refresh, memo):  # noqa: ANN001, ANN202
    """Each body's linearised step: W = (I - dt G)^-1 (G the friction's Jacobian, symmetrised) and its
    velocity with no contact impulse f = W (q* + dt (a(q) - G q)); a held body none (W = 0, f = 0). The
    friction a(q) is evaluated at q (kept in ``a0s``); its Jacobian by forward differences there where
    ``refresh`` says so for the body, else the one kept in ``Gs`` (the chord method: close to the solution it
    hardly changes); a fresh one is kept in ``memo`` too. A sliding body at rest to within rounding is tested for sticking first (it may become
    held), unless the modes are ``frozen``: then it is linearised about the velocity the engine's solve gave
    it (and its Jacobian computed afresh)."""
    A = np.zeros((3, 3))
    qt = np.zeros(3)
    for ii in range(b1 - b0):
        i = b0 + ii
        j = int(isl[i, IB_ROW])
        W[ii, :, :] = 0.0
        if mode[ii] == 2:
            f[ii, :] = 0.0
            continue
        if mode[ii] == 0:
            for r in range(3):
                W[ii, r, r] = 1.0
                f[ii, r] = isl[i, IB_FREE_QX + r]
            continue
        rg = isl[i, IB_GYRATION]
        ca = isl[i, IB_COS]
        sa = isl[i, IB_SIN]
        nq = math.sqrt(q[i, 0] ** 2 + q[i, 1] ** 2 + q[i, 2] ** 2)
        if nq <= PASS_REST * scale[ii] and frozen:
            q[i, 0], q[i, 1], q[i, 2] = isl[i, IB_ENGINE_QX], isl[i, IB_ENGINE_QY], isl[i, IB_ENGINE_QW]
            nq = math.sqrt(q[i, 0] ** 2 + q[i, 1] ** 2 + q[i, 2] ** 2)
        if nq <= PASS_REST * scale[ii] and _sticky(j, bodies):
            # at rest to within rounding: no direction to linearise about; held, or its break-away twist
            held, vx, vy, vw = _at_rest(i, isl, s[ii], dt, bodies, shapes, geo)
            if held:
                mode[ii] = 2
                q[i, :] = 0.0
                f[ii, :] = 0.0
                continue
            q[i, 0], q[i, 1], q[i, 2] = vx, vy, vw
            nq = math.sqrt(vx * vx + vy * vy + vw * vw)
            refresh[ii] = True
        a0x, a0y, a0w = _accel(j, ca, sa, q[i, 0], q[i, 1], q[i, 2], rg, bodies, shapes, geo, tables)
        a0s[ii, 0] = a0x
        a0s[ii, 1] = a0y
        a0s[ii, 2] = a0w
        G = Gs[ii]
        if refresh[ii]:
            h = FD_STEP * max(nq, PASS_REST * scale[ii])
            for r in range(3):
                qt[0] = q[i, 0]
                qt[1] = q[i, 1]
                qt[2] = q[i, 2]
                qt[r] += h
                ax, ay, aw = _accel(j, ca, sa, qt[0], qt[1], qt[2], rg, bodies, shapes, geo, tables)
                G[0, r] = (ax - a0x) / h
                G[1, r] = (ay - a0y) / h
                G[2, r] = (aw - a0w) / h
            for r in range(3):
                for c2 in range(3):
                    G[r, c2] = 0.5 * (G[r, c2] + G[c2, r]) if r <= c2 else G[c2, r]
            refresh[ii] = False
            _remember(i, isl, q, G, memo)
        for r in range(3):
            for c2 in range(3):
                A[r, c2] = (1.0 if r == c2 else 0.0) - dt * G[r, c2]
        if not _inv3(A, W[ii]):  # not monotone here (a law whose friction falls with speed): explicit
            for r in range(3):
                for c2 in range(3):
                    W[ii, r, c2] = 1.0 if r == c2 else 0.0
                    G[r, c2] = 0.0
            refresh[ii] = True
        g0 = isl[i, IB_FREE_QX] + dt * (a0x - G[0, 0] * q[i, 0] - G[0, 1] * q[i, 1] - G[0, 2] * q[i, 2])
        g1 = isl[i, IB_FREE_QY] + dt * (a0y - G[1, 0] * q[i, 0] - G[1, 1] * q[i, 1] - G[1, 2] * q[i, 2])
        g2 = isl[i, IB_FREE_QW] + dt * (a0w - G[2, 0] * q[i, 0] - G[2, 1] * q[i, 1] - G[2, 2] * q[i, 2])
        for r in range(3):
            f[ii, r] = W[ii, r, 0] * g0 + W[ii, r, 1] * g1 + W[ii, r, 2] * g2


@njit(cache=True)
def _programme(b0, b1, k0, k1, isl, con, W, f, lam, s, qn, keff, jac, slack, max_sweeps):  # noqa: ANN001, ANN202
    """The linearised step's quadratic programme by projected Gauss-Seidel over the contact points, from
    the impulses ``lam``: the velocities ``qn`` and the contacts' impulses per unit mass ``s`` on each body.
    Stops when no sweep moves a relative velocity by more than ``slack`` (m/s). Returns the sweeps and, where they did not settle
    within ``max_sweeps``, the largest speed at which a contact still closes beyond its bounce (m/s; 0 if settled)."""
    nb = b1 - b0
    for ii in range(nb):
        s[ii, :] = 0.0
    for k in range(k0, k1):
        _rows(con, k, isl, jac)
        a = int(con[k, CN_A])
        b = int(con[k, CN_B])
        for r in range(2):
            kr = 0.0
            for side in range(2):
                bi = a if side == 0 else b
                if bi < 0:
                    continue
                m = isl[bi, IB_MASS]
                for c1 in range(3):
                    for c2 in range(3):
                        kr += jac[r, 3 * side + c1] * W[bi - b0, c1, c2] * jac[r, 3 * side + c2] / m
                    s[bi - b0, c1] += jac[r, 3 * side + c1] * lam[k, r] / m
            keff[k - k0, r] = kr
    for ii in range(nb):
        for r in range(3):
            qn[ii, r] = f[ii, r] + W[ii, r, 0] * s[ii, 0] + W[ii, r, 1] * s[ii, 1] + W[ii, r, 2] * s[ii, 2]
    sw = 0
    for sw in range(1, max_sweeps + 1):
        biggest = 0.0
        for k in range(k0, k1):
            _rows(con, k, isl, jac)
            a = int(con[k, CN_A])
            b = int(con[k, CN_B])
            for r in range(2):
                kr = keff[k - k0, r]
                if kr <= 0.0:
                    continue
                v = con[k, CN_FIXED_VN] if r == 0 else con[k, CN_FIXED_VT]
                if a >= 0:
                    for c1 in range(3):
                        v += jac[r, c1] * qn[a - b0, c1]
                if b >= 0:
                    for c1 in range(3):
                        v += jac[r, 3 + c1] * qn[b - b0, c1]
                old = lam[k, r]
                if r == 0:
                    new = max(old - (v + con[k, CN_BOUNCE]) / kr, 0.0)
                else:
                    bound = con[k, CN_FRICTION] * lam[k, 0]
                    new = min(max(old - v / kr, -bound), bound)
                d = new - old
                if d == 0.0:
                    continue
                lam[k, r] = new
                biggest = max(biggest, abs(d) * kr)
                for side in range(2):
                    bi = a if side == 0 else b
                    if bi < 0:
                        continue
                    m = isl[bi, IB_MASS]
                    for c1 in range(3):
                        ds = jac[r, 3 * side + c1] * d / m
                        s[bi - b0, c1] += ds
                        for c2 in range(3):
                            qn[bi - b0, c2] += W[bi - b0, c2, c1] * ds
        if biggest <= slack:
            return sw, 0.0
    # not settled within max_sweeps: how far the contacts' normal conditions are from met (a squeeze between
    # bodies that cannot give way has no answer, and its impulses only grow)
    worst = 0.0
    for k in range(k0, k1):
        _rows(con, k, isl, jac)
        a = int(con[k, CN_A])
        b = int(con[k, CN_B])
        v = con[k, CN_FIXED_VN] + con[k, CN_BOUNCE]
        if a >= 0:
            for c1 in range(3):
                v += jac[0, c1] * qn[a - b0, c1]
        if b >= 0:
            for c1 in range(3):
                v += jac[0, 3 + c1] * qn[b - b0, c1]
        worst = max(worst, -v)
    return sw, worst


@njit(cache=True)
def _newton(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s, qn, mode, flips, scale, vscale,
            tol, max_iter, max_sweeps, max_flips, memo):  # noqa: ANN001, ANN202
    """Newton's method on the island from ``q`` (each body's starting velocity) in its ``mode``s: the
    linearised step's programme, then sticking and letting go with its impulses (at most ``max_flips``
    times a body; 0 keeps the modes), then a line search on the objective. The first iteration takes a
    body's Jacobian from ``memo`` where the memo's is close (:func:`_recall`). Leaves the last programme's
    answer in ``qn`` (the impulses in ``lam``, ``s``). Returns (iterations, sweeps, the last relative
    change, its body's index in the island or -1)."""
    nb = b1 - b0
    nk = k1 - k0
    W = np.zeros((nb, 3, 3))
    f = np.zeros((nb, 3))
    Gs = np.zeros((nb, 3, 3))  # each body's friction Jacobian (the chord method keeps it between iterations)
    a0s = np.zeros((nb, 3))  # its friction at the current velocity
    refresh = np.ones(nb, dtype=np.bool_)
    keff = np.zeros((max(nk, 1), 2))
    Wt = np.zeros((nb, 3, 3))  # the programme's arrays for a body tried at rest
    ft = np.zeros((nb, 3))
    st = np.zeros((nb, 3))
    qt2 = np.zeros((nb, 3))
    jac = np.zeros((2, 6))
    qt = np.zeros(3)
    dry = np.zeros(nb, dtype=np.bool_)
    for ii in range(nb):
        dry[ii] = bodies[int(isl[b0 + ii, IB_ROW]), LAW] == LAW_DRY
    slack = 1e-3 * tol * vscale
    sweeps = 0
    feasible = False  # whether q meets the contacts (a programme's answer, or between two of them)
    phi_known = False  # whether phi holds the objective at q
    phi = 0.0
    last = math.inf  # the last step's relative size
    crawl = 0  # line searches in a row that cut the step below a quarter
    rubbing = False  # whether a contact has friction of its own (its part of the objective moves with the impulses)
    for k in range(k0, k1):
        if con[k, CN_FRICTION] > 0.0:
            rubbing = True
    change = math.inf
    worst = -1
    it = 0
    for it in range(1, max_iter + 1):
        if it == 1:
            for ii in range(nb):  # (a fresh Jacobian, unless the last step's is close)
                refresh[ii] = mode[ii] != 1 or not _recall(b0 + ii, isl, q, scale[ii], memo, Gs[ii])
        elif last > CHORD:
            refresh[:] = True  # (far from the answer, or a restart: a fresh Jacobian)
        _linearise(b0, b1, isl, bodies, shapes, geo, tables, dt, q, s, mode, scale, W, f, max_flips == 0, Gs, a0s,
                   refresh, memo)
        inner = slack
        n_sw, closing = _programme(b0, b1, k0, k1, isl, con, W, f, lam, s, qn, keff, jac, inner, max_sweeps)
        sweeps += n_sw
        # sticking and letting go, with the impulses just found (a body that has changed max_flips times
        # keeps sliding: the line search below then takes it to rest, if that is where it goes)
        changed = False
        for ii in range(nb):
            i = b0 + ii
            j = int(isl[i, IB_ROW])
            if flips[ii] >= max_flips:
                continue
            if mode[ii] == 2 and _pushed(i, b0, k0, k1, con, isl, qn, mode, jac, slack):
                # something that cannot give way pushes into it: it moves, from where the engine's solve put it
                mode[ii] = 1
                q[i, 0], q[i, 1], q[i, 2] = isl[i, IB_ENGINE_QX], isl[i, IB_ENGINE_QY], isl[i, IB_ENGINE_QW]
                flips[ii] += 1
                changed = True
            elif mode[ii] == 2:
                held, vx, vy, vw = _at_rest(i, isl, s[ii], dt, bodies, shapes, geo)
                if not held:
                    mode[ii] = 1
                    q[i, 0], q[i, 1], q[i, 2] = vx, vy, vw
                    flips[ii] += 1
                    changed = True
            elif mode[ii] == 1 and _sticky(j, bodies):
                nq = math.sqrt(qn[ii, 0] ** 2 + qn[ii, 1] ** 2 + qn[ii, 2] ** 2)
                through = qn[ii, 0] * q[i, 0] + qn[ii, 1] * q[i, 1] + qn[ii, 2] * q[i, 2] <= 0.0
                if nq <= PASS_REST * scale[ii] or through:
                    # tried at rest: the programme again with it held (its contacts' impulses then are those that
                    # hold it), and held only where its limit set takes the load those leave and nothing that
                    # cannot give way pushes it
                    mode[ii] = 2
                    held = not _pushed(i, b0, k0, k1, con, isl, qn, mode, jac, slack)
                    if held:
                        Wt[:, :, :] = W
                        ft[:, :] = f
                        Wt[ii, :, :] = 0.0
                        ft[ii, :] = 0.0
                        lt = lam.copy()
                        sweeps += _programme(b0, b1, k0, k1, isl, con, Wt, ft, lt, st, qt2, keff, jac, inner,
                                             max_sweeps)[0]
                        held = _at_rest(i, isl, st[ii], dt, bodies, shapes, geo)[0]
                    if held:
                        q[i, :] = 0.0
                        flips[ii] += 1
                        changed = True
                    else:
                        mode[ii] = 1
        if not changed and closing > SQUEEZE * vscale:
            return it, sweeps, -1.0, -1  # squeezed: no body lets go, and no velocity meets the contacts
        if changed:
            feasible = False  # a body restarted from a guess: the next step is taken whole
            phi_known = False
            change = math.inf
            last = math.inf
            worst = -1
            continue
        # the line search on the objective, from a velocity that meets the contacts (dry friction; other laws
        # take the full step)
        step = 1.0
        stalled = False
        all_dry = True
        for ii in range(nb):
            if mode[ii] == 1 and not dry[ii]:
                all_dry = False
        if all_dry and feasible and last < math.inf and _newtons(b0, nb, q, qn, mode):
            phi_known = False  # a step this small against each sliding body's velocity: Newton's own, taken whole
        elif all_dry and feasible:
            # (the objective at q is the last search's accepted value, where no contact has friction of its own:
            # only those parts change with the impulses)
            phi0 = phi if (phi_known and not rubbing) else _objective(b0, nb, k0, k1, isl, con, lam, q, qn, 0.0, mode,
                                                                      dt, bodies, shapes, geo, tables, qt, jac, a0s)
            stalled = True
            for _ in range(40):
                phi = _objective(b0, nb, k0, k1, isl, con, lam, q, qn, step, mode, dt, bodies, shapes, geo, tables, qt,
                                 jac, a0s)
                if phi <= phi0:
                    stalled = False
                    break
                step *= 0.5
            phi_known = not stalled
            if stalled and last < math.inf and _largest(b0, nb, q, qn, scale) <= SMALL_STEP:
                # close to the answer the objective's fixed-bound model of the contacts' own friction (the
                # programme's Coulomb bounds move with its impulses) can miss a decrease the step makes: the
                # step is taken whole, as Newton's near its answer
                stalled = False
                step = 1.0
            elif stalled:  # no decrease along a large step: as far as rounding lets it go (reported below)
                step = 0.0
        else:
            phi_known = False
        feasible = True
        change = 0.0
        worst = -1
        for ii in range(nb):
            i = b0 + ii
            dq = 0.0
            full = 0.0
            for r in range(3):
                d = qn[ii, r] - q[i, r]
                full += d * d
                dq += (step * d) ** 2
                q[i, r] += step * d
            rel = math.sqrt(full if stalled else dq) / scale[ii]
            if rel > change:
                change = rel
                worst = ii
        if change <= tol or stalled:
            break
        # converging fast: the next step's size is about this one's times their ratio (an estimate that
        # overstates a quadratic rate); where that is within tol, this step has landed
        if step == 1.0 and last < math.inf and change < 0.5 * last and change * change / last <= tol:
            change = change * change / last
            break
        # crawling: a body that may stick or let go no more, and the line search cutting step after step (the
        # kink of its friction at rest in the way): the Gauss-Seidel iteration settles such an island faster
        crawl = crawl + 1 if step < 0.25 else 0
        if crawl >= 3 and max_flips > 0:
            for ii in range(nb):
                if flips[ii] >= max_flips:
                    return it, sweeps, change, worst
        last = change
    return it, sweeps, change, worst


@njit(cache=True)
def _consistent(b0, b1, k0, k1, isl, con, bodies, shapes, geo, dt, qn, s, mode, tol, vscale):  # noqa: ANN001, ANN202
    """Whether a converged Newton answer's modes hold: every held body's load inside its limit set and not
    pushed by what cannot give way."""
    jac = np.zeros((2, 6))
    for ii in range(b1 - b0):
        i = b0 + ii
        if mode[ii] == 2:
            if _pushed(i, b0, k0, k1, con, isl, qn, mode, jac, 1e-3 * tol * vscale):
                return False
            if not _at_rest(i, isl, s[ii], dt, bodies, shapes, geo)[0]:
                return False
    return True


@njit(cache=True)
def _solve_island(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, pinned, fric, tol,
                  max_iter, max_sweeps, out, memo):  # noqa: ANN001, ANN202
    """One island: bodies [b0, b1) of ``isl``, contact points [k0, k1) of ``con`` (their body indices
    into ``isl``). ``q`` holds each body's starting guess and receives its velocity (q coordinates),
    ``lam`` each point's normal and tangential impulse (N s: warm start in, answer out), ``pinned``
    1 for a body held at rest, ``fric`` its friction per unit mass (q coordinates, m/s^2). Writes the
    report to ``out``; ``memo``: the Jacobian memo (``MEMO_*``, a row per plane row).

    Newton's method first (:func:`_newton`). Where it does not settle which bodies stick (its active set
    cycles: several bodies sticking and letting go in turn through their contacts), the nonsmooth
    Gauss-Seidel iteration (:func:`_nsgs`) takes over from where it stopped and settles them, and Newton,
    the modes now fixed, polishes its answer; if that answer's modes do not hold, the Gauss-Seidel answer
    stands, with its own last change reported."""
    nb = b1 - b0
    s = np.zeros((nb, 3))  # the contact impulses per unit mass on each body, q coordinates
    qn = np.zeros((nb, 3))
    scale = np.zeros(nb)
    mode = np.zeros(nb, dtype=np.int64)
    flips = np.zeros(nb, dtype=np.int64)
    if nb > MAX_ISLAND:  # too large to solve at a useful cost: left to the engine, as a squeezed island
        for ii in range(nb):
            pinned[b0 + ii] = -1
        out[OUT_ITER] = 0
        out[OUT_SWEEPS] = 0
        out[OUT_RESIDUAL] = 0.0
        out[OUT_WORST] = -1
        out[OUT_LEFT] = 2.0
        return
    vscale = _start(b0, b1, isl, bodies, shapes, geo, dt, q, s, mode, scale)
    cap = max(MIN_SWEEPS, ISLAND_WORK // (k1 - k0 + nb))
    max_sweeps = min(max_sweeps, cap)
    nsgs_sweeps = min(NSGS_PER_ITER * max_iter, cap)
    it, sweeps, change, worst = _newton(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s, qn,
                                        mode, flips, scale, vscale, tol, max_iter, max_sweeps, MAX_FLIPS, memo)
    if change < 0.0:  # squeezed: left to the engine (its velocities, its friction as the split step applied it)
        for ii in range(nb):
            pinned[b0 + ii] = -1
        out[OUT_ITER] = it
        out[OUT_SWEEPS] = sweeps
        out[OUT_RESIDUAL] = 0.0
        out[OUT_WORST] = -1
        out[OUT_LEFT] = 1.0
        return
    for ii in range(nb):
        for r in range(3):
            q[b0 + ii, r] = 0.0 if mode[ii] == 2 else qn[ii, r]
    if change > tol:
        jac = np.zeros((2, 6))
        n_sw, change, worst = _nsgs(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s, scale,
                                    max(tol, SETTLED), nsgs_sweeps, jac)
        sweeps += n_sw
        # Newton from there, the modes the Gauss-Seidel answer has
        keep_q = q[b0:b1].copy()
        keep_lam = lam[k0:k1].copy()
        keep_s = s.copy()
        for ii in range(nb):
            if mode[ii] != 0:
                held = q[b0 + ii, 0] == 0.0 and q[b0 + ii, 1] == 0.0 and q[b0 + ii, 2] == 0.0
                mode[ii] = 2 if held and _sticky(int(isl[b0 + ii, IB_ROW]), bodies) else 1
        for ii in range(nb):  # a body at rest that what cannot give way pushes moves (its bounce, a pusher)
            if mode[ii] == 2 and _pushed(b0 + ii, b0, k0, k1, con, isl, q[b0:b1], mode, jac, 1e-3 * tol * vscale):
                mode[ii] = 1
        it2, sw2, change2, worst2 = _newton(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s, qn,
                                            mode, flips, scale, vscale, tol, max_iter, max_sweeps, 0, memo)
        it += it2
        sweeps += sw2
        if 0.0 <= change2 <= tol and _consistent(b0, b1, k0, k1, isl, con, bodies, shapes, geo, dt, qn, s, mode, tol, vscale):
            change, worst = change2, worst2
            for ii in range(nb):
                for r in range(3):
                    q[b0 + ii, r] = 0.0 if mode[ii] == 2 else qn[ii, r]
        else:  # the Gauss-Seidel answer stands: on to the tolerance
            q[b0:b1] = keep_q
            lam[k0:k1] = keep_lam
            s[:, :] = keep_s
            if change > tol:
                n_sw, change, worst = _nsgs(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s,
                                            scale, tol, nsgs_sweeps, jac)
                sweeps += n_sw
    for ii in range(nb):
        i = b0 + ii
        held = q[i, 0] == 0.0 and q[i, 1] == 0.0 and q[i, 2] == 0.0 and _sticky(int(isl[i, IB_ROW]), bodies)
        for r in range(3):
            fric[i, r] = (q[i, r] - isl[i, IB_FREE_QX + r] - s[ii, r]) / dt
        pinned[i] = 1 if held else 0
    out[OUT_ITER] = it
    out[OUT_SWEEPS] = sweeps
    out[OUT_RESIDUAL] = change
    out[OUT_WORST] = -1 if worst < 0 else b0 + worst
    out[OUT_LEFT] = 0.0


@njit(cache=True)
def _prox_newton(i, isl, u, dt, bodies, shapes, geo, tables, qv, iters):  # noqa: ANN001, ANN202
    """Newton on q = u + dt a(q) from ``qv`` (updated in place), at most ``iters`` iterations; True where it
    met the equation (to 1e-14 of its scale) without passing through rest (a sliding answer: the proximal map
    is unique, so that is it)."""
    j = int(isl[i, IB_ROW])
    rg = isl[i, IB_GYRATION]
    ca = isl[i, IB_COS]
    sa = isl[i, IB_SIN]
    scale = math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2) + dt * bodies[j, FRICTION_COEFF] + 1e-300
    G = np.zeros((3, 3))
    W = np.zeros((3, 3))
    qt = np.zeros(3)
    sticky = _sticky(j, bodies)
    for _ in range(iters):
        nq = math.sqrt(qv[0] ** 2 + qv[1] ** 2 + qv[2] ** 2)
        if sticky and nq <= PASS_REST * scale:
            return False
        a0x, a0y, a0w = _accel(j, ca, sa, qv[0], qv[1], qv[2], rg, bodies, shapes, geo, tables)
        rx = qv[0] - u[0] - dt * a0x
        ry = qv[1] - u[1] - dt * a0y
        rw = qv[2] - u[2] - dt * a0w
        if math.sqrt(rx * rx + ry * ry + rw * rw) <= 1e-14 * scale:
            return True
        h = FD_STEP * max(nq, PASS_REST * scale)
        for r in range(3):
            qt[0] = qv[0]
            qt[1] = qv[1]
            qt[2] = qv[2]
            qt[r] += h
            ax, ay, aw = _accel(j, ca, sa, qt[0], qt[1], qt[2], rg, bodies, shapes, geo, tables)
            G[0, r] = (ax - a0x) / h
            G[1, r] = (ay - a0y) / h
            G[2, r] = (aw - a0w) / h
        A = np.eye(3) - 0.5 * dt * (G + G.T)
        if not _inv3(A, W):
            W[:, :] = np.eye(3)
        n0 = qv[0] - (W[0, 0] * rx + W[0, 1] * ry + W[0, 2] * rw)
        n1 = qv[1] - (W[1, 0] * rx + W[1, 1] * ry + W[1, 2] * rw)
        n2 = qv[2] - (W[2, 0] * rx + W[2, 1] * ry + W[2, 2] * rw)
        if sticky and n0 * qv[0] + n1 * qv[1] + n2 * qv[2] <= 0.0:
            return False  # through rest: the limit-set test decides
        qv[0], qv[1], qv[2] = n0, n1, n2
    return False


@njit(cache=True)
def _prox(i, isl, u, dt, bodies, shapes, geo, tables, guess):  # noqa: ANN001, ANN202
    """Island body i's velocity after one implicit step of its friction alone from the velocity u (q
    coordinates): the proximal map. From a sliding ``guess`` (the body's last answer), Newton on
    q = u + dt a(q) with the body's own friction evaluation (a wrench table where it has one); where that
    does not settle as a slide, or there is no sliding guess, dry friction's exact answer: at rest if its
    limit set holds the load u / dt (static friction's coefficient for a body at rest at the step's start),
    else the maximum-dissipation twist (:func:`rrbody.physics.limit.at_rest`); another law that sticks starts
    Newton from that twist."""
    j = int(isl[i, IB_ROW])
    scale = math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2) + dt * bodies[j, FRICTION_COEFF] + 1e-300
    qv = guess.copy()
    if math.sqrt(qv[0] ** 2 + qv[1] ** 2 + qv[2] ** 2) > PASS_REST * scale:
        if _prox_newton(i, isl, u, dt, bodies, shapes, geo, tables, qv, 8) and (
                math.sqrt(qv[0] ** 2 + qv[1] ** 2 + qv[2] ** 2) > NEAR_REST * scale or not _sticky(j, bodies)):
            return qv[0], qv[1], qv[2]
        qv[:] = guess  # (a slide this slow may be a rest the Newton iteration only approaches: the test decides)
    if _sticky(j, bodies):
        s = np.array([u[0] - isl[i, IB_FREE_QX], u[1] - isl[i, IB_FREE_QY], u[2] - isl[i, IB_FREE_QW]])
        held, vx, vy, vw = _at_rest(i, isl, s, dt, bodies, shapes, geo)
        if held:
            return 0.0, 0.0, 0.0
        if bodies[j, LAW] == LAW_DRY:
            return vx, vy, vw
        qv[0], qv[1], qv[2] = vx, vy, vw
    _prox_newton(i, isl, u, dt, bodies, shapes, geo, tables, qv, 30)
    return qv[0], qv[1], qv[2]


@njit(cache=True)
def _nsgs(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, s, scale, tol, max_sweeps,
          jac):  # noqa: ANN001, ANN202
    """The nonsmooth Gauss-Seidel iteration over one island, from velocities ``q`` and impulses ``lam``
    (``s``: the contacts' impulses per unit mass on each body, kept up to date): blocks of each contact point
    (its normal and tangential impulse, the plain masses) and of each body's friction (its proximal map,
    :func:`_prox`: the friction impulse that the body's velocity, less its last friction impulse, calls for).
    Block coordinate ascent on the dual of a convex problem: it converges, linearly. Returns (sweeps, the
    last sweep's largest relative change of a body's velocity or of its contacts' impulse per unit mass, that
    body)."""
    nb = b1 - b0
    pt = np.zeros((nb, 3))  # each body's friction impulse per unit mass
    for ii in range(nb):
        i = b0 + ii
        for r in range(3):
            pt[ii, r] = q[i, r] - isl[i, IB_FREE_QX + r] - s[ii, r]
    u = np.zeros(3)
    last_u = np.full((nb, 3), np.nan)
    change = math.inf
    worst = -1
    sw = 0
    for sw in range(1, max_sweeps + 1):
        start = q[b0:b1].copy()
        start_s = s.copy()
        for k in range(k0, k1):
            _rows(con, k, isl, jac)
            a = int(con[k, CN_A])
            b = int(con[k, CN_B])
            for r in range(2):
                kr = 0.0
                v = con[k, CN_FIXED_VN] if r == 0 else con[k, CN_FIXED_VT]
                for side in range(2):
                    bi = a if side == 0 else b
                    if bi < 0:
                        continue
                    for c1 in range(3):
                        kr += jac[r, 3 * side + c1] ** 2 / isl[bi, IB_MASS]
                        v += jac[r, 3 * side + c1] * q[bi, c1]
                if kr <= 0.0:
                    continue
                old = lam[k, r]
                if r == 0:
                    new = max(old - (v + con[k, CN_BOUNCE]) / kr, 0.0)
                else:
                    bound = con[k, CN_FRICTION] * lam[k, 0]
                    new = min(max(old - v / kr, -bound), bound)
                d = new - old
                if d == 0.0:
                    continue
                lam[k, r] = new
                for side in range(2):
                    bi = a if side == 0 else b
                    if bi < 0:
                        continue
                    for c1 in range(3):
                        dv = jac[r, 3 * side + c1] * d / isl[bi, IB_MASS]
                        q[bi, c1] += dv
                        s[bi - b0, c1] += dv
        for ii in range(nb):
            i = b0 + ii
            if bodies[int(isl[i, IB_ROW]), FRICTION_COEFF] == 0.0:
                continue
            for r in range(3):
                u[r] = q[i, r] - pt[ii, r]
            if u[0] == last_u[ii, 0] and u[1] == last_u[ii, 1] and u[2] == last_u[ii, 2]:
                continue  # the same load as last time: the same answer
            last_u[ii, :] = u
            q[i, 0], q[i, 1], q[i, 2] = _prox(i, isl, u, dt, bodies, shapes, geo, tables, q[i].copy())
            for r in range(3):
                pt[ii, r] = q[i, r] - u[r]
        change = 0.0
        worst = -1
        for ii in range(nb):
            # (the velocity's change and the contacts' impulses': a body held while a contact's impulse on it
            # still grows has not settled)
            d = math.sqrt((q[b0 + ii, 0] - start[ii, 0]) ** 2 + (q[b0 + ii, 1] - start[ii, 1]) ** 2
                          + (q[b0 + ii, 2] - start[ii, 2]) ** 2) / scale[ii]
            d = max(d, math.sqrt((s[ii, 0] - start_s[ii, 0]) ** 2 + (s[ii, 1] - start_s[ii, 1]) ** 2
                                 + (s[ii, 2] - start_s[ii, 2]) ** 2) / scale[ii])
            if d > change:
                change = d
                worst = ii
        if change <= tol:
            break
    return sw, change, worst


@njit(cache=True)
def couple(isl: np.ndarray, con: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
           tables: np.ndarray, dt: float, q: np.ndarray, lam: np.ndarray, pinned: np.ndarray, fric: np.ndarray,
           tol: float, max_iter: int, max_sweeps: int, report: np.ndarray, memo: np.ndarray) -> int:
    """The coupled step of every island: ``isl`` rows sorted by island (IB_ISLAND: 0, 1, ...), ``con``
    rows sorted by the island of their bodies. ``q`` (start guesses in, velocities out), ``lam``,
    ``pinned``, ``fric``, ``memo``: see :func:`_solve_island`; ``report`` gets a row (N_OUT) per island. Returns
    the number of islands that did not converge to ``tol`` within ``max_iter`` Newton iterations."""
    nb = isl.shape[0]
    nk = con.shape[0]
    b0 = 0
    k0 = 0
    bad = 0
    n_isl = 0
    while b0 < nb:
        label = isl[b0, IB_ISLAND]
        b1 = b0
        while b1 < nb and isl[b1, IB_ISLAND] == label:
            b1 += 1
        k1 = k0
        while k1 < nk:
            a = int(con[k1, CN_A])
            b = int(con[k1, CN_B])
            owner = a if a >= 0 else b
            if owner < b0 or owner >= b1:
                break
            k1 += 1
        _solve_island(b0, b1, k0, k1, isl, con, bodies, shapes, geo, tables, dt, q, lam, pinned, fric, tol,
                      max_iter, max_sweeps, report[n_isl], memo)
        if report[n_isl, OUT_RESIDUAL] > tol:
            bad += 1
        n_isl += 1
        b0 = b1
        k0 = k1
    return bad
