"""The compiled reads and writes of the MuJoCo adapter (:mod:`rrbody.mujoco_adapter.plane`): MuJoCo's state in,
the plugin kernel's ``got`` rows out (:func:`gather`), and the kernel's friction back into MuJoCo
(:func:`scatter`, :func:`set_planar`). No MuJoCo import here: they take MuJoCo's arrays (numpy views).

Frames: ``frame`` rows are the plane's axes t1, t2 and normal n in the world frame; a body's in-plane
state is its centre of gravity's velocity along t1, t2 (m/s), its spin about n (rad/s) and its angle
about n (rad, from its pose when the adapter was built). Free joints: qvel holds the body origin's
linear velocity (world frame) then the angular velocity in the body frame, and qfrc_constraint the
force (world) and the torque about the body origin (body frame).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact import kernel as K

__all__ = ["gather", "scatter", "unapply", "set_planar", "hold", "RESIDUE"]

#: what counts as MuJoCo's numerical residue on a body at rest (its normal contacts' solver, the
#: tipping it keeps; measured 1e-12 to 1e-8 m/s on boxes): in-plane motion with every point slower
#: than RESIDUE mu g dt (far below what the rest rule stops in one step, mu g dt), and an in-plane load
#: below RESIDUE mu_static N (force) and RESIDUE mu_static N reach (torque), deep inside the limit surface
RESIDUE = 1e-4


@njit(cache=True, inline="always")
def _mat(qpos: np.ndarray, p: int) -> tuple[float, float, float, float, float, float, float, float, float]:
    """The rotation matrix (row-major) of the unit quaternion (w, x, y, z) at ``qpos[p:p + 4]``: from the
    current qpos, not MuJoCo's xmat, which after ``mj_step`` still holds the pose the step started from."""
    w, x, y, z = qpos[p], qpos[p + 1], qpos[p + 2], qpos[p + 3]
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return (1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),
            s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x),
            s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y))


@njit(cache=True, inline="always")
def _rot(R: tuple[float, float, float, float, float, float, float, float, float], x: float, y: float,
         z: float) -> tuple[float, float, float]:
    """R (x, y, z): a body-frame vector in the world frame."""
    return (R[0] * x + R[1] * y + R[2] * z, R[3] * x + R[4] * y + R[5] * z, R[6] * x + R[7] * y + R[8] * z)


@njit(cache=True, inline="always")
def _rot_t(R: tuple[float, float, float, float, float, float, float, float, float], x: float, y: float,
           z: float) -> tuple[float, float, float]:
    """R^T (x, y, z): a world-frame vector in the body frame."""
    return (R[0] * x + R[3] * y + R[6] * z, R[1] * x + R[4] * y + R[7] * z, R[2] * x + R[5] * y + R[8] * z)


@njit(cache=True, inline="always")
def _offset(i: int, R: tuple[float, float, float, float, float, float, float, float, float],
            ipos: np.ndarray) -> tuple[float, float, float]:
    """r = the centre of gravity from the body origin (m, world frame)."""
    return _rot(R, ipos[i, 0], ipos[i, 1], ipos[i, 2])


@njit(cache=True)
def gather(dof: np.ndarray, qadr: np.ndarray, ids: np.ndarray, ipos: np.ndarray, ref: np.ndarray,
           frame: np.ndarray, gvec: np.ndarray, mu: np.ndarray, mus: np.ndarray, geom_row: np.ndarray, plane: int,
           qpos: np.ndarray, qvel: np.ndarray, qfrc_constraint: np.ndarray, xfrc: np.ndarray, efc_force: np.ndarray,
           cg1: np.ndarray, cg2: np.ndarray, cefc: np.ndarray, ncon: int, bodies: np.ndarray, got: np.ndarray,
           load: np.ndarray, dt: float) -> None:
    """Fill ``got`` (rows angle, vx, vy, w, fx, fy, torque: the in-plane state and the load, as the plugin
    kernel reads pymunk) and each body's normal load ``load`` (N: the sum of MuJoCo's normal forces of
    its contacts with the plane geom ``plane`` in its last step), and set the kernel's FRICTION_COEFF and STATIC_COEFF
    (mu N / m and mu_static N / m, m/s^2). The load in ``got`` is every force but friction in the
    plane: gravity's in-plane part, the user's ``xfrc_applied``, and the other constraints' forces of
    the last step (a finger's push), force at the centre of gravity and torque about it.

    Per body i: ``dof[i]``, ``qadr[i]`` its free joint's qvel and qpos addresses, ``ids[i]`` its MuJoCo
    body id, ``ipos[i]`` its centre of gravity in its own frame (m), ``ref[i]`` the body-frame vector
    along t1 at angle 0."""
    n = dof.shape[0]
    for i in range(n):
        load[i] = 0.0
    for k in range(ncon):
        if cg1[k] == plane:
            other = cg2[k]
        elif cg2[k] == plane:
            other = cg1[k]
        else:
            continue
        row = geom_row[other]
        if row >= 0 and cefc[k] >= 0:
            load[row] += efc_force[cefc[k]]  # condim 1: the contact's one row is its normal force
    t1x, t1y, t1z = frame[0, 0], frame[0, 1], frame[0, 2]
    t2x, t2y, t2z = frame[1, 0], frame[1, 1], frame[1, 2]
    nx, ny, nz = frame[2, 0], frame[2, 1], frame[2, 2]
    for i in range(n):
        a = dof[i]
        b = ids[i]
        R = _mat(qpos, qadr[i] + 3)
        m = bodies[i, K.MASS]
        nl = max(load[i], 0.0)
        bodies[i, K.FRICTION_COEFF] = mu[i] * nl / m
        bodies[i, K.STATIC_COEFF] = mus[i] * nl / m
        wx, wy, wz = _rot(R, qvel[a + 3], qvel[a + 4], qvel[a + 5])
        rx, ry, rz = _offset(i, R, ipos)
        # the centre of gravity's velocity: the origin's plus w x r
        vx = qvel[a] + wy * rz - wz * ry
        vy = qvel[a + 1] + wz * rx - wx * rz
        vz = qvel[a + 2] + wx * ry - wy * rx
        ex, ey, ez = _rot(R, ref[i, 0], ref[i, 1], ref[i, 2])
        got[i, 0] = math.atan2(ex * t2x + ey * t2y + ez * t2z, ex * t1x + ey * t1y + ez * t1z)
        got[i, 1] = vx * t1x + vy * t1y + vz * t1z
        got[i, 2] = vx * t2x + vy * t2y + vz * t2z
        got[i, 3] = wx * nx + wy * ny + wz * nz
        if math.hypot(got[i, 1], got[i, 2]) + abs(got[i, 3]) * bodies[i, K.REACH] \
                <= RESIDUE * bodies[i, K.FRICTION_COEFF] * dt:
            # what MuJoCo's step leaves of a body the rest rule has zeroed (its normal contacts' solver,
            # the tipping it keeps): at rest, as for the plugin, whose bodies pymunk leaves exactly at rest
            got[i, 1] = 0.0
            got[i, 2] = 0.0
            got[i, 3] = 0.0
        # MuJoCo moves the velocity first, then the positions with it: its qvel after a step belongs to half
        # a step before data.time (pymunk's to half a step after), so friction for the coming step acts at
        # the current angle, which the kernel reaches from this one by its prediction alpha + w dt
        got[i, 0] -= got[i, 3] * dt
        qx = qfrc_constraint[a]
        qy = qfrc_constraint[a + 1]
        qz = qfrc_constraint[a + 2]
        fx = m * gvec[0] + xfrc[b, 0] + qx
        fy = m * gvec[1] + xfrc[b, 1] + qy
        fz = m * gvec[2] + xfrc[b, 2] + qz
        cx, cy, cz = _rot(R, qfrc_constraint[a + 3], qfrc_constraint[a + 4], qfrc_constraint[a + 5])
        # the constraints' torque about the origin, moved to the centre of gravity: - r x F_c
        cx -= ry * qz - rz * qy
        cy -= rz * qx - rx * qz
        cz -= rx * qy - ry * qx
        lx = fx * t1x + fy * t1y + fz * t1z
        ly = fx * t2x + fy * t2y + fz * t2z
        lt = (xfrc[b, 3] + cx) * nx + (xfrc[b, 4] + cy) * ny + (xfrc[b, 5] + cz) * nz
        small = RESIDUE * m * bodies[i, K.STATIC_COEFF]
        if math.hypot(lx, ly) <= small and abs(lt) <= small * bodies[i, K.REACH]:
            lx = ly = lt = 0.0  # the rounding of the constraint forces, not a load: the static test is then free
        got[i, 4] = lx
        got[i, 5] = ly
        got[i, 6] = lt


@njit(cache=True)
def set_planar(i: int, vx: float, vy: float, w: float, dof: np.ndarray, qadr: np.ndarray, ipos: np.ndarray,
               frame: np.ndarray, qpos: np.ndarray, qvel: np.ndarray) -> None:
    """Set body i's in-plane velocity of its centre of gravity to (vx, vy) (m/s, along t1, t2) and its
    spin about the normal to w (rad/s), keeping the rest of its motion (along the normal, tipping)."""
    a = dof[i]
    R = _mat(qpos, qadr[i] + 3)
    wx, wy, wz = _rot(R, qvel[a + 3], qvel[a + 4], qvel[a + 5])
    rx, ry, rz = _offset(i, R, ipos)
    ux = qvel[a] + wy * rz - wz * ry
    uy = qvel[a + 1] + wz * rx - wx * rz
    uz = qvel[a + 2] + wx * ry - wy * rx
    du1 = vx - (ux * frame[0, 0] + uy * frame[0, 1] + uz * frame[0, 2])
    du2 = vy - (ux * frame[1, 0] + uy * frame[1, 1] + uz * frame[1, 2])
    dw = w - (wx * frame[2, 0] + wy * frame[2, 1] + wz * frame[2, 2])
    ux += du1 * frame[0, 0] + du2 * frame[1, 0]
    uy += du1 * frame[0, 1] + du2 * frame[1, 1]
    uz += du1 * frame[0, 2] + du2 * frame[1, 2]
    wx += dw * frame[2, 0]
    wy += dw * frame[2, 1]
    wz += dw * frame[2, 2]
    # back to the origin's velocity, and the spin to the body frame
    qvel[a] = ux - (wy * rz - wz * ry)
    qvel[a + 1] = uy - (wz * rx - wx * rz)
    qvel[a + 2] = uz - (wx * ry - wy * rx)
    qvel[a + 3], qvel[a + 4], qvel[a + 5] = _rot_t(R, wx, wy, wz)


@njit(cache=True)
def scatter(dof: np.ndarray, qadr: np.ndarray, ids: np.ndarray, ipos: np.ndarray, frame: np.ndarray,
            bodies: np.ndarray, qpos: np.ndarray, qvel: np.ndarray, xfrc: np.ndarray, user: np.ndarray,
            got: np.ndarray, moving: np.ndarray, t_stop: np.ndarray, t: float, dt: float) -> int:
    """After the plugin kernel: add each body's friction (its FRICTION_FX, FRICTION_FY, FRICTION_TORQUE: in-plane force,
    N, and torque about the normal, N m) to ``xfrc_applied``, keeping the user's own rows in ``user`` (put back
    after the step, bit for bit: :func:`unapply`), and set exactly zero the in-plane motion of the bodies the
    rest rule zeroes. Stops: the rest rule's in this step, or (the limiter's impulse having left only
    MuJoCo's residue, read as rest) in the last one; ``got``'s velocities belong to t - dt/2, so the stop
    lies within half a step of t + dt/2 (the rest rule) or t - dt/2, written to ``t_stop`` (s).
    ``moving`` keeps whether each body moved at this read. Returns the number of new stops."""
    n_new = 0
    for i in range(dof.shape[0]):
        b = ids[i]
        f1 = bodies[i, K.FRICTION_FX]
        f2 = bodies[i, K.FRICTION_FY]
        tq = bodies[i, K.FRICTION_TORQUE]
        for c in range(6):
            user[i, c] = xfrc[b, c]
        for c in range(3):
            xfrc[b, c] += f1 * frame[0, c] + f2 * frame[1, c]
            xfrc[b, 3 + c] += tq * frame[2, c]
        stop = bodies[i, K.STOP]
        if stop == K.ZEROED:
            set_planar(i, 0.0, 0.0, 0.0, dof, qadr, ipos, frame, qpos, qvel)
        now = got[i, 1] != 0.0 or got[i, 2] != 0.0 or got[i, 3] != 0.0
        if stop == K.STOPPING:
            t_stop[i] = t + 0.5 * dt
            n_new += 1
        elif moving[i] and not now:
            t_stop[i] = t - 0.5 * dt
            n_new += 1
        moving[i] = now
    return n_new


@njit(cache=True)
def unapply(ids: np.ndarray, xfrc: np.ndarray, user: np.ndarray) -> None:
    """Put the user's own ``xfrc_applied`` rows back after the step (:func:`scatter` kept them)."""
    for i in range(ids.shape[0]):
        for c in range(6):
            xfrc[ids[i], c] = user[i, c]


@njit(cache=True)
def hold(dof: np.ndarray, qadr: np.ndarray, ipos: np.ndarray, frame: np.ndarray, ref: np.ndarray, reach: np.ndarray,
         com0: np.ndarray, yaw0: np.ndarray, qpos: np.ndarray, qvel: np.ndarray, last: np.ndarray) -> float:
    """Hold each body in the plane (:mod:`rrbody.mujoco_adapter.seat`, on a copy of MuJoCo's data): put its centre of
    gravity's position along t1, t2 back to ``com0[i]`` (m, world) and its angle about the normal back to ``yaw0[i]``
    (rad, measured as :func:`gather` does), and zero its in-plane velocity and spin, keeping its motion along the
    normal and in its tilt. ``last[i]`` keeps (the centre of gravity along n, the normal in the body frame);
    returns the most any body moved since the last call along the normal plus its tilt times ``reach[i]`` (m)."""
    nx, ny, nz = frame[2, 0], frame[2, 1], frame[2, 2]
    most = 0.0
    for i in range(dof.shape[0]):
        p = qadr[i] + 3
        R = _mat(qpos, p)
        ex, ey, ez = _rot(R, ref[i, 0], ref[i, 1], ref[i, 2])
        yaw = math.atan2(ex * frame[1, 0] + ey * frame[1, 1] + ez * frame[1, 2],
                         ex * frame[0, 0] + ey * frame[0, 1] + ez * frame[0, 2])
        half = -0.5 * (yaw - yaw0[i])
        c, s = math.cos(half), math.sin(half)
        w, x, y, z = qpos[p], qpos[p + 1], qpos[p + 2], qpos[p + 3]
        # turned back about n (world frame): (cos, sin n) q
        w, x, y, z = (c * w - s * (nx * x + ny * y + nz * z), c * x + s * (nx * w + ny * z - nz * y),
                      c * y + s * (ny * w - nx * z + nz * x), c * z + s * (nz * w + nx * y - ny * x))
        k = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
        qpos[p], qpos[p + 1], qpos[p + 2], qpos[p + 3] = w * k, x * k, y * k, z * k
        R = _mat(qpos, p)
        rx, ry, rz = _offset(i, R, ipos)
        ox = com0[i, 0] - qpos[p - 3] - rx
        oy = com0[i, 1] - qpos[p - 2] - ry
        oz = com0[i, 2] - qpos[p - 1] - rz
        on = ox * nx + oy * ny + oz * nz
        qpos[p - 3] += ox - on * nx
        qpos[p - 2] += oy - on * ny
        qpos[p - 1] += oz - on * nz
        set_planar(i, 0.0, 0.0, 0.0, dof, qadr, ipos, frame, qpos, qvel)
        h = (qpos[p - 3] + rx) * nx + (qpos[p - 2] + ry) * ny + (qpos[p - 1] + rz) * nz
        ux, uy, uz = _rot_t(R, nx, ny, nz)
        moved = abs(h - last[i, 0]) + reach[i] * math.sqrt((ux - last[i, 1]) ** 2 + (uy - last[i, 2]) ** 2
                                                           + (uz - last[i, 3]) ** 2)
        most = max(most, moved)
        last[i, 0], last[i, 1], last[i, 2], last[i, 3] = h, ux, uy, uz
    return most
