"""The one stepping loop: every system (driven body, free body, the next ones), explicit or stiff.

:func:`advance` integrates y' = f(t, y) for the equations ``system`` of
:func:`rrbody.physics.dynamics.rhs` with an adaptive one-step method and reports through the one
event detector of :mod:`rrbody.integrate.events`:

- methods: DOP853 (explicit, order 8; :mod:`rrbody.integrate.dop853`), Radau IIA (implicit,
  order 5, stage order 3; :mod:`rrbody.integrate.radau`, the stiff method of driven bodies) and
  RODAS4 (L-stable Rosenbrock, order 4; :mod:`rrbody.integrate.rodas`, the stiff method of free
  bodies). ``mode`` 0 starts with DOP853 and switches by a stiffness detector (Hairer's for DOP853:
  h |lambda| from the last two stages above ``STIFF_HLAMB`` on ``STIFF_COUNT`` steps, accepted or
  rejected, without 6 non-stiff accepted steps in between; back when the stiff step times the
  spectral radius of J stays below ``NONSTIFF_HRHO``); ``mode`` 1, 2, 3 force DOP853, RODAS4, Radau;
- events of a driven body (local minima of phi, T_1) are located to the method's accuracy by Newton
  iteration on the step size from the start of the step that brackets them (each iterate is a fresh
  step, so an event inherits the order of the solution rather than that of an interpolant;
  :mod:`rrbody.integrate.refine`);
- a Poincare section of a driven body (``ev[E_SECTION]`` = theta_s, rad; NaN: none): every crossing
  of theta = phi - omega t + pi = theta_s (mod 2 pi) in the direction ``ev[E_SECDIR]`` (1: theta'
  > 0, -1: theta' < 0) is located like T_1 and written to
  ``out`` as a row (t, phi, phi') in place of the dense output (``dt_out`` 0);
- stop rules (``stop``, :data:`rrbody.integrate.events.STOP_T_END` ...): flip settled, RR decided,
  rest of a free body under dry friction (``rest``: steps capped at a fraction of the time left to
  rest, steps that would gain energy rejected, the last stretch below ``u_stop``
  completed analytically);
- dense output on a fixed grid ``dt_out`` by re-stepping from the step start: out rows (t, y...).

Error control: RMS over components of (error / scale), scale = ``scale`` (rtol times each
component's size; absolute for angles, which grow without bound); component ``track`` (-1: none)
has its scale raised to rtol times its running maximum of |y|.

The loop state ``st`` (float vector, :func:`new_loop_state`) carries time, step, counters and the
current method between calls, so a long run goes in compiled chunks (progress bar, Ctrl-C;
:mod:`rrbody.integrate.chunks`).
Return codes: :data:`STATUS`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import literally, njit

from rrbody.integrate.dop853 import TABLEAU, hlamb, step_factor, trial_step
from rrbody.integrate.events import (
    E_HAVEMIN,
    E_PHIMIN,
    E_SECDIR,
    E_SECTION,
    E_T1,
    E_THETA0,
    E_TMIN,
    E_TSTOP,
    STOP_REST,
    crossings,
    record_minimum,
    rest_admissible,
    rest_reached,
    rest_step_limit,
    section_crossings,
    section_gap,
    stop_reached,
)
from rrbody.integrate.radau import K_ROWS, radau_memory
from rrbody.integrate.refine import method_step, refine_event
from rrbody.integrate.rodas import spectral_radius, stiff_factor
from rrbody.physics import params as P
from rrbody.physics.dynamics import SYSTEM_DRIVEN, jacobian
from rrbody.physics.effects import compiled_code

__all__ = ["advance", "advance_for", "new_loop_state", "STATUS", "STEP_METHODS", "L_T", "L_H", "L_NSTEP", "L_NREJ",
           "L_NOUT",
           "L_NROS", "L_NSWITCH"]

#: ``method`` names -> ``mode`` of :func:`advance`
STEP_METHODS = {"auto": 0, "dop853": 1, "rodas": 2, "radau": 3}
#: return codes of :func:`advance` (1 means "flip settled" for a driven body, "came to rest" for a free one)
STATUS = {0: "reached t_end", 1: "stop rule met", 2: "RR decided", 4: "step size underflow", 5: "chunk done"}

L_T, L_H, L_NSTEP, L_NREJ, L_NOUT, L_NEXTOUT, L_REJECTED, L_METH, L_NSTIFF, L_NONSTIFF, L_NSWITCH, L_NROS, \
    L_YSCALE = range(13)
_LOOP_SIZE = 16

#: RODAS4 never works below this tolerance: at rtol 1e-13 its error estimate is at its rounding
#: floor on the stiff cases (H 0.2, k 1e6: step count x30 per decade of rtol instead of 10^(1/4)),
#: while at 1e-11 its t_f is already within 1e-12 of scipy's Radau at 1e-12 (tests/test_stiff.py)
STIFF_RTOL_FLOOR: float = 1e-11
#: the stiff method of the automatic mode for driven bodies (1 RODAS4, 2 Radau IIA)
STIFF_METHOD: int = 2
STIFF_HLAMB: float = 6.1
STIFF_COUNT: int = 15
NONSTIFF_HRHO: float = 2.0


_FIRST_METHOD = (0.0, 0.0, 1.0, 2.0)  # method code of the first step per mode (auto, dop853, radau, rodas)


def new_loop_state(h0: float, mode: int, yscale: float = 0.0) -> np.ndarray:
    """Loop state at t = 0 with first trial step h0 (s); ``yscale``: running maximum of the
    tracked component's |y| so far."""
    st = np.zeros(_LOOP_SIZE)
    st[L_H] = h0
    st[L_METH] = _FIRST_METHOD[mode]
    st[L_YSCALE] = yscale
    return st


@njit(cache=True)
def _rest_output(t, y, tau, out, st, dt_out, t_end, icm):  # noqa: ANN001
    """Output rows over the analytic last stretch (uniform deceleration over tau s), then rest."""
    n = y.shape[0]
    while st[L_NEXTOUT] <= t_end and st[L_NOUT] < out.shape[0]:
        k = int(st[L_NOUT])
        to = st[L_NEXTOUT]
        dtl = min(max(to - t, 0.0), tau)
        frac = 1.0 - dtl / tau if tau > 0.0 else 0.0
        move = dtl * (1.0 - 0.5 * dtl / tau) if tau > 0.0 else 0.0
        out[k, 0] = to
        for j in range(n // 2):
            out[k, 1 + j] = y[j] + y[n // 2 + j] * move
            out[k, 1 + n // 2 + j] = y[n // 2 + j] * frac
        if icm <= 0.0:
            out[k, n] = 0.0
        st[L_NOUT] += 1
        st[L_NEXTOUT] = st[L_NOUT] * dt_out


@njit(cache=True)
def advance(system, y, f, st, ev, p, S, t_end, stop, settle_turns, settle_periods, rtol, scale, track,  # noqa: ANN001
            hmax, max_steps, minima, out, dt_out, mode, u_stop, A, B, C, E3, E5):
    """Advance (y, f = f(t, y)) from st[L_T] until t_end, a stop rule, or max_steps accepted steps.

    Returns a key of :data:`STATUS`. ``ev`` is the event state (:func:`rrbody.integrate.events.new_event_state`),
    ``minima`` its buffer of located minima, ``u_stop`` the speed (m/s) below which a free body's
    stop is completed analytically (``stop`` = STOP_REST). ``system`` (the scene's compiled code,
    :func:`rrbody.physics.effects.compiled_code`: a driven body's friction law, or a free body) is
    compiled in as a constant: four loops in all; the area method is read from ``p`` at run time."""
    literally(system)
    n = y.shape[0]
    K = np.zeros((K_ROWS, n))  # zeros: no Radau memory yet (rrbody.integrate.radau)
    K2 = np.zeros((K_ROWS, n))
    ynew = np.empty(n)
    y2 = np.empty(n)
    ytmp = np.empty(n)
    J = np.empty((n, n))
    fx = np.empty(n)
    omega = p[P.OMEGA]
    icm = p[P.ICM]
    driven = system % 10 == SYSTEM_DRIVEN
    rest = stop == STOP_REST
    boost = max(1.0, STIFF_RTOL_FLOOR / rtol)
    # the stiff method: Radau IIA for the 2-state driven body, RODAS4 otherwise
    stiff = STIFF_METHOD if driven else 1
    # the carried state lives in locals during the loop (stores into st would alias y and K for the
    # compiler and cost reloads every step); it is written back once, at the exit
    t = st[L_T]
    h = st[L_H]
    meth = int(st[L_METH])
    nstep = st[L_NSTEP]
    nrej = st[L_NREJ]
    rejected = st[L_REJECTED] != 0.0
    nstiff = st[L_NSTIFF]
    nonstiff = st[L_NONSTIFF]
    nswitch = st[L_NSWITCH]
    nros = st[L_NROS]
    yscale = st[L_YSCALE]
    t1_open = math.isnan(ev[E_T1])
    target = ev[E_THETA0] - 2.0 * math.pi
    theta_s = ev[E_SECTION]
    section = driven and not math.isnan(theta_s)
    havemin = ev[E_HAVEMIN] != 0.0
    phimin = ev[E_PHIMIN]
    tmin = ev[E_TMIN]
    if meth != 0:
        jacobian(system, t, y, p, S, f, J, fx)
    steps = 0
    code = 0
    while True:
        if t >= t_end or steps >= max_steps:
            code = 0 if t >= t_end else 5
            break
        if rest:
            reached, tau = rest_reached(y, f, icm, u_stop)
            if reached:
                if dt_out > 0.0:
                    _rest_output(t, y, tau, out, st, dt_out, t_end, icm)
                for j in range(n // 2):
                    y[j] += 0.5 * y[n // 2 + j] * tau
                    y[n // 2 + j] = 0.0
                ev[E_TSTOP] = t + tau
                t = t_end
                code = 1
                break
        hh = min(h, t_end - t, hmax)
        if rest:
            hh = min(hh, rest_step_limit(y, f, icm))
        # the smallest step that still moves t (a few ulps); below it the problem is singular
        if hh <= 4e-16 * abs(t) + 1e-300:
            if t_end - t <= 4e-16 * abs(t) + 1e-300:
                # the last step landed within rounding of t_end (t + (t_end - t) rounds short): reached
                t = t_end
                break
            code = 4
            break
        if track >= 0:
            scale[track] = rtol * max(yscale, abs(y[track]))
        # direct: trial_step is inlined by LLVM without the reference counts method_step's arrays would add
        if meth == 0:
            err = trial_step(system, t, y, f, hh, p, S, A, B, C, E3, E5, K, ynew, ytmp, scale)
        else:
            err = method_step(meth, system, t, y, f, hh, p, S, J, fx, K, ynew, ytmp, scale, A, B, C, E3, E5, boost,
                              rtol)
        if not math.isfinite(err):
            err = 1e10
        bad = rest and not rest_admissible(y, ynew, icm, p[P.GTX], p[P.GTY])
        if bad or err >= 1.0:
            if bad:
                h = 0.5 * hh
            elif meth == 0:
                h = hh * step_factor(err, rejected)
                # a rejected step at the stability limit is stiffness evidence too: at the impulsive
                # start the controller alternates rejections and acceptances there
                if mode == 0 and hlamb(K, hh, ynew, ytmp) > STIFF_HLAMB:
                    nstiff += 1
                    if nstiff >= STIFF_COUNT:
                        meth = stiff
                        nswitch += 1
                        nstiff = 0.0
                        nonstiff = 0.0
                        jacobian(system, t, y, p, S, f, J, fx)
            else:
                h = hh * stiff_factor(err, rejected, meth)
            rejected = True
            nrej += 1
            continue
        # ---- accepted step [t, t + hh] ----
        if meth == 2:  # re-steps from t (output, events) start Newton on this step's polynomial
            radau_memory(K, K2)
        if track >= 0:
            yscale = max(yscale, abs(ynew[track]))
        switch = False
        if mode == 0 and meth == 0:  # stiffness test, before ytmp is reused below
            if hlamb(K, hh, ynew, ytmp) > STIFF_HLAMB:
                nonstiff = 0.0
                nstiff += 1
                switch = nstiff >= STIFF_COUNT
            else:
                nonstiff += 1
                if nonstiff >= 6:
                    nstiff = 0.0
        if dt_out > 0.0:
            while st[L_NEXTOUT] <= t + hh and st[L_NOUT] < out.shape[0]:
                ho = st[L_NEXTOUT] - t
                k = int(st[L_NOUT])
                out[k, 0] = t + ho if ho > 0.0 else t
                if ho <= 0.0:
                    for j in range(n):
                        out[k, 1 + j] = y[j]
                else:
                    method_step(meth, system, t, y, f, ho, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, 1.0, rtol)
                    for j in range(n):
                        out[k, 1 + j] = y2[j]
                st[L_NOUT] += 1
                st[L_NEXTOUT] = st[L_NOUT] * dt_out
        if driven:
            which, gmin, gt1 = crossings(t1_open, target, t, y[0], y[1], t + hh, ynew[0], ynew[1], omega)
            if which & 1:
                # the event's number as np.int64: literal constants would compile refine_event once per event
                hm, phim, _ = refine_event(meth, system, t, y, f, gmin, hh, np.int64(1), p, S, J, fx, K2, y2, ytmp,
                                           scale,
                                           A, B, C, E3, E5, omega, 0.0, rtol)
                record_minimum(ev, minima, t + hm, phim)
                havemin = True
                phimin = ev[E_PHIMIN]
                tmin = ev[E_TMIN]
            if which & 2:
                hm, _, _ = refine_event(meth, system, t, y, f, gt1, hh, np.int64(2), p, S, J, fx, K2, y2, ytmp, scale,
                                        A, B, C, E3, E5, omega, target, rtol)
                ev[E_T1] = t + hm
                t1_open = False
            if section:  # a Poincare section: its crossings in this step, each located as T_1 is
                k0, k1 = section_crossings(theta_s, ev[E_SECDIR], t, y[0], t + hh, ynew[0], omega)
                for kk in range(k0, k1 + 1):
                    if st[L_NOUT] >= out.shape[0]:
                        break
                    surf = theta_s + 2.0 * math.pi * kk
                    g0 = section_gap(y[0], t, omega, surf)
                    g1 = section_gap(ynew[0], t + hh, omega, surf)
                    hm, phis, phids = refine_event(meth, system, t, y, f, hh * g0 / (g0 - g1), hh, np.int64(2), p, S,
                                                   J, fx,
                                                   K2, y2, ytmp, scale, A, B, C, E3, E5, omega, surf, rtol)
                    k = int(st[L_NOUT])
                    out[k, 0] = t + hm
                    out[k, 1] = phis
                    out[k, 2] = phids
                    st[L_NOUT] += 1
        t = t + hh
        for j in range(n):
            y[j] = ynew[j]
            f[j] = K[12, j]
        steps += 1
        nstep += 1
        if meth == 0:
            h = hh * step_factor(err, rejected)
        else:
            nros += 1
            h = hh * stiff_factor(err, rejected)
            jacobian(system, t, y, p, S, f, J, fx)
            if mode == 0:
                if min(h, hmax) * spectral_radius(J) < NONSTIFF_HRHO:
                    nonstiff += 1
                    if nonstiff >= STIFF_COUNT:
                        meth = 0
                        nswitch += 1
                        nonstiff = 0.0
                        nstiff = 0.0
                else:
                    nonstiff = 0.0
        rejected = False
        if switch:
            meth = stiff
            nswitch += 1
            nstiff = 0.0
            nonstiff = 0.0
            jacobian(system, t, y, p, S, f, J, fx)
        if driven:
            code = stop_reached(stop, havemin, phimin, tmin, not t1_open, t, y[0], omega, settle_turns,
                                settle_periods)
            if code != 0:
                break
    st[L_T] = t
    st[L_H] = h
    st[L_METH] = float(meth)
    st[L_NSTEP] = nstep
    st[L_NREJ] = nrej
    st[L_REJECTED] = 1.0 if rejected else 0.0
    st[L_NSTIFF] = nstiff
    st[L_NONSTIFF] = nonstiff
    st[L_NSWITCH] = nswitch
    st[L_NROS] = nros
    st[L_YSCALE] = yscale
    return code


_SPECIALISED: dict[int, Any] = {}


def advance_for(system: int) -> Any:
    """The loop for the system code ``system``: a compiled function with the arguments of
    :func:`advance` from ``y`` to ``u_stop`` (the DOP853 tableau is built in). One per compiled code
    (:func:`rrbody.physics.effects.compiled_code`: driven with its law, or free), whatever the area method (read
    from ``p`` at run time), so a new combination of effects compiles nothing. numba caches each on
    disk (its closure constant is part of the cache key), and calling it costs no dispatch on the
    code (a direct call of :func:`advance` with a literal argument would retype per call)."""
    code = compiled_code(system)
    if code not in _SPECIALISED:
        _SPECIALISED[code] = _make_advance(code)
    return _SPECIALISED[code]


def _make_advance(code: int) -> Any:
    # the DOP853 tableau enters as globals, which numba freezes into the compiled loop as constants:
    # five fewer arrays for the dispatcher to type-check on every call
    A, B, C, E3, E5 = TABLEAU

    @njit(cache=True)
    def run(y, f, st, ev, p, S, t_end, stop, settle_turns, settle_periods, rtol, scale, track,  # noqa: ANN001
            hmax, max_steps, minima, out, dt_out, mode, u_stop):
        return advance(code, y, f, st, ev, p, S, t_end, stop, settle_turns, settle_periods, rtol, scale, track,
                       hmax, max_steps, minima, out, dt_out, mode, u_stop, A, B, C, E3, E5)

    return run
