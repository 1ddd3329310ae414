"""Driven extended bodies (disks, ellipses): limits, geometry edge cases, both friction methods, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rrbody.analysis.flip import flip_time
from rrbody.analysis.simulate import simulate
from rrbody.integrate.ode import integrate_driven
from rrbody.model.bodies import Disk, Ellipse, RodMass
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene, rod_mass_scene
from rrbody.physics import params as P
from rrbody.physics.bind import kernel_params
from rrbody.physics.dynamics import driven_rhs

W = 0.6
DRIVE = CircularDrive(omega=W, d=1.0)


def _scene(body, k: float = 0.033, **kw) -> Scene:
    return Scene(body=body, drive=kw.pop("drive", DRIVE), friction=Friction.from_k("dry", k, kw.pop("d", 1.0)),
                 phi0=kw.pop("phi0", math.pi), **kw)


def _phi(scene: Scene, t_max: float = 20.0, dt: float = 0.05, rtol: float = 1e-11) -> np.ndarray:
    return simulate(scene, t_max=t_max, dt_out=dt, rtol=rtol).phi


def test_small_disk_converges_to_rod_mass_like_R_squared() -> None:
    # the paper's inset (k = 0.033, H -> 0.2, phi0 = pi): max |phi_disk - phi_rod| over 20 s.
    # I_cm ~ R^2 and the spread of friction directions ~ R, whose first-order effect cancels by
    # symmetry, so the difference should scale like R^2: measured local slopes 2.03, 2.02 between
    # R = 0.02, 0.01, 0.005 (docs/extended.md; at R = 0.05 the flip moves to another minimum)
    ref = _phi(rod_mass_scene(H=0.2, k=0.033, omega=W))
    Rs = np.array([0.02, 0.01, 0.005])
    diffs = np.array([np.max(np.abs(_phi(_scene(Disk(R=R, l=0.2))) - ref)) for R in Rs])
    slopes = np.diff(np.log(diffs)) / np.diff(np.log(Rs))
    assert np.all((slopes > 1.9) & (slopes < 2.1)), slopes


def test_icr_and_sampled_give_the_same_flip() -> None:
    # the paper's disk (R0 = 0.4036, l = 0.2, k = 0.0033): the sampled rule's wrench error at N
    # elements is ~1/N (test_area), so t_f should agree to ~1e-4 relative at N ~ 12k
    body = Disk(R=0.4036, l=0.2)
    icr = flip_time(_scene(body, k=0.0033), rtol=1e-9)
    smp = flip_time(_scene(body, k=0.0033, friction_method="sampled", samples=12_288), rtol=1e-9)
    assert icr.t_f is not None and smp.t_f is not None
    assert smp.t_f == pytest.approx(icr.t_f, rel=1e-3)


def test_flip_time_converges_with_icr_nodes() -> None:
    # the quadrature is not the accuracy bottleneck: changing the default node count to 4x moves
    # t_f far less than tightening the ODE tolerance from 1e-11 to 1e-12 does (measured: 4e-8 s vs
    # 1.1e-6 s for this needle; docs/extended.md)
    body = Ellipse(R0=0.3, delta=0.9, l=0.2)
    sc = _scene(body, k=0.0033)
    p, S = kernel_params(sc)

    def tf(nodes: float, rtol: float) -> float:
        q = p.copy()
        q[P.NQ] = nodes
        return integrate_driven(q, S, (sc.phi0, sc.initial_phi_dot), t_end=200.0, rtol=rtol, stop="flip").t_min

    n0 = p[P.NQ]
    d_nodes = abs(tf(n0, 1e-12) - tf(4 * n0, 1e-12))
    d_rtol = abs(tf(n0, 1e-11) - tf(n0, 1e-12))
    assert d_nodes < 0.2 * d_rtol


def test_pivot_at_centre_l0_spin_decays_at_the_translation_rate() -> None:
    # l = 0: P at the CM, which follows the drive (speed d omega). A disk given spin Omega0 sheds
    # it by friction; once |Omega| R << d omega the torque is linear in Omega with the exact rate
    # mu g <(rho . v_hat)^2> / (|v| I_cm/m) = mu g / (2 d omega) for a disk (area.py docstring)
    mu_g = 0.05
    sc = Scene(body=Disk(R=0.2, l=0.0), drive=DRIVE, friction=Friction("dry", mu_g), phi0=0.3, phi_dot0=2.0)
    assert math.isinf(sc.H)
    tr = simulate(sc, t_max=60.0, dt_out=0.5, rtol=1e-11)
    assert np.all(np.isfinite(tr.phi))
    # CM = P exactly, |spin| never grows
    assert np.max(np.hypot(tr.x_cm - tr.x_p, tr.y_cm - tr.y_p)) < 1e-15
    assert np.all(np.diff(np.abs(tr.spin)) <= 1e-15)
    late = tr.t > 40.0
    rate = -np.polyfit(tr.t[late], np.log(tr.spin[late]), 1)[0]
    assert rate == pytest.approx(mu_g / (2 * W), rel=1e-3)  # O((Omega R/v)^2) corrections: < 1e-4 here


def test_pivot_at_centre_without_spin_stays_still() -> None:
    # a translating disk feels no torque about its centre: phi stays phi0 to rounding
    tr = simulate(_scene(Disk(R=0.3, l=0.0), phi0=1.0, phi_dot0=0.0), t_max=30.0, dt_out=1.0)
    assert np.max(np.abs(tr.phi - 1.0)) < 1e-12


def test_pivot_far_outside_matches_rod_mass() -> None:
    # P 5 m from a 5 cm disk (d = 10 m): the disk is a rod-mass up to (R/l)^2 ~ 1e-4 in H and in
    # the friction spread; phi agrees to ~1e-3 rad over 10 s
    d = 10.0
    drive = CircularDrive(omega=W, d=d)
    disk = _scene(Disk(R=0.05, l=5.0), drive=drive, d=d)
    rod = Scene(body=RodMass(l=5.0), drive=drive, friction=Friction.from_k("dry", 0.033, d), phi0=math.pi)
    a, b = _phi(disk, t_max=10.0), _phi(rod, t_max=10.0)
    assert np.all(np.isfinite(a))
    assert np.max(np.abs(a - b)) < 2e-3


@pytest.mark.parametrize("delta", [0.99, -0.99])
def test_extreme_ellipses(delta: float) -> None:
    # needles: P (0.2 m along R_A) inside for +0.99, far outside the 3 mm semi-axis... the R_B
    # extent for -0.99; the run is finite, and the sampled rule agrees on phi(t) to ~1e-3 rad
    body = Ellipse(R0=0.3, delta=delta, l=0.2)
    a = _phi(_scene(body), t_max=8.0, dt=0.1, rtol=1e-9)
    b = _phi(_scene(body, friction_method="sampled", samples=12_288), t_max=8.0, dt=0.1, rtol=1e-9)
    assert np.all(np.isfinite(a))
    assert np.max(np.abs(a - b)) < 2e-3


@pytest.mark.parametrize("R", [1e-7, 100.0])
def test_tiny_and_huge_disks(R: float) -> None:
    body = Disk(R=R, l=0.2)
    phi = _phi(_scene(body), t_max=10.0, dt=0.1)
    assert np.all(np.isfinite(phi))
    if R < 1e-3:
        # indistinguishable from the rod-mass (difference ~ R^2 ~ 1e-14)
        ref = _phi(rod_mass_scene(H=0.2, k=0.033, omega=W), t_max=10.0, dt=0.1)
        assert np.max(np.abs(phi - ref)) < 1e-8
    else:
        # I_P/m = R^2/2 + l^2 = 5000 m^2: the drive torque (<= omega^2 l d = 0.072) and the friction
        # torque (<= mu g (R + l) ~ 3.4) turn it by at most 0.5 * 3.5/5000 * t^2 = 0.035 rad in 10 s
        assert np.max(np.abs(phi - math.pi)) < 0.035


@pytest.mark.parametrize("body", [Disk(R=0.4036, l=0.2), Ellipse(R0=0.3, delta=0.9, l=0.2),
                                  Ellipse(R0=0.3, delta=-0.9, l=0.2)], ids=["disk", "ell+", "ell-"])
def test_phi0_pi_start_is_finite(body) -> None:
    # at phi0 = pi the rod-mass CM is at rest (0/0); an extended body's CM moves at
    # d omega I_cm / I_P but the RHS must be finite whatever the friction method
    for method in ("icr", "sampled"):
        sc = _scene(body, friction_method=method, samples=1024)
        p, S = kernel_params(sc)
        out = np.empty(2)
        driven_rhs(0.0, np.array([math.pi, sc.initial_phi_dot]), p, S, out)
        assert np.all(np.isfinite(out))
    assert flip_time(_scene(body, k=0.0033), rtol=1e-8).t_f is not None


def test_orientation_y_equals_swapped_axes() -> None:
    # R_A along y with delta is the same body, same place, as R_A along x with -delta
    a = _phi(_scene(Ellipse(R0=0.3, delta=0.5, l=0.2, orientation="y")), t_max=10.0)
    b = _phi(_scene(Ellipse(R0=0.3, delta=-0.5, l=0.2, orientation="x")), t_max=10.0)
    assert np.max(np.abs(a - b)) < 1e-9  # both at rtol 1e-11; the ICR rule differs only by rounding


def test_H_is_derived_and_the_paper_values_hold() -> None:
    # the paper's Fig. ExtendedPhi caption: the ExtendedPhi bodies all have H = 0.607
    for body in (Disk(R=0.4036, l=0.2), Ellipse(R0=0.3, delta=0.9, l=0.2), Ellipse(R0=0.3, delta=-0.9, l=0.2)):
        assert _scene(body).H == pytest.approx(0.607, abs=5e-4)


@pytest.mark.parametrize("make, name", [
    (lambda: Disk(R=0.0), "R"), (lambda: Disk(R=-1.0), "R"), (lambda: Disk(R=float("nan")), "R"),
    (lambda: Disk(R=float("inf")), "R"), (lambda: Disk(R=0.1, l=-0.1), "l"), (lambda: Disk(R=0.1, l=float("nan")), "l"),
    (lambda: Ellipse(R0=0.1, delta=1.0), "delta"), (lambda: Ellipse(R0=0.1, delta=-1.0), "delta"),
    (lambda: Ellipse(R0=0.1, delta=float("nan")), "delta"), (lambda: Ellipse(R0=0.0, delta=0.1), "R0"),
    (lambda: Ellipse(R0=float("nan")), "R0"), (lambda: Ellipse(R0=0.1, delta="0.5"), "delta"),  # type: ignore[arg-type]
    (lambda: Ellipse(R0=0.1, l=-1e-9), "l"), (lambda: Disk(R=0.1, orientation="z"), "orientation"),  # type: ignore[arg-type]
])
def test_bad_shape_parameters(make, name: str) -> None:
    with pytest.raises(ValueError, match=rf"^{name} must"):
        make()


def test_cli_extended_and_free(cli, tmp_path) -> None:
    r = cli("simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.9", "--l", "0.2", "--omega", "0.6",
            "--k", "0.0033", "--t-max", "2", "--json")
    assert r.code == 0, r.err
    out = json.loads(r.out)
    assert out["scene"]["H"] == pytest.approx(0.60725)
    r = cli("simulate", "--body", "disk", "--R0", "0.1", "--no-drive", "--v0", "1,0", "--spin0", "5",
            "--mu", "0.2", "--t-max", "5", "--out", str(tmp_path / "free.csv"))
    assert r.code == 0, r.err
    assert "stop time" in r.out and (tmp_path / "free.csv").exists()
    r = cli("simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "1.5", "--omega", "1", "--k", "1",
            "--t-max", "1")
    assert r.code == 2 and "--delta" in r.err


@pytest.mark.parametrize("body", [Disk(R=0.3, l=0.2), Ellipse(R0=0.3, delta=-0.9, l=0.2)], ids=["disk", "ell-"])
def test_energy_balance_driver_work_equals_kinetic_change_plus_dissipation(body) -> None:
    # per unit mass: dK/dt = F_drive . v_P - P_fric, K = (v_cm^2 + (I_cm/m) Omega^2)/2, with the
    # drive force F_drive = a_cm - F_fric and P_fric = -(F_fric . v_cm + tau_cm Omega) >= 0.
    # Integrated by the trapezoid rule on a 1 ms grid (error ~ dt^2 |K'''| T ~ 1e-7 here).
    from rrbody.physics.area import icr_wrench

    sc = _scene(body, k=0.05)
    tr = simulate(sc, t_max=10.0, dt_out=1e-3, rtol=1e-12)
    p, S = kernel_params(sc)
    icm, l, mu_g = body.inertia_per_mass, body.l, sc.friction.coeff
    n = len(tr)
    p_drive = np.empty(n)
    p_fric = np.empty(n)
    out = np.empty(2)
    for i in range(n):
        t, phi, phid = tr.t[i], tr.phi[i], tr.phi_dot[i]
        driven_rhs(t, np.array([phi, phid]), p, S, out)
        e = np.array([math.cos(phi), math.sin(phi)])
        eperp = np.array([-e[1], e[0]])
        P_acc = -W * W * np.array([tr.x_p[i], tr.y_p[i]])
        a_cm = P_acc - l * out[1] * eperp + l * phid * phid * e
        fx, fy, tau = icr_wrench(body, tr.body_angle[i], tr.vx_cm[i], tr.vy_cm[i], tr.spin[i], coeff=mu_g)
        v_p = W * np.array([-tr.y_p[i], tr.x_p[i]])
        p_drive[i] = (a_cm - np.array([fx, fy])) @ v_p
        p_fric[i] = -(fx * tr.vx_cm[i] + fy * tr.vy_cm[i] + tau * tr.spin[i])
    assert np.all(p_fric >= 0.0)  # friction never does positive work
    K = 0.5 * (tr.vx_cm ** 2 + tr.vy_cm ** 2 + icm * tr.spin ** 2)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (p_drive[1:] + p_drive[:-1] - p_fric[1:] - p_fric[:-1])
                                            * np.diff(tr.t))])
    assert np.max(np.abs(K - K[0] - work)) < 1e-6 * max(1.0, np.max(np.abs(work)))
