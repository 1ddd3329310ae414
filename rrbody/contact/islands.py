"""The coupled step's islands, from the contacts an engine reports (:mod:`rrbody.contact.coupled` solves them).

An engine adapter reads, after its own step, every contact point of the bodies on the plane into *raw point
rows* (one per point, ``RP_*`` columns: the plane body a, the other body b, the point on each, the normal from
a to b, the contact's friction, restitution and surface velocity, and, where b is not on the plane, its
velocity and centre of gravity), and the state of each body on the plane that touched something into its
*raw body row* (``RB_*``: its centre of gravity, angle and velocity after the engine's step, and whether a
joint holds it). :func:`assemble` groups the bodies into islands (bodies on the plane joined by contacts),
leaves out the islands the coupled step cannot take (one that holds a dynamic body off the plane, whose
velocity before the step is not known, or a body held by a joint: the engine's own solve stands there),
and writes the solver's rows in a canonical order (by island, then by plane row, then by the point's
coordinates), so that the answer does not depend on the order the engine lists its bodies and contacts in.

Units SI, world frame; ``bodies`` rows are :mod:`rrbody.contact.columns`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact import coupled as CP
from rrbody.contact import rest as R
from rrbody.contact.columns import (
    FRICTION_COEFF,
    FRICTION_FX,
    FRICTION_FY,
    FRICTION_TORQUE,
    INERTIA_PER_MASS,
    LAW,
    LOAD_FX,
    LOAD_FY,
    LOAD_TORQUE,
    MASS,
    PREV_SPIN,
    PREV_VX,
    PREV_VY,
    STOP,
)

__all__ = ["RP_A", "RP_B", "RP_KIND", "RP_NX", "RP_NY", "RP_POINT_AX", "RP_POINT_AY", "RP_POINT_BX", "RP_POINT_BY",
           "RP_FRICTION", "RP_RESTITUTION", "RP_SURFACE_VX", "RP_SURFACE_VY", "RP_B_VX", "RP_B_VY", "RP_B_SPIN",
           "RP_B_CGX", "RP_B_CGY", "N_RP", "KIND_PLANE", "KIND_STATIC", "KIND_KINEMATIC", "KIND_OFF", "RB_CGX",
           "RB_CGY", "RB_ANGLE", "RB_VX", "RB_VY", "RB_SPIN", "RB_JOINT", "RB_SEEN", "N_RB", "assemble",
           "couple_islands"]

#: raw point columns: the plane rows of body a and body b (-1: b is not on the plane), b's kind, the unit
#: normal from a to b, the point on a's surface and on b's (m), the contact's friction coefficient and
#: restitution, the surface velocity (m/s, as the engine adds it to b's velocity relative to a's), and for a
#: b not on the plane its velocity (m/s, rad/s) and centre of gravity (m)
(RP_A, RP_B, RP_KIND, RP_NX, RP_NY, RP_POINT_AX, RP_POINT_AY, RP_POINT_BX, RP_POINT_BY, RP_FRICTION, RP_RESTITUTION,
 RP_SURFACE_VX, RP_SURFACE_VY, RP_B_VX, RP_B_VY, RP_B_SPIN, RP_B_CGX, RP_B_CGY) = range(18)
N_RP = 18
#: what body b is: on the plane (a row of ``bodies``), static, kinematic, or dynamic off the plane
KIND_PLANE, KIND_STATIC, KIND_KINEMATIC, KIND_OFF = 0.0, 1.0, 2.0, 3.0
#: raw body columns (a row per plane row): its centre of gravity (m) and angle (rad) after the engine's step,
#: the velocity the engine gave it (m/s, rad/s), 1.0 if a joint holds it, 1.0 if it touched something
(RB_CGX, RB_CGY, RB_ANGLE, RB_VX, RB_VY, RB_SPIN, RB_JOINT, RB_SEEN) = range(8)
N_RB = 8


#: a body that slid through the last coupled step starts Newton from its velocity plus that step's change where
#: the change is at most this fraction of its velocity (steady sliding: the first iteration's step is then of
#: the change's own change, and the second lands)
EXTRAPOLATE = 1e-2


@njit(cache=True)
def _root(parent: np.ndarray, k: int) -> int:
    while parent[k] != k:
        parent[k] = parent[parent[k]]
        k = parent[k]
    return k


@njit(cache=True)
def _decel(j: int, bodies: np.ndarray) -> float:
    """The deceleration the plane's friction gives body row j at any speed (m/s^2): mu g cos(tilt) for a law
    that sticks (dry, Stribeck), none for one whose force vanishes at rest (viscous)."""
    return bodies[j, FRICTION_COEFF] if R.law_sticks(bodies[j, LAW]) else 0.0


@njit(cache=True)
def _before(raw: np.ndarray, where: np.ndarray, k: int, m: int) -> bool:
    """Whether raw point k comes before raw point m in the canonical order: by a's island body, b's (a body
    not on the plane first), then the point on a and the point on b."""
    ka = where[int(raw[k, RP_A])]
    ma = where[int(raw[m, RP_A])]
    if ka != ma:
        return ka < ma
    kb = where[int(raw[k, RP_B])] if raw[k, RP_KIND] == KIND_PLANE else -1
    mb = where[int(raw[m, RP_B])] if raw[m, RP_KIND] == KIND_PLANE else -1
    if kb != mb:
        return kb < mb
    for col in (RP_POINT_AX, RP_POINT_AY, RP_POINT_BX, RP_POINT_BY):
        if raw[k, col] != raw[m, col]:
            return raw[k, col] < raw[m, col]
    return k < m


@njit(cache=True)
def _canonical(raw: np.ndarray, pick: np.ndarray, where: np.ndarray) -> np.ndarray:
    """The raw points ``pick`` in canonical order (:func:`_before`): a merge sort (stable, n log n)."""
    n = pick.shape[0]
    if n <= 1:
        return pick
    out = pick.copy()
    tmp = np.empty(n, dtype=np.int64)
    width = 1
    while width < n:
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i = lo
            j = mid
            k = lo
            while i < mid and j < hi:
                if _before(raw, where, out[j], out[i]):
                    tmp[k] = out[j]
                    j += 1
                else:
                    tmp[k] = out[i]
                    i += 1
                k += 1
            while i < mid:
                tmp[k] = out[i]
                i += 1
                k += 1
            while j < hi:
                tmp[k] = out[j]
                j += 1
                k += 1
        out, tmp = tmp, out
        width *= 2
    return out


@njit(cache=True)
def assemble(raw: np.ndarray, n_raw: int, body: np.ndarray, bodies: np.ndarray, dt: float, damp: float, gx: float,
             gy: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The solver's rows from ``n_raw`` raw point rows and the raw body rows ``body`` (a row per plane row;
    RB_SEEN marks the bodies that touched something): (isl, con, the plane row of each island body).

    Each body's free velocity is the engine's velocity update without friction or contacts, from its
    velocity at the step's start (PREV_VX, PREV_VY, PREV_SPIN: the plane step's history) and the loads the plane step
    applied besides friction (LOAD_FX, LOAD_FY, LOAD_TORQUE), with the engine's gravity (gx, gy, m/s^2) and its damping
    factor over the step (``damp``). A contact's bounce is the restitution times its normal relative
    velocity at the step's start (as the engine asks), none where the two bodies' plane friction takes it
    away within the step (the separation the step would ask for cannot last to its end)."""
    n = bodies.shape[0]
    parent = np.arange(n)
    blocked = np.zeros(n, dtype=np.bool_)
    for k in range(n_raw):
        a = int(raw[k, RP_A])
        if raw[k, RP_KIND] == KIND_PLANE:
            ra = _root(parent, a)
            rb = _root(parent, int(raw[k, RP_B]))
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
        elif raw[k, RP_KIND] == KIND_OFF:
            blocked[a] = True
    for j in range(n):
        if body[j, RB_SEEN] > 0.0 and body[j, RB_JOINT] > 0.0:
            blocked[j] = True
    bad = np.zeros(n, dtype=np.bool_)
    for j in range(n):
        if blocked[j]:
            bad[_root(parent, j)] = True
    # the island bodies, by island (its smallest row) then by row: canonical
    where = np.full(n, -1, dtype=np.int64)
    order = np.empty(n, dtype=np.int64)
    nb = 0
    for j in range(n):
        if body[j, RB_SEEN] > 0.0 and not bad[_root(parent, j)]:
            order[nb] = j
            nb += 1
    order = order[:nb]
    if nb > 1:
        keys = np.empty(nb)
        for i in range(nb):
            keys[i] = _root(parent, order[i]) * float(n) + order[i]
        order = order[np.argsort(keys, kind="mergesort")]
    isl = np.zeros((nb, CP.N_IB))
    label = -1
    last = -1
    for i in range(nb):
        j = order[i]
        where[j] = i
        r = _root(parent, j)
        if r != last:
            label += 1
            last = r
        m = bodies[j, MASS]
        rg = math.sqrt(bodies[j, INERTIA_PER_MASS])
        vx, vy, w = bodies[j, PREV_VX], bodies[j, PREV_VY], bodies[j, PREV_SPIN]  # the velocity the step started from
        isl[i, CP.IB_ROW] = j
        isl[i, CP.IB_MASS] = m
        isl[i, CP.IB_GYRATION] = rg
        isl[i, CP.IB_COS] = math.cos(body[j, RB_ANGLE])
        isl[i, CP.IB_SIN] = math.sin(body[j, RB_ANGLE])
        isl[i, CP.IB_FREE_QX] = vx * damp + dt * (gx + bodies[j, LOAD_FX] / m)
        isl[i, CP.IB_FREE_QY] = vy * damp + dt * (gy + bodies[j, LOAD_FY] / m)
        isl[i, CP.IB_FREE_QW] = rg * (w * damp + dt * bodies[j, LOAD_TORQUE] / (m * bodies[j, INERTIA_PER_MASS]))
        isl[i, CP.IB_START_QX] = vx
        isl[i, CP.IB_START_QY] = vy
        isl[i, CP.IB_START_QW] = rg * w
        isl[i, CP.IB_REST] = 1.0 if (vx == 0.0 and vy == 0.0 and w == 0.0) else 0.0
        isl[i, CP.IB_ISLAND] = label
        isl[i, CP.IB_ENGINE_QX] = body[j, RB_VX]
        isl[i, CP.IB_ENGINE_QY] = body[j, RB_VY]
        isl[i, CP.IB_ENGINE_QW] = rg * body[j, RB_SPIN]
    # the points of the islands kept, in canonical order: island (its first body), a, b, the point
    pick = np.empty(n_raw, dtype=np.int64)
    nk = 0
    for k in range(n_raw):
        if where[int(raw[k, RP_A])] >= 0:
            pick[nk] = k
            nk += 1
    pick = _canonical(raw, pick[:nk], where)
    # (by a's island body index: the island bodies are in island order, so the points are grouped by island)
    con = np.zeros((nk, CP.N_CN))
    for p in range(nk):
        k = pick[p]
        ia = where[int(raw[k, RP_A])]
        ja = order[ia]
        nx = raw[k, RP_NX]
        ny = raw[k, RP_NY]
        tx = -ny
        ty = nx
        r1x = raw[k, RP_POINT_AX] - body[ja, RB_CGX]
        r1y = raw[k, RP_POINT_AY] - body[ja, RB_CGY]
        wa = bodies[ja, PREV_SPIN]
        va0x = bodies[ja, PREV_VX] - wa * r1y
        va0y = bodies[ja, PREV_VY] + wa * r1x
        stop = _decel(ja, bodies)
        if raw[k, RP_KIND] == KIND_PLANE:
            jb = int(raw[k, RP_B])
            ib = where[jb]
            r2x = raw[k, RP_POINT_BX] - body[jb, RB_CGX]
            r2y = raw[k, RP_POINT_BY] - body[jb, RB_CGY]
            wb = bodies[jb, PREV_SPIN]
            vb0x = bodies[jb, PREV_VX] - wb * r2y
            vb0y = bodies[jb, PREV_VY] + wb * r2x
            fixx = 0.0
            fixy = 0.0
            stop += _decel(jb, bodies)
        else:
            ib = -1
            r2x = raw[k, RP_POINT_BX] - raw[k, RP_B_CGX]
            r2y = raw[k, RP_POINT_BY] - raw[k, RP_B_CGY]
            fixx = raw[k, RP_B_VX] - raw[k, RP_B_SPIN] * r2y
            fixy = raw[k, RP_B_VY] + raw[k, RP_B_SPIN] * r2x
            vb0x = fixx
            vb0y = fixy
        bounce = raw[k, RP_RESTITUTION] * ((vb0x - va0x) * nx + (vb0y - va0y) * ny)
        if -bounce <= stop * dt:
            bounce = 0.0
        sx = fixx + raw[k, RP_SURFACE_VX]
        sy = fixy + raw[k, RP_SURFACE_VY]
        con[p, CP.CN_A] = ia
        con[p, CP.CN_B] = ib
        con[p, CP.CN_NX] = nx
        con[p, CP.CN_NY] = ny
        con[p, CP.CN_ARM_AX] = r1x
        con[p, CP.CN_ARM_AY] = r1y
        con[p, CP.CN_ARM_BX] = r2x
        con[p, CP.CN_ARM_BY] = r2y
        con[p, CP.CN_FRICTION] = raw[k, RP_FRICTION]
        con[p, CP.CN_BOUNCE] = bounce
        con[p, CP.CN_FIXED_VN] = sx * nx + sy * ny
        con[p, CP.CN_FIXED_VT] = sx * tx + sy * ty
    return isl, con, order


@njit(cache=True)
def couple_islands(raw: np.ndarray, n_raw: int, body: np.ndarray, bodies: np.ndarray, shapes: np.ndarray,
                   geo: np.ndarray, tables: np.ndarray, dt: float, damp: float, gx: float, gy: float, tol: float,
                   max_iter: int, max_sweeps: int, order: np.ndarray, vel: np.ndarray, stopped: np.ndarray,
                   report: np.ndarray, memo: np.ndarray) -> tuple[int, int, int, int, int]:
    """The coupled step of every island (:func:`assemble`, then :func:`rrbody.contact.coupled.couple`, each body
    starting from its velocity at the step's start, or from the engine's where it was at rest, or, sliding steadily,
    from its velocity plus the last step's change: ``memo``). Writes each island body's friction (FRICTION_FX,
    FRICTION_FY, FRICTION_TORQUE: N, N m) and clears its rest-rule flag (STOP) in ``bodies``; into the caller's arrays
    (a row per plane row at least) the plane rows solved (``order``), their velocities (``vel``: m/s, rad/s), the plane
    rows of the bodies it brought to rest in this step (``stopped``: held now, moving at the step's start) and each
    island's report (``report``: a row of :data:`rrbody.contact.coupled.N_OUT`, its worst body as a plane row);
    ``memo``: the solver's memo (each body's Jacobian and last change), a row per plane row, kept by the caller from
    step to step (:data:`rrbody.contact.coupled.N_MEMO` columns; zeros: none). Returns (the bodies whose velocity it
    set, the bodies stopped, the islands, how many islands did not converge, how many were left to the engine for their
    size). An island squeezed between bodies that cannot give way (:data:`rrbody.contact.coupled.SQUEEZE`) keeps the
    engine's velocities and the plane step's friction: none of its bodies is among those set."""
    isl, con, rows = assemble(raw, n_raw, body, bodies, dt, damp, gx, gy)
    nb = isl.shape[0]
    q = np.zeros((nb, 3))
    n_isl = 0
    for i in range(nb):
        j = rows[i]
        if isl[i, CP.IB_REST] > 0.0:
            q[i, 0], q[i, 1], q[i, 2] = isl[i, CP.IB_ENGINE_QX], isl[i, CP.IB_ENGINE_QY], isl[i, CP.IB_ENGINE_QW]
        else:
            q[i, 0], q[i, 1], q[i, 2] = isl[i, CP.IB_START_QX], isl[i, CP.IB_START_QY], isl[i, CP.IB_START_QW]
            if memo[j, CP.MEMO_MOVED] > 0.0:
                # a body sliding steadily: its last step's change once more (only where that change is small
                # against its velocity, so that the guess stays on the same side of rest)
                dx, dy, dw = memo[j, CP.MEMO_DX], memo[j, CP.MEMO_DY], memo[j, CP.MEMO_DW]
                if dx * dx + dy * dy + dw * dw <= EXTRAPOLATE ** 2 * (q[i, 0] ** 2 + q[i, 1] ** 2 + q[i, 2] ** 2):
                    q[i, 0] += dx
                    q[i, 1] += dy
                    q[i, 2] += dw
        memo[j, CP.MEMO_MOVED] = 0.0
        n_isl = max(n_isl, int(isl[i, CP.IB_ISLAND]) + 1)
    lam = np.zeros((con.shape[0], 2))
    pinned = np.zeros(nb, dtype=np.int64)
    fric = np.zeros((nb, 3))
    n_bad = CP.couple(isl, con, bodies, shapes, geo, tables, dt, q, lam, pinned, fric, tol, max_iter, max_sweeps,
                      report, memo)
    n_ev = 0
    n_set = 0
    for i in range(nb):
        if pinned[i] < 0:
            continue  # left to the engine: its velocity, and the friction the plane step applied before it
        j = rows[i]
        rg = isl[i, CP.IB_GYRATION]
        m = isl[i, CP.IB_MASS]
        order[n_set] = j
        vel[n_set, 0] = q[i, 0]
        vel[n_set, 1] = q[i, 1]
        vel[n_set, 2] = q[i, 2] / rg
        n_set += 1
        bodies[j, FRICTION_FX] = m * fric[i, 0]
        bodies[j, FRICTION_FY] = m * fric[i, 1]
        bodies[j, FRICTION_TORQUE] = m * rg * fric[i, 2]
        bodies[j, STOP] = 0.0  # (the plane step's rest rule does not act on a body the coupled step solved)
        if pinned[i] == 0 and isl[i, CP.IB_REST] == 0.0:
            memo[j, CP.MEMO_MOVED] = 1.0
            memo[j, CP.MEMO_DX] = q[i, 0] - isl[i, CP.IB_START_QX]
            memo[j, CP.MEMO_DY] = q[i, 1] - isl[i, CP.IB_START_QY]
            memo[j, CP.MEMO_DW] = q[i, 2] - isl[i, CP.IB_START_QW]
        if pinned[i] > 0 and isl[i, CP.IB_REST] == 0.0:
            stopped[n_ev] = j
            n_ev += 1
    n_large = 0
    for r in range(n_isl):
        if report[r, CP.OUT_WORST] >= 0:
            report[r, CP.OUT_WORST] = rows[int(report[r, CP.OUT_WORST])]
        if report[r, CP.OUT_LEFT] == 2.0:
            n_large += 1
    return n_set, n_ev, n_isl, n_bad, n_large
