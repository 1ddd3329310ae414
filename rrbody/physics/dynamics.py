"""Right-hand sides composed from a scene's effects (compiled, pure functions of (t, y, p, S)).

``code`` is the scene's compiled code (:func:`rrbody.physics.effects.compiled_code`: the kind,
:data:`SYSTEM_DRIVEN` or :data:`SYSTEM_FREE`, which says which state and which equations, plus 10
times a driven body's friction law). The kernels are compiled once per code, with the code as a
compile-time constant (the state size fixes the loops' trip counts; a driven body's law read at run
time was measured to cost the stiff runs a quarter of their speed; a free body's law is read from
``p[LAW]``, its Jacobian being numerical). The area method is chosen at run time from ``p[BODY]``, so every area
method runs in the same compiled code and a new combination of effects compiles nothing (docs/compile.md). The point
mass, where an evaluation costs a few ns, is written inline; an extended body's area method is one call of
:func:`_driven_extended` or :func:`_free`, so the loop's code does not grow with the area methods.

Driven body (the impulsive start, docs/physics.md), state y = (phi, phi') with phi the angle of CM -> P (rad):

    (I_cm/m + l^2) phi'' = omega^2 l d sin(phi - omega t) + tau_P / m

The body angle is alpha = phi - beta, so the same state serves l = 0 (P at the CM), where phi is
simply the body angle shifted by beta. tau_P is the friction torque about P (world frame).

Free body, y = (x, y, alpha, vx, vy, spin) (m, rad, m/s, rad/s): friction, on a tilted plane
gravity's pull along it (:mod:`rrbody.physics.effects.tilt`, which adds its torque about P to a
driven body's phi''), and an active body's propulsion and drag (:mod:`rrbody.physics.effects.active`).
Its Langevin noise is no term of the right-hand side: it is additive, and the fixed-step scheme of
:mod:`rrbody.integrate.sde` adds it to this drift (:func:`rrbody.physics.effects.active.ode_noise`).
"""

from __future__ import annotations

import math
import types
from typing import Any

import numpy as np
from numba import literally, njit

from rrbody._private import no_refcount
from rrbody.physics import params as P
from rrbody.physics.areas import POINT, body_frame_wrench, body_wrench
from rrbody.physics.effects import DRIVEN, active, compiled_code, drive_circular, tangent, tilt
from rrbody.physics.effects.laws import NONE, element_perp, law_params

__all__ = ["rhs", "rhs_near", "rhs_for", "tangent_rhs_for", "driven_rhs", "driven_tangent", "driven_kinematics",
           "jacobian", "system_from_params", "SYSTEM_DRIVEN",
           "SYSTEM_FREE"]

SYSTEM_DRIVEN = 0  # kind code: y = (phi, phi')
SYSTEM_FREE = 1    # kind code: y = (x, y, alpha, vx, vy, spin)

driven_kinematics = drive_circular.kinematics


@njit(cache=True, inline="always")
def _driven_point(law, t, y, p, d, s0, c0):  # noqa: ANN001 (numba)
    """(phi', phi'') of a point mass: friction at the CM only. Work in the frame (e, e_perp) of
    CM -> P, where the CM velocity is (d w sin psi, d w cos psi - l phi') with psi = phi - w t
    (its sine and cosine from :func:`drive_circular.sincos_psi`), and the speed is a sum of squares
    (no cancelling square root at the phi0 = pi start)."""
    s, c = drive_circular.sincos_psi(t, y[0], p, d, s0, c0)
    torque = drive_circular.torque(s, p)
    if law != NONE:
        ve, vp = drive_circular.rod_velocity(s, c, y[1], p)
        f_perp, _, _ = element_perp(law, ve, vp, p[P.COEFF], p[P.VEPS], law_params(p))
        torque -= p[P.L] * f_perp  # (r - P) x F with r - P = -l e
    # times 1/I_P: a division would sit on the critical path of every Runge-Kutta stage
    return y[1], torque * p[P.INV_IP]


@njit(cache=True, **no_refcount())
def _driven_extended(law, area, t, phi, phid, p, S, d, s0, c0):  # noqa: ANN001 (numba)
    """(phi', phi'') of an extended body, or of a point mass on a tilted plane (one sampled element
    at its CM: :func:`rrbody.physics.bind.area_model`): one sine and cosine of the drive phase per evaluation, as
    for a point mass (:func:`drive_circular.sincos_psi`). The CM
    velocity in the rod frame (e, e_perp) of CM -> P is (d w sin psi, d w cos psi - l phi'),
    psi = phi - w t; the body frame is the rod frame turned by the constant beta = phi - alpha, so
    v_b = R(beta) v_rod and F_rod = R(-beta) F_b (cos, sin beta precomputed in p)."""
    s, c = drive_circular.sincos_psi(t, phi, p, d, s0, c0)
    torque = drive_circular.torque(s, p)
    if p[P.TILTED] != 0.0:
        torque += tilt.pivot_torque(phi, p)
    if law != NONE:
        ve, vp = drive_circular.rod_velocity(s, c, phid, p)
        cb = p[P.CBETA]
        sb = p[P.SBETA]
        fbx, fby, tau_cm = body_frame_wrench(area, law, S, p[P.RA], p[P.RB], int(p[P.NQ]), p[P.ICM],
                                             cb * ve - sb * vp, sb * ve + cb * vp, phid, p[P.COEFF], p[P.VEPS],
                                             law_params(p))
        # torque about P: tau_cm + (r - P) x F with r - P = -l e, i.e. -l times F's e_perp component
        torque += tau_cm - p[P.L] * (cb * fby - sb * fbx)
    return phid, torque * p[P.INV_IP]


@njit(cache=True, inline="always")
def _free_body(law, area, t, y, p, S):  # noqa: ANN001 (numba)
    """Accelerations (Fx, Fy, spin') of a free body: friction alone. A point mass (I_cm = 0) keeps
    its spin constant: it has no rotational inertia to decelerate. Inlined for a point mass; an
    extended body calls it through :func:`_free`."""
    fx, fy = tilt.pull(p)  # gravity along a tilted plane (0 on a level one)
    tau = 0.0
    aw = 0.0
    if p[P.ACTIVE] != 0.0:  # self-propulsion fixed in the body frame, a medium's drag
        ax, ay, aw = active.ode_terms(y[2], y[3], y[4], y[5], p)
        fx += ax
        fy += ay
    if law != NONE:
        gx, gy, tau = body_wrench(area, law, S, p[P.RA], p[P.RB], int(p[P.NQ]), p[P.ICM], y[2], y[3], y[4], y[5],
                                  p[P.COEFF], p[P.VEPS], law_params(p))
        fx += gx
        fy += gy
    return fx, fy, (tau / p[P.ICM] if p[P.ICM] > 0.0 else 0.0) + aw


@njit(cache=True, **no_refcount())
def _free(law, area, t, y, p, S):  # noqa: ANN001 (numba)
    """:func:`_free_body` of an extended body, a call of its own (as :func:`_driven_extended`)."""
    return _free_body(law, area, t, y, p, S)


@njit(cache=True, **no_refcount())
def driven_tangent(law, area, t, y, p, S, out, row):  # noqa: ANN001 (numba)
    """The tangent vectors' derivatives (:mod:`rrbody.physics.effects.tangent`) at the base state
    y[:2]: analytic for a point mass (its Jacobian's terms, as in :func:`jacobian`), central
    differences of phi'' elsewhere."""
    if area == POINT:
        w = p[P.OMEGA]
        dd = p[P.D]
        l = p[P.L]
        s, c = drive_circular.sincos_psi(t, y[0], p, math.nan, 0.0, 0.0)
        dtq_dphi = w * w * l * dd * c
        dtq_dphid = 0.0
        if law != NONE:
            _, dfe, dfp = element_perp(law, dd * w * s, dd * w * c - l * y[1], p[P.COEFF], p[P.VEPS], law_params(p))
            # torque -= l f_p; dv_e/dphi = d w c, dv_p/dphi = -d w s, dv_p/dphi' = -l
            dtq_dphi -= l * (dfe * dd * w * c - dfp * dd * w * s)
            dtq_dphid += l * l * dfp
        tangent.advance(y, out, row, dtq_dphi * p[P.INV_IP], dtq_dphid * p[P.INV_IP])
        return
    h0 = tangent.EPS * max(abs(y[0]), 1.0)
    h1 = tangent.EPS * max(abs(y[1]), abs(p[P.OMEGA]), 1e-300)
    nan = math.nan
    a = (_driven_extended(law, area, t, y[0] + h0, y[1], p, S, nan, 0.0, 0.0)[1]
         - _driven_extended(law, area, t, y[0] - h0, y[1], p, S, nan, 0.0, 0.0)[1]) / (2.0 * h0)
    b = (_driven_extended(law, area, t, y[0], y[1] + h1, p, S, nan, 0.0, 0.0)[1]
         - _driven_extended(law, area, t, y[0], y[1] - h1, p, S, nan, 0.0, 0.0)[1]) / (2.0 * h1)
    tangent.advance(y, out, row, a, b)


@njit(cache=True, **no_refcount())
def rhs_near(code, t, y, p, S, out, row, d, s0, c0):  # noqa: ANN001
    """out[row, :] = y' for the equations of the compiled code ``code`` and the area method of ``p`` (module
    docstring), where a driven body's drive phase psi = phi - omega t is psi0 + d with (sin, cos)(psi0) = (s0, c0): a
    Runge-Kutta stage passes its step's start (:func:`drive_circular.sincos_psi`; d = NaN: no base).

    Compiled once per code (``literally``); the area method is read from ``p`` (a load and a
    predictable branch per evaluation: the price of compiling once for every area method). The
    result goes to a row of a 2-D array (a stage of the integrator's K) rather than to a row view,
    which would cost a reference-count update per evaluation. Compiled without reference counting
    (``_nrt=False``; nothing here allocates): passing ``S`` on to a method's own compiled kernel
    (the wrench table, the quadrature) would otherwise cost two atomic reference-count updates per
    evaluation (measured: an ellipse's table right-hand side 132 -> 108 ns in the benchmark's
    compiled loop, which can then inline it; its flip-time steps ~5 % cheaper)."""
    literally(code)
    area = int(p[P.BODY])
    if code % 10 == DRIVEN:
        law = (code // 10) % 10  # compiled in
        if area == POINT:
            a, b = _driven_point(law, t, y, p, d, s0, c0)
        else:
            a, b = _driven_extended(law, area, t, y[0], y[1], p, S, d, s0, c0)
        out[row, 0] = a
        out[row, 1] = b
    else:
        law_free = int(p[P.LAW])  # a free body's law: a run-time choice (compiled_code)
        if area == POINT:
            ax, ay, aw = _free_body(law_free, POINT, t, y, p, S)
        else:
            ax, ay, aw = _free(law_free, area, t, y, p, S)
        out[row, 0] = y[3]
        out[row, 1] = y[4]
        out[row, 2] = y[5]
        out[row, 3] = ax
        out[row, 4] = ay
        out[row, 5] = aw


def _twin(fn: Any, name: str) -> Any:
    """The Python function ``fn`` under another name (its own numba function and cache entry)."""
    code = fn.__code__.replace(co_name=name, co_qualname=name)
    twin = types.FunctionType(code, fn.__globals__, name, fn.__defaults__, fn.__closure__)
    twin.__qualname__, twin.__doc__, twin.__module__ = name, fn.__doc__, fn.__module__
    return twin


#: :func:`rhs_near` compiled a second time, for every caller but the DOP853 stages (:func:`rhs`: the
#: stiff methods, the first step, the Jacobian). With one compiled function for all, LLVM stopped
#: inlining it into the DOP853 step, which became measurably slower per step;
#: with literal constant rows, as before, numba compiled it three times per law, not twice.
_rhs_other = njit(cache=True, **no_refcount())(_twin(rhs_near.py_func, "rhs_other"))


@njit(cache=True, **no_refcount())
def rhs(code, t, y, p, S, out, row):  # noqa: ANN001
    """out[row, :] = y' at (t, y): :func:`rhs_near` without a base angle (the library's sin and cos).
    Callers pass a constant ``row`` as ``np.int64(...)``: numba compiles a callee again for each
    literal constant argument."""
    literally(code)
    _rhs_other(code, t, y, p, S, out, row, math.nan, 0.0, 0.0)


def system_from_params(p: np.ndarray, kind: int) -> int:
    """The system code (kind + 10 law + 100 area, :func:`rrbody.physics.effects.system_code`) of a
    parameter vector from :func:`rrbody.physics.bind.kernel_params`; the kernels are compiled for its
    :func:`rrbody.physics.effects.compiled_code`."""
    return int(kind) + 10 * int(p[P.LAW]) + 100 * int(p[P.BODY])


_RHS_KERNELS: dict[int, Any] = {}


def rhs_for(system: int) -> Any:
    """A compiled ``f(t, y, p, S, out)`` for the system code ``system`` (one per compiled code,
    cached on disk by numba: the closure constant is part of the cache key; the area method comes
    from ``p``)."""
    code = compiled_code(system)
    if code not in _RHS_KERNELS:

        @njit(cache=True)
        def kernel(t, y, p, S, out):  # noqa: ANN001
            rhs(code, t, y, p, S, out.reshape((1, out.shape[0])), np.int64(0))

        _RHS_KERNELS[code] = kernel
    return _RHS_KERNELS[code]


_TANGENT_KERNELS: dict[int, Any] = {}


def tangent_rhs_for(system: int) -> Any:
    """:func:`rhs_for` of a driven state that carries tangent vectors (effect tangent): y' including
    theirs. A kernel of its own: the stepping methods' right-hand side (:func:`rhs`) stays free of
    the tangent's branch (DOP853 steps the vectors in ``dop853.tangent_stages``)."""
    code = compiled_code(system)
    if code not in _TANGENT_KERNELS:

        @njit(cache=True)
        def kernel(t, y, p, S, out):  # noqa: ANN001
            out2 = out.reshape((1, out.shape[0]))
            rhs(code, t, y, p, S, out2, np.int64(0))
            if y.shape[0] > 2:
                driven_tangent((code // 10) % 10, int(p[P.BODY]), t, y, p, S, out2, np.int64(0))

        _TANGENT_KERNELS[code] = kernel
    return _TANGENT_KERNELS[code]


def driven_rhs(t: float, y: np.ndarray, p: np.ndarray, S: np.ndarray, out: np.ndarray) -> None:
    """out = (phi', phi'') for the driven body of ``p``, ``S`` (a convenience for tests and set-up:
    the stepping loop calls :func:`rhs` with its compiled code)."""
    rhs_for(system_from_params(p, SYSTEM_DRIVEN))(t, y, p, S, out)


def free_rhs(t: float, y: np.ndarray, p: np.ndarray, S: np.ndarray, out: np.ndarray) -> None:
    """out = y' for the free body of ``p``, ``S`` (set-up convenience, as :func:`driven_rhs`)."""
    rhs_for(system_from_params(p, SYSTEM_FREE))(t, y, p, S, out)


@njit(cache=True)
def jacobian(code, t, y, p, S, f0, J, fx):  # noqa: ANN001
    """J = df/dy and fx = df/dt at (t, y) for the equations of the compiled code ``code`` (area method
    from ``p``); f0 = f(t, y).

    Analytic for the driven point mass (where the stiffness lives): with psi = phi - w t the CM
    velocity in the frame (e, e_perp) is (v_e, v_p) = (d w sin psi, d w cos psi - l phi');
    phi'' = (w^2 l d sin psi - l f_p(v_e, v_p)) / I_P, d/dt = -w d/dphi at fixed phi'. Elsewhere
    one-sided finite differences with steps 1.5e-8 times the component's size (error ~1e-8
    relative: a Rosenbrock method keeps its stability with an approximate J, and its order
    conditions here are met to that level, far below the tolerances it is used at).
    """
    literally(code)
    law = (code // 10) % 10
    area = int(p[P.BODY])
    if code % 10 == DRIVEN and area == POINT:
        w = p[P.OMEGA]
        d = p[P.D]
        l = p[P.L]
        ip = p[P.IP]
        psi = y[0] - w * t
        s = math.sin(psi)
        c = math.cos(psi)
        dtq_dphi = w * w * l * d * c
        dtq_dphid = 0.0
        if law != NONE:
            _, dfe, dfp = element_perp(law, d * w * s, d * w * c - l * y[1], p[P.COEFF], p[P.VEPS], law_params(p))
            # torque -= l f_p; dv_e/dphi = d w c, dv_p/dphi = -d w s, dv_p/dphi' = -l
            dtq_dphi -= l * (dfe * d * w * c - dfp * d * w * s)
            dtq_dphid -= l * (-l * dfp)
        fx[0] = 0.0
        fx[1] = -w * dtq_dphi / ip
        J[0, 0] = 0.0
        J[0, 1] = 1.0
        J[1, 0] = dtq_dphi / ip
        J[1, 1] = dtq_dphid / ip
        return
    _jacobian_fd(code, t, y, p, S, f0, J, fx)


@njit(cache=True)
def _jacobian_fd(code, t, y, p, S, f0, J, fx):  # noqa: ANN001
    """:func:`jacobian` by one-sided finite differences (its docstring); a call of its own, so the
    analytic point-mass Jacobian stays free of its allocations (a run-time branch between the two
    still costs the point mass its reference counts: the stiff runs' steps are ~7 % slower than with
    the area method compiled in, docs/compile.md)."""
    literally(code)
    n = y.shape[0]
    yp = y.copy()
    fp = np.empty((1, n))
    for j in range(n):
        dj = 1.5e-8 * max(abs(y[j]), 1.0)
        yp[j] = y[j] + dj
        rhs(code, t, yp, p, S, fp, np.int64(0))
        for i in range(n):
            J[i, j] = (fp[0, i] - f0[i]) / dj
        yp[j] = y[j]
    dt = 1.5e-8 * max(abs(t), 1.0)
    rhs(code, t + dt, y, p, S, fp, np.int64(0))
    for i in range(n):
        fx[i] = (fp[0, i] - f0[i]) / dt
