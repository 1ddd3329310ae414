"""Re-seating the MuJoCo adapter's bodies (:mod:`rrbody.mujoco_adapter.plane`): the switch of the plane's contacts to
their normal row moves the pose at which MuJoCo's soft contacts hold a body at rest, so each body touching the
plane when the adapter is built is moved by that change before its first step.

Why it moves: MuJoCo's soft contact holds a body at the depth where the constraint's regularisation R balances
its weight, and R depends on the contact's parameters. A pyramidal cone gives each of its 2 (condim - 1) edges
R = 2 mu^2 R_n (``mj_makeImpedance``), so its normal stiffness goes as 1/mu^2 (equal to the normal row's at
mu = 1: a 0.2 m box 2 cm thick rests 17 um deep at mu 0.5 and 108 um with the normal row alone); and the
plane's priority replaces the mix of the two geoms' ``solref``/``solimp`` with the plane's own. A body settled
under the old contacts would sink or rise to the new depth over a few of the contact's time constants, its
normal force, which rrbody's friction reads, swinging with it.

How: on a copy of ``data`` (``data`` itself is not stepped), every adapter body is held in the plane (its centre
of gravity's in-plane position and its angle about the normal put back, its in-plane velocity and spin zeroed,
after each ``mj_step``) while MuJoCo settles it along the normal and in its tilt, first under the contacts as they
were, then under the switched ones. Each body touching the plane is moved by the difference of the two resting
poses: its centre of gravity along the normal and its tilt (a rotation about an in-plane axis), its in-plane pose
and its velocities (world frame) kept. A settled body so starts settled; one still settling keeps its offset from
its resting pose, as if the contacts had always been normal-only.
"""

from __future__ import annotations

import copy
import math
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from rrbody.model.extras import require
from rrbody.mujoco_adapter import kernel as MK

mujoco = require("mujoco", purpose="the MuJoCo adapter (rrbody.mujoco)")

__all__ = ["reseat", "SEAT_DECAYS", "SEAT_SPEED", "SEAT_MAX_STEPS"]

#: how long the copy settles, in the slowest decay time of the plane contacts' closed loop (e^-30: the
#: settling's own remainder, far below the solver's tolerance)
SEAT_DECAYS = 30.0
#: an earlier end: every body moves along the normal (and in its tilt, times its reach) slower than this
#: (m/s; with a decay time of 0.02 s a remainder of 2e-12 m)
SEAT_SPEED = 1e-10
#: the most steps the copy takes (a warning says when the horizon needed more)
SEAT_MAX_STEPS = 100_000


def _mats(q: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation matrices of (n, 4) quaternions (w, x, y, z)."""
    w, x, y, z = q.T
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return np.stack([1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),
                     s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x),
                     s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y)], axis=1).reshape(-1, 3, 3)


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Quaternion products a b, row by row."""
    aw, ax, ay, az = a.T
    bw, bx, by, bz = b.T
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=1)


def _conj(q: np.ndarray) -> np.ndarray:
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def _swing(q: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The part of rotations q (world frame) about axes in the plane: q without its twist about n."""
    v = q[:, 1:] @ n
    twist = np.column_stack([q[:, 0], v[:, None] * n])
    norm = np.linalg.norm(twist, axis=1)
    twist = np.where(norm[:, None] > 0.0, twist / np.where(norm > 0.0, norm, 1.0)[:, None], [1.0, 0.0, 0.0, 0.0])
    return _qmul(q, _conj(twist))


def _decay_time(m: Any, d: Any, plane: int) -> float:
    """The slowest decay time (s) of the plane contacts' closed loop a + imp (b v + k r) = 0 (MuJoCo's soft
    constraint, its ``solref`` and ``solimp`` as the contacts hold them; the lowest impedance), 0 with no
    contact."""
    ncon = int(d.ncon)
    if not ncon:
        return 0.0
    c = d.contact
    on = (np.asarray(c.geom1[:ncon]) == plane) | (np.asarray(c.geom2[:ncon]) == plane)
    if not on.any():
        return 0.0
    ref, imp = np.array(c.solref[:ncon][on]), np.array(c.solimp[:ncon][on])
    if m.opt.enableflags & mujoco.mjtEnableBit.mjENBL_OVERRIDE:
        ref[:], imp[:] = m.opt.o_solref, m.opt.o_solimp
    slowest = 0.0
    for (r0, r1), (d0, d1, *_rest) in zip(ref, imp):
        width = max(d1, 1e-15)
        if r0 > 0.0:  # standard: time constant and damping ratio (MuJoCo's floor of two steps)
            if not m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_REFSAFE:
                r0 = max(r0, 2.0 * m.opt.timestep)
            k, b = 1.0 / max(width * width * r0 * r0 * r1 * r1, 1e-300), 2.0 / max(width * r0, 1e-300)
        else:  # direct: stiffness and damping
            k, b = -r0 / (width * width), -r1 / width
        g = max(min(d0, d1), 1e-15)
        disc = (g * b) ** 2 - 4.0 * g * k
        rate = 0.5 * g * b if disc < 0.0 else 0.5 * (g * b - math.sqrt(disc))
        if rate > 0.0:
            slowest = max(slowest, 1.0 / rate)
    return slowest


def _settle(m: Any, d: Any, plane: int, rows: tuple, com0: np.ndarray, yaw0: np.ndarray,
            quat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step the copy ``d``, the bodies held in the plane, until they rest along the normal; their resting
    centres of gravity along the normal (m) and orientations (quaternions)."""
    last = np.full((com0.shape[0], 4), np.nan)
    MK.hold(*rows, com0, yaw0, d.qpos, d.qvel, last)
    mujoco.mj_forward(m, d)
    dt = float(m.opt.timestep)
    horizon = SEAT_DECAYS * _decay_time(m, d, plane)
    steps = math.ceil(horizon / dt)
    if steps > SEAT_MAX_STEPS:
        warnings.warn(f"PlaneFriction: the plane's contacts settle in {horizon:.3g} s, {steps} steps of "
                      f"{dt:g} s; the bodies on it were settled for {SEAT_MAX_STEPS} steps only, so they may "
                      f"still sink or rise a little under the normal-only contacts", RuntimeWarning, stacklevel=4)
        steps = SEAT_MAX_STEPS
    for _ in range(steps):
        mujoco.mj_step(m, d)
        if MK.hold(*rows, com0, yaw0, d.qpos, d.qvel, last) <= SEAT_SPEED * dt:
            break
    return last[:, 0].copy(), d.qpos[quat].copy()


def reseat(m: Any, d: Any, *, plane: int, ids: np.ndarray, dof: np.ndarray, qadr: np.ndarray, ipos: np.ndarray,
           frame: np.ndarray, ref: np.ndarray, reach: np.ndarray, switch: Callable[[], None]) -> np.ndarray:
    """Call ``switch()`` (it changes the plane's contacts) and move the bodies (MuJoCo ids ``ids``) that touch the
    plane by the change it makes to their resting poses (module docstring). ``d`` is changed only there: the
    bodies' positions and orientations, their velocities kept in the world frame. Returns which bodies moved."""
    mujoco.mj_forward(m, d)
    ncon = int(d.ncon)
    g1, g2 = np.asarray(d.contact.geom1[:ncon]), np.asarray(d.contact.geom2[:ncon])
    other = np.concatenate([g2[g1 == plane], g1[g2 == plane]])
    touch = np.isin(ids, m.geom_bodyid[other])
    if not touch.any():  # nothing touches the plane: nothing for the switch to unsettle
        switch()
        return touch
    n = frame[2]
    quat = qadr[:, None] + np.arange(3, 7)
    R = _mats(d.qpos[quat])
    com0 = d.qpos[qadr[:, None] + np.arange(3)] + np.einsum("nij,nj->ni", R, ipos)
    e = np.einsum("nij,nj->ni", R, ref)
    yaw0 = np.arctan2(e @ frame[1], e @ frame[0])
    rows = (dof, qadr, ipos, frame, ref, reach)
    scratch = copy.copy(d)  # settled on a copy: your data is not stepped
    h_old, q_old = _settle(m, scratch, plane, rows, com0, yaw0, quat)
    switch()
    h_new, q_new = _settle(m, scratch, plane, rows, com0, yaw0, quat)
    # the touching bodies moved by the change: the centre of gravity along n, the tilt about an in-plane axis
    k = np.flatnonzero(touch)
    tilt = _swing(_qmul(q_new[k], _conj(q_old[k])), n)
    w = np.einsum("nij,nj->ni", R[k], d.qvel[dof[k, None] + np.arange(3, 6)])
    v = d.qvel[dof[k, None] + np.arange(3)] + np.cross(w, np.einsum("nij,nj->ni", R[k], ipos[k]))
    q = _qmul(tilt, d.qpos[quat[k]])
    q /= np.linalg.norm(q, axis=1)[:, None]
    R1 = _mats(q)
    r1 = np.einsum("nij,nj->ni", R1, ipos[k])
    d.qpos[quat[k]] = q
    d.qpos[qadr[k, None] + np.arange(3)] = com0[k] + np.outer(h_new[k] - h_old[k], n) - r1
    d.qvel[dof[k, None] + np.arange(3)] = v - np.cross(w, r1)
    d.qvel[dof[k, None] + np.arange(3, 6)] = np.einsum("nji,nj->ni", R1, w)
    return touch
