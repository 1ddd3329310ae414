"""Direct ODE path for the circularly driven body: set-up and report around the one stepping loop.

The loop is :func:`rrbody.integrate.loop.advance` (DOP853 with automatic switching to Radau IIA where
stiff); the events and stop rules are those of :mod:`rrbody.integrate.events`:

- local minima of phi (phi' crosses 0 upwards): every one is recorded (up to a buffer size),
  located by Newton iteration on the step size (each iterate a fresh step of the method);
- T_1, the first time theta = phi - omega t + pi has fallen by 2 pi (the RR test, docs/physics.md,
  "Definitions rrbody fixes").

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
from typing import Any

import numpy as np
from numba import njit

from rrbody.integrate.chunks import run_in_chunks
from rrbody.integrate.events import E_HAVEMIN, E_NMIN, E_PHIMIN, E_T1, E_TMIN, new_event_state
from rrbody.integrate.loop import (
    L_METH,
    L_NOUT,
    L_NREJ,
    L_NROS,
    L_NSTEP,
    L_NSWITCH,
    L_T,
    STEP_METHODS,
    STIFF_HLAMB,
    STIFF_METHOD,
    advance_for,
    new_loop_state,
)
from rrbody.integrate.rodas import spectral_radius
from rrbody.model.laws import law_coded
from rrbody.physics import params as P
from rrbody.physics.dynamics import SYSTEM_DRIVEN, driven_kinematics, jacobian, rhs, system_from_params
from rrbody.physics.effects import compiled_code

__all__ = ["DrivenResult", "integrate_driven", "driven_steps", "STOP_RULES", "STEP_METHODS"]

STOP_RULES = {"t_end": 0, "flip": 1, "rr": 2}
STATUS = {0: "reached t_end", 1: "flip settled", 2: "RR decided", 3: "max_steps reached",
          4: "step size underflow", 5: "chunk done"}


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


_STARTS: dict[int, Any] = {}


def _start_for(system: int) -> Any:
    """Compiled ``start(y, f, p, S, h0) -> bool`` for the system code ``system`` (one per compiled
    code, :func:`rrbody.physics.effects.compiled_code`): fills f = f(0, y)
    and says whether the run starts stiff, probing with a step of h0 s (one call: the set-up is part
    of every short run's cost).

    Stiff start: dry friction with the CM at rest at t = 0 (phi0 = pi), and h0 times the spectral
    radius of J at (h0, y + h0 f) beyond DOP853's stability limit (the detector's STIFF_HLAMB).
    There the CM speed grows like t, so the relaxation rate of its direction, mu g / |v|, falls like
    1 / t and h |lambda| at steps h ~ t is the same at every t near the start (about k H / (1 + H) in
    the paper's units): one probe decides. Below the limit DOP853 steps through the start as cheaply
    as anywhere else (phixtpm: h |lambda| = 0.02), and more accurately than the stiff method at loose
    tolerances."""
    code = compiled_code(system)
    if code not in _STARTS:
        # a law that sticks (dry): its force stays finite as the speed vanishes, the stiff start's cause
        dry = law_coded((code // 10) % 10).sticks

        @njit(cache=True)
        def start(y, f, p, S, h0):  # noqa: ANN001
            rhs(code, 0.0, y, p, S, f.reshape((1, 2)), np.int64(0))
            if not dry:
                return False
            _, _, vx, vy, _, _ = driven_kinematics(0.0, y[0], y[1], p)
            if math.hypot(vx, vy) > 10.0 * p[P.VEPS]:
                return False
            yp = y + h0 * f
            fp = np.empty((1, 2))
            rhs(code, h0, yp, p, S, fp, np.int64(0))
            J = np.empty((2, 2))
            jacobian(code, h0, yp, p, S, fp[0], J, np.empty(2))
            return h0 * spectral_radius(J) > STIFF_HLAMB

        _STARTS[code] = start
    return _STARTS[code]


def driven_steps(omega: float, phid0: float) -> tuple[float, float, float]:
    """The driven loop's scales from the drive rate omega (rad/s, > 0) and phi'(0) (rad/s): phi''s
    error scale (rad/s; phi is an angle that grows without bound, so its own scale is absolute, pi,
    and phi' tracks its running maximum from this), the largest step (s: an event needs at least 8
    steps per driving period) and the first trial step (s: a small fraction of the fastest time
    scale; the controller adapts at once)."""
    yscale = max(omega, abs(phid0))
    hmax = 0.125 * 2.0 * math.pi / omega
    h0 = min(1e-3 * (1.0 / max(omega, abs(phid0), 1e-300)), 1e-2 * (2.0 * math.pi / omega))
    return yscale, hmax, h0


def integrate_driven(p: np.ndarray, S: np.ndarray, y0: tuple[float, float], *, t_end: float, rtol: float,
                     stop: str = "t_end", dt_out: float = 0.0, settle_turns: float = 2.0,
                     settle_periods: float = 3.0, max_steps: int = 50_000_000, max_minima: int = 200_000,
                     progress: bool = False, desc: str = "integrating", method: str = "auto") -> DrivenResult:
    """Integrate the driven body from t = 0 with state y0 = (phi0, phi'0).

    ``method``: ``"auto"`` (default) starts with DOP853 and switches to the implicit Radau IIA where a
    stiffness detector finds the explicit method at its stability limit (and back where the problem
    is no longer stiff); ``"dop853"``, ``"radau"`` or ``"rodas"`` force one method (:data:`STEP_METHODS`).

    ``p``/``S`` come from :meth:`rrbody.scene.Scene.kernel_params`. The loop runs in compiled
    chunks so that a progress bar can update and Ctrl-C is honoured between chunks. Memory is
    bounded by the output grid (``dt_out``) and the minima buffer, never by the step count.
    """
    if method not in STEP_METHODS:
        raise ValueError(f"method must be one of {', '.join(repr(m) for m in STEP_METHODS)}, got {method!r}")
    mode = STEP_METHODS[method]
    # Python floats throughout the set-up (an operation on a numpy scalar costs many times one on a
    # float): it is part of every short run's cost
    omega = float(p[P.OMEGA])
    phi0 = float(y0[0])
    phid0 = float(y0[1])
    y = np.array((phi0, phid0))
    f = np.empty(2)
    ev = new_event_state(phi0, phid0)
    yscale, hmax, h0 = driven_steps(omega, phid0)
    scale = np.array((rtol * math.pi, rtol * yscale))
    system = system_from_params(p, SYSTEM_DRIVEN)
    stiff = _start_for(system)(y, f, p, S, h0)
    st = new_loop_state(h0, mode, yscale=yscale)
    if stiff and mode == 0:
        # the impulsive start with the CM at rest under strong dry friction (phi0 = pi) is singularly
        # stiff: start with the stiff method; the detector hands over to DOP853 where it stops being stiff
        st[L_METH] = float(STIFF_METHOD)
    if math.isfinite(t_end) and dt_out > 0.0:
        n_out = int(math.floor(t_end / dt_out + 1e-9)) + 1
    else:
        n_out = 0
        dt_out = 0.0
    out = np.empty((n_out, 3))
    minima = np.empty((max_minima, 2))
    stop_code = STOP_RULES[stop]
    run = advance_for(system)
    t0 = time.perf_counter()
    status = run_in_chunks(
        lambda n: run(y, f, st, ev, p, S, t_end, stop_code, settle_turns, settle_periods, rtol, scale, 1, hmax, n,
                      minima, out, dt_out, mode, 0.0),
        st, max_steps, progress=progress, total=t_end if math.isfinite(t_end) else None, desc=desc)
    wall = time.perf_counter() - t0
    n_min = int(ev[E_NMIN])
    status_text = STATUS[status]
    if status == 3:
        status_text = f"max_steps reached (cap max_steps={max_steps})"
    elif status == 4:
        status_text = f"step size underflow (step below {4e-16 * abs(st[L_T]) + 1e-300:.3g} s)"
    if status in (3, 4):
        status_text += f" at t={st[L_T]:.6g} s after {wall:.3g} s of computing"
    return DrivenResult(
        t_end=float(st[L_T]), y_end=y.copy(), status=status_text, phi_min=float(ev[E_PHIMIN]),
        t_min=float(ev[E_TMIN]), has_min=bool(ev[E_HAVEMIN]), T1=float(ev[E_T1]),
        minima=minima[: min(n_min, max_minima)].copy(), n_minima=n_min, out=out[: int(st[L_NOUT])].copy(),
        n_steps=int(st[L_NSTEP]), n_rejected=int(st[L_NREJ]), wall=wall,
        stats={"n_stiff_steps": int(st[L_NROS]), "n_switches": int(st[L_NSWITCH])},
    )
