"""Effect ``active``: self-propulsion fixed in the body frame, a medium's drag, Langevin noise.

The model is :mod:`rrbody.model.active` (:class:`rrbody.model.active.Active`). This module holds
what both paths compile: the layout of the plugin's ``active`` array (one row per plugin body, a
row of zeros for a body that is not active) and the per-body load :func:`load` that
:func:`rrbody.contact.kernel.plane_step` adds to each body's force where a tilt's pull is added,
before friction is evaluated (so the limiter, the rest rule and static friction see it as a load);
and, for one free body on the ODE path, :func:`ode_terms`, the same deterministic terms for its
right-hand side (:mod:`rrbody.physics.dynamics`; parameters in ``p``, :mod:`rrbody.physics.params`), and
:func:`ode_noise`, the noise's additive scales on the velocity and the spin, which the fixed-step
scheme of :mod:`rrbody.integrate.sde` adds (docs/active.md, "Noise on the ODE path").

Time stepping on the plugin path (docs/active.md)
-------------------------------------------------
pymunk moves positions with the velocity, then kicks the velocity (the staggered scheme of
docs/engine.md: the velocity read at a step belongs to half a step before the force). The
propulsion acts at the angle alpha + w dt and the drag at the velocity extrapolated from the last
two steps, both at the time friction is evaluated: second order in dt for the deterministic part.
The noise is Euler-Maruyama on the velocities: a force m gamma_t sqrt(2 D_t / dt) xi (world frame,
two components) and a torque I gamma_r sqrt(2 D_r / dt) xi' held over the step, xi, xi' independent
standard normal numbers drawn anew each step (``noise``, filled by the plugin from one seeded
``numpy.random.Generator`` (PCG64) in one vectorised call per step: the noisy components only, a
body's first at its row's column NOISE_START). The velocity increments have
exactly the Wiener increments' variance 2 gamma^2 D dt; with additive noise the scheme has strong
and weak order 1 (the drift's own error is second order).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics import params as P

__all__ = ["PROPULSION_X", "PROPULSION_Y", "PROPULSION_TORQUE", "DRAG", "ROT_DRAG", "NOISE_FORCE", "NOISE_TORQUE",
           "NOISE_START", "N_ACTIVE", "row", "noise_count", "load", "ode_terms", "ode_noise"]

NAME = "active"

#: columns of ``active``: the propulsion in the body frame (N) and its torque about the centre of
#: gravity (N m), the drag rates gamma_t, gamma_r (1/s), the noise's force and torque scales
#: m gamma_t sqrt(2 D_t) (N s^0.5) and I gamma_r sqrt(2 D_r) (N m s^0.5), and where the body's
#: normal numbers start in ``noise`` (two for the force if NOISE_FORCE > 0, then one for the torque if NOISE_TORQUE > 0)
PROPULSION_X, PROPULSION_Y, PROPULSION_TORQUE, DRAG, ROT_DRAG, NOISE_FORCE, NOISE_TORQUE, NOISE_START = range(8)
N_ACTIVE = 8


def row(force: tuple[float, float], torque: float, drag: float, rot_drag: float, diffusion: float,
        rot_diffusion: float, mass: float, moment: float, first: int = 0) -> np.ndarray:
    """One row of ``active`` for a body of mass ``mass`` (kg) and moment ``moment`` (kg m^2) about its
    centre of gravity (units as in :class:`rrbody.model.active.Active`), its normal numbers from
    ``noise[first]`` on (:func:`noise_count` of them)."""
    r = np.zeros(N_ACTIVE)
    r[NOISE_START] = first
    r[PROPULSION_X], r[PROPULSION_Y] = force
    r[PROPULSION_TORQUE] = torque
    r[DRAG] = drag
    r[ROT_DRAG] = rot_drag
    r[NOISE_FORCE] = mass * drag * math.sqrt(2.0 * diffusion)
    r[NOISE_TORQUE] = moment * rot_drag * math.sqrt(2.0 * rot_diffusion)
    return r


def noise_count(diffusion: float, rot_diffusion: float) -> int:
    """How many standard normal numbers a body draws per step: two for a translational noise, one
    for a rotational one."""
    return (2 if diffusion > 0.0 else 0) + (1 if rot_diffusion > 0.0 else 0)


@njit(cache=True, inline="always")
def load(j, ca, sa, ex, ey, ew, mass, ipm, dt, active, noise):  # noqa: ANN001 (numba)
    """(fx, fy, torque) of body row ``j``'s active effect for the step of length dt (s): N (world
    frame) and N m about the centre of gravity. ``ca``, ``sa`` are the cosine and sine of the angle
    the step evaluates its loads at (the angle at the step's start plus w dt, where friction is
    evaluated), (ex, ey, ew) the velocity (m/s, world) and spin (rad/s) friction is evaluated at (the
    staggered scheme's extrapolation, :func:`rrbody.contact.body.extrapolated`), where the drag acts;
    ``noise`` holds this step's standard normal numbers, the body's from column NOISE_START of its row on."""
    fbx = active[j, PROPULSION_X]
    fby = active[j, PROPULSION_Y]
    fx = ca * fbx - sa * fby
    fy = sa * fbx + ca * fby
    tq = active[j, PROPULSION_TORQUE]
    gt = active[j, DRAG]
    gr = active[j, ROT_DRAG]
    if gt != 0.0 or gr != 0.0:
        fx -= mass * gt * ex
        fy -= mass * gt * ey
        tq -= mass * ipm * gr * ew
    s = active[j, NOISE_FORCE]
    r = active[j, NOISE_TORQUE]
    if s != 0.0 or r != 0.0:
        h = 1.0 / math.sqrt(dt)
        k = int(active[j, NOISE_START])
        if s != 0.0:
            fx += s * h * noise[k]
            fy += s * h * noise[k + 1]
            k += 2
        if r != 0.0:
            tq += r * h * noise[k]
    return fx, fy, tq


@njit(cache=True, inline="always")
def ode_terms(alpha, vx, vy, w, p):  # noqa: ANN001 (numba)
    """The deterministic active terms of a free body on the ODE path: (ax, ay) (m/s^2, world frame)
    and the angular acceleration (rad/s^2) at body angle ``alpha`` (rad) and velocity (vx, vy, w)."""
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    fbx = p[P.AFX]
    fby = p[P.AFY]
    return (ca * fbx - sa * fby - p[P.ADRAG] * vx, sa * fbx + ca * fby - p[P.ADRAG] * vy,
            p[P.AALPHA] - p[P.ARDRAG] * w)


def ode_noise(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The active effect's Langevin noise on a free body's ODE state y = (x, y, alpha, vx, vy, w): the
    components it enters (int64 array: 3 and 4 for a translational noise, then 5 for a rotational one,
    the plugin's order) and their additive scales, dv = ... + sigma dW (float64 array: gamma_t sqrt(2 D_t)
    in m s^-1.5, gamma_r sqrt(2 D_r) in rad s^-1.5; from ``p``, :mod:`rrbody.physics.params`). Empty
    arrays without noise. The noise is additive (its scales depend on nothing in the state), which is
    what the stochastic Runge-Kutta scheme of :mod:`rrbody.integrate.sde` needs."""
    idx: list[int] = []
    sig: list[float] = []
    if p[P.ACTIVE] != 0.0:
        if p[P.ANOISE] > 0.0:
            idx += [3, 4]
            sig += [float(p[P.ANOISE])] * 2
        if p[P.ARNOISE] > 0.0:
            idx.append(5)
            sig.append(float(p[P.ARNOISE]))
    return np.array(idx, dtype=np.int64), np.array(sig, dtype=np.float64)
