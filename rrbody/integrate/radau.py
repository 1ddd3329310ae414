"""Compiled Radau IIA (order 5, three stages, L-stable, stage order 3) for small systems.

The second stiff method of the stepping loop. Unlike a Rosenbrock method, Radau IIA keeps its
order on stiff problems whose slow manifold moves with time (stage order 3: no order reduction in
the dragged-mass phase, where RODAS4's steps shrink 20x per 100x of tolerance). Each step solves the
collocation equations by simplified Newton iteration with the transformation of Hairer and Wanner
(*Solving ODEs II*, section IV.8) that splits them into one real and one complex n x n system with
the Jacobian at the step start; the error estimate is the embedded one of RADAU5, filtered through
(I/(h gamma) - J)^-1. The constants are those of scipy's ``Radau`` (``scipy.integrate._ivp.radau``),
loaded from its source so that they are not retyped.
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit

from rrbody.physics.dynamics import rhs

__all__ = ["radau_step", "RADAU_TABLE", "NEWTON_MAXITER"]

NEWTON_MAXITER: int = 6


def _load() -> tuple[np.ndarray, ...]:
    """(C, E, T, TI, [MU_REAL, MU_COMPLEX.real, MU_COMPLEX.imag]) from scipy's radau module."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.find_spec("scipy")
    if spec is None or spec.origin is None:
        raise ImportError("scipy is required")
    path = Path(spec.origin).parent / "integrate" / "_ivp" / "radau.py"
    src = path.read_text()
    # only the constant block (the module's imports would pull in scipy.linalg)
    start = src.index("S6 = 6 ** 0.5")
    end = src.index("TI_REAL")
    ns: dict[str, object] = {"np": np}
    exec(compile(src[start:end], str(path), "exec"), ns)  # noqa: S102 - scipy's own constants
    mu_c = complex(ns["MU_COMPLEX"])  # type: ignore[arg-type]
    return (np.ascontiguousarray(ns["C"], dtype=np.float64), np.ascontiguousarray(ns["E"], dtype=np.float64),
            np.ascontiguousarray(ns["T"], dtype=np.float64), np.ascontiguousarray(ns["TI"], dtype=np.float64),
            np.array([float(ns["MU_REAL"]), mu_c.real, mu_c.imag]))  # type: ignore[arg-type]


RADAU_TABLE: tuple[np.ndarray, ...] = _load()
# global arrays are compile-time constants for numba
_RC, _RE, _RT, _RTI, _RMU = RADAU_TABLE


@njit(cache=True)
def radau_step(system, t, y, f0, h, p, S, J, K, ynew, ytmp, scale, rtol):  # noqa: ANN001
    """One Radau IIA step of size h from (t, y), f0 = f(t, y), J = df/dy at (t, y), for n = 2.

    Fills ``ynew`` and K[12] = f(t + h, ynew). Returns the scaled RMS error norm, or 1e10 if the
    Newton iteration does not converge (the loop then rejects the step and shrinks h).
    """
    literally(system)
    n = 2
    RC = _RC
    RE = _RE
    RT = _RT
    RTI = _RTI
    RMU = _RMU
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
    Z = np.zeros((3, n))
    W = np.zeros((3, n))
    F = np.empty((3, n))
    tol = max(10.0 * 2.220446049250313e-16 / rtol, min(0.03, math.sqrt(rtol)))
    old = -1.0
    converged = False
    for it in range(NEWTON_MAXITER):
        for i in range(3):
            for j in range(n):
                ytmp[j] = y[j] + Z[i, j]
            rhs(system, t + RC[i] * h, ytmp, p, S, F, i)
        fr0 = RTI[0, 0] * F[0, 0] + RTI[0, 1] * F[1, 0] + RTI[0, 2] * F[2, 0] - mr * W[0, 0]
        fr1 = RTI[0, 0] * F[0, 1] + RTI[0, 1] * F[1, 1] + RTI[0, 2] * F[2, 1] - mr * W[0, 1]
        fc0 = complex(RTI[1, 0] * F[0, 0] + RTI[1, 1] * F[1, 0] + RTI[1, 2] * F[2, 0],
                      RTI[2, 0] * F[0, 0] + RTI[2, 1] * F[1, 0] + RTI[2, 2] * F[2, 0]) - mc * complex(W[1, 0], W[2, 0])
        fc1 = complex(RTI[1, 0] * F[0, 1] + RTI[1, 1] * F[1, 1] + RTI[1, 2] * F[2, 1],
                      RTI[2, 0] * F[0, 1] + RTI[2, 1] * F[1, 1] + RTI[2, 2] * F[2, 1]) - mc * complex(W[1, 1], W[2, 1])
        dr0 = (a11 * fr0 - a01 * fr1) / detr
        dr1 = (a00 * fr1 - a10 * fr0) / detr
        dc0 = (c11 * fc0 - c01 * fc1) / detc
        dc1 = (c00 * fc1 - c10 * fc0) / detc
        if not (math.isfinite(dr0) and math.isfinite(dr1) and math.isfinite(dc0.real) and math.isfinite(dc1.real)):
            break
        nrm = math.sqrt(((dr0 / scale[0]) ** 2 + (dr1 / scale[1]) ** 2 + (dc0.real / scale[0]) ** 2
                         + (dc1.real / scale[1]) ** 2 + (dc0.imag / scale[0]) ** 2 + (dc1.imag / scale[1]) ** 2)
                        / 6.0)
        rate = nrm / old if old > 0.0 else -1.0
        if rate >= 1.0 or (rate > 0.0 and rate ** (NEWTON_MAXITER - it) / (1.0 - rate) * nrm > tol):
            break
        W[0, 0] += dr0
        W[0, 1] += dr1
        W[1, 0] += dc0.real
        W[1, 1] += dc1.real
        W[2, 0] += dc0.imag
        W[2, 1] += dc1.imag
        for i in range(3):
            for j in range(n):
                Z[i, j] = RT[i, 0] * W[0, j] + RT[i, 1] * W[1, j] + RT[i, 2] * W[2, j]
        if nrm == 0.0 or (rate > 0.0 and rate / (1.0 - rate) * nrm < tol):
            converged = True
            break
        old = nrm
    if not converged:
        return 1e10
    for j in range(n):
        ynew[j] = y[j] + Z[2, j]
    # embedded error, filtered through (mr I - J)^-1
    e0 = f0[0] + (RE[0] * Z[0, 0] + RE[1] * Z[1, 0] + RE[2] * Z[2, 0]) / h
    e1 = f0[1] + (RE[0] * Z[0, 1] + RE[1] * Z[1, 1] + RE[2] * Z[2, 1]) / h
    er0 = (a11 * e0 - a01 * e1) / detr
    er1 = (a00 * e1 - a10 * e0) / detr
    rhs(system, t + h, ynew, p, S, K, np.int64(12))
    return math.sqrt(((er0 / scale[0]) ** 2 + (er1 / scale[1]) ** 2) / 2.0)
