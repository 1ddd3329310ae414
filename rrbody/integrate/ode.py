"""Direct ODE path: the compiled DOP853 loop with events, for the circularly driven body.

Events are located to integrator accuracy by Newton iteration on the step size from the start
of the step that brackets them (each iterate is a fresh DOP853 step, so the event inherits the
8th-order accuracy of the solution rather than that of an interpolant):

- local minima of phi (phi' crosses 0 upwards): every one is recorded (up to a buffer size);
- T_1, the first time theta = phi - omega t + pi has fallen by 2 pi (the RR test, SPEC section 4).

Error control: phi is an angle that grows without bound (|phi| ~ 1e4 in long fast-driving runs),
so its error scale is absolute, ``rtol * pi``; phi' is scaled by ``rtol * max(omega, |phi'(0)|,
|phi'|)``. A tolerance thus means the same thing at t = 0 and after ten thousand turns.

Stopping rules (``stop``):
- ``"t_end"``: run to the horizon;
- ``"flip"``: stop once the flip is settled: the lowest minimum so far, phi_min at t_min, is
  followed by a rise of phi to at least phi_min + 2 pi * ``settle_turns`` and at least
  ``settle_periods`` driving periods have passed since t_min. A later, lower minimum would need
  the body to fall back by that many turns against the drive; ``tests/test_flip.py`` checks the
  rule against runs continued ten times longer.
- ``"rr"``: stop as soon as the RR question is decided: T_1 found (RR iff omega T_1 < 2 pi), or
  omega t > 2 pi without it (no RR).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from rrbody.physics import params as P
from rrbody.integrate.dop853 import TABLEAU, error_norm, rk_step, step_factor
from rrbody.integrate.rodas import ros_step, spectral_radius
from rrbody.physics.dynamics import SYSTEM_DRIVEN, driven_rhs, jacobian

__all__ = ["DrivenResult", "integrate_driven", "STOP_RULES", "STEP_METHODS"]

STOP_RULES = {"t_end": 0, "flip": 1, "rr": 2}
#: ``method`` of :func:`integrate_driven`: automatic stiffness switching, or one method forced
STEP_METHODS = {"auto": 0, "dop853": 1, "rodas": 2}
STATUS = {0: "reached t_end", 1: "flip settled", 2: "RR decided", 3: "max_steps reached",
          4: "step size underflow", 5: "chunk done"}

# indices into the carried state vector `st`
_T, _H, _PHIMIN, _TMIN, _HAVEMIN, _THETA0, _T1, _NSTEP, _NREJ, _NMIN, _NOUT, _NEXTOUT, _PHID_SCALE, \
    _REJECTED, _METH, _NSTIFF, _NONSTIFF, _NSWITCH, _NROS, _NREJROW = range(20)
_ST_SIZE = 24

#: stiffness detection (Hairer's DOP853): h |lambda| estimated from the last two stages above this
#: value (the explicit method works at its stability limit) on STIFF_COUNT accepted steps in a row
STIFF_HLAMB: float = 6.1
STIFF_COUNT: int = 15
#: back to DOP853 when the Rosenbrock step times the spectral radius of J stays below this (the
#: explicit method would be stable at that step with margin) for STIFF_COUNT steps in a row
NONSTIFF_HRHO: float = 2.0
#: rejected DOP853 steps in a row (each with h |lambda| above STIFF_HLAMB) that switch at once: the
#: impulsive start at large k, where no explicit step is stable
STIFF_REJECTIONS: int = 4


@njit(cache=True)
def _step(meth, t, y, f, h, p, S, J, fx, K, ynew, ytmp, scale, A, B, C, E3, E5):  # noqa: ANN001
    """One trial step of the current method (0 DOP853, 1 RODAS4); returns its error norm.

    Both fill ``ynew`` and K[12] = f(t + h, ynew). DOP853 leaves the state of its last stage (at
    t + h) in ``ytmp``, which the stiffness detector reads."""
    if meth == 0:
        rk_step(SYSTEM_DRIVEN, t, y, f, h, p, S, A, B, C, K, ynew, ytmp)
        return error_norm(K, h, scale, E3, E5)
    return ros_step(SYSTEM_DRIVEN, t, y, f, h, p, S, J, fx, K, ynew, ytmp, scale)


@njit(cache=True)
def _ros_factor(err, rejected):  # noqa: ANN001
    """RODAS4 step factor: err^(-1/4) with safety 0.9, within [1/5, 6] (Hairer's FAC1, FAC2)."""
    if err == 0.0:
        fac = 6.0
    else:
        fac = min(6.0, max(0.2, 0.9 * err ** -0.25))
    if rejected:
        fac = min(1.0, fac)
    return fac


@njit(cache=True)
def _hlamb(K, h, ynew, ystage):  # noqa: ANN001
    """h |lambda| from DOP853's last two evaluations, both at t + h (Hairer's stiffness test)."""
    num = 0.0
    den = 0.0
    for j in range(ynew.shape[0]):
        num += (K[12, j] - K[11, j]) ** 2
        den += (ynew[j] - ystage[j]) ** 2
    if den <= 0.0:
        return 0.0
    return h * math.sqrt(num / den)


@njit(cache=True)
def _refine(meth, t, y, f, h0, hmax, which, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, omega,
            target):  # noqa: ANN001
    """Newton on h in (0, hmax] for the event `which` (0: phi' = 0; 1: theta = target); every
    iterate is a fresh step of the current method from the step start."""
    h = min(max(h0, 0.0), hmax)
    for _ in range(12):
        _step(meth, t, y, f, h, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5)
        if which == 0:
            g = y2[1]
            dg = K2[12, 1]
        else:
            g = y2[0] - omega * (t + h) + math.pi - target
            dg = y2[1] - omega
        if dg == 0.0:
            break
        dh = -g / dg
        hn = min(max(h + dh, 0.0), hmax)
        if abs(hn - h) <= 4e-16 * (abs(t) + abs(h)) + 1e-300:
            h = hn
            break
        h = hn
    _step(meth, t, y, f, h, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5)
    return h


@njit(cache=True)
def _advance(y, f, st, p, S, t_end, stop, settle_turns, settle_periods, rtol, hmax, max_steps,
             minima, out, dt_out, mode, A, B, C, E3, E5):  # noqa: ANN001
    """Advance the carried state until t_end, a stop rule fires, or max_steps accepted steps.

    ``mode``: 0 automatic switching between DOP853 and RODAS4, 1 DOP853 only, 2 RODAS4 only."""
    n = y.shape[0]
    K = np.empty((13, n))
    K2 = np.empty((13, n))
    ynew = np.empty(n)
    y2 = np.empty(n)
    ytmp = np.empty(n)
    scale = np.empty(n)
    J = np.empty((n, n))
    fx = np.empty(n)
    omega = p[P.OMEGA]
    period = 2.0 * math.pi / omega
    t = st[_T]
    h = st[_H]
    meth = int(st[_METH])
    if meth == 1:
        jacobian(SYSTEM_DRIVEN, t, y, p, S, f, J, fx)
    steps = 0
    while True:
        if t >= t_end:
            st[_T] = t
            st[_H] = h
            return 0
        if steps >= max_steps:
            st[_T] = t
            st[_H] = h
            return 5
        hh = min(h, t_end - t, hmax)
        # the smallest step that still moves t (a few ulps); below it the problem is singular
        if hh <= 4e-16 * abs(t) + 1e-300:
            st[_T] = t
            st[_H] = h
            return 4
        scale[0] = rtol * math.pi
        scale[1] = rtol * max(st[_PHID_SCALE], abs(y[1]))
        err = _step(meth, t, y, f, hh, p, S, J, fx, K, ynew, ytmp, scale, A, B, C, E3, E5)
        if not math.isfinite(err):
            err = 1e10
        st[_PHID_SCALE] = max(st[_PHID_SCALE], abs(ynew[1]) if math.isfinite(ynew[1]) else 0.0)
        scale[1] = rtol * st[_PHID_SCALE]
        rejected = st[_REJECTED] != 0.0
        if err >= 1.0:
            if meth == 0:
                h = hh * step_factor(err, rejected)
                if mode == 0 and _hlamb(K, hh, ynew, ytmp) > STIFF_HLAMB:
                    st[_NREJROW] += 1
                    if st[_NREJROW] >= STIFF_REJECTIONS:
                        meth = 1
                        st[_METH] = 1.0
                        st[_NSWITCH] += 1
                        st[_NSTIFF] = 0.0
                        st[_NREJROW] = 0.0
                        jacobian(SYSTEM_DRIVEN, t, y, p, S, f, J, fx)
            else:
                h = hh * _ros_factor(err, rejected)
            st[_REJECTED] = 1.0
            st[_NREJ] += 1
            continue
        st[_NREJROW] = 0.0
        # ---- accepted step [t, t + hh] ----
        # stiffness detection before ytmp is reused below
        switch = False
        if mode == 0 and meth == 0:
            if _hlamb(K, hh, ynew, ytmp) > STIFF_HLAMB:
                st[_NONSTIFF] = 0.0
                st[_NSTIFF] += 1
                if st[_NSTIFF] >= STIFF_COUNT:
                    switch = True
            else:
                st[_NONSTIFF] += 1
                if st[_NONSTIFF] >= 6:
                    st[_NSTIFF] = 0.0
        # dense output on the fixed grid, by re-stepping from the step start
        if dt_out > 0.0:
            while st[_NEXTOUT] <= t + hh and st[_NOUT] < out.shape[0]:
                ho = st[_NEXTOUT] - t
                k = int(st[_NOUT])
                if ho <= 0.0:
                    out[k, 0] = t
                    out[k, 1] = y[0]
                    out[k, 2] = y[1]
                else:
                    _step(meth, t, y, f, ho, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5)
                    out[k, 0] = t + ho
                    out[k, 1] = y2[0]
                    out[k, 2] = y2[1]
                st[_NOUT] += 1
                st[_NEXTOUT] = (st[_NOUT]) * dt_out
        # local minimum of phi: phi' crosses zero upwards
        if y[1] < 0.0 and ynew[1] >= 0.0:
            h0 = hh * (-y[1]) / (ynew[1] - y[1])
            hm = _refine(meth, t, y, f, h0, hh, 0, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, omega, 0.0)
            tm = t + hm
            k = int(st[_NMIN])
            if k < minima.shape[0]:
                minima[k, 0] = tm
                minima[k, 1] = y2[0]
            st[_NMIN] += 1
            if st[_HAVEMIN] == 0.0 or y2[0] < st[_PHIMIN]:
                st[_PHIMIN] = y2[0]
                st[_TMIN] = tm
                st[_HAVEMIN] = 1.0
        # T_1: theta falls to theta0 - 2 pi for the first time
        if math.isnan(st[_T1]):
            target = st[_THETA0] - 2.0 * math.pi
            g0 = y[0] - omega * t + math.pi - target
            g1 = ynew[0] - omega * (t + hh) + math.pi - target
            if g0 > 0.0 and g1 <= 0.0:
                h0 = hh * g0 / (g0 - g1)
                hm = _refine(meth, t, y, f, h0, hh, 1, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, omega,
                             target)
                st[_T1] = t + hm
        t = t + hh
        for j in range(n):
            y[j] = ynew[j]
            f[j] = K[12, j]
        steps += 1
        st[_NSTEP] += 1
        st[_REJECTED] = 0.0
        if meth == 0:
            h = hh * step_factor(err, rejected)
        else:
            st[_NROS] += 1
            h = hh * _ros_factor(err, rejected)
            jacobian(SYSTEM_DRIVEN, t, y, p, S, f, J, fx)
            if mode == 0:
                if min(h, hmax) * spectral_radius(J) < NONSTIFF_HRHO:
                    st[_NONSTIFF] += 1
                    if st[_NONSTIFF] >= STIFF_COUNT:
                        meth = 0
                        st[_NSWITCH] += 1
                        st[_NONSTIFF] = 0.0
                        st[_NSTIFF] = 0.0
                else:
                    st[_NONSTIFF] = 0.0
        if switch:
            meth = 1
            st[_NSWITCH] += 1
            st[_NSTIFF] = 0.0
            st[_NONSTIFF] = 0.0
            jacobian(SYSTEM_DRIVEN, t, y, p, S, f, J, fx)
        st[_METH] = float(meth)
        # stopping rules
        if stop == 1 and st[_HAVEMIN] != 0.0:
            if y[0] >= st[_PHIMIN] + 2.0 * math.pi * settle_turns and t - st[_TMIN] >= settle_periods * period:
                st[_T] = t
                st[_H] = h
                return 1
        if stop == 2:
            if not math.isnan(st[_T1]) or omega * t > 2.0 * math.pi:
                st[_T] = t
                st[_H] = h
                return 2


@dataclass
class DrivenResult:
    """Raw output of :func:`integrate_driven` (times in s, angles in rad)."""

    t_end: float
    y_end: np.ndarray
    status: str
    phi_min: float
    t_min: float
    has_min: bool
    T1: float
    minima: np.ndarray
    n_minima: int
    out: np.ndarray
    n_steps: int
    n_rejected: int
    wall: float
    stats: dict[str, float] = field(default_factory=dict)


def integrate_driven(p: np.ndarray, S: np.ndarray, y0: tuple[float, float], *, t_end: float, rtol: float,
                     stop: str = "t_end", dt_out: float = 0.0, settle_turns: float = 2.0,
                     settle_periods: float = 3.0, max_steps: int = 50_000_000, max_minima: int = 200_000,
                     progress: bool = False, desc: str = "integrating", method: str = "auto") -> DrivenResult:
    """Integrate the driven body from t = 0 with state y0 = (phi0, phi'0).

    ``method``: ``"auto"`` (default) starts with DOP853 and switches to the L-stable RODAS4 where a
    stiffness detector finds the explicit method at its stability limit (and back where the problem
    is no longer stiff); ``"dop853"`` or ``"rodas"`` force one method (:data:`STEP_METHODS`).

    ``p``/``S`` come from :meth:`rrbody.scene.Scene.kernel_params`. The loop runs in compiled
    chunks so that a progress bar can update and Ctrl-C is honoured between chunks. Memory is
    bounded by the output grid (``dt_out``) and the minima buffer, never by the step count.
    """
    if method not in STEP_METHODS:
        raise ValueError(f"method must be one of {', '.join(repr(m) for m in STEP_METHODS)}, got {method!r}")
    mode = STEP_METHODS[method]
    A, B, C, E3, E5 = TABLEAU
    omega = float(p[P.OMEGA])
    y = np.array(y0, dtype=np.float64)
    f = np.empty(2)
    driven_rhs(0.0, y, p, S, f)
    st = np.zeros(_ST_SIZE)
    st[_PHIMIN] = np.nan
    st[_TMIN] = np.nan
    st[_T1] = np.nan
    st[_THETA0] = y[0] + math.pi
    st[_PHID_SCALE] = max(omega, abs(y[1]))
    st[_METH] = 1.0 if mode == 2 else 0.0
    # initial step: a small fraction of the fastest time scale; the controller adapts at once
    st[_H] = 1e-3 * min(1.0 / omega, 1.0 / max(abs(y[1]), 1e-300))
    st[_H] = min(st[_H], 1e-2 * (2 * math.pi / omega))
    if y[1] >= 0.0:  # phi rises from the start: t = 0 is the first minimum candidate
        st[_PHIMIN] = y[0]
        st[_TMIN] = 0.0
        st[_HAVEMIN] = 1.0
    hmax = 0.125 * 2.0 * math.pi / omega  # an event needs at least 8 steps per driving period
    if math.isfinite(t_end) and dt_out > 0.0:
        n_out = int(math.floor(t_end / dt_out + 1e-9)) + 1
    else:
        n_out = 0
        dt_out = 0.0
    out = np.empty((n_out, 3))
    minima = np.empty((max_minima, 2))
    stop_code = STOP_RULES[stop]
    chunk = 200_000
    t0 = time.perf_counter()
    bar = None
    if progress:
        from tqdm import tqdm

        total = t_end if math.isfinite(t_end) else None
        bar = tqdm(total=total, desc=desc, unit="s(sim)", leave=False, dynamic_ncols=True)
    status = 5
    try:
        while True:
            left = max_steps - int(st[_NSTEP])
            if left <= 0:
                status = 3
                break
            before = st[_T]
            status = _advance(y, f, st, p, S, t_end, stop_code, settle_turns, settle_periods, rtol,
                              hmax, min(chunk, left), minima, out, dt_out, mode, A, B, C, E3, E5)
            if bar is not None:
                bar.update(st[_T] - before)
            if status != 5:
                break
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0
    n_min = int(st[_NMIN])
    status_text = STATUS[status]
    if status == 3:
        status_text = f"max_steps reached (cap max_steps={max_steps})"
    elif status == 4:
        status_text = f"step size underflow (step below {4e-16 * abs(st[_T]) + 1e-300:.3g} s)"
    if status in (3, 4):
        status_text += f" at t={st[_T]:.6g} s after {wall:.3g} s of computing"
    return DrivenResult(
        t_end=float(st[_T]), y_end=y.copy(), status=status_text, phi_min=float(st[_PHIMIN]),
        t_min=float(st[_TMIN]), has_min=bool(st[_HAVEMIN]), T1=float(st[_T1]),
        minima=minima[: min(n_min, max_minima)].copy(), n_minima=n_min, out=out[: int(st[_NOUT])].copy(),
        n_steps=int(st[_NSTEP]), n_rejected=int(st[_NREJ]), wall=wall,
        stats={"n_stiff_steps": int(st[_NROS]), "n_switches": int(st[_NSWITCH])},
    )
