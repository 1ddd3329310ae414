"""Fixed steps for a free body with Langevin noise: the stochastic Runge-Kutta scheme SRA1.

An active body's noise (:mod:`rrbody.model.active`, :func:`rrbody.physics.effects.active.ode_noise`)
makes the free body's equations an SDE with additive noise on the velocities,

    dy = f(y) dt + B dW,   y = (x, y, alpha, vx, vy, w),

with f the free body's right-hand side, composed from the scene's effects exactly as the adaptive
loop's (:func:`rrbody.physics.dynamics.rhs`: friction, tilt, the active effect's propulsion and
drag), and B constant: gamma_t sqrt(2 D_t) on vx and vy, gamma_r sqrt(2 D_r) on w. White noise has
no smooth solution for an error estimate to control, so the steps are fixed (``h``) and the scheme
is Roessler's SRA1 (A. Roessler, SIAM J. Numer. Anal. 48, 922 (2010); the tableau as in
DifferentialEquations.jl and diffrax):

    H     = y + (3/4) h f(y) + (3/2) B I10 / h
    y_new = y + h (f(y) / 3 + 2 f(H) / 3) + B dW

with, per noisy component, the Wiener increment dW = sqrt(h) xi_1 and the iterated integral
I10 = int_0^h (W(s) - W(0)) ds = h^1.5 (xi_1 + xi_2 / sqrt(3)) / 2 (xi_1, xi_2 independent standard
normal numbers: E[dW^2] = h, E[dW I10] = h^2 / 2, E[I10^2] = h^3 / 3, the exact joint law). For
additive noise and a smooth f it has **strong order 1.5 and weak order 2**; its drift part is
Ralston's second-order Runge-Kutta method (two evaluations of f per step). The positions receive the
noise's integral I10 exactly (for x' = v, v' = sigma xi the step is exact), which Euler-Maruyama and
the stochastic Heun scheme miss (strong order 1). For the Ornstein-Uhlenbeck velocity
v' = -gamma v + sigma xi the stationary variance comes out as (sigma^2 / (2 gamma)) (1 - x^2/6 + O(x^3)),
x = gamma h: -4e-4 relative at the default x = 0.05, -4.3 % at the largest a Scene takes, x = 0.5
(:data:`rrbody.model.scene.NOISE_STEP_MAX`); the scheme is unstable beyond x = 2. Dry friction is not
smooth at zero sliding speed: there the orders above are not claimed.

Steps and seed: the step is the scene's ``noise_dt`` (default :func:`default_noise_dt`), shortened to
h = dt_out / ceil(dt_out / noise_dt) so that the output times k dt_out are step ends (the samples are
states of the scheme, not interpolants); the last step ends on the horizon. The normal numbers come
from one ``numpy.random.Generator(PCG64(scene.seed))``, as the plugin's: two per noisy component and
step, drawn a chunk of steps at a time in step order (translation x, y, then rotation), so the same
scene, seed, horizon and output interval give bit-identical runs whatever the chunking.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import literally, njit

from rrbody.integrate.chunks import run_in_chunks
from rrbody.integrate.loop import L_NOUT, L_NSTEP, L_T
from rrbody.model.scene import Scene
from rrbody.physics.dynamics import SYSTEM_FREE, rhs, system_from_params
from rrbody.physics.effects import active as A
from rrbody.physics.effects import compiled_code

__all__ = ["run_sde", "default_noise_dt", "uses_sde", "DEFAULT_RATE_STEP"]

#: the default step times the fastest rate of the motion (:func:`default_noise_dt`): the stationary
#: variance's bias x^2 / 6 is then 4e-4 (module docstring), below any ensemble's statistical error
DEFAULT_RATE_STEP: float = 0.05


def uses_sde(scene: Scene) -> bool:
    """Whether the ODE path runs ``scene`` with the fixed-step scheme: an active body with noise, or with
    ``noise_dt`` given (the deterministic limit)."""
    return scene.active is not None and (scene.active.noisy or scene.noise_dt is not None)


def default_noise_dt(scene: Scene, t_max: float) -> float:
    """The step (s) for ``scene`` without ``noise_dt``: :data:`DEFAULT_RATE_STEP` over the fastest rate of
    its motion (1/s): drag, rot_drag, a viscous friction's gamma (:attr:`Scene.noise_rate`), the initial
    spin, the propulsion's terminal spin tau / (I gamma_r) and the noise's spin sqrt(gamma_r D_r); at
    most ``t_max`` / 100."""
    a = scene.active
    rates = [scene.noise_rate, abs(scene.spin0)]
    if a is not None and not scene.body.is_point:
        icm = scene.body.inertia_per_mass
        if a.rot_drag > 0.0:
            rates.append(abs(a.torque) / (scene.body.mass * icm * a.rot_drag))
        rates.append(math.sqrt(a.rot_drag * a.rot_diffusion))
    r = max(rates)
    return min(t_max / 100.0, DEFAULT_RATE_STEP / r) if r > 0.0 else t_max / 100.0


@njit(cache=True)
def sra_advance(code, y, st, p, S, t_end, h, n_sub, out, dt_out, idx, sig, xi, nmax):  # noqa: ANN001 (numba)
    """At most ``nmax`` SRA1 steps of length h (s) of the free body (y, in place) from step st[L_NSTEP]
    (t = k h) towards ``t_end``; every ``n_sub``-th step end is written to ``out`` (row j: t = j dt_out,
    y). Component idx[c] gets the noise sig[c] dW with the normal numbers xi[step, 2c], xi[step, 2c + 1].
    Returns 0 at t_end, 5 after nmax steps (the loop's codes, :data:`rrbody.integrate.loop.STATUS`)."""
    literally(code)
    n = y.shape[0]
    m = idx.shape[0]
    K = np.empty((2, n))
    H = np.empty(n)
    k = int(st[L_NSTEP])
    r3 = 1.0 / math.sqrt(3.0)
    code_out = 5
    for s in range(nmax):
        t = k * h  # a multiple of h, not a running sum: no drift of the output times
        left = t_end - t
        if left <= 1e-9 * h:
            code_out = 0
            break
        hk = left if left <= h * (1.0 + 1e-9) else h  # the last step ends on t_end
        rhs(code, t, y, p, S, K, np.int64(0))
        for i in range(n):
            H[i] = y[i] + 0.75 * hk * K[0, i]
        sq = math.sqrt(hk)
        for c in range(m):
            # I10 / h = sqrt(h) (xi_1 + xi_2 / sqrt(3)) / 2
            H[idx[c]] += 1.5 * sig[c] * 0.5 * sq * (xi[s, 2 * c] + r3 * xi[s, 2 * c + 1])
        rhs(code, t + 0.75 * hk, H, p, S, K, np.int64(1))
        for i in range(n):
            y[i] += hk * (K[0, i] / 3.0 + 2.0 * K[1, i] / 3.0)
        for c in range(m):
            y[idx[c]] += sig[c] * sq * xi[s, 2 * c]
        k += 1
        if k % n_sub == 0:
            j = k // n_sub
            if j < out.shape[0]:
                out[j, 0] = j * dt_out
                for i in range(n):
                    out[j, 1 + i] = y[i]
                st[L_NOUT] = j + 1
    else:
        code_out = 5 if t_end - k * h > 1e-9 * h else 0
    st[L_NSTEP] = k
    st[L_T] = min(k * h, t_end)
    return code_out


_SPECIALISED: dict[int, Any] = {}


def _sde_for(system: int) -> Any:
    """:func:`sra_advance` for the system code ``system``, one compiled function per compiled code (as
    :func:`rrbody.integrate.loop.advance_for`)."""
    code = compiled_code(system)
    if code not in _SPECIALISED:

        @njit(cache=True)
        def run(y, st, p, S, t_end, h, n_sub, out, dt_out, idx, sig, xi, nmax):  # noqa: ANN001
            return sra_advance(code, y, st, p, S, t_end, h, n_sub, out, dt_out, idx, sig, xi, nmax)

        _SPECIALISED[code] = run
    return _SPECIALISED[code]


def run_sde(scene: Scene, p: np.ndarray, S: np.ndarray, y: np.ndarray, st: np.ndarray, out: np.ndarray, *,
            t_max: float, dt_out: float, max_steps: int, progress: bool = False) -> tuple[int, float]:
    """Integrate the free body of ``scene`` (parameters ``p``, ``S`` from
    :func:`rrbody.physics.bind.ode_params`) from the state ``y`` at t = 0 to ``t_max`` (s) with SRA1
    (module docstring), in place: ``y`` ends at t_max, ``out`` gets rows (t, y) at t = j dt_out
    (row 0 at t = 0), ``st`` the loop state's time, step and output counters. Returns the status (0 at
    t_max, 3 after ``max_steps`` steps) and the step used (s)."""
    step = scene.noise_dt if scene.noise_dt is not None else default_noise_dt(scene, t_max)
    n_sub = max(1, math.ceil(dt_out / step - 1e-9))
    h = dt_out / n_sub
    idx, sig = A.ode_noise(p)
    rng = np.random.Generator(np.random.PCG64(scene.seed))
    out[0, 0] = 0.0
    out[0, 1:] = y
    st[L_NOUT] = 1
    run = _sde_for(system_from_params(p, SYSTEM_FREE))
    width = 2 * idx.shape[0]
    total = math.ceil(t_max / h - 1e-9)  # steps to the horizon (the last one may be shorter)

    def chunk(n: int) -> int:
        # the numbers of the next steps, in step order: the stream does not depend on the chunking (only
        # numbers past the horizon's step go unused); no more than the steps left are drawn
        n = max(1, min(n, total + 1 - int(st[L_NSTEP])))
        return run(y, st, p, S, t_max, h, n_sub, out, dt_out, idx, sig, rng.standard_normal((n, width)), n)

    status = run_in_chunks(chunk, st, max_steps, progress=progress, total=t_max, desc="free body (noise)")
    return status, h
