"""The one event detector: its per-step entry point (for paths that cannot re-step, the engine)
agrees with the loop's re-stepped events on the same trajectory."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody import rod_mass_scene, simulate
from rrbody.integrate.events import (E_NMIN, E_T1, E_TMIN, FLIP_SETTLED, GO_ON, STOP_FLIP, hermite,
                                     new_event_state, on_step)
from rrbody.physics.bind import kernel_params
from rrbody.integrate.ode import integrate_driven


def test_hermite_is_exact_for_cubics() -> None:
    c = np.array([0.3, -1.2, 0.7, 2.0])
    p = np.polynomial.Polynomial(c)
    dp = p.deriv()
    h = 0.7
    for s in (0.0, 0.1, 0.35, 0.69, 0.7):
        v, d = hermite(s, h, p(0.0), dp(0.0), p(h), dp(h))
        assert v == pytest.approx(p(s), abs=1e-14) and d == pytest.approx(dp(s), abs=1e-13)


def test_on_step_reports_the_loops_events() -> None:
    # Feed the per-step entry the ODE's own states every dt = 1e-3 s: the minima and T_1 it locates
    # on the Hermite cubic differ from the loop's re-stepped ones by the interpolation error,
    # O(dt^4 |phi''''|) ~ 1e-12 s here; the bound 1e-8 s still fails for a wrong bracket or a
    # linear-interpolation locator (error O(dt^2) ~ 1e-6 s).
    sc = rod_mass_scene(0.6, 0.003, 0.6)   # paper's SSs scene: reverse rotation with many minima
    p, S = kernel_params(sc)
    ref = integrate_driven(p, S, (sc.phi0, sc.initial_phi_dot), t_end=40.0, rtol=1e-13, stop="t_end")
    dt = 1e-3
    tr = simulate(sc, t_max=40.0, dt_out=dt, rtol=1e-13)
    ev = new_event_state(sc.phi0, sc.initial_phi_dot)
    minima = np.empty((100, 2))
    codes = []
    for i in range(len(tr.t) - 1):
        codes.append(on_step(ev, minima, tr.t[i], tr.phi[i], tr.phi_dot[i], tr.t[i + 1], tr.phi[i + 1],
                             tr.phi_dot[i + 1], sc.omega, STOP_FLIP, 2.0, 3.0))
    n = int(ev[E_NMIN])
    assert n == ref.n_minima >= 2
    assert np.allclose(minima[:n, 0], ref.minima[:, 0], rtol=0, atol=1e-8)
    assert np.allclose(minima[:n, 1], ref.minima[:, 1], rtol=0, atol=1e-9)
    assert math.isfinite(ref.T1) and ev[E_T1] == pytest.approx(ref.T1, abs=1e-8)
    assert ev[E_TMIN] == pytest.approx(ref.t_min, abs=1e-8)
    assert set(codes) <= {GO_ON, FLIP_SETTLED}
