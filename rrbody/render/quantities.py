"""Mechanical quantities along a run, for pictures: friction force and torque, energy, powers.

Everything is computed from the trajectory's own samples (CM velocity, body angle, spin) with the
scene's own friction kernel, :func:`rrbody.friction.body_wrench` (the function both integrator
paths call), so a number shown beside the motion is the model's number, not a re-derivation.

Per unit mass (the mass cancels everywhere in rrbody): forces in m/s^2 (= N/kg), torques about the
CM in m^2/s^2, energies in J/kg, powers in W/kg; world frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rrbody.model.trajectory import Trajectory

__all__ = ["Mechanics", "mechanics"]


@dataclass(frozen=True)
class Mechanics:
    """Per-sample arrays (same length as the trajectory), per unit mass.

    ``fx, fy``: friction force on the body (m/s^2); ``tau_cm``: friction torque about the CM
    (m^2/s^2); ``kinetic``: 1/2 v_cm . v_cm + 1/2 (I_cm/m) spin^2 (J/kg); ``friction_power``:
    F . v_cm + tau_cm spin (W/kg, <= 0: friction only removes energy); ``dissipated``: the
    energy friction has removed since the first sample, the integral of -friction_power by the
    trapezoidal rule on the samples (J/kg).
    """

    fx: np.ndarray
    fy: np.ndarray
    tau_cm: np.ndarray
    kinetic: np.ndarray
    friction_power: np.ndarray
    dissipated: np.ndarray


def mechanics(traj: Trajectory) -> Mechanics | None:
    """The run's friction wrench and energies, or None without a scene description in ``traj.meta``."""
    from rrbody.model.scene import Scene
    from rrbody.physics.bind import kernel_params
    from rrbody.physics.wrench import body_wrench

    sc = traj.meta.get("scene") or {}
    if "body" not in sc:
        return None
    scene = Scene.from_description(sc)
    p, S = kernel_params(scene)
    n = len(traj)
    vx, vy = np.asarray(traj.vx_cm, float), np.asarray(traj.vy_cm, float)
    spin, ang = np.asarray(traj.spin, float), np.asarray(traj.body_angle, float)
    F = np.zeros((n, 3))
    if scene.friction.active:
        for i in range(n):  # one compiled kernel call per sample, the run's own friction: no second code path
            F[i] = body_wrench(p, S, float(ang[i]), float(vx[i]), float(vy[i]), float(spin[i]))
    kinetic = 0.5 * (vx * vx + vy * vy) + 0.5 * scene.body.inertia_per_mass * spin * spin
    power = F[:, 0] * vx + F[:, 1] * vy + F[:, 2] * spin
    t = np.asarray(traj.t, float)
    dissipated = np.concatenate([[0.0], np.cumsum(-0.5 * (power[1:] + power[:-1]) * np.diff(t))])
    return Mechanics(F[:, 0].copy(), F[:, 1].copy(), F[:, 2].copy(), kinetic, power, dissipated)
