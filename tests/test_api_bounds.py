"""Finding classes "Python API" and "horizon": max_steps must be a whole
number of steps in range (NaN switched the cap off); a trajectory ends at the horizon asked for."""

from __future__ import annotations

import math

import pytest

from rrbody import Disk, Friction, Scene, flip_time, rod_mass_scene, simulate
from rrbody.model.checks import LIMITS


@pytest.mark.parametrize("bad", [math.nan, math.inf, -1, 0, 1.5, -0.5, "100", True, 10**13])
def test_max_steps_is_validated(bad: object) -> None:
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    for call in (lambda: flip_time(sc, max_steps=bad), lambda: simulate(sc, t_max=1.0, max_steps=bad)):
        with pytest.raises(ValueError, match=r"^max_steps must be an integer in \[1, 1000000000000\]"):
            call()


def test_max_steps_whole_float_is_accepted() -> None:
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    assert flip_time(sc, max_steps=1e6).t_f == flip_time(sc, max_steps=1_000_000).t_f


@pytest.mark.parametrize("dt_out", [0.3, 0.07, 1 / 3])
def test_driven_trajectory_ends_at_t_max(dt_out: float) -> None:
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    tr = simulate(sc, t_max=1.0, dt_out=dt_out)
    assert tr.t[-1] == 1.0 and tr.t[-2] < 1.0
    # the appended state is the integrator's own at t = 1: a grid that hits 1 exactly (0.25 * 4) gives
    # the same step sequence (output never changes the steps), so the same numbers to round-off
    ref = simulate(sc, t_max=1.0, dt_out=0.25)
    assert ref.t[-1] == 1.0
    assert tr.phi[-1] == pytest.approx(ref.phi[-1], rel=1e-14, abs=1e-14)
    assert tr.phi_dot[-1] == pytest.approx(ref.phi_dot[-1], rel=1e-14, abs=1e-14)
    assert len(simulate(sc, t_max=1.0, dt_out=0.25)) == 5  # no duplicate sample when the grid hits t_max


def test_free_trajectory_ends_at_t_max() -> None:
    sc = Scene(body=Disk(R=0.1), drive=None, friction=Friction("dry", 0.5), v0=(1.0, 0.0), spin0=3.0)
    tr = simulate(sc, t_max=0.7, dt_out=0.3)  # still sliding at 0.7 s (stops near 2 s)
    assert tr.t[-1] == 0.7 and tr.t[-2] == pytest.approx(0.6)
    assert tr.meta["status"] == "reached t_end"
    stopped = simulate(sc, t_max=10.0, dt_out=3.0)  # at rest before 10 s: the last sample is the rest state
    assert stopped.t[-1] == 10.0 and stopped.vx_cm[-1] == 0.0


def test_one_message_format() -> None:
    """name, valid range with unit, the bad value: the same shape for every parameter."""
    cases = [(lambda: rod_mass_scene(0.2, 0.05, -1.0), "omega", LIMITS["omega"].text()),
             (lambda: rod_mass_scene(1e-320, 0.05, 1.0), "H", LIMITS["H"].text()),
             (lambda: Disk(R=1e-320), "R", LIMITS["R"].text()),
             (lambda: Friction.from_k("dry", 1e-320, 1.0), "k", LIMITS["k"].text()),
             (lambda: rod_mass_scene(0.2, 0.05, 1.0, t_max=-1.0), "t_max", LIMITS["t_max"].text())]
    for make, name, valid in cases:
        with pytest.raises(ValueError) as e:
            make()
        assert str(e.value).startswith(f"{name} must be {valid}, got ")


def test_engine_trajectory_ends_at_t_max() -> None:
    sc = rod_mass_scene(0.2, 0.05, 0.6)
    tr = simulate(sc, method="engine", t_max=1.0, dt_out=0.3)
    ode = simulate(sc, t_max=1.0, dt_out=0.3)
    assert list(tr.t) == list(ode.t) and tr.t[-1] == 1.0  # the same grid on both paths, ending at t_max
    # the sample at t_max is interpolated inside an engine step like every grid sample, so its error
    # against the ODE is of the same size as theirs (measured: 2.2e-7 at 1 s vs 1.4e-7 at 0.9 s,
    # dt = 1e-3); a value taken half a step off t_max would be ~|phi'| dt / 2 ~ 1e-3 off
    err = abs(tr.phi - ode.phi)
    assert err[-1] <= 5.0 * max(err[1:-1].max(), 1e-12) and err[-1] < 1e-5
