"""The plugin's per-step operator for a free body on point feet: a foot held at rest by static friction
while the body turns about it, and its break-away (the plugin's side of docs/contacts.md, "Pivoting
on a foot"; the ODE path's is :mod:`rrbody.integrate.pivot`).

A body on feet slides with each foot's kinetic friction -c_k w_k u_k/|u_k| (per unit mass; c_k =
mu g cos(tilt), w_k the foot's share of the load, u_k its velocity). As the sliding dies away one foot
comes to rest and the body turns about it (a Filippov sliding mode). Per-step kinetic friction follows
that mode only approximately (the foot's velocity flips sign every step, a leak of O(c_k dt) per
step) and only up to the kinetic disc c_k w_k; static friction holds the foot up to c_s w_k
(c_s = mu_static g cos(tilt) >= c_k). This operator makes the foot's rest exact in the step's
velocity update (pymunk's symplectic Euler: v' = v + dt a, then the pose moves with v'):

- for a foot i, with the other feet's kinetic friction f_k (at the kernel's evaluation state) and the
  load L (force per unit mass, m/s^2, world) and l (torque per unit mass, m^2/s^2), the foot's
  velocity after the step is u_i' = b + dt K F with b = u_i + dt A_0, A_0 = L + sum_{k != i} f_k +
  ((l + sum_{k != i} r_k x f_k) / j) z x r_i, K = 1 + t t^T / j (t = z x r_i, j = I_cm / m), F the
  friction the foot itself gives. The lever r_i is taken at the angle the coming pose update turns
  through halfway (alpha + w dt / 2), so u_i' = 0 leaves the foot in place to O(dt^3) per step;
- u_i' = 0 asks F = -K^-1 b / dt. The foot is held when |F| <= c_s w_i, and a sliding foot arrives at
  rest in this step when, besides, its kinetic friction alone can take its velocity away:
  |K^-1 u_i| / dt <= c_k w_i (the step in which the kinetic deceleration reaches zero velocity; the
  ODE path's arrival, then its static test);
- a held foot whose reaction leaves the static disc breaks away: it slips with the kinetic friction
  F = -c_k w_i u'/|u'| of the slip u' it ends the step with (the maximum-dissipation rule at the
  velocity level, as the ODE path's :func:`rrbody.physics.pivot_foot.release` at the
  acceleration level): u' (1 + (dt c_k w_i / |u'|) K) = b, one scalar root |u'| in (0, |b|).

The caller (:func:`rrbody.contact.kernel.plane_step`) keeps which foot is held between steps, hands
the spin's stop to its rest rule (a held body whose spin would pass zero in the step), and uses this
only for dry bodies the rest rule governs, on two or more feet.

Units: SI per unit mass; positions in m (body frame from the centre of gravity for the feet rows,
world frame for levers), angles in rad, velocities m/s, spins rad/s.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact.lean import NO_REFCOUNT
from rrbody.physics import contact as C
from rrbody.physics.effects import law_dry

__all__ = ["feet_step", "breakaway"]

#: bisection steps for the break-away's scalar root (halving (0, |b|) to below rounding)
_BISECT = 200


@njit(cache=True)
def breakaway(bx: float, by: float, tx: float, ty: float, j: float, cw: float, dt: float) -> tuple[float, float]:
    """The kinetic friction (Fx, Fy) (m/s^2, world) of a foot breaking away: F = -cw u'/|u'| with
    u' (1 + (dt cw / |u'|) K) = b, K = 1 + t t^T / j; ``b`` (m/s) the foot's velocity after the step
    without its own friction, ``t`` = z x r (m) its lever, ``cw`` = c_k w_i (m/s^2). Needs
    |K^-1 b| > dt cw (the foot cannot be stopped by cw), so the root |u'| lies in (0, |b|)."""
    t2 = tx * tx + ty * ty
    bn = math.hypot(bx, by)
    lo = 0.0
    hi = bn
    ux = bx
    uy = by
    for _ in range(_BISECT):
        s = 0.5 * (lo + hi)
        if s <= lo or s >= hi:
            break
        lam = dt * cw / s
        # (a 1 + g t t^T)^-1 b = (b - g (t.b) t / (a + g |t|^2)) / a, a = 1 + lam, g = lam / j
        a = 1.0 + lam
        g = lam / j
        k = g * (tx * bx + ty * by) / (a + g * t2)
        ux = (bx - k * tx) / a
        uy = (by - k * ty) / a
        if math.hypot(ux, uy) > s:
            lo = s
        else:
            hi = s
    un = math.hypot(ux, uy)
    if un == 0.0:
        return 0.0, 0.0
    return -cw * ux / un, -cw * uy / un


@njit(cache=True, **NO_REFCOUNT)
def feet_step(shapes: np.ndarray, s0: int, s1: int, alpha_e: float, alpha_m: float, alpha_u: float, vx: float,
              vy: float, w: float, ex: float, ey: float, ew: float, lx: float, ly: float, lt: float, ck: float,
              cs: float, j: float, v_eps: float, dt: float, reach: float, held: int) -> tuple[int, float, float, float]:
    """One step of friction on a body on the feet ``shapes[s0:s1]`` (POINT rows: CENTRE_X, CENTRE_Y body frame from
    the centre of gravity, m; LOAD_SHARE the shares), with a foot held or arriving at rest.

    Body angle ``alpha_e`` and velocity (ex, ey, ew) (m/s world, rad/s) are where the kernel evaluates
    the sliding feet's friction; ``alpha_m`` the mid-update angle and (vx, vy, w) the velocity the step
    updates, which belongs to the angle ``alpha_u`` (the staggered reading: the velocity read moves the
    pose in this step, so it belongs to that move's midpoint); (lx, ly) (m/s^2, world) and lt (m^2/s^2)
    the load per unit mass; ck, cs kinetic and static friction per unit mass and load (m/s^2);
    j = I_cm / m (m^2); ``reach`` the footprint's largest distance from the centre of gravity (m);
    ``held`` the foot held since the last step, or -1.

    Returns (foot, fx, fy, tq): the foot now held (-1: none; with fx = fy = tq = 0 then, and the
    caller applies its usual friction) and the friction on the body, force per unit mass (m/s^2,
    world) and torque per unit mass about the centre of gravity (m^2/s^2). A foot that breaks away
    returns -2 with its step's friction (the caller applies it; no foot is held after it).
    """
    cm = math.cos(alpha_m)
    sm = math.sin(alpha_m)
    # a foot that could stop within the step: |u| below what the whole friction and load change in dt
    # (a cheap bound that skips the common case of every foot sliding fast: no friction evaluated)
    bound = dt * (2.0 * ck * (1.0 + reach * reach / j) + math.hypot(lx, ly) + abs(lt) * reach / j)
    if held < 0:
        slow = False
        for k in range(s0, s1):
            px = shapes[k, C.CENTRE_X]
            py = shapes[k, C.CENTRE_Y]
            if math.hypot(vx - w * (sm * px + cm * py), vy + w * (cm * px - sm * py)) <= bound:
                slow = True
                break
        if not slow:
            return -1, 0.0, 0.0, 0.0
    ce = math.cos(alpha_e)
    se = math.sin(alpha_e)
    # every foot's kinetic friction at the evaluation state, summed (force and torque)
    fx = 0.0
    fy = 0.0
    tq = 0.0
    for k in range(s0, s1):
        px = shapes[k, C.CENTRE_X]
        py = shapes[k, C.CENTRE_Y]
        rx = ce * px - se * py
        ry = se * px + ce * py
        gx, gy = law_dry.force(ex - ew * ry, ey + ew * rx, ck * shapes[k, C.LOAD_SHARE], v_eps)
        fx += gx
        fy += gy
        tq += rx * gy - ry * gx
    best = -1
    best_ratio = math.inf
    bfx = 0.0
    bfy = 0.0
    btq = 0.0
    for k in range(s0, s1):
        if held >= 0 and k - s0 != held:
            continue  # a held foot is the only one tested
        px = shapes[k, C.CENTRE_X]
        py = shapes[k, C.CENTRE_Y]
        wk = shapes[k, C.LOAD_SHARE]
        # the lever at the mid-update angle, t = z x r
        rx = cm * px - sm * py
        ry = sm * px + cm * py
        tx = -ry
        ty = rx
        ux = vx + w * tx
        uy = vy + w * ty
        if held < 0 and math.hypot(ux, uy) > bound:
            continue
        # the other feet's friction: all less this foot's own (at the evaluation state)
        qx = ce * px - se * py
        qy = se * px + ce * py
        gx, gy = law_dry.force(ex - ew * qy, ey + ew * qx, ck * wk, v_eps)
        ox = fx - gx
        oy = fy - gy
        ot = tq - (qx * gy - qy * gx)
        wd = (lt + ot) / j
        bx = ux + dt * (lx + ox + wd * tx)
        by = uy + dt * (ly + oy + wd * ty)
        # F = -K^-1 b / dt, K^-1 = 1 - t t^T / (j + |t|^2)
        q = (tx * bx + ty * by) / (j + tx * tx + ty * ty)
        Fx = -(bx - q * tx) / dt
        Fy = -(by - q * ty) / dt
        need = math.hypot(Fx, Fy)
        if held >= 0:
            if need <= cs * wk:
                return held, ox + Fx, oy + Fy, ot + rx * Fy - ry * Fx
            Fx, Fy = breakaway(bx, by, tx, ty, j, ck * wk, dt)
            return -2, ox + Fx, oy + Fy, ot + rx * Fy - ry * Fx
        # arriving: kinetic friction alone takes the foot's velocity away in the step (its velocity
        # where that velocity belongs: the turn of the lever since is the centripetal part of the
        # holding reaction, which static friction gives), and static friction holds it
        vux = vx - w * (math.sin(alpha_u) * px + math.cos(alpha_u) * py)
        vuy = vy + w * (math.cos(alpha_u) * px - math.sin(alpha_u) * py)
        qu = (tx * vux + ty * vuy) / (j + tx * tx + ty * ty)
        stop = math.hypot(vux - qu * tx, vuy - qu * ty) / dt
        if stop <= ck * wk and need <= cs * wk and need / (cs * wk) < best_ratio:
            best = k - s0
            best_ratio = need / (cs * wk)
            bfx = ox + Fx
            bfy = oy + Fy
            btq = ot + rx * Fy - ry * Fx
    return best, bfx, bfy, btq
