"""The one event detector: its per-step entry point (for paths that cannot re-step, the engine)
agrees with the loop's re-stepped events on the same trajectory."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody import rod_mass_scene, simulate
from rrbody.integrate.events import (
    E_NMIN,
    E_T1,
    E_TMIN,
    FLIP_SETTLED,
    GO_ON,
    STOP_FLIP,
    hermite,
    new_event_state,
    on_step,
)
from rrbody.integrate.ode import integrate_driven
from rrbody.physics.bind import kernel_params


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


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_loop_minima_are_located_to_the_steps_accuracy(rtol: float) -> None:
    # The loop returns each minimum at the Newton-updated time t + h + d without stepping there,
    # with phi carried by its Taylor polynomial. Check it against the run's own trajectory: the
    # same run stopped at t_end = t_min takes the same steps and ends with one fresh step from the
    # bracketing step's start to t_min, i.e. the state the Newton iterate would have had. There
    # phi' must vanish to within |phi''| times the iteration's stop tolerance rtol * h_max (h_max =
    # period / 8 bounds every step) plus the step's own phi' error scale rtol * max(omega, |phi'|);
    # phi must agree to within the local error of the two steps compared, each below the error
    # scale of phi, rtol * pi. Returning the last iterate's time instead of the updated one (with
    # the curvature stop) fails at rtol 1e-4; phi at a minimum is stationary, so its Taylor value
    # differs from the iterate's phi only at O(d^2) and is checked rather than discriminated here.
    sc = rod_mass_scene(0.6, 0.003, 0.6)   # paper's SSs scene: reverse rotation with many minima
    p, S = kernel_params(sc)
    y0 = (sc.phi0, sc.initial_phi_dot)
    run = integrate_driven(p, S, y0, t_end=40.0, rtol=rtol, stop="t_end")
    assert run.n_minima >= 3
    hmax = 0.125 * 2.0 * math.pi / sc.omega
    yscale = max(sc.omega, abs(sc.initial_phi_dot))
    for t_min, phi_min in run.minima:
        at = integrate_driven(p, S, y0, t_end=float(t_min), rtol=rtol, stop="t_end")
        phid = at.y_end[1]
        phidd = (sc.omega ** 2 * sc.body.l * sc.d * abs(math.sin(at.y_end[0] - sc.omega * t_min))
                 / sc.inertia_about_pivot)
        assert abs(phid) <= ((phidd + sc.friction.coeff * sc.body.l / sc.inertia_about_pivot) * rtol * hmax
                             + rtol * yscale)
        assert abs(at.y_end[0] - phi_min) <= 2.0 * rtol * math.pi
