"""Compiled Rosenbrock method RODAS4 (order 4, embedded order 3, L-stable, stiffly accurate).

The stiff method of the stepping loop (:mod:`rrbody.integrate.ode`). A Rosenbrock step needs no
Newton iteration: each of its six stages solves one linear system with the matrix
W = I / (h gamma) - J, J = df/dy at the step start, and the right-hand side's time derivative
df/dt enters the first four stages (the equations are non-autonomous: the drive turns with t).
J and df/dt come from :func:`rrbody.physics.dynamics.jacobian` (analytic 2x2 for a driven point
mass, where the stiffness lives; finite differences otherwise).

Coefficients: E. Hairer and G. Wanner, *Solving Ordinary Differential Equations II* (2nd ed.,
Springer 1996), section IV.7, method RODAS (their ``rodas.f``, METH = 1). In that formulation the
stages k_i are increments of y (not slopes), the last two stage states coincide with the solution
(stiffly accurate: y_new = y_6 + k_6 with y_6 = y_5 + k_5), and k_6 is the local error estimate
of the embedded 3rd-order solution y_6.

Why RODAS4 here: where the problem is stiff (slow driving with strong dry friction, and the
impulsive start from phi0 = pi at large k) the friction relaxes the velocity direction on a time
scale |v| / (mu g) that an explicit method must resolve for stability alone; an L-stable method
takes steps set by the accuracy of the slow (dragged-mass) motion instead.
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit

from rrbody.integrate.radau import NEWTON_FAILED
from rrbody.physics.dynamics import rhs

__all__ = ["ros_step", "ROS_ORDER", "solve_w", "spectral_radius", "stiff_factor"]

#: order of the embedded error estimate is 3, so the step scales with err^(-1/4)
ROS_ORDER: int = 4

_GAMMA = 0.25
_C2, _C3, _C4 = 0.386, 0.21, 0.63
_D1, _D2, _D3, _D4 = 0.25, -0.1043, 0.1035, -0.3620000000000023e-01
_A21 = 1.544
_A31, _A32 = 0.9466785280815826, 0.2557011698983284
_A41, _A42, _A43 = 3.314825187068521, 2.896124015972201, 0.9986419139977817
_A51, _A52, _A53, _A54 = 1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950
_C21 = -5.6688
_C31, _C32 = -2.430093356833875, -0.2063599157091915
_C41, _C42, _C43 = -0.1073529058151375, -9.594562251023355, -20.47028614809616
_C51, _C52, _C53, _C54 = 7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160
_C61, _C62, _C63, _C64, _C65 = (8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136,
                                -6.058818238834054)


@njit(cache=True)
def solve_w(M, b, x):  # noqa: ANN001 (numba)
    """x = M^-1 b for a small dense M (n x n, n <= 6): closed form for n = 2, else Gaussian
    elimination with partial pivoting on a copy (M and b are left unchanged)."""
    n = b.shape[0]
    if n == 2:
        det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
        x[0] = (M[1, 1] * b[0] - M[0, 1] * b[1]) / det
        x[1] = (M[0, 0] * b[1] - M[1, 0] * b[0]) / det
        return
    A = M.copy()
    for j in range(n):
        x[j] = b[j]
    for c in range(n):
        piv = c
        for r in range(c + 1, n):
            if abs(A[r, c]) > abs(A[piv, c]):
                piv = r
        if piv != c:
            for q in range(n):
                A[c, q], A[piv, q] = A[piv, q], A[c, q]
            x[c], x[piv] = x[piv], x[c]
        for r in range(c + 1, n):
            m = A[r, c] / A[c, c]
            for q in range(c, n):
                A[r, q] -= m * A[c, q]
            x[r] -= m * x[c]
    for c in range(n - 1, -1, -1):
        acc = x[c]
        for q in range(c + 1, n):
            acc -= A[c, q] * x[q]
        x[c] = acc / A[c, c]


@njit(cache=True)
def ros_step(system, t, y, f0, h, p, S, J, fx, K, ynew, ytmp, scale):  # noqa: ANN001 (numba)
    """One RODAS4 step of size h from (t, y), f0 = f(t, y), J = df/dy and fx = df/dt at (t, y).

    Fills ``ynew`` and K[12] = f(t + h, ynew) (the loop's first stage of the next step and the
    slope that event location uses, as for DOP853); K[0..5] hold the stage increments. Returns
    the RMS norm of the error estimate k_6 / ``scale`` (scale = rtol times the component's scale).
    Compiled once per compiled code (``literally``; :func:`rrbody.physics.effects.compiled_code`).
    """
    literally(system)
    n = y.shape[0]
    W = np.empty((n, n))
    inv = 1.0 / (h * _GAMMA)
    for i in range(n):
        for j in range(n):
            W[i, j] = -J[i, j]
        W[i, i] += inv
    b = np.empty(n)
    fs = np.empty((1, n))
    x = np.empty(n)
    ih = 1.0 / h
    # stage 1
    for j in range(n):
        b[j] = f0[j] + h * _D1 * fx[j]
    solve_w(W, b, x)
    for j in range(n):
        K[0, j] = x[j]
    # stage 2
    for j in range(n):
        ytmp[j] = y[j] + _A21 * K[0, j]
    rhs(system, t + _C2 * h, ytmp, p, S, fs, np.int64(0))
    for j in range(n):
        b[j] = fs[0, j] + ih * (_C21 * K[0, j]) + h * _D2 * fx[j]
    solve_w(W, b, x)
    for j in range(n):
        K[1, j] = x[j]
    # stage 3
    for j in range(n):
        ytmp[j] = y[j] + _A31 * K[0, j] + _A32 * K[1, j]
    rhs(system, t + _C3 * h, ytmp, p, S, fs, np.int64(0))
    for j in range(n):
        b[j] = fs[0, j] + ih * (_C31 * K[0, j] + _C32 * K[1, j]) + h * _D3 * fx[j]
    solve_w(W, b, x)
    for j in range(n):
        K[2, j] = x[j]
    # stage 4
    for j in range(n):
        ytmp[j] = y[j] + _A41 * K[0, j] + _A42 * K[1, j] + _A43 * K[2, j]
    rhs(system, t + _C4 * h, ytmp, p, S, fs, np.int64(0))
    for j in range(n):
        b[j] = fs[0, j] + ih * (_C41 * K[0, j] + _C42 * K[1, j] + _C43 * K[2, j]) + h * _D4 * fx[j]
    solve_w(W, b, x)
    for j in range(n):
        K[3, j] = x[j]
    # stage 5 (at t + h; no df/dt term)
    for j in range(n):
        ytmp[j] = y[j] + _A51 * K[0, j] + _A52 * K[1, j] + _A53 * K[2, j] + _A54 * K[3, j]
    rhs(system, t + h, ytmp, p, S, fs, np.int64(0))
    for j in range(n):
        b[j] = fs[0, j] + ih * (_C51 * K[0, j] + _C52 * K[1, j] + _C53 * K[2, j] + _C54 * K[3, j])
    solve_w(W, b, x)
    for j in range(n):
        K[4, j] = x[j]
    # stage 6: y_6 = y_5 + k_5 is the embedded 3rd-order solution
    for j in range(n):
        ytmp[j] += K[4, j]
    rhs(system, t + h, ytmp, p, S, fs, np.int64(0))
    for j in range(n):
        b[j] = fs[0, j] + ih * (_C61 * K[0, j] + _C62 * K[1, j] + _C63 * K[2, j] + _C64 * K[3, j] + _C65 * K[4, j])
    solve_w(W, b, x)
    err = 0.0
    for j in range(n):
        K[5, j] = x[j]
        ynew[j] = ytmp[j] + x[j]
        err += (x[j] / scale[j]) ** 2
    rhs(system, t + h, ynew, p, S, fs, np.int64(0))
    for j in range(n):
        K[12, j] = fs[0, j]
    return math.sqrt(err / n)


@njit(cache=True)
def spectral_radius(J):  # noqa: ANN001
    """|largest eigenvalue| of J (exact for 2x2; the infinity-norm bound for larger J)."""
    n = J.shape[0]
    if n == 2:
        tr = J[0, 0] + J[1, 1]
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        disc = tr * tr - 4.0 * det
        if disc >= 0.0:
            s = math.sqrt(disc)
            return max(abs(0.5 * (tr + s)), abs(0.5 * (tr - s)))
        return math.sqrt(abs(det))
    best = 0.0
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += abs(J[i, j])
        best = max(best, acc)
    return best


@njit(cache=True, inline="always")
def stiff_factor(err, rejected, meth=1):  # noqa: ANN001
    """Stiff step factor: err^(-1/4) with safety 0.9, within [1/5, 6] (Hairer's FAC1, FAC2); 1/2 after
    a Radau step whose Newton iteration failed (RADAU5's: its error norm says nothing of the step)."""
    if meth == 2 and err >= NEWTON_FAILED:
        return 0.5
    fac = 6.0 if err == 0.0 else min(6.0, max(0.2, 0.9 * err ** -0.25))
    if rejected:
        fac = min(1.0, fac)
    return fac
