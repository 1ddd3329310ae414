"""What the engine run loop (:mod:`rrbody.engine.scenes.run`) does after every step of a driven body, in one
compiled call: read the body's state, sample phi and phi' onto the output grid, pass the step to the
event detector, track the pivot's distance from the drive circle and test the horizon.

Each of these was a Python statement per step (property reads through pymunk, a tuple per sample,
the output loop, the detector's dispatch, the clock), together about twice the cost of the step
itself; they now cost one call (docs/engine.md, "Cost"). The body's angle, spin and position are
read from its Chipmunk struct (:mod:`rrbody.engine.memory.bodymem`, the offsets the plugin's struct reader
uses) or, where that layout is unknown, written into the state vector by the caller first.

Units: SI (s, rad, m, rad/s).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact.columns import PREV_GAP, PREV_SPIN, STAGGERED, STOP
from rrbody.engine.memory.bodymem import ANGLE, SPIN, VX, VY, X, Y, f64_at
from rrbody.integrate.events import GO_ON, on_step

__all__ = ["track_step", "new_track", "REACHED_END", "T_END", "T_PREV", "PHI_PREV", "PHID_PREV", "K_OUT", "MAX_PIV",
           "ANG_IN", "SPIN_IN", "X_IN", "Y_IN", "REST_IN", "N_TRACK"]

#: what :func:`track_step` returns when the run has reached its horizon (the detector's codes are 0-2)
REACHED_END: int = 100

# the state vector ``fs``: constants first (set by new_track), then what changes every step
(_BETA, _AX, _AY, _D, _OMEGA, _DT, _DT_OUT, _N_GRID, _N_OUT, T_END, _RULE, _TURNS, _PERIODS,
 T_PREV, PHI_PREV, PHID_PREV, K_OUT, MAX_PIV, ANG_IN, SPIN_IN, X_IN, Y_IN, REST_IN) = range(23)
N_TRACK = 23


def new_track(*, beta: float, anchor: tuple[float, float], d: float, omega: float, dt: float, dt_out: float,
              n_grid: int, n_out: int, t_end: float, rule: int, settle_turns: float, settle_periods: float,
              phi0: float, phid0: float) -> np.ndarray:
    """The state vector of :func:`track_step` for a run from t = 0 with (phi, phi') = (phi0, phid0)
    (rad, rad/s): beta (rad) the angle of CM -> P in the body frame, ``anchor`` P in the body frame
    (m), the drive radius ``d`` (m) and rate ``omega`` (rad/s), the step ``dt`` and output interval
    ``dt_out`` (s) with ``n_grid`` grid rows of ``n_out`` (the last one ``t_end`` itself when the grid
    misses it), the stop ``rule`` of the detector and its settle margins."""
    fs = np.zeros(N_TRACK)
    fs[:T_PREV] = (beta, anchor[0], anchor[1], d, omega, dt, dt_out, n_grid, n_out, t_end, rule, settle_turns,
                   settle_periods)
    fs[PHI_PREV], fs[PHID_PREV] = phi0, phid0
    return fs


@njit(cache=True)
def track_step(t, addr, offs, j, bodies, fs, ev, minima, out):  # noqa: ANN001 (numba)
    """After an engine step that ended at ``t`` (s since the start): phi and phi' of plugin row ``j``
    of ``bodies`` (phi' the mean of the two half-step spins, as :meth:`PlaneFriction.velocity` reads
    it), the output rows up to ``t`` (linear interpolation from the step's start), the event detector
    (:func:`rrbody.integrate.events.on_step`), the pivot error (m) into fs[MAX_PIV]. The body's state
    is read from its struct at ``addr`` (offsets ``offs``), or from fs[ANG_IN:] when ``addr`` is 0
    (REST_IN: 1.0 if its velocity and spin are all zero).

    Returns the detector's code if it stops the run, REACHED_END at the horizon (the next step would
    pass it, or a pending last sample is written), else GO_ON."""
    if addr != 0:
        ang = f64_at(addr + offs[ANGLE])
        w = f64_at(addr + offs[SPIN])
        x = f64_at(addr + offs[X])
        y = f64_at(addr + offs[Y])
        at_rest = w == 0.0 and f64_at(addr + offs[VX]) == 0.0 and f64_at(addr + offs[VY]) == 0.0
    else:
        ang, w, x, y = fs[ANG_IN], fs[SPIN_IN], fs[X_IN], fs[Y_IN]
        at_rest = fs[REST_IN] != 0.0
    phi = ang + fs[_BETA]
    if bodies[j, PREV_GAP] <= 0.0 or bodies[j, STAGGERED] == 0.0:
        phid = w
    elif bodies[j, STOP] > 0.0 and at_rest:
        phid = 0.0
    else:
        phid = 0.5 * (bodies[j, PREV_SPIN] + w)
    # the pivot: P of the body (its CM at (x, y), the anchor turned by the body angle) against the circle
    ca = math.cos(ang)
    sa = math.sin(ang)
    wt = fs[_OMEGA] * t
    err = math.hypot(x + ca * fs[_AX] - sa * fs[_AY] - fs[_D] * math.cos(wt),
                     y + sa * fs[_AX] + ca * fs[_AY] - fs[_D] * math.sin(wt))
    fs[MAX_PIV] = max(fs[MAX_PIV], err)
    t_prev = fs[T_PREV]
    phi_prev = fs[PHI_PREV]
    phid_prev = fs[PHID_PREV]
    n_grid = int(fs[_N_GRID])
    n_out = int(fs[_N_OUT])
    k = int(fs[K_OUT])
    dt = fs[_DT]
    while k < n_out:
        to = k * fs[_DT_OUT] if k < n_grid else fs[T_END]
        if to > t + 1e-12 * dt:
            break
        a = (to - t_prev) / (t - t_prev)
        out[k, 0] = to
        out[k, 1] = phi_prev + a * (phi - phi_prev)
        out[k, 2] = phid_prev + a * (phid - phid_prev)
        k += 1
    fs[K_OUT] = k
    code = on_step(ev, minima, t_prev, phi_prev, phid_prev, t, phi, phid, fs[_OMEGA], int(fs[_RULE]), fs[_TURNS],
                   fs[_PERIODS])
    if code != GO_ON:
        return code
    fs[T_PREV] = t
    fs[PHI_PREV] = phi
    fs[PHID_PREV] = phid
    # the horizon: one step more only for a pending output row (t_end itself)
    if t >= fs[T_END] - (0.5 * dt if k >= n_out else 1e-12 * dt):
        return REACHED_END
    return GO_ON
