"""Stribeck friction (rrbody.physics.effects.law_stribeck): its limits, brute-force references on both paths,
its quadrature over a footprint, its parameters on the command line, and what it refuses.

mu(v) = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2); ``mu`` (or ``k``) is mu_k, the law's parameters mu_s and v_s.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.optimize import minimize_scalar

from rrbody.analysis.flip import flip_time
from rrbody.integrate.free import simulate_free
from rrbody.model.laws import LAWS, law_named, zero_speed_mu
from rrbody.model.scene import scene_from_params
from rrbody.physics.bind import kernel_params
from rrbody.physics.wrench import body_wrench

G = 9.81
H, K, OMEGA = 0.6, 0.003, 0.6  # the paper's rod-mass scene of Fig. SSs (k = mu_k g / d, d = 1 m)
MU_K = K / G


def _rod(v_s: float, ratio: float = 1.5, **kw: object) -> object:
    return scene_from_params(body="rod", H=H, k=K, omega=OMEGA, friction="stribeck", mu_s=ratio * MU_K, v_s=v_s,
                             **kw)


def _brute_flip(mu_s: float, v_s: float, t_end: float = 60.0) -> float:
    """The rod-mass body's flip time (the global minimum of phi) by an independent integration: the point mass
    at CM = P - l (cos phi, sin phi), P = d (cos wt, sin wt) (d = 1 m), its tangential equation
    l phi'' = (f - P'') . t_hat with t_hat = (sin phi, -cos phi) and f = -mu(|v|) g v_hat, from the impulsive
    start phi'(0) = (omega / H) cos(phi0) (the mass at rest), by scipy's DOP853 at rtol 1e-12."""
    l = H

    def f(t: float, y: np.ndarray) -> list[float]:
        phi, dphi = y
        tx, ty = math.sin(phi), -math.cos(phi)
        vx = -OMEGA * math.sin(OMEGA * t) + l * dphi * tx
        vy = OMEGA * math.cos(OMEGA * t) + l * dphi * ty
        s = math.hypot(vx, vy)
        mu = MU_K + (mu_s - MU_K) * math.exp(-((s / v_s) ** 2))
        fx, fy = (-mu * G * vx / s, -mu * G * vy / s) if s > 0.0 else (0.0, 0.0)
        ax, ay = -OMEGA**2 * math.cos(OMEGA * t), -OMEGA**2 * math.sin(OMEGA * t)
        return [dphi, ((fx - ax) * tx + (fy - ay) * ty) / l]

    sol = solve_ivp(f, (0.0, t_end), [math.pi, OMEGA / H * math.cos(math.pi)], method="DOP853", rtol=1e-12,
                    atol=1e-12, dense_output=True)
    t = np.linspace(0.0, t_end, 60001)
    i = int(np.argmin(sol.sol(t)[0]))
    r = minimize_scalar(lambda x: float(sol.sol(x)[0]), bounds=(t[max(i - 1, 0)], t[min(i + 1, t.size - 1)]),
                        method="bounded", options={"xatol": 1e-10})
    return float(r.x)


def test_the_law_is_in_the_table_with_its_parameters() -> None:
    law = law_named("stribeck")
    assert "stribeck" in LAWS
    assert [q.name for q in law.params] == ["mu_s", "v_s"]
    assert law.sticks and law.load_scaled and not law.smooth
    assert set(law.areas) == {"point", "sampled", "contact"}
    assert zero_speed_mu("stribeck", 0.3, (("mu_s", 0.5), ("v_s", 0.1))) == 0.5
    assert zero_speed_mu("dry", 0.3, ()) == 0.3


@pytest.mark.parametrize("v_s, mu", [(1e-9, MU_K), (1e9, 1.5 * MU_K)])
def test_flip_time_in_the_limits_is_coulombs(v_s: float, mu: float) -> None:
    """v_s -> 0: Coulomb with mu_k; v_s -> infinity: Coulomb with mu_s. At these v_s the element forces
    agree with dry friction's to rounding (exp(-(v/v_s)^2) underflows to 0, or is 1 - O(1e-18)), so the
    flip times agree to the integrator's reproducibility, far below its rtol (1e-10 by default): 1e-9."""
    dry = scene_from_params(body="rod", H=H, mu=mu, omega=OMEGA, friction="dry")
    assert flip_time(_rod(v_s)).t_f == pytest.approx(flip_time(dry).t_f, rel=1e-9)


def test_flip_time_against_brute_force() -> None:
    """t_f of the driven rod-mass body under Stribeck friction (v_s = 0.3 m/s, where the law sits between its
    limits) against an independent scipy integration. The same brute force gives dry friction's t_f within
    5e-10 (measured), so 1e-8 bounds both integrations' errors (rtol 1e-10 and 1e-12) with margin."""
    t_f = flip_time(_rod(0.3)).t_f
    assert t_f == pytest.approx(_brute_flip(1.5 * MU_K, 0.3), rel=1e-8)
    # between its limits (mu_s flips first), and apart from both
    lo, hi = flip_time(_rod(1e9)).t_f, flip_time(_rod(1e-9)).t_f
    assert lo < t_f and abs(t_f - hi) > 1e-4 * hi


def _spin_down_time(R: float, mu_k: float, mu_s: float, v_s: float, w0: float) -> float:
    """A disk of radius R spinning about its centre: I w' = -int mu(|w| r) g r dm, so with I/m = R^2/2,
    dw/dt = -(4 g / R^4) int_0^R mu(w r) r^2 dr, and it stops after T = int_0^w0 R^4 / (4 g J(w)) dw
    (nested scipy quadratures, independent of rrbody)."""
    def J(w: float) -> float:
        return quad(lambda r: (mu_k + (mu_s - mu_k) * math.exp(-((w * r / v_s) ** 2))) * r * r, 0.0, R,
                    epsabs=0.0, epsrel=1e-13, limit=200)[0]

    return quad(lambda w: R**4 / (4.0 * G * J(w)), 0.0, w0, epsabs=0.0, epsrel=1e-12, limit=200)[0]


R, MUK, MUS, VS, W0 = 0.1, 0.3, 0.5, 0.05, 20.0


def test_a_disk_spins_down_and_stops_as_brute_force_says_ode_path() -> None:
    """The contact method (the footprint quadrature about the disk's centre: the integrand is smooth in r,
    spectral) stops the disk at the brute-force time; measured within 5e-9, bounded by 1e-7 (the ODE path's
    default rtol 1e-10 and its rest event)."""
    T = _spin_down_time(R, MUK, MUS, VS, W0)
    s = scene_from_params(body="disk", R0=R, no_drive=True, spin0=W0, friction="stribeck", mu=MUK, mu_s=MUS,
                          v_s=VS, friction_method="contact")
    tr = simulate_free(s, t_max=2.0 * T, dt_out=T / 20.0)
    assert tr.events["t_stop"] == pytest.approx(T, rel=1e-7)


def test_a_disk_spins_down_and_stops_as_brute_force_says_plugin() -> None:
    """The same disk as a pymunk body in the plugin: its semi-implicit step of dt stops it within 2 dt of the
    brute-force time (a first-order step; measured 1.3 dt at dt = 1e-4 s), and it stays at rest."""
    pymunk = pytest.importorskip("pymunk")
    from rrbody.plugin import PlaneFriction

    T = _spin_down_time(R, MUK, MUS, VS, W0)
    space = pymunk.Space()
    body = pymunk.Body(1.0, 0.5 * R * R)
    space.add(body, pymunk.Circle(body, R))
    body.angular_velocity = W0
    pf = PlaneFriction(space, g=G)
    pf.add(body, mu=MUK, law="stribeck", params={"mu_s": MUS, "v_s": VS})
    dt, t = 1e-4, 0.0
    while body.angular_velocity != 0.0 and t < 2.0 * T:
        pf.step(dt)
        t += dt
    assert abs(t - T) <= 2.0 * dt
    for _ in range(10):
        pf.step(dt)
    assert body.angular_velocity == 0.0 and body.velocity.length == 0.0


def _midpoint_box(hx: float, hy: float, vx: float, vy: float, w: float, cs: float, ck: float,
                  vs: float, n: int = 2400) -> np.ndarray:
    """Stribeck friction per unit mass on a uniform box (half-sides hx, hy, centred) by a midpoint sum of
    n x n/2 cells (the reference: independent of rrbody's rules)."""
    x = (np.arange(n) + 0.5) / n * 2 * hx - hx
    y = (np.arange(n // 2) + 0.5) / (n // 2) * 2 * hy - hy
    X, Y = np.meshgrid(x, y)
    ux, uy = vx - w * Y, vy + w * X
    s = np.hypot(ux, uy)
    c = (ck + (cs - ck) * np.exp(-((s / vs) ** 2))) / s
    return np.array([-(c * ux).mean(), -(c * uy).mean(), (-X * c * uy + Y * c * ux).mean()])


def test_the_footprint_quadrature_against_a_fine_sum() -> None:
    """A box's Stribeck wrench by the contact method (mu_s g as dry friction's exact kernel plus the quadrature
    of the rest, rrbody.physics.footprint_quad) against a 2400 x 1200 midpoint sum, the instantaneous centre
    inside the box and out: measured within 5.3e-5 mu_s g (force) and mu_s g R (torque) over these twists,
    where the midpoint sum's own error is below 1e-5; bound 2e-4."""
    hx, hy = 0.1, 0.05
    s = scene_from_params(body="box", R0=0.075, delta=1.0 / 3.0, no_drive=True, v0=(0.1, 0.0), friction="stribeck",
                          mu=MUK, mu_s=MUS, v_s=VS)
    p, S = kernel_params(s)
    reach = math.hypot(hx, hy)
    rng = np.random.default_rng(2)
    for _ in range(6):
        vx, vy = rng.normal(0.0, 0.3, 2)
        w = float(rng.normal(0.0, 5.0))
        got = np.array(body_wrench(p, S, 0.0, vx, vy, w))
        ref = _midpoint_box(hx, hy, vx, vy, w, MUS * G, MUK * G, VS)
        err = np.abs(got - ref) / (MUS * G * np.array([1.0, 1.0, reach]))
        assert err.max() < 2e-4, (vx, vy, w, err)


def test_methods_without_a_form_are_refused_by_name() -> None:
    for method in ("icr", "table"):
        with pytest.raises(ValueError, match=rf"friction 'stribeck' has no form for the area method '{method}'|"
                                              rf"friction_method '{method}' does not apply"):
            kernel_params(scene_from_params(body="disk", R0=0.1, no_drive=True, spin0=1.0, friction="stribeck",
                                            mu=0.3, mu_s=0.5, v_s=0.1, friction_method=method))


def test_bad_parameters_name_the_parameter_and_the_range() -> None:
    with pytest.raises(ValueError, match=r"v_s must be in \[1e-9, 1e9\] m/s, got 0"):
        _rod(0.0)
    with pytest.raises(ValueError, match=r"missing parameters v_s"):
        scene_from_params(body="rod", H=H, k=K, omega=OMEGA, friction="stribeck", mu_s=0.5)
    with pytest.raises(ValueError, match=r"friction 'stribeck' has no parameter 'v_x'"):
        scene_from_params(body="rod", H=H, k=K, omega=OMEGA, friction="stribeck", mu_s=0.5, v_s=0.1, v_x=1.0)
    with pytest.raises(ValueError, match=r"mu_static must be >= mu_s \(0.5"):
        scene_from_params(body="disk", R0=0.1, no_drive=True, spin0=1.0, friction="stribeck", mu=0.3, mu_s=0.5,
                          v_s=0.1, mu_static=0.4)


def test_the_plugin_holds_a_body_at_rest_with_mu_s_by_default() -> None:
    """Static friction's default is the law's coefficient at zero speed (mu_s), not mu_k: a box pushed by
    0.4 m g (between mu_k 0.3 and mu_s 0.5) stays at rest; pushed by 0.6 m g it slides."""
    pymunk = pytest.importorskip("pymunk")
    from rrbody.plugin import PlaneFriction

    for push, moves in ((0.4, False), (0.6, True)):
        space = pymunk.Space()
        body = pymunk.Body(1.0, 1.0 / 600.0)
        space.add(body, pymunk.Poly.create_box(body, (0.1, 0.1)))
        pf = PlaneFriction(space, g=G)
        pf.add(body, mu=MUK, law="stribeck", params={"mu_s": MUS, "v_s": VS})
        for _ in range(100):
            body.apply_force_at_local_point((push * G, 0.0))
            pf.step(1e-3)
        assert (body.velocity.length > 0.0) is moves
    other = pymunk.Body(1.0, 1.0 / 600.0)
    space.add(other, pymunk.Poly.create_box(other, (0.1, 0.1)))
    with pytest.raises(ValueError, match=r"mu_static must be >= mu_s \(0.5"):
        pf.add(other, mu=MUK, law="stribeck", params={"mu_s": MUS, "v_s": VS}, mu_static=0.4)
    assert len(pf.bodies) == 1  # nothing added


def test_the_command_line_takes_the_law_and_refuses_a_bad_speed() -> None:
    run = [sys.executable, "-m", "rrbody.cli", "flip-time", "--H", str(H), "--k", str(K), "--omega", str(OMEGA),
           "--friction", "stribeck", "--mu-s", str(1.5 * MU_K), "--v-s"]
    ok = subprocess.run([*run, "0.3", "--json"], capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0, ok.stderr
    assert '"t_f"' in ok.stdout
    bad = subprocess.run([*run, "0"], capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and bad.stderr.strip().count("\n") == 0
    assert "--v-s must be in [1e-9, 1e9] m/s, got 0" in bad.stderr
    missing = subprocess.run(run[:-1], capture_output=True, text=True, timeout=300)
    assert missing.returncode == 2 and "missing required options: --v-s" in missing.stderr


#: a Stribeck flip that never settles (mu_s = 0.5 against mu_k = 0.05 / g: the full run ends unsettled after
#: 4e5 s, phi never having turned), cut at 10 s: phi is still falling there too
NO_MIN = {"body": "rod", "H": 0.2, "k": 0.05, "omega": 0.6, "friction": "stribeck", "mu_s": 0.5, "v_s": 0.1}


def test_a_flip_time_without_a_minimum_has_no_phi_min(cli, tmp_path: Path) -> None:  # noqa: ANN001
    """No minimum, no phi_min: never phi0 beside a missing t_phi_min, in the result, the JSON (single and
    batch), the text and a sweep's table."""
    from rrbody.analysis.simulate import simulate
    from rrbody.analysis.sweep import load_sweep

    scene = scene_from_params(**NO_MIN)
    traj = simulate(scene, t_max=10.0, dt_out=0.01)
    assert (traj.phi_dot < 0.0).all()  # phi falls all along: it has no minimum in the span
    r = flip_time(scene, t_max=10.0)
    assert r.t_f is None and r.n_minima == 0 and math.isnan(r.t_phi_min) and math.isnan(r.phi_min)
    opts = ["--friction", "stribeck", "--mu-s", "0.5", "--v-s", "0.1", "--k", "0.05", "--omega", "0.6",
            "--t-max", "10"]
    d = json.loads(cli("flip-time", "--H", "0.2", *opts, "--json").out)
    assert d["phi_min"] is None and d["t_phi_min"] is None and d["t_f"] is None and d["n_minima"] == 0
    text = cli("flip-time", "--H", "0.2", *opts).out
    assert "no minimum, so there is no phi_min" in text and "phi_min =" not in text, text
    lines = tmp_path / "in.jsonl"
    lines.write_text(json.dumps({"H": 0.2}) + "\n")
    b = cli("flip-time", *opts, "--batch", str(lines))
    assert b.code == 0 and json.loads(b.out)["phi_min"] is None, b
    s = cli("sweep", *opts, "--axis", "H=0.2,0.25", "--workers", "0", "--out", str(tmp_path / "s.csv"))
    assert s.code == 0, s.err
    rows = load_sweep(tmp_path / "s.csv")
    assert rows[0]["t_f"] == "" and rows[0]["phi_min"] == "" and rows[0]["t_phi_min"] == "", rows[0]
