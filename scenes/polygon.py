"""Polygons: t_f(omega) and H_c(k), a square and a triangle by a disk and an ellipse (no paper figure; real contacts)

The paper's questions asked of shapes it could not ask. Four bodies of equal area A = pi (0.1 m)^2:
a square (side a = sqrt A), an equilateral triangle (circumradius from A, a vertex on the body's +x
axis), a disk (R0 = 0.1 m) and an ellipse (delta = 0.3, R0 from A, R_A along the body's x axis),
each with P at l = 0.05 m from the centre (inside all four: P starts on the body's -x side, phi0 = pi,
so it lies towards a side's midpoint of the square and the triangle and along the ellipse's long
axis), dry friction, uniform pressure (polygons: the exact contact wrench; disk and ellipse: the
instantaneous-centre method).

(a) t_f(omega) at k = mu g/d = 0.05 s^-2, d = 1 m (local process pool, rrbody.analysis.sweep); NaN
where no reverse rotation exists (open markers: the "incomplete RR" minimum of phi, not a flip).
(b) H_c(k) at omega = 0.3 rad/s, phi0 = pi (scan + bisection, rrbody.analysis.flip.critical_h_of):
for an extended body H = I_P / (m d l) is set through the drive radius d = (I_cm/m + l^2) / (H l)
at fixed l and fixed k (so mu = k d / g grows with d); k = 0 is frictionless. The rod-mass H_c(k)
is the reference. Without friction a driven body's phi obeys the rod-mass pendulum equation with
this H (checked: phi(t) equal to 1e-13 rad), so every body's H_c(0) is 0.79272623.
(c) The free square's pure-spin deceleration on the ODE path against the exact
mu g (sqrt 2 + ln(1 + sqrt 2)) / a (a linear fit of the spin before it stops).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import critical_h, critical_h_of
from rrbody.analysis.report import write_summary
from rrbody.analysis.simulate import simulate
from rrbody.analysis.sweep import run_fresh_or_resume
from rrbody.analysis.sweep_spec import Sweep
from rrbody.model.scene import Scene, scene_from_params
from rrbody.physics.polygon import box_spin_torque
from rrbody.render.figures import save_figure

AREA = math.pi * 0.1 ** 2  # m^2, the common area
SIDE = math.sqrt(AREA)  # m, the square's side
DELTA = 0.3
BODIES: dict[str, dict] = {
    "square": {"body": "box", "R0": SIDE / 2},
    "triangle": {"body": "polygon", "sides": 3, "R0": math.sqrt(4 * AREA / (3 * math.sqrt(3)))},
    "disk": {"body": "disk", "R0": 0.1},
    f"ellipse_{DELTA}": {"body": "ellipse", "R0": 0.1 / math.sqrt(1 - DELTA ** 2), "delta": DELTA},
}
L, D, K = 0.05, 1.0, 0.05  # m, m, s^-2 (panel a)
OMEGAS = np.geomspace(0.2, 20.0, 12)  # rad/s (panel a)
OMEGA_HC = 0.3  # rad/s (panel b, the paper's H_c definition with phi0 = pi)
KS = np.array([0.0, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0])  # s^-2 (panel b): denser where H_c falls fastest
ACCURACY, TOL_H, H_LO, H_HI, N_SCAN = "default", 1e-8, 1e-3, 1.0, 64
MU_SPIN, SPIN0 = 0.5, 10.0  # the free box check


def hc_family(body: dict, k: float, *, omega: float = OMEGA_HC, l: float = L) -> Callable[[float], Scene]:
    """H -> the driven scene of ``body`` with P at ``l`` and drive radius d = I_P / (m H l), k fixed
    (k = 0: frictionless)."""
    fric = {"friction": "none"} if k == 0 else {"k": float(k)}
    ip = scene_from_params(**body, l=l, omega=omega, friction="none").inertia_about_pivot
    return lambda H: scene_from_params(**body, l=l, d=ip / (H * l), omega=omega, phi0=math.pi, **fric)


def _hc(scene_at: Callable[[float], Scene], what: str) -> float:
    try:
        return critical_h_of(scene_at, tol=TOL_H, accuracy=ACCURACY, H_lo=H_LO, H_hi=H_HI, n_scan=N_SCAN, what=what)
    except ValueError as e:  # no RR -> no-RR boundary in [H_LO, H_HI]
        print(f"polygon scene: H_c = NaN for {what}: {e}")
        return math.nan


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, b in BODIES.items():
        assert scene_from_params(**b, l=L, omega=1.0, friction="none").body.pivot_inside, name
    # 1. t_f(omega) at k = 0.05 s^-2, d = 1 m: one checkpointed sweep per body (tf_<body>.nc), in this
    #    process: the 48 points take ~5 s here, while each pool worker spends ~35 s getting the polygon
    #    kernels before its first point (measured on 2 cores).
    tf, tf_incomplete, H_a = {}, {}, {}
    for name, b in BODIES.items():
        ds = run_fresh_or_resume(Sweep(base={**b, "l": L, "d": D, "k": K}, axes={"omega": OMEGAS},
                                       options={"accuracy": ACCURACY}), out_dir / f"tf_{name}.nc", workers=0)
        t, rr = np.asarray(ds["t_f"].values, dtype=float), np.asarray(ds["reverse_rotation"].values, dtype=bool)
        tf[name], tf_incomplete[name] = np.where(rr, t, np.nan), np.where(rr, np.nan, t)
        H_a[name] = scene_from_params(**b, l=L, d=D, k=K, omega=1.0).H
    # 2. H_c(k) at omega = 0.3 rad/s: each body through its drive radius, and the rod-mass reference.
    hc = {name: np.array([_hc(hc_family(b, k), f"{name}, k={k:g}") for k in KS]) for name, b in BODIES.items()}
    hc_rod = np.array([critical_h(float(k), OMEGA_HC, friction="none" if k == 0 else "dry", tol=TOL_H,
                                  accuracy=ACCURACY, H_lo=H_LO, H_hi=H_HI, n_scan=N_SCAN) for k in KS])
    # 3. The free square spinning down: slope of spin(t) before it stops, against the exact rate.
    alpha_exact = MU_SPIN * 9.81 * box_spin_torque(SIDE) / (SIDE ** 2 / 6)
    t_end = 0.9 * SPIN0 / alpha_exact
    tr = simulate(scene_from_params(**BODIES["square"], no_drive=True, spin0=SPIN0, mu=MU_SPIN, g=9.81,
                                    t_max=t_end), dt_out=t_end / 200, accuracy=ACCURACY)
    alpha_ode = -float(np.polyfit(tr.t, tr.spin, 1)[0])
    # 4. Figure: (a) t_f(omega) log-log, (b) H_c(k) with the rod mass and, inset, the ratio to it.
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
    style = {"square": ("s", "tab:blue"), "triangle": ("^", "tab:green"), "disk": ("o", "tab:orange"),
             f"ellipse_{DELTA}": ("D", "tab:purple")}
    for name, (m, c) in style.items():
        a.loglog(OMEGAS, tf[name], m + "-", ms=4, lw=0.8, color=c, label=f"{name} (H = {H_a[name]:.3f})")
        a.loglog(OMEGAS, tf_incomplete[name], m, ms=5, mfc="none", color=c)
    a.set_xlabel(r"$\omega$ (rad/s)")
    a.set_ylabel(r"$t_f$ (s)")
    a.set_title(rf"(a) $\mu g/d$ = {K} s$^{{-2}}$, d = {D:g} m, l = {L} m, $\phi_0=\pi$; equal areas $\pi$(0.1 m)$^2$"
                "\nopen: incomplete RR (time of min $\\phi$; no RR, NaN in summary)", fontsize=9)
    a.legend(fontsize=8)
    k_fine = np.linspace(0.01, KS[-1], 60)  # the reference curve on a fine grid (about 5 ms a point)
    b.plot(k_fine, [critical_h(float(k), OMEGA_HC, tol=1e-6, H_lo=H_LO, H_hi=H_HI) for k in k_fine], "k-", lw=1,
           label="rod mass (critical_h)")
    b.plot(KS, hc_rod, "k.", ms=5, label="rod mass, bodies' k grid")
    for name, (m, c) in style.items():
        b.plot(KS, hc[name], m, ms=5, mfc="none", color=c, label=name)
    b.set_yscale("log")
    b.set_xlabel(r"$k = \mu g/d$ (s$^{-2}$)")
    b.set_ylabel(r"$H_c$ (H = $I_P/(m\,d\,l)$, set through d at l = 0.05 m)")
    b.set_title(rf"(b) $\omega$ = {OMEGA_HC} rad/s, $\phi_0=\pi$; k = 0 frictionless; bisection tol {TOL_H:g}",
                fontsize=9)
    b.legend(fontsize=7, loc="lower left")
    ins = b.inset_axes((0.55, 0.55, 0.4, 0.38))
    for name, (m, c) in style.items():
        ins.plot(KS, hc[name] / hc_rod, m + "-", ms=3, lw=0.7, mfc="none", color=c)
    ins.axhline(1.0, color="k", lw=0.7)
    ins.set_xlabel(r"$k$ (s$^{-2}$)", fontsize=7, labelpad=1)
    ins.set_ylabel(r"$H_c / H_c^{\rm rod}$", fontsize=7, labelpad=1)
    ins.tick_params(labelsize=6)
    save_figure(fig, out_dir, "polygon", force=force)
    # 5. Summary (NaN -> null).
    write_summary(out_dir, {
        "omega": OMEGAS.tolist(), "t_f": {n: v.tolist() for n, v in tf.items()}, "l": L, "k": K,
        "Hc": {"k": KS.tolist(), **{n: v.tolist() for n, v in hc.items()}}, "Hc_rod_mass": hc_rod.tolist(),
        "box_spin_check": {"alpha_exact": alpha_exact, "alpha_ode": alpha_ode,
                           "rel_err": abs(alpha_ode - alpha_exact) / alpha_exact},
        "accuracy": ACCURACY, "tol_H": TOL_H,
    }, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "polygon")
