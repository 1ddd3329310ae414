"""Effect ``pivot_foot``: a body on point feet pinned on one of them (the foot at rest, the body
turning about it), the reaction that holds the foot and the foot's break-away.

A body on feet (pressure ``points``) slides with every foot's kinetic friction -c_k w_k u_k / |u_k|
(c_k = mu g cos(tilt) per unit mass, w_k the foot's share of the load, u_k its velocity). That force
is discontinuous where a foot's velocity vanishes, and as the sliding dies away the instantaneous
centre of rotation is drawn onto one foot and stays there: a Filippov sliding mode, that foot at
rest and the body turning about it, the other feet sliding on circles around it
(:mod:`rrbody.integrate.pivot` follows it; docs/contacts.md, "Pivoting on a foot").

The rule, per unit mass, with j = I_cm / m, r_i the pinned foot's offset from the centre of gravity
(world frame), t_i = z x r_i and G a tilt's pull:

- pinned on foot i the body has one degree of freedom, its spin Omega about the foot:
  (j + |r_i|^2) Omega' = sum_{k != i} (r_k - r_i) x f_k + (-r_i) x G, the driven body's equation with
  its pivot at rest (:func:`rrbody.physics.bind.pinned_params`);
- the friction that keeps the foot at rest is R = a_cm - G - sum_{k != i} f_k, with the centre of
  gravity's acceleration a_cm = Omega' z x (-r_i) + Omega^2 r_i; the foot stays at rest while R lies
  in its static friction disc, |R| <= c_s w_i (c_s = mu_static g cos(tilt));
- the foot's acceleration is linear in the friction F it feels, a_i = A_0 + K F with
  K = 1 + t_i t_i^T / j (its inverse effective mass, per unit body mass), and the holding reaction
  is R = -K^-1 A_0. Once R leaves the disc the foot breaks away with the acceleration a = s e
  (s >= 0, |e| = 1) that the kinetic friction -c_k w_i e of that same motion leaves:
  (s K^-1 + c_k w_i) e = -R, one root s of a scalar equation (|e(s)| falls monotonically from
  |R| / (c_k w_i) >= 1 at s = 0). The maximum-dissipation rule for a point contact.

Plain Python on a few feet: these run once per accepted step of the integrator, not per stage.
Units: SI per unit mass (m/s^2, m^2/s^2); positions in m, angles in rad, world frame unless said.
"""

from __future__ import annotations

import math

import numpy as np

from rrbody.physics import contact as C

__all__ = ["feet_of", "foot_offsets", "foot_motion", "pinned", "release", "pivot_state", "free_state"]

NAME = "pivot_foot"


def feet_of(S: np.ndarray) -> np.ndarray | None:
    """Rows (x, y, share) of the feet of a packed footprint ``S`` (body frame from the centre of
    gravity, m; shares summing to 1), or None if any part is not a point (then there is no pivot)."""
    n = int(S[0, C.H_PARTS])
    rows = S[C.HEADER:C.HEADER + n]
    if n == 0 or np.any(rows[:, C.KIND] != C.POINT):
        return None
    return np.ascontiguousarray(rows[:, [C.CENTRE_X, C.CENTRE_Y, C.LOAD_SHARE]])


def foot_offsets(alpha: float, feet: np.ndarray) -> np.ndarray:
    """The feet's offsets from the centre of gravity in the world frame (m) at body angle ``alpha``."""
    c, s = math.cos(alpha), math.sin(alpha)
    return np.column_stack([c * feet[:, 0] - s * feet[:, 1], s * feet[:, 0] + c * feet[:, 1]])


def foot_motion(y: np.ndarray, f: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (m/s) and accelerations (m/s^2) of the feet at offsets ``r`` (world) of the free body
    in state ``y`` = (x, y, alpha, vx, vy, Omega) with y' = ``f``: u = v + Omega z x r,
    a = v' + Omega' z x r - Omega^2 r."""
    w = y[5]
    u = np.column_stack([y[3] - w * r[:, 1], y[4] + w * r[:, 0]])
    a = np.column_stack([f[3] - f[5] * r[:, 1] - w * w * r[:, 0], f[4] + f[5] * r[:, 0] - w * w * r[:, 1]])
    return u, a


def _others(r: np.ndarray, feet: np.ndarray, i: int, ux0: float, uy0: float, w: float, ck: float,
            v_eps: float) -> tuple[float, float, float]:
    """Kinetic friction (m/s^2, world) of every foot but ``i`` and its torque about the centre of
    gravity (m^2/s^2), the centre of gravity moving at (ux0, uy0) m/s with spin ``w`` rad/s."""
    fx = fy = tq = 0.0
    for k in range(r.shape[0]):
        if k == i:
            continue
        ux, uy = ux0 - w * r[k, 1], uy0 + w * r[k, 0]
        sp = math.hypot(ux, uy)
        if sp <= v_eps:
            continue
        gx, gy = -ck * feet[k, 2] * ux / sp, -ck * feet[k, 2] * uy / sp
        fx += gx
        fy += gy
        tq += r[k, 0] * gy - r[k, 1] * gx
    return fx, fy, tq


def pinned(alpha: float, w: float, i: int, feet: np.ndarray, ck: float, gx: float, gy: float, j: float,
           v_eps: float) -> tuple[float, float, float]:
    """The body pinned on foot ``i`` (at rest) at angle ``alpha`` (rad) turning at ``w`` (rad/s) about
    it: (Omega' in rad/s^2, and the reaction (Rx, Ry) in m/s^2, world frame, that friction must give
    at the foot to keep it at rest). ``ck`` kinetic friction per unit mass (m/s^2), (gx, gy) a tilt's
    pull (m/s^2, world), ``j`` = I_cm / m (m^2)."""
    r = foot_offsets(alpha, feet)
    rx, ry = r[i]
    # pinned: the centre of gravity moves with w z x (-r_i)
    fx, fy, tq = _others(r, feet, i, w * ry, -w * rx, w, ck, v_eps)
    # torque about the foot: about the centre of gravity, plus (cg - foot) x (forces), (cg - foot) = -r_i
    tq_q = tq - rx * (fy + gy) + ry * (fx + gx)
    wd = tq_q / (j + rx * rx + ry * ry)
    ax = wd * ry + w * w * rx
    ay = -wd * rx + w * w * ry
    return wd, ax - gx - fx, ay - gy - fy


def release(alpha: float, w: float, i: int, feet: np.ndarray, ck: float, gx: float, gy: float, j: float,
            v_eps: float, Rx: float, Ry: float) -> tuple[float, float, float, float, float]:
    """The break-away of foot ``i`` from the pinned motion whose sticking reaction is (Rx, Ry)
    (outside the foot's static disc): the foot's acceleration s e (|e| = 1, s >= 0, m/s^2) under the
    kinetic friction -c_k w_i e of that same motion, from (s K^-1 + c_k w_i) e = -R (module
    docstring); returns (ax, ay, Omega', ex, ey): the body's accelerations (m/s^2 world, rad/s^2)
    at the break-away and the foot's slip direction e."""
    r = foot_offsets(alpha, feet)
    rx, ry = r[i]
    tx, ty = -ry, rx
    cw = ck * feet[i, 2]
    q = j + tx * tx + ty * ty  # K^-1 = 1 - t t^T / (j + |t|^2) (Sherman-Morrison)

    def e_of(s: float) -> tuple[float, float]:
        # (s K^-1 + cw) e = -R: the matrix is (s + cw) 1 - (s / q) t t^T, inverted in closed form
        a = s + cw
        b = s / q
        # (a 1 - b t t^T)^-1 = (1 / a) (1 + b t t^T / (a - b |t|^2))
        k = b / (a - b * (tx * tx + ty * ty))
        dot = tx * Rx + ty * Ry
        return -(Rx + k * dot * tx) / a, -(Ry + k * dot * ty) / a

    lo, hi = 0.0, 1.0
    while math.hypot(*e_of(hi)) > 1.0:
        hi *= 2.0
    ex, ey = e_of(lo)
    if math.hypot(ex, ey) > 1.0:
        for _ in range(200):  # |e(s)| falls monotonically in s: bisection to rounding
            mid = 0.5 * (lo + hi)
            if mid <= lo or mid >= hi:
                break
            if math.hypot(*e_of(mid)) > 1.0:
                lo = mid
            else:
                hi = mid
        ex, ey = e_of(hi)
    n = math.hypot(ex, ey)
    ex, ey = (ex / n, ey / n) if n > 0.0 else (0.0, 0.0)
    # the body's accelerations with the foot's kinetic friction -cw e, at the pinned velocities
    fx, fy, tq = _others(r, feet, i, w * ry, -w * rx, w, ck, v_eps)
    Fx, Fy = -cw * ex, -cw * ey
    return gx + fx + Fx, gy + fy + Fy, (tq + rx * Fy - ry * Fx) / j, ex, ey


def pivot_state(y: np.ndarray, foot: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """(Qx, Qy, l, beta, phi, Omega) of the free state ``y`` pinned at ``foot`` (body frame, m): the
    foot's world position Q (m), its distance l from the centre of gravity (m) and direction beta
    in the body frame (rad; 0 for a foot at the centre of gravity), and the driven state: phi the
    world angle of CM -> foot (rad), Omega the spin (rad/s)."""
    l = math.hypot(foot[0], foot[1])
    beta = math.atan2(foot[1], foot[0]) if l > 0.0 else 0.0
    phi = y[2] + beta
    return y[0] + l * math.cos(phi), y[1] + l * math.sin(phi), l, beta, phi, y[5]


def free_state(qx: float, qy: float, l: float, beta: float, phi: float, w: float, out: np.ndarray) -> None:
    """The free state (x, y, alpha, vx, vy, Omega) of the body pinned at Q = (qx, qy) (m) with the
    CM -> foot direction ``phi`` (rad) and spin ``w`` (rad/s), written into ``out[:6]``: the centre of
    gravity at Q - l e(phi), moving with w z x (-l e(phi))."""
    c, s = math.cos(phi), math.sin(phi)
    out[0] = qx - l * c
    out[1] = qy - l * s
    out[2] = phi - beta
    out[3] = l * w * s
    out[4] = -l * w * c
    out[5] = w
