"""Free bodies: no drive; a body launched with a CM velocity and a spin slides to rest under friction.

State y = (x, y, alpha, vx, vy, Omega): CM position (m, world frame, starting at the origin), body
angle (rad), CM velocity (m/s) and spin (rad/s); equations in :func:`rrbody.dynamics.free_rhs`
(friction wrench from :func:`rrbody.friction.body_wrench`: point, sampled area or ICR quadrature).

Stopping (dry friction)
-----------------------
Coulomb friction stops a body in finite time, with a discontinuous right-hand side at rest. The
compiled DOP853 loop below stops it exactly and cleanly:

- kinetic energy per unit mass K = (v^2 + (I_cm/m) Omega^2)/2 and dissipated power P = -(F.v + tau Omega)
  give the time left before rest if the decelerations stay as they are: tau_left = 2 K / P
  (exact for a point mass, and asymptotically for any body, whose approach to rest is self-similar:
  v and Omega both decay linearly with a fixed ratio). Steps are capped at ``STEP_FRACTION`` of
  tau_left, so the integration approaches the stop geometrically and never steps across it;
- a step that would raise K or reverse the velocity or the spin is rejected and halved;
- once sqrt(2 K) falls below ``STOP_SPEED_FRACTION`` of its initial value, the last 2K/P seconds
  are completed analytically (linear decay: distance v tau/2, turn Omega tau/2), velocities are
  set to exactly zero and stay there. The stop time is reported in ``events['t_stop']``.

A point mass has no rotational inertia: its spin is kinematic only (kept as given while it slides)
and set to zero when it stops. Viscous friction decays exponentially and never stops: t_stop is None.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit

from rrbody.physics.bind import kernel_params
from rrbody._version import __version__
from rrbody.physics import params as P
from rrbody.integrate.dop853 import TABLEAU, error_norm, rk_step, step_factor
from rrbody.physics.dynamics import SYSTEM_FREE, free_rhs
from rrbody.model.scene import Scene
from rrbody.model.trajectory import Trajectory

__all__ = ["simulate_free", "STEP_FRACTION", "STOP_SPEED_FRACTION"]

#: steps are capped at this fraction of the estimated time to rest 2K/P
STEP_FRACTION: float = 0.5
#: the last stretch (speed below this fraction of the initial one) is completed analytically
STOP_SPEED_FRACTION: float = 1e-11

_T, _H, _NSTEP, _NREJ, _NOUT, _NEXTOUT, _TSTOP, _REJ = range(8)
_ST_SIZE = 8


@njit(cache=True, inline="always")
def _energy_power(y, f, icm):  # noqa: ANN001
    """Kinetic energy per unit mass (m^2/s^2) and dissipated power per unit mass (m^2/s^3)."""
    k = 0.5 * (y[3] * y[3] + y[4] * y[4] + icm * y[5] * y[5])
    pw = -(f[3] * y[3] + f[4] * y[4] + icm * f[5] * y[5])
    return k, pw


@njit(cache=True)
def _advance_free(y, f, st, p, S, t_end, scale, dry, u_stop, max_steps, out, dt_out,  # noqa: ANN001
                  A, B, C, E3, E5):
    """Advance the free body until t_end, rest, or max_steps accepted steps.

    Returns 0 (t_end), 1 (stopped), 3 (max_steps), 4 (step underflow)."""
    n = 6
    K = np.empty((13, n))
    K2 = np.empty((13, n))
    ynew = np.empty(n)
    y2 = np.empty(n)
    ytmp = np.empty(n)
    icm = p[P.ICM]
    t = st[_T]
    h = st[_H]
    steps = 0
    while True:
        if t >= t_end:
            st[_T] = t
            st[_H] = h
            return 0
        if steps >= max_steps:
            st[_T] = t
            st[_H] = h
            return 3
        kin, pw = _energy_power(y, f, icm)
        if dry and math.sqrt(2.0 * kin) <= u_stop:
            # complete the last stretch analytically (uniform deceleration) and come to rest
            tau = 2.0 * kin / pw if pw > 0.0 else 0.0
            ts = t + tau
            if dt_out > 0.0:
                while st[_NEXTOUT] <= t_end and st[_NOUT] < out.shape[0]:
                    k = int(st[_NOUT])
                    to = st[_NEXTOUT]
                    dtl = min(max(to - t, 0.0), tau)
                    frac = 1.0 - dtl / tau if tau > 0.0 else 0.0
                    out[k, 0] = to
                    out[k, 1] = y[0] + y[3] * dtl * (1.0 - 0.5 * dtl / tau if tau > 0.0 else 0.0)
                    out[k, 2] = y[1] + y[4] * dtl * (1.0 - 0.5 * dtl / tau if tau > 0.0 else 0.0)
                    out[k, 3] = y[2] + y[5] * dtl * (1.0 - 0.5 * dtl / tau if tau > 0.0 else 0.0)
                    out[k, 4] = y[3] * frac
                    out[k, 5] = y[4] * frac
                    out[k, 6] = y[5] * frac if icm > 0.0 else 0.0
                    st[_NOUT] += 1
                    st[_NEXTOUT] = st[_NOUT] * dt_out
            y[0] += 0.5 * y[3] * tau
            y[1] += 0.5 * y[4] * tau
            y[2] += 0.5 * y[5] * tau
            y[3] = 0.0
            y[4] = 0.0
            y[5] = 0.0
            st[_TSTOP] = ts
            st[_T] = t_end
            return 1
        hh = min(h, t_end - t)
        if dry and pw > 0.0:
            hh = min(hh, STEP_FRACTION * 2.0 * kin / pw)
        if hh <= 1e-15 * max(1.0, abs(t)):
            st[_T] = t
            st[_H] = h
            return 4
        rk_step(SYSTEM_FREE, t, y, f, hh, p, S, A, B, C, K, ynew, ytmp)
        err = error_norm(K, hh, scale, E3, E5)
        rejected = st[_REJ] != 0.0
        bad = False
        if dry:
            kin_new = 0.5 * (ynew[3] * ynew[3] + ynew[4] * ynew[4] + icm * ynew[5] * ynew[5])
            # friction cannot raise the energy nor reverse a sliding velocity or a spin in one go
            if kin_new > kin * (1.0 + 1e-14):
                bad = True
            if y[3] * ynew[3] + y[4] * ynew[4] < 0.0:
                bad = True
            if icm > 0.0 and y[5] * ynew[5] < 0.0:
                bad = True
        if bad or err >= 1.0:
            h = hh * (0.5 if bad else step_factor(err, rejected))
            st[_REJ] = 1.0
            st[_NREJ] += 1
            continue
        # dense output on the fixed grid, by re-stepping from the step start
        if dt_out > 0.0:
            while st[_NEXTOUT] <= t + hh and st[_NOUT] < out.shape[0]:
                ho = st[_NEXTOUT] - t
                k = int(st[_NOUT])
                out[k, 0] = st[_NEXTOUT]
                if ho <= 0.0:
                    for j in range(n):
                        out[k, 1 + j] = y[j]
                else:
                    rk_step(SYSTEM_FREE, t, y, f, ho, p, S, A, B, C, K2, y2, ytmp)
                    for j in range(n):
                        out[k, 1 + j] = y2[j]
                st[_NOUT] += 1
                st[_NEXTOUT] = st[_NOUT] * dt_out
        t = t + hh
        for j in range(n):
            y[j] = ynew[j]
            f[j] = K[12, j]
        steps += 1
        st[_NSTEP] += 1
        st[_REJ] = 0.0
        h = hh * step_factor(err, rejected)


def simulate_free(scene: Scene, *, t_max: float, dt_out: float, rtol: float = 1e-10, max_steps: int = 50_000_000,
                  progress: bool = False) -> Trajectory:
    """Integrate a free (undriven) scene from t = 0 to ``t_max`` (s), sampled every ``dt_out`` (s).

    The CM starts at the origin with velocity ``scene.v0`` (m/s, world frame), the body angle at
    ``scene.body.alpha0`` with spin ``scene.spin0`` (rad/s); P (for the phi / x_p, y_p columns) is
    the body point at distance l along the direction ``phi0`` at t = 0. ``events['t_stop']`` is
    the time of rest (s; None if the body still moves at ``t_max``), ``events['stop_position']``
    the CM there (m). ``rtol`` scales the error control: positions by the sliding distance scale,
    velocities by the initial speed, angles by pi, spin by the initial rotation rate.
    """
    if scene.driven:
        raise ValueError("simulate_free needs a free scene (drive=None); use rrbody.simulate for driven ones")
    A, B, C, E3, E5 = TABLEAU
    p, S = kernel_params(scene)
    body = scene.body
    icm = body.inertia_per_mass
    rmax = max(body.semi_axes)
    v0 = np.array(scene.v0, dtype=np.float64)
    w0 = scene.spin0
    y = np.array([0.0, 0.0, body.alpha0, v0[0], v0[1], w0])
    f = np.empty(6)
    free_rhs(0.0, y, p, S, f)
    dry = scene.friction.active and scene.friction.law == "dry"
    # speed scale: translation plus rotation (gyration radius for bodies with inertia)
    u0 = math.hypot(v0[0], v0[1]) + math.sqrt(icm) * abs(w0)
    decel = scene.friction.coeff if dry else (scene.friction.coeff * max(u0, 1e-300) if scene.friction.active else 0.0)
    t_scale = min(t_max, u0 / decel) if decel > 0.0 and u0 > 0.0 else t_max
    length = max(rmax, u0 * t_scale, 1e-300)
    wscale = max(abs(w0), u0 / max(rmax, 1e-300) if rmax > 0.0 else abs(w0), 1e-300)
    uscale = max(u0, wscale * rmax, 1e-300)
    scale = rtol * np.array([length, length, math.pi, uscale, uscale, wscale])
    st = np.zeros(_ST_SIZE)
    st[_TSTOP] = np.nan
    rates = [r for r in (abs(w0), decel / max(u0, 1e-300) if decel > 0 else 0.0) if r > 0.0]
    st[_H] = 1e-3 / max(rates) if rates else t_max
    n_out = int(math.floor(t_max / dt_out + 1e-9)) + 1
    out = np.empty((n_out, 7))
    # above the kernels' zero-speed threshold v_eps, below which dry friction is switched off
    u_stop = max(STOP_SPEED_FRACTION * max(u0, 1e-300), 10.0 * p[P.VEPS])
    t0 = time.perf_counter()
    status = 0
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=t_max, desc="free body", unit="s(sim)", leave=False, dynamic_ncols=True)
    try:
        if u0 == 0.0 and dry:
            st[_TSTOP] = 0.0
            status = 1
            out[:, 0] = np.arange(n_out) * dt_out
            out[:, 1:] = y
            out[:, 4:7] = 0.0
            st[_NOUT] = n_out
        else:
            chunk = 200_000
            while True:
                left = max_steps - int(st[_NSTEP])
                if left <= 0:
                    status = 3
                    break
                before = st[_T]
                status = _advance_free(y, f, st, p, S, t_max, scale, dry, u_stop, min(chunk, left), out, dt_out,
                                       A, B, C, E3, E5)
                if bar is not None:
                    bar.update(st[_T] - before)
                if status != 3 or int(st[_NSTEP]) >= max_steps:
                    break
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0
    n_done = int(st[_NOUT])
    if status == 1 and n_done < n_out:
        # at rest: the remaining samples repeat the final state exactly (no drift)
        rest = np.empty((n_out - n_done, 7))
        rest[:, 0] = np.arange(n_done, n_out) * dt_out
        rest[:, 1:] = y
        out[n_done:] = rest
        n_done = n_out
    o = out[:n_done]
    if status in (0, 1) and (n_done == 0 or t_max - o[-1, 0] > 1e-9 * dt_out):
        o = np.vstack([o, np.concatenate([[t_max], y])])  # end on the horizon asked for (issue 13)
    t = o[:, 0]
    alpha = o[:, 3]
    beta = scene.phi0 - body.alpha0
    phi = alpha + beta
    l = body.l
    traj = Trajectory(t=t, phi=phi, phi_dot=o[:, 6].copy(), x_cm=o[:, 1], y_cm=o[:, 2], vx_cm=o[:, 4], vy_cm=o[:, 5],
                      x_p=o[:, 1] + l * np.cos(phi), y_p=o[:, 2] + l * np.sin(phi), body_angle=alpha,
                      spin=o[:, 6].copy(), meta={"scene": scene.describe(), "rrbody_version": __version__})
    stopped = status == 1 and math.isfinite(st[_TSTOP])
    statuses = {0: "reached t_end", 1: "came to rest", 3: "max_steps reached", 4: "step size underflow"}
    traj.events = {
        "t_stop": float(st[_TSTOP]) if stopped and st[_TSTOP] <= t_max else None,
        "stop_position": [float(y[0]), float(y[1])] if stopped else None,
        "distance": float(math.hypot(y[0], y[1])) if stopped else None,
        "turn": float(y[2] - body.alpha0) if stopped else None,
    }
    traj.meta = {**traj.meta, "method": "ode", "rtol": rtol, "status": statuses.get(status, str(status)),
                 "n_steps": int(st[_NSTEP]), "n_rejected": int(st[_NREJ]), "wall_s": wall}
    if status in (3, 4):
        traj.meta["warning"] = f"integration stopped early: {statuses[status]} at t={st[_T]:.6g} s"
    return traj
