"""extended-phi: phi(t) of a disk and two delta = +-0.9 ellipses; inset: small disk vs point (paper Fig. ExtendedPhi).

Main panel: disk R0 = 0.4036 m and ellipses R0 = 0.3 m with delta = +0.9 and -0.9 (R_A along x at
t = 0), all with l = 0.2 m, d = 1 m (so H = 0.607), k = mu g/d = 0.0033 s^-2, omega = 0.6 rad/s,
phi0 = pi; area-integrated Coulomb friction by the instantaneous-centre quadrature.
Inset: a disk R0 = 0.05 m and the point mass, k = 0.033 s^-2, H = 0.2 (the disk's l = 0.19354 m
gives H = 0.2 exactly), omega = 0.6 rad/s, phi0 = pi.

Note on delta = -0.9: with R_A = 0.03 m along x, P (0.2 m from the CM along -x at phi0 = pi) lies
*outside* the body, joined by a massless rod, although the paper's text says P is inside all
three bodies. With R_A along x there is no other reading: the ellipse with its long axis towards P
is the delta = +0.9 curve (tests/test_extended.py::test_orientation_y_equals_swapped_axes).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rrbody.analysis.flip import flip_time
from rrbody.analysis.report import write_summary, write_table
from rrbody.analysis.simulate import simulate
from rrbody.model.bodies import Disk, Ellipse, RodMass
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene
from rrbody.render.figures import save_figure

OMEGA, D, PHI0 = 0.6, 1.0, math.pi  # rad/s, m, rad (paper caption)
K_MAIN, L_MAIN = 0.0033, 0.2  # s^-2, m
K_INSET, H_INSET, R_INSET = 0.033, 0.2, 0.05  # s^-2, -, m
DT_OUT = 0.05  # s: ~200 samples per driving period


def _scene(body: object, k: float) -> Scene:
    return Scene(body=body, drive=CircularDrive(omega=OMEGA, d=D), friction=Friction.from_k("dry", k, D),  # type: ignore[arg-type]
                 phi0=PHI0)


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. The three bodies of the main panel (same l, H and I_cm; different shapes).
    main_bodies = {
        "disk": Disk(R=0.4036, l=L_MAIN),
        "ellipse_d+0.9": Ellipse(R0=0.3, delta=0.9, l=L_MAIN),
        "ellipse_d-0.9": Ellipse(R0=0.3, delta=-0.9, l=L_MAIN),
    }
    # 2. The inset: point mass (l = H d) and the small disk at the same H (l from H d l = R^2/2 + l^2).
    l_disk = 0.5 * (H_INSET * D + math.sqrt((H_INSET * D) ** 2 - 2.0 * R_INSET ** 2))
    inset_bodies = {"point": RodMass(l=H_INSET * D), "disk_R0.05": Disk(R=R_INSET, l=l_disk)}
    # 3. Flip times (direct ODE path, stops once the flip is settled), then a common horizon per panel.
    flips = {n: flip_time(_scene(b, K_MAIN)) for n, b in main_bodies.items()}
    flips_in = {n: flip_time(_scene(b, K_INSET)) for n, b in inset_bodies.items()}
    t_main = 2.0 * max(float(r.t_f) for r in flips.values() if r.t_f is not None)
    t_in = 2.0 * max(float(r.t_f) for r in flips_in.values() if r.t_f is not None)
    trajs = {n: simulate(_scene(b, K_MAIN), t_max=t_main, dt_out=DT_OUT) for n, b in main_bodies.items()}
    trajs_in = {n: simulate(_scene(b, K_INSET), t_max=t_in, dt_out=DT_OUT) for n, b in inset_bodies.items()}
    # 4. Data: one CSV per panel, phi(t) on the common grid; flip times and H in the metadata line.
    meta = {"omega": OMEGA, "d": D, "phi0": PHI0, "k": K_MAIN, "l": L_MAIN,
            "H": {n: _scene(b, K_MAIN).H for n, b in main_bodies.items()},
            "t_f": {n: r.t_f for n, r in flips.items()}, "friction_method": "icr",
            "note": "delta=-0.9: R_A=0.03 m along x, P lies outside the body (massless rod)"}
    t = trajs["disk"].t
    write_table(out_dir / "extended_phi.csv", ["t", *[f"phi_{n}" for n in main_bodies]],
                np.column_stack([t, *[trajs[n].phi for n in main_bodies]]).tolist(), force=force, meta=meta)
    ti = trajs_in["point"].t
    write_table(out_dir / "extended_phi_inset.csv", ["t", *[f"phi_{n}" for n in inset_bodies]],
                np.column_stack([ti, *[trajs_in[n].phi for n in inset_bodies]]).tolist(), force=force,
                meta={"omega": OMEGA, "d": D, "phi0": PHI0, "k": K_INSET, "H": H_INSET, "l_disk": l_disk,
                      "t_f": {n: r.t_f for n, r in flips_in.items()}})
    # 5. Figure: main panel with flip times marked, inset in the upper left.
    fig, ax = plt.subplots(figsize=(7.0, 4.8), constrained_layout=True)
    styles = {"disk": ("tab:orange", r"disk $R_0$ = 0.4036 m"),
              "ellipse_d+0.9": ("#74c476", r"ellipse $R_0$ = 0.3 m, $\delta$ = +0.9"),
              "ellipse_d-0.9": ("#006d2c", r"ellipse $R_0$ = 0.3 m, $\delta$ = $-$0.9 (P outside)")}
    for n, (c, lab) in styles.items():
        r = flips[n]
        ax.plot(trajs[n].t, trajs[n].phi, color=c, lw=1.3, label=f"{lab}, $t_f$ = {r.t_f:.2f} s")
        ax.plot([r.t_f], [r.phi_min], "o", color=c, ms=4)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\phi$ (rad)")
    ax.set_xlim(0, t_main)
    ax.set_title(r"$\mu g/d$ = 0.0033 s$^{-2}$, $\omega$ = 0.6 rad/s, H = 0.607, l = 0.2 m, "
                 r"$\phi_0=\pi$", fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, 0.535), fontsize=7.5)
    ins = ax.inset_axes((0.07, 0.61, 0.36, 0.33))
    for n, c, lab in (("point", "k", "point mass"), ("disk_R0.05", "tab:red", r"disk $R_0$ = 0.05 m")):
        ins.plot(trajs_in[n].t, trajs_in[n].phi, color=c, lw=1.0, label=f"{lab}, $t_f$ = {flips_in[n].t_f:.1f} s")
    ins.set_title(r"$\mu g/d$ = 0.033 s$^{-2}$, H = 0.2", fontsize=7)
    ins.tick_params(labelsize=7)
    ins.set_xlabel("t (s)", fontsize=7, labelpad=1)
    ins.set_ylabel(r"$\phi$ (rad)", fontsize=7, labelpad=1)
    ins.legend(fontsize=6, loc="upper right")
    save_figure(fig, out_dir, "extended_phi", force=force)
    # 6. Summary for the report.
    write_summary(out_dir, {
        "omega": OMEGA, "phi0": PHI0,
        "main": [{"body": n, "k": K_MAIN, "H": _scene(b, K_MAIN).H, "t_f": flips[n].t_f,
                  "phi_min": flips[n].phi_min, "regime": flips[n].regime} for n, b in main_bodies.items()],
        "inset": [{"body": n, "k": K_INSET, "H": _scene(b, K_INSET).H, "t_f": flips_in[n].t_f}
                  for n, b in inset_bodies.items()],
        "note": "delta=-0.9 (R_A=0.03 m along x): P is outside the body, joined by a massless rod",
    }, force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "extended-phi")
