"""Independent references for the tests: a plain scipy solution of the paper's Eq. 2 and the exact
quasi-static (omega -> 0) flip time. Nothing here imports rrbody's integrator."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad, solve_ivp


def scipy_flip_time(H: float, k: float, w: float, phi0: float, t_end: float, *, viscous: bool = False,
                    rtol: float = 1e-13) -> tuple[float, float]:
    """(t_f, phi_min) from scipy's DOP853 on Eq. 2 with a Python right-hand side."""

    def f(t: float, y: np.ndarray) -> list[float]:
        phi, pd = y
        c = math.cos(phi - w * t)
        s = math.sin(phi - w * t)
        num = w * c - H * pd
        if viscous:
            fr = k / H * num
        else:
            # speed^2 written as a sum of squares: no cancellation, and the 0/0 start gives 0
            ve = w * s
            den = math.hypot(ve, num)
            fr = k / H * num / den if den > 1e-12 * w else 0.0
        return [pd, w * w / H * s + fr]

    def ev(t: float, y: np.ndarray) -> float:
        return y[1]

    ev.direction = 1  # type: ignore[attr-defined]
    sol = solve_ivp(f, (0.0, t_end), [phi0, w / H * math.cos(phi0)], method="DOP853", rtol=rtol, atol=rtol,
                    events=ev)
    te = sol.t_events[0]
    ye = sol.y_events[0][:, 0]
    i = int(np.argmin(ye))
    return float(te[i]), float(ye[i])


def quasi_static_tf_times_omega(H: float) -> float:
    """Exact omega -> 0 limit of omega * t_f from phi0 = pi (dragged-mass dynamics).

    With inertia negligible (k >> omega^2) the friction torque about P must vanish, so the CM
    moves along the rod: phi' = (w/H) cos(psi), psi = phi - w t, psi' = -w (1 - cos(psi)/H),
    psi(0) = pi; phi' = 0 at psi = pi/2, hence w t_f = int_{pi/2}^{pi} H / (H - cos psi) dpsi.
    """
    return quad(lambda s: H / (H - math.cos(s)), 0.5 * math.pi, math.pi, epsabs=1e-14, epsrel=1e-14)[0]


def scipy_stiff_flip_time(H: float, k: float, w: float, t_end: float, *, method: str = "Radau",
                          rtol: float = 1e-12, dead_band: float = 1e-9) -> tuple[float, float]:
    """(t_f, phi_min) from phi0 = pi by scipy's implicit ``method`` (Radau or LSODA) with the
    analytic Jacobian of Eq. 2 (rod-mass, d = 1 m, dry friction), written here independently of
    rrbody's kernels. Where the CM speed is below ``dead_band`` * 2 w (the impulsive start) the dry
    term is taken as 0, as rrbody does (its effect there is below rounding: docs/accuracy.md)."""
    eps = dead_band * 2.0 * w

    def parts(t: float, y: np.ndarray) -> tuple[float, float, float, float, float]:
        s = math.sin(y[0] - w * t)
        c = math.cos(y[0] - w * t)
        ve = w * s                 # CM velocity along the rod (over d)
        vp = w * c - H * y[1]      # and across it
        return s, c, ve, vp, math.hypot(ve, vp)

    def f(t: float, y: np.ndarray) -> list[float]:
        s, c, ve, vp, sp = parts(t, y)
        fr = k * vp / sp if sp > eps else 0.0
        return [y[1], (w * w * s + fr) / H]

    def jac(t: float, y: np.ndarray) -> list[list[float]]:
        s, c, ve, vp, sp = parts(t, y)
        a = w * w * c
        b = 0.0
        if sp > eps:
            # d(vp/|v|) = (ve^2 dvp - ve vp dve) / |v|^3 with dve/dphi = w c, dvp/dphi = -w s, dvp/dphi' = -H
            a += k * (ve * ve * (-w * s) - ve * vp * (w * c)) / sp**3
            b += k * ve * ve * (-H) / sp**3
        return [[0.0, 1.0], [a / H, b / H]]

    def ev(t: float, y: np.ndarray) -> float:
        return y[1]

    ev.direction = 1  # type: ignore[attr-defined]
    sol = solve_ivp(f, (0.0, t_end), [math.pi, -w / H], method=method, rtol=rtol, atol=rtol * w / H, jac=jac,
                    events=ev)
    if not sol.success:
        raise RuntimeError(f"scipy {method} failed: {sol.message}")
    te = sol.t_events[0]
    ye = sol.y_events[0][:, 0]
    i = int(np.argmin(ye))
    return float(te[i]), float(ye[i])
