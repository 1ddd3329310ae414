"""Compiled Dormand-Prince 8(5,3) step with scipy's own Butcher tableau.

The tableau is Hairer's (:mod:`rrbody.integrate.tableaus`, copied digit for digit from scipy's and tested
against it); the loop is compiled with numba because a Python-level ``solve_ivp`` pays ~50 us of interpreter
overhead per step, which dominates for these 2- to 6-dimensional systems. The error norm and the
step-size controller follow scipy's ``DOP853`` (Hairer's combined 5th/3rd-order estimate).
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit

from rrbody._private import no_refcount
from rrbody.integrate.tableaus import DOP853_A, DOP853_B, DOP853_C, DOP853_E3, DOP853_E5, DOP853_STAGES
from rrbody.physics import params as P
from rrbody.physics.dynamics import driven_tangent, rhs_near

__all__ = ["TABLEAU", "rk_step", "error_norm", "trial_step", "ORDER", "hlamb"]

N_STAGES: int = DOP853_STAGES
ORDER: int = 8
ERROR_EXPONENT: float = -1.0 / 8.0  # error estimator order 7
SAFETY: float = 0.9
MIN_FACTOR: float = 0.2
MAX_FACTOR: float = 10.0

# A (12x12), B (12), C (12), E3 (13), E5 (13) as contiguous float64 arrays for numba.
TABLEAU: tuple[np.ndarray, ...] = (DOP853_A, DOP853_B, DOP853_C, DOP853_E3, DOP853_E5)


@njit(cache=True, inline="always")
def rk_step(system, t, y, f0, h, p, S, A, B, C, K, ynew, ytmp):  # noqa: ANN001 (numba)
    """One DOP853 step of size h from (t, y) with f0 = rhs(system, t, y, ...).

    Fills K[0..12] (K[12] = f(t+h, ynew)) and ``ynew``. ``system`` selects the equations
    (:func:`rrbody.dynamics.rhs`; an integer rather than a function argument, because numba
    cannot cache functions that take other compiled functions as arguments). ``p`` and ``S``
    are the parameter vector and the area-sample array. Inlined into :func:`trial_step`, which is
    compiled once per compiled code (``literally``; :func:`rrbody.physics.effects.compiled_code`).
    """
    # the state size as a compile-time constant (2 for a driven body, 6 for a free one), so the stage
    # loops below have constant trip counts and are unrolled
    driven = system % 10 == 0
    n = 2 if driven else 6
    # a driven body's stages see the drive phase as psi0 + d (sin psi0, cos psi0 once per step;
    # physics.effects.drive_circular.sincos_psi): d is h times phi's stage weight sum minus w c h
    w = p[P.OMEGA]
    s0 = 0.0
    c0 = 0.0
    if driven:
        psi0 = y[0] - w * t
        s0 = math.sin(psi0)
        c0 = math.cos(psi0)
    for j in range(n):
        K[0, j] = f0[j]
    for s in range(1, N_STAGES):
        d = math.nan
        for j in range(n):
            acc = 0.0
            for r in range(s):
                acc += A[s, r] * K[r, j]
            ytmp[j] = y[j] + h * acc
            if j == 0 and driven:
                d = h * acc - w * (C[s] * h)
        rhs_near(system, t + C[s] * h, ytmp, p, S, K, s, d, s0, c0)
    d = math.nan
    for j in range(n):
        acc = 0.0
        for r in range(N_STAGES):
            acc += B[r] * K[r, j]
        ynew[j] = y[j] + h * acc
        if j == 0 and driven:
            d = h * acc - w * h
    # np.int64: the constant N_STAGES would compile rhs_near once more, for the literal 12
    rhs_near(system, t + h, ynew, p, S, K, np.int64(N_STAGES), d, s0, c0)
    if y.shape[0] > n:  # tangent vectors ride along (effect tangent): one branch per step here
        tangent_stages(system, t, y, f0, h, p, S, A, B, C, K, ynew, ytmp)


@njit(cache=True, **no_refcount())
def tangent_stages(system, t, y, f0, h, p, S, A, B, C, K, ynew, ytmp):  # noqa: ANN001
    """The stages of the tangent vectors (components 2.. of a driven state, effect tangent), after
    :func:`rk_step` has stepped the body: their equations are linear along the body's trajectory, so
    each stage's body state is rebuilt from the body's own stages in K (y + h sum A K) and the
    tangent derivative evaluated there. Out of line, so a run without tangent vectors pays one
    branch per step. Leaves ``ytmp`` holding the last stage's state, as rk_step does."""
    literally(system)
    law = (system // 10) % 10
    area = int(p[P.BODY])
    m = y.shape[0]
    for j in range(2, m):
        K[0, j] = f0[j]
    for s in range(1, N_STAGES):
        for j in range(m):
            acc = 0.0
            for r in range(s):
                acc += A[s, r] * K[r, j]
            ytmp[j] = y[j] + h * acc
        driven_tangent(law, area, t + C[s] * h, ytmp, p, S, K, s)
    for j in range(2, m):
        acc = 0.0
        for r in range(N_STAGES):
            acc += B[r] * K[r, j]
        ynew[j] = y[j] + h * acc
    driven_tangent(law, area, t + h, ynew, p, S, K, np.int64(N_STAGES))


@njit(cache=True, inline="always")
def _error_terms(K, j, scale, E3, E5):  # noqa: ANN001
    """Component j's squared scaled 5th- and 3rd-order error estimates (without the step size)."""
    a5 = 0.0
    a3 = 0.0
    for r in range(N_STAGES + 1):
        a5 += E5[r] * K[r, j]
        a3 += E3[r] * K[r, j]
    return (a5 / scale[j]) ** 2, (a3 / scale[j]) ** 2


@njit(cache=True, inline="always")
def error_norm(system, K, h, scale, E3, E5):  # noqa: ANN001
    """scipy's DOP853 error norm (RMS over components of the scaled 5th/3rd-order estimates);
    ``system`` fixes the state size at compile time, as in :func:`rk_step` (inlined into the loop,
    which is compiled per compiled code)."""
    n = 2 if system % 10 == 0 else 6
    e5 = 0.0
    e3 = 0.0
    for j in range(n):
        a5, a3 = _error_terms(K, j, scale, E3, E5)
        e5 += a5
        e3 += a3
    if scale.shape[0] > n:  # tangent vectors (rk_step): under the same error control
        for j in range(n, scale.shape[0]):
            a5, a3 = _error_terms(K, j, scale, E3, E5)
            e5 += a5
            e3 += a3
        n = scale.shape[0]
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, forceinline=True, error_model="numpy", **no_refcount())
def trial_step(system, t, y, f0, h, p, S, A, B, C, E3, E5, K, ynew, ytmp, scale):  # noqa: ANN001
    """One DOP853 trial step (:func:`rk_step`) and its error norm (:func:`error_norm`) for the
    stepping loop. Three compile options, each measured on the fast driven case (about 0.45 us a
    step, 85k steps):

    - ``_nrt=False``: no reference counting (it only reads and writes the arrays it is given), so
      its 13 array arguments cost no atomic count updates (numba's own ``inline="always"`` would
      add them: 2 % of the run);
    - ``forceinline=True``: LLVM inlines it into its callers (the loop, the event refinement), as a
      call would pass the 13 arrays as ~90 words on the stack every step (8 % of the run);
    - ``error_model="numpy"``: no zero test and raise path per float division (Python's model
      keeps them even where the quotient is unused, as for the Jacobian terms of the dry law's
      ``perp``: 6 % of the run). Every divisor here is positive by construction (the validated
      I_P/m, the error scales, speeds above the dead band); were one zero, the error norm would
      come out inf or NaN, and the loop rejects such a step.

    Results are bitwise the same as with a plain call: only the code around the arithmetic changes."""
    literally(system)
    rk_step(system, t, y, f0, h, p, S, A, B, C, K, ynew, ytmp)
    return error_norm(system, K, h, scale, E3, E5)


@njit(cache=True, inline="always")
def step_factor(err: float, rejected: bool) -> float:
    """New-step factor from the error norm (scipy's controller)."""
    if err < 1.0:
        fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err**ERROR_EXPONENT)
        if rejected:
            fac = min(1.0, fac)
        return fac
    return max(MIN_FACTOR, SAFETY * err**ERROR_EXPONENT)


@njit(cache=True, inline="always")
def hlamb(K, h, ynew, ystage):  # noqa: ANN001
    """h |lambda| from DOP853's last two evaluations, both at t + h (Hairer's stiffness test)."""
    num = 0.0
    den = 0.0
    for j in range(ynew.shape[0]):
        num += (K[12, j] - K[11, j]) ** 2
        den += (ynew[j] - ystage[j]) ** 2
    if den <= 0.0:
        return 0.0
    return h * math.sqrt(num / den)
