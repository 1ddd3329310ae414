"""Bodies on point feet (pressure ``points``) on the ODE path: driven and free, against the
engine path, the plugin and exact results.

A driven body has one degree of freedom, so a foot's velocity v_P + phi' z x (r_foot - P) (two
conditions) vanishes only at isolated instants and the right-hand side runs as it is. A free body's
sliding ends pivoting on one foot (a Filippov sliding mode), which the ODE path follows in its pivot
mode (rrbody.integrate.pivot): the foot held by static friction while the reaction it needs lies in
its disc mu_static N_i, released when it leaves it.

Tolerances and where they come from:
- the ODE path's own error: rtol 1e-12 against 1e-13 (measured ~1e-14 on the free runs, ~5e-12 on
  the driven one, whose feet pass near rest and cost DOP853 its smoothness there);
- the plugin and the engine path: their convergence to the ODE path, measured at halving dt: second
  order for the driven body and for a free body before it pivots; FIRST order at worst through a
  pivot (the plugin holds the foot exactly at rest, rrbody.contact.feet, but the pivot's start, its
  release and the stop fall on step boundaries: err <= 0.05 dt and <= 0.15 dt on the two cases below,
  the measured maxima 0.040 dt and 0.12 dt);
- exact references (constant deceleration while pinned): to 1e-12 relative, DOP853 integrating a
  constant right-hand side to rounding and the stop completed analytically; the pivot foot's world
  position to 1e-15 m (rounding of positions ~0.1 m).
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from rrbody import pressure as rp
from rrbody.analysis.simulate import simulate
from rrbody.engine import PlaneFriction
from rrbody.model.scene import scene_from_params

G = 9.81
R = 0.1
TWO = [(0.05, 0.0, 1.0), (-0.05, 0.0, 1.0)]
THREE = [(0.06, 0.0, 1.0), (-0.03, 0.05, 1.0), (-0.03, -0.05, 1.0)]


def _text(feet: list[tuple[float, float, float]]) -> str:
    return "points:" + ";".join(",".join(f"{v:g}" for v in foot) for foot in feet)


def _free(feet: list[tuple[float, float, float]], *, v0: tuple[float, float], w0: float, T: float,
          mu: float = 0.3, mu_static: float | None = None, rtol: float = 1e-12, dt_out: float = 1e-3):
    sc = scene_from_params(body="disk", R0=R, no_drive=True, v0=v0, spin0=w0, mu=mu, g=G, mu_static=mu_static,
                           pressure=_text(feet), t_max=T)
    return simulate(sc, dt_out=dt_out, rtol=rtol)


def _plugin(feet: list[tuple[float, float, float]], *, v0: tuple[float, float], w0: float, T: float, dt: float,
            mu: float = 0.3, mu_static: float | None = None,
            pivots: list[list[float]] | None = None) -> tuple[np.ndarray, float | None]:
    """(x, y, angle) at T and the stop time of the same disk on the same feet in the plugin; the
    pivots it reports (``pf.held_foot``) appended to ``pivots`` as [foot, start, end] (s)."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=G)
    b = pymunk.Body()
    s = pymunk.Circle(b, R)
    s.density = 1.0
    space.add(b, s)
    b.velocity, b.angular_velocity = v0, w0
    pf.add(b, mu=mu, pressure=rp.points(feet), mu_static=mu_static)
    last = None
    for _ in range(round(T / dt)):
        t0 = pf.t
        pf.step(dt)
        foot = pf.held_foot(b)
        if pivots is not None and foot != last:
            if last is not None:
                pivots[-1][2] = t0  # held through the last step, not through this one
            if foot is not None:
                pivots.append([foot, t0, math.inf])
        last = foot
    return np.array([b.position.x, b.position.y, b.angle]), pf.stop_time(b)


def _foot_world(tr, foot: tuple[float, float, float], mask: np.ndarray) -> np.ndarray:
    a = tr.body_angle[mask]
    return np.column_stack([tr.x_cm[mask] + np.cos(a) * foot[0] - np.sin(a) * foot[1],
                            tr.y_cm[mask] + np.sin(a) * foot[0] + np.cos(a) * foot[1]])


def test_driven_body_on_feet_runs_and_the_engine_path_converges_at_second_order() -> None:
    """A driven disk on three feet: the ODE path runs it (rtol 1e-12 and 1e-13 agree to 1e-10 rad:
    measured 5e-12), and the engine path's phi at T approaches it 4x closer per halving of dt
    (measured 3.98-4.00)."""
    sc = scene_from_params(body="disk", R0=R, l=0.05, omega=2.0, k=0.5, pressure=_text(THREE), t_max=3.0)
    ode = simulate(sc, rtol=1e-12).phi[-1]
    assert abs(simulate(sc, rtol=1e-13).phi[-1] - ode) < 1e-10
    errs = [abs(simulate(sc, method="engine", dt=dt).phi[-1] - ode) for dt in (2e-3, 1e-3, 5e-4)]
    rates = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    assert all(1.8 < r < 2.2 for r in rates), (errs, rates)


def test_free_body_on_feet_pivots_on_one_foot_then_stops() -> None:
    """Two and three feet, launched sliding and spinning: the run ends pivoting on one foot, the
    events report it, the foot's world position stays fixed to rounding while it pivots, and the
    ODE path is converged (rtol 1e-12 against 1e-13: stop time to 1e-12 s, measured 1e-14)."""
    for feet in (TWO, THREE):
        tr = _free(feet, v0=(0.5, 0.1), w0=8.0, T=0.5)
        ref = _free(feet, v0=(0.5, 0.1), w0=8.0, T=0.5, rtol=1e-13)
        (pv,) = tr.events["pivots"]
        assert pv["ended_by"] == "stop" and pv["end"] == tr.events["t_stop"]
        assert 0.0 < pv["start"] < pv["end"] < 0.5
        assert abs(tr.events["t_stop"] - ref.events["t_stop"]) < 1e-12
        assert np.allclose(tr.events["stop_position"], ref.events["stop_position"], rtol=0, atol=1e-12)
        mask = (tr.t >= pv["start"]) & (tr.t <= pv["end"] + 0.05)  # while pivoting, and at rest after
        q = _foot_world(tr, feet[pv["foot"]], mask)
        assert mask.sum() > 30 and np.max(np.ptp(q, axis=0)) < 1e-15
        # the other feet still slide while it pivots, so the body turns about it
        assert np.all(np.abs(tr.spin[mask & (tr.t < pv["end"])]) > 0.0)


def test_free_body_on_feet_ode_and_plugin_agree_at_the_measured_orders() -> None:
    """The plugin against the ODE path: second order in dt while every foot slides (measured
    1.93-1.98 at T = 0.2 s, before the pivot at 0.216 s), first order through the pivot and the stop
    (at T = 0.5 s, after it: see the module docstring), the stop times within two steps of the
    plugin's."""
    v0, w0 = (0.5, 0.1), 8.0
    before = _free(TWO, v0=v0, w0=w0, T=0.2)
    assert not before.events["pivots"]
    want = np.array([before.x_cm[-1], before.y_cm[-1], before.body_angle[-1]])
    errs = [float(np.max(np.abs(_plugin(TWO, v0=v0, w0=w0, T=0.2, dt=dt)[0] - want))) for dt in (4e-3, 2e-3, 1e-3)]
    rates = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    assert all(1.8 < r < 2.2 for r in rates), (errs, rates)
    dts = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4)
    for feet in (TWO, THREE):
        tr = _free(feet, v0=v0, w0=w0, T=0.5)
        want = np.array([tr.x_cm[-1], tr.y_cm[-1], tr.body_angle[-1]])
        runs = [_plugin(feet, v0=v0, w0=w0, T=0.5, dt=dt) for dt in dts]
        errs = [float(np.max(np.abs(end - want))) for end, _ in runs]
        # first order at worst (measured err/dt 0.035-0.040 for two feet, at most 0.005 for three)
        assert all(err <= 0.05 * dt for err, dt in zip(errs, dts)), errs
        assert errs[-1] < errs[0] / 8, errs  # over a factor 16 in dt: an order of 0.75 at least
        for dt, (_, t_stop) in zip(dts, runs):
            assert t_stop is not None and abs(t_stop - tr.events["t_stop"]) <= 2.0 * dt


def test_pinned_spin_down_is_the_closed_form() -> None:
    """Launched turning about foot 0 (at rest): pinned (mu_static N_0 holds the reaction), the other
    feet slide on circles about it, and the spin falls at the constant rate
    sum_k mu g w_k |r_k - r_0| / (I_cm/m + |r_0|^2) (the parallel-axis theorem) to rest at
    Omega0 / rate, the centre of gravity turned about the foot by Omega0^2 / (2 rate): to 1e-12."""
    feet = [(0.06, 0.0, 2.0), (-0.03, 0.05, 1.0), (-0.03, -0.05, 1.0)]
    w = np.array([f[2] for f in feet]) / 4.0
    mu, w0 = 0.3, 3.0
    r0 = np.array(feet[0][:2])
    # at rest on foot 0: the centre of gravity moves with w0 z x (-r0)
    tr = _free(feet, v0=(w0 * r0[1], -w0 * r0[0]), w0=w0, T=1.0, mu=mu, mu_static=0.5)
    lever = sum(w[k] * math.hypot(*(np.array(feet[k][:2]) - r0)) for k in (1, 2))
    rate = mu * G * lever / (R * R / 2 + r0 @ r0)
    (pv,) = tr.events["pivots"]
    assert pv["foot"] == 0 and pv["start"] == 0.0 and pv["ended_by"] == "stop"
    t_stop = w0 / rate
    assert abs(tr.events["t_stop"] - t_stop) < 1e-12 * t_stop
    moving = tr.t < t_stop
    assert np.max(np.abs(tr.spin[moving] - (w0 - rate * tr.t[moving]))) < 1e-12 * w0
    turn = w0 * w0 / (2 * rate)
    assert abs(tr.events["turn"] - turn) < 1e-12 * turn
    # the centre of gravity swung about the fixed foot (at (0.06, 0)) by that angle
    want = r0 + np.array([math.cos(turn), math.sin(turn)]) * -r0[0]
    assert np.allclose(tr.events["stop_position"], want, rtol=0, atol=1e-13)
    assert np.max(np.ptp(_foot_world(tr, feet[0], tr.t >= 0.0), axis=0)) < 1e-15


def test_a_light_pivot_foot_breaks_away_when_its_reaction_leaves_the_static_disc() -> None:
    """Feet A = (-a, -e) (share 1/5) and B = (a, -e) (4/5), the body launched turning about A at
    Omega0 = 5 rad/s. Pinned, B slides on a circle about A, Omega' = -2 a mu g w_B / (j + a^2 + e^2)
    and (body frame) the reaction A needs is R = (-Omega' e - X a, Omega' a + mu g w_B - X e),
    X = Omega^2. Its size falls and then grows again as the spin runs down; A breaks away where
    |R| = mu_s g w_A, the smaller root X* of (a^2 + e^2) X^2 - 2 e mu g w_B X + (Omega' e)^2 +
    (Omega' a + mu g w_B)^2 - (mu_s g w_A)^2 = 0, at t = (Omega0 - sqrt X*) / |Omega'|: to 1e-11
    relative (the release is located on a right-hand side that is constant while pinned)."""
    a, e, mu, mus, w0 = 0.05, 0.04, 0.3, 0.45, 5.0
    feet = [(-a, -e, 1.0), (a, -e, 4.0)]
    wa, wb = 0.2, 0.8
    c, lim = mu * G, mus * G * wa
    j = R * R / 2
    wd = -2 * a * c * wb / (j + a * a + e * e)
    A2, B1 = a * a + e * e, -2 * e * c * wb
    C0 = (wd * e) ** 2 + (wd * a + c * wb) ** 2 - lim ** 2
    x_star = (-B1 - math.sqrt(B1 * B1 - 4 * A2 * C0)) / (2 * A2)
    assert 0.0 < x_star < w0 * w0
    t_rel = (w0 - math.sqrt(x_star)) / -wd
    tr = _free(feet, v0=(w0 * -e, -w0 * -a), w0=w0, T=0.5, mu=mu, mu_static=mus)
    pv = tr.events["pivots"][0]
    assert pv["foot"] == 0 and pv["start"] == 0.0 and pv["ended_by"] == "release"
    assert abs(pv["end"] - t_rel) < 1e-11 * t_rel
    # the foot slides after the release (no re-pinning in the instant after it), and the body stops
    later = tr.t > t_rel + 0.01
    q = _foot_world(tr, feet[0], later & (tr.t < tr.events["t_stop"]))
    assert np.max(np.ptp(q, axis=0)) > 1e-4
    assert tr.events["t_stop"] is not None and tr.events["t_stop"] > t_rel


def test_plugin_holds_a_pivot_foot_with_static_friction_as_the_ode_path_does() -> None:
    """The light-foot case above in the plugin (rrbody.contact.feet): foot A held from the start, released
    where its reaction leaves the static disc, foot B held later until the stop, every event within
    two steps of the ODE path's and the final pose within 0.15 dt (at worst first order: the events
    fall on step boundaries; measured 0.009-0.12 dt). With mu_static = mu both paths release A
    earlier (0.047 s against 0.074 s): the plugin follows that too, so it does hold with mu_static."""
    a, e, mu, w0 = 0.05, 0.04, 0.3, 5.0
    feet = [(-a, -e, 1.0), (a, -e, 4.0)]
    v0 = (w0 * -e, -w0 * -a)  # foot A at rest
    for mus in (0.45, mu):
        tr = _free(feet, v0=v0, w0=w0, T=0.5, mu=mu, mu_static=mus)
        want = np.array([tr.x_cm[-1], tr.y_cm[-1], tr.body_angle[-1]])
        ode = [[p["foot"], p["start"], p["end"]] for p in tr.events["pivots"]]
        assert [p[0] for p in ode] == [0, 1]
        dts = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4) if mus > mu else (1e-3,)
        for dt in dts:
            pivots: list[list[float]] = []
            end, t_stop = _plugin(feet, v0=v0, w0=w0, T=0.5, dt=dt, mu=mu, mu_static=mus, pivots=pivots)
            assert [p[0] for p in pivots] == [0, 1], (dt, pivots)
            for got, ref in zip(pivots, ode):
                assert abs(got[1] - ref[1]) <= 2 * dt and abs(got[2] - ref[2]) <= 2 * dt, (dt, got, ref)
            assert t_stop is not None and abs(t_stop - tr.events["t_stop"]) <= 2 * dt
            if mus > mu:  # (at mu_static = mu A slips from its disc's rim, at a rate growing from zero:
                # the events still agree, the pose only to ~dt, measured 1.1e-3 at dt = 1e-3)
                assert float(np.max(np.abs(end - want))) <= 0.15 * dt
