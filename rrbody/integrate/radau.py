"""Compiled Radau IIA (order 5, three stages, L-stable, stage order 3) for small systems.

The second stiff method of the stepping loop. Unlike a Rosenbrock method, Radau IIA keeps its
order on stiff problems whose slow manifold moves with time (stage order 3: no order reduction in
the dragged-mass phase, where RODAS4's steps shrink 20x per 100x of tolerance). Each step solves the
collocation equations by simplified Newton iteration with the transformation of Hairer and Wanner
(*Solving ODEs II*, section IV.8) that splits them into one real and one complex n x n system with
the Jacobian at the step start; the error estimate is the embedded one of RADAU5, filtered through
(I/(h gamma) - J)^-1. The constants are those of scipy's ``Radau``, copied into :mod:`rrbody.integrate.tableaus` (and
tested against scipy's).
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit

from rrbody.integrate.tableaus import RADAU_C, RADAU_E, RADAU_MU_COMPLEX, RADAU_MU_REAL, RADAU_P, RADAU_T, RADAU_TI
from rrbody.physics.dynamics import rhs

__all__ = ["radau_step", "RADAU_TABLE", "NEWTON_MAXITER", "NEWTON_FAILED", "K_ROWS"]

NEWTON_MAXITER: int = 6
#: what :func:`radau_step` returns when its Newton iteration does not converge (an error norm no step passes)
NEWTON_FAILED: float = 1e10
#: the rows of the stage array ``K`` a Radau step uses (13 for the stages of the other methods, 5 of memory)
K_ROWS: int = 18


RADAU_TABLE: tuple[np.ndarray, ...] = (
    RADAU_C, RADAU_E, RADAU_T, RADAU_TI, np.array([RADAU_MU_REAL, RADAU_MU_COMPLEX.real, RADAU_MU_COMPLEX.imag]),
                                       RADAU_P)
"""(C, E, T, TI, [MU_REAL, MU_COMPLEX.real, MU_COMPLEX.imag], P): the Radau IIA constants
(:mod:`rrbody.integrate.tableaus`), P the dense-output coefficients, Z(s) = sum_q (Z^T P)_q s^(q+1)."""
# global arrays are compile-time constants for numba
_RC, _RE, _RT, _RTI, _RMU, _RP = RADAU_TABLE


@njit(cache=True)
def radau_step(system, t, y, f0, h, p, S, J, K, ynew, ytmp, scale, rtol):  # noqa: ANN001
    """One Radau IIA step of size h from (t, y), f0 = f(t, y), J = df/dy at (t, y), for n = 2.

    Fills ``ynew`` and K[12] = f(t + h, ynew). Returns the scaled RMS error norm, or
    :data:`NEWTON_FAILED` if the Newton iteration does not converge (the loop then halves h).

    ``K`` (at least :data:`K_ROWS` rows) is also the step's memory: rows 0-8 are scratch (the stage
    increments Z, their transform W, the stage slopes), rows 13-15 the collocation polynomial of the
    last converged step (power-basis coefficients of Z(s), s in units of its h), row 16 its (t, h)
    and K[17, 0] its Newton contraction factor. The Newton iteration starts from that polynomial, extrapolated to this
    step's stages, when this step starts where that one started or ended (as RADAU5 and scipy's Radau do), else from Z
    = 0: one to two iterations fewer per step in smooth stretches, and fewer failed iterations where the step is
    limited by Newton's convergence rather than by the error.
    """
    literally(system)
    n = 2
    RC = _RC
    RE = _RE
    RT = _RT
    RTI = _RTI
    RMU = _RMU
    RP = _RP
    mr = RMU[0] / h
    mc = complex(RMU[1], RMU[2]) / h
    # real matrix mr I - J and complex matrix mc I - J (2x2, closed-form inverses)
    a00 = mr - J[0, 0]
    a01 = -J[0, 1]
    a10 = -J[1, 0]
    a11 = mr - J[1, 1]
    detr = a00 * a11 - a01 * a10
    c00 = mc - J[0, 0]
    c01 = complex(-J[0, 1], 0.0)
    c10 = complex(-J[1, 0], 0.0)
    c11 = mc - J[1, 1]
    detc = c00 * c11 - c01 * c10
    # the start of the iteration: Z_i = u(s_i) - u(s_0) on the stored polynomial u, s = (time - t_b) / h_b
    tb = K[16, 0]
    hb = K[16, 1]
    guess = hb > 0.0 and (t == tb or t == tb + hb)
    s0 = (t - tb) / hb if guess else 0.0
    u0 = 0.0
    for j in range(n):
        u0 = ((K[15, j] * s0 + K[14, j]) * s0 + K[13, j]) * s0 if guess else 0.0
        for i in range(3):
            si = (t + RC[i] * h - tb) / hb if guess else 0.0
            K[i, j] = ((K[15, j] * si + K[14, j]) * si + K[13, j]) * si - u0 if guess else 0.0
        for i in range(3):
            K[3 + i, j] = RTI[i, 0] * K[0, j] + RTI[i, 1] * K[1, j] + RTI[i, 2] * K[2, j]
    tol = max(10.0 * 2.220446049250313e-16 / rtol, min(0.03, math.sqrt(rtol)))
    # from a guess, the last contraction factor rate / (1 - rate), relaxed toward 1 (RADAU5's FACCON):
    # a first increment below tol / faccon ends the iteration, which also keeps an increment at the
    # rounding level (a guess already converged) from reading as divergence (rate >= 1)
    faccon = max(K[17, 0], 2.220446049250313e-16) ** 0.8 if guess and K[17, 0] > 0.0 else 1.0
    old = -1.0
    converged = False
    for it in range(NEWTON_MAXITER):
        for i in range(3):
            for j in range(n):
                ytmp[j] = y[j] + K[i, j]
            rhs(system, t + RC[i] * h, ytmp, p, S, K, 6 + i)
        fr0 = RTI[0, 0] * K[6, 0] + RTI[0, 1] * K[7, 0] + RTI[0, 2] * K[8, 0] - mr * K[3, 0]
        fr1 = RTI[0, 0] * K[6, 1] + RTI[0, 1] * K[7, 1] + RTI[0, 2] * K[8, 1] - mr * K[3, 1]
        fc0 = complex(RTI[1, 0] * K[6, 0] + RTI[1, 1] * K[7, 0] + RTI[1, 2] * K[8, 0],
                      RTI[2, 0] * K[6, 0] + RTI[2, 1] * K[7, 0] + RTI[2, 2] * K[8, 0]) - mc * complex(K[4, 0], K[5, 0])
        fc1 = complex(RTI[1, 0] * K[6, 1] + RTI[1, 1] * K[7, 1] + RTI[1, 2] * K[8, 1],
                      RTI[2, 0] * K[6, 1] + RTI[2, 1] * K[7, 1] + RTI[2, 2] * K[8, 1]) - mc * complex(K[4, 1], K[5, 1])
        dr0 = (a11 * fr0 - a01 * fr1) / detr
        dr1 = (a00 * fr1 - a10 * fr0) / detr
        dc0 = (c11 * fc0 - c01 * fc1) / detc
        dc1 = (c00 * fc1 - c10 * fc0) / detc
        if not (math.isfinite(dr0) and math.isfinite(dr1) and math.isfinite(dc0.real) and math.isfinite(dc1.real)):
            break
        nrm = math.sqrt(((dr0 / scale[0]) ** 2 + (dr1 / scale[1]) ** 2 + (dc0.real / scale[0]) ** 2
                         + (dc1.real / scale[1]) ** 2 + (dc0.imag / scale[0]) ** 2 + (dc1.imag / scale[1]) ** 2)
                        / 6.0)
        if it > 0:
            rate = nrm / old
            if rate >= 1.0 or rate ** (NEWTON_MAXITER - it) / (1.0 - rate) * nrm > tol:
                break
            faccon = rate / (1.0 - rate)
        K[3, 0] += dr0
        K[3, 1] += dr1
        K[4, 0] += dc0.real
        K[4, 1] += dc1.real
        K[5, 0] += dc0.imag
        K[5, 1] += dc1.imag
        for i in range(3):
            for j in range(n):
                K[i, j] = RT[i, 0] * K[3, j] + RT[i, 1] * K[4, j] + RT[i, 2] * K[5, j]
        if faccon * nrm < tol:
            converged = True
            break
        old = max(nrm, 1e-300)
    if not converged:
        return NEWTON_FAILED
    # this step's collocation polynomial, the next step's start (scipy's Q = Z^T P)
    for j in range(n):
        for q in range(3):
            K[13 + q, j] = K[0, j] * RP[0, q] + K[1, j] * RP[1, q] + K[2, j] * RP[2, q]
        ynew[j] = y[j] + K[2, j]
    K[16, 0] = t
    K[16, 1] = h
    K[17, 0] = faccon
    # embedded error, filtered through (mr I - J)^-1
    e0 = f0[0] + (RE[0] * K[0, 0] + RE[1] * K[1, 0] + RE[2] * K[2, 0]) / h
    e1 = f0[1] + (RE[0] * K[0, 1] + RE[1] * K[1, 1] + RE[2] * K[2, 1]) / h
    er0 = (a11 * e0 - a01 * e1) / detr
    er1 = (a00 * e1 - a10 * e0) / detr
    rhs(system, t + h, ynew, p, S, K, np.int64(12))
    return math.sqrt(((er0 / scale[0]) ** 2 + (er1 / scale[1]) ** 2) / 2.0)


@njit(cache=True, inline="always")
def radau_memory(K, K2):  # noqa: ANN001
    """Copy the step memory of :func:`radau_step` (K rows 13-17) from ``K`` to ``K2``: a re-step from
    the same start (dense output, event location) then starts Newton on the accepted step's polynomial."""
    for r in range(13, 18):
        for j in range(K.shape[1]):
            K2[r, j] = K[r, j]
