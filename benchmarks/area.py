"""Area friction: sampled elements at growing N vs the instantaneous-centre (ICR) quadrature at growing
node counts. Error vs cost per evaluation, with the ICR inside and outside the body; and the cost
of an extended-body right-hand side against a point-mass one.

Bodies: a disk (R = 0.1 m; reference: the closed form in complete elliptic integrals,
:func:`rrbody.area.disk_closed_form`) and an ellipse (R0 = 0.1 m, delta = 0.5; reference: the ICR
quadrature at its largest node count, checked against the finest sampled grid). Dry friction,
mu g = 1 m/s^2. Motion: spin Omega = 1 rad/s, CM speed eps * Omega * R_max with eps = 0.3 (ICR
inside), 0.9 (inside, near the edge) and 3 (outside).

Error = |(Fx, Fy, tau/R_max) - reference| / |reference| (relative, force and torque together).
Cost per evaluation: a compiled loop of M calls of the kernel (best of 3), divided by M.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.physics.bind import kernel_params

from .common import StudyResult, Target, fmt, machine_text, md_table, module_available, save_figure, write_csv

NAME = "area"
TITLE = "Area friction: sampled elements vs instantaneous-centre quadrature"

SAMPLES = [48, 192, 768, 3072, 12288, 49152, 196608]
NODES = [8, 12, 16, 20, 24, 32, 48, 64, 96, 128]
EPS = {"inside (eps=0.3)": 0.3, "near edge (eps=0.9)": 0.9, "outside (eps=3)": 3.0}


def _per_call(fn: Any, m: int) -> float:
    fn(max(1, m // 100))  # compile / warm
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        fn(m)
        best = min(best, time.perf_counter() - t0)
    return best / m


def _err(w: tuple[float, float, float], ref: tuple[float, float, float], R: float) -> float:
    a = np.array([w[0], w[1], w[2] / R])
    b = np.array([ref[0], ref[1], ref[2] / R])
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def run(out: Path, *, quick: bool = False) -> StudyResult:
    ok, why = module_available("rrbody.physics.icr")
    if ok:
        from rrbody.physics import area

        try:
            area.area_samples(__import__("rrbody.model.bodies", fromlist=["Disk"]).Disk(R=0.1), 48)
        except Exception as e:  # noqa: BLE001
            ok, why = False, f"area_samples not usable yet: {e}"
    if not ok:
        print(f"[area] skipped: rrbody.area / rrbody._icr not ready ({why})", flush=True)
        return StudyResult(NAME, TITLE, skipped=f"rrbody.area/_icr not importable or incomplete ({why})")
    from rrbody.model.bodies import Disk, Ellipse
    from rrbody.model.drive import CircularDrive
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene, rod_mass_scene

    from ._kernels import loop_icr as _loop_icr
    from ._kernels import loop_rhs as _loop_rhs
    from ._kernels import loop_sampled as _loop_sampled

    t_study = time.perf_counter()
    samples = SAMPLES[:4] if quick else SAMPLES
    nodes = NODES[:5] if quick else NODES
    bodies = {"disk R=0.1": Disk(R=0.1), "ellipse R0=0.1 delta=0.5": Ellipse(R0=0.1, delta=0.5)}
    rows: list[dict[str, Any]] = []
    for bname, body in bodies.items():
        a, b = body.semi_axes
        R = max(a, b)
        for ename, eps in EPS.items():
            spin = 1.0
            speed = eps * spin * R
            # CM velocity at 30 degrees to the body x axis (a generic direction for the ellipse)
            vx, vy = speed * math.cos(0.5236), speed * math.sin(0.5236)
            if isinstance(body, Disk):
                ref = area.disk_closed_form(R, vx, vy, spin, mu_g=1.0)
                ref_name = "closed form (elliptic integrals)"
            else:
                ref = area.icr_wrench(body, 0.0, vx, vy, spin, law="dry", coeff=1.0, nodes=512)
                ref_name = "ICR, 512 nodes/panel"
            for n in nodes:
                w = area.icr_wrench(body, 0.0, vx, vy, spin, law="dry", coeff=1.0, nodes=n)
                m = 20000
                cost = _per_call(lambda mm: _loop_icr(a, b, n, mm, vx, vy, spin, body.inertia_per_mass), m)
                rows.append({"body": bname, "motion": ename, "method": "icr", "resolution": n, "error": _err(w, ref, R),
                             "ns_per_eval": cost * 1e9, "reference": ref_name})
            for N in samples:
                S = area.area_samples(body, N)
                w = area.sampled_wrench(body, 0.0, vx, vy, spin, law="dry", coeff=1.0, samples=N)
                m = max(20, int(2e6 // S.shape[0]))
                cost = _per_call(lambda mm: _loop_sampled(S, mm, vx, vy, spin), m)
                rows.append({"body": bname, "motion": ename, "method": "sampled", "resolution": S.shape[0],
                             "error": _err(w, ref, R), "ns_per_eval": cost * 1e9, "reference": ref_name})
            print(f"[area] {bname} {ename} done", flush=True)
    files = [str(write_csv(out / "area.csv", rows))]
    files.append(str(_plot(out / "area_work_precision.png", rows, bodies, samples)))

    # ---- extended-body RHS vs point-mass RHS ----
    drive = CircularDrive(omega=0.6, d=1.0)
    point = rod_mass_scene(0.2, 0.05, 0.6)
    # the default method ("auto": a dry disk's wrench table) is what the target judges; the quadrature
    # ("icr") is timed beside it
    disk = Scene(body=Disk(R=0.1, l=0.2), drive=drive, friction=Friction("dry", 0.05))
    p0, S0 = kernel_params(point)
    p1, S1 = kernel_params(disk)
    p2, S2 = kernel_params(Scene(body=disk.body, drive=drive, friction=Friction("dry", 0.05), friction_method="icr"))
    t_point = _per_call(lambda mm: _loop_rhs(p0, S0, mm), 1_000_000)
    t_disk = _per_call(lambda mm: _loop_rhs(p1, S1, mm), 100_000)
    t_icr = _per_call(lambda mm: _loop_rhs(p2, S2, mm), 100_000)
    # does the RHS really see the ICR friction? compare with friction switched off
    from rrbody.physics.dynamics import driven_rhs

    y = np.array([3.0, -2.0])
    o1 = np.empty(2)
    o2 = np.empty(2)
    driven_rhs(0.3, y, p1, S1, o1)
    p_off = p1.copy()
    p_off[5] = 0.0  # LAW = none
    driven_rhs(0.3, y, p_off, S1, o2)
    icr_active = abs(o1[1] - o2[1]) > 0.0
    n_default = int(p1[11])
    # the ICR kernel alone at the default node count (upper bound of the extended RHS if not dispatched yet)
    a1, b1 = disk.body.semi_axes
    t_kernel = _per_call(lambda mm: _loop_icr(a1, b1, n_default, mm, 0.01, 0.02, 1.0, disk.body.inertia_per_mass),
                         100_000)
    ratio = t_disk / t_point if icr_active else (t_point + t_kernel) / t_point
    targets = [Target("extended-body RHS (default method) vs point-mass RHS", "<= 5x",
                      f"{ratio:.1f}x ({t_disk * 1e9 if icr_active else (t_point + t_kernel) * 1e9:.0f} ns vs "
                      f"{t_point * 1e9:.0f} ns per evaluation; disk, its wrench table; "
                      f"friction_method 'icr' ({n_default} nodes/panel): {t_icr / t_point:.1f}x)",
                      ratio <= 5.0, "" if icr_active else
                      "driven_rhs does not dispatch to the ICR kernel yet: RHS + kernel cost estimated")]
    rhs_rows = [{"what": "point-mass driven_rhs", "ns_per_eval": t_point * 1e9},
                {"what": "disk (default: table) driven_rhs", "ns_per_eval": t_disk * 1e9,
                 "icr_dispatched": icr_active},
                {"what": f"ICR kernel alone ({n_default} nodes)", "ns_per_eval": t_kernel * 1e9},
                {"what": f"disk (icr, {n_default} nodes) driven_rhs", "ns_per_eval": t_icr * 1e9,
                 "icr_dispatched": icr_active}]
    files.append(str(write_csv(out / "area_rhs_cost.csv", rhs_rows, ["what", "ns_per_eval", "icr_dispatched"])))

    # ---- summary: cheapest resolution reaching 1e-6 and 1e-10 per motion ----
    summ = []
    for bname in bodies:
        for ename in EPS:
            for meth in ("icr", "sampled"):
                rs = [r for r in rows if r["body"] == bname and r["motion"] == ename and r["method"] == meth]
                cells = []
                for lvl in (1e-3, 1e-6, 1e-10):
                    good = [r for r in rs if r["error"] <= lvl]
                    best = min(good, key=lambda r: r["ns_per_eval"]) if good else None
                    cells.append(f"{best['resolution']} ({fmt(best['ns_per_eval'])} ns)" if best else
                                 f"not reached (best {fmt(min(r['error'] for r in rs))})")
                summ.append((bname, ename, meth, *cells))
    md = [f"## {TITLE}", "", machine_text(), "",
          "Dry friction, mu g = 1 m/s^2, spin 1 rad/s, CM speed eps * R_max * spin at 30 deg to body x. "
          "Reference: disk closed form; ellipse: ICR at 512 nodes/panel. Error: relative norm of "
          "(Fx, Fy, tau/R_max). Cost: ns per call in a compiled loop (best of 3).", "",
          "Cheapest resolution (ICR: nodes per panel; sampled: elements) reaching each error level:", "",
          md_table(["body", "ICR position", "method", "err <= 1e-3", "err <= 1e-6", "err <= 1e-10"], summ), "",
          "Right-hand side cost (driven body, compiled loop):", "",
          md_table(["what", "ns per evaluation"], [(r["what"], r["ns_per_eval"]) for r in rhs_rows]), "",
          "Plot: `area_work_precision.png`; data: `area.csv`, `area_rhs_cost.csv`."]
    icr = [r for r in rows if r["method"] == "icr"]
    need = []
    for bname in bodies:
        for ename in EPS:
            good = [r for r in icr if r["body"] == bname and r["motion"] == ename and r["error"] <= 1e-10]
            need.append(min(r["resolution"] for r in good) if good else None)
    sampled_best = min(r["error"] for r in rows if r["method"] == "sampled" and r["motion"].startswith("inside"))
    hl = [(f"ICR quadrature reaches 1e-10 with <= {max(need)} nodes per panel in every tested position"
           if None not in need else "ICR quadrature does not reach 1e-10 in every tested position")
          + f"; sampled elements with the ICR inside the body reach only {fmt(sampled_best)} with up to "
          f"{max(samples)} elements."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.extra = {"highlights": hl}
    res.wall_s = time.perf_counter() - t_study
    return res


def _plot(path: Path, rows: list[dict[str, Any]], bodies: dict[str, Any], samples: list[int]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(bodies), figsize=(6 * len(bodies), 4.5), squeeze=False)
    colors = dict(zip(EPS, ["tab:blue", "tab:orange", "tab:green"]))
    for j, bname in enumerate(bodies):
        ax = axes[0, j]
        for ename in EPS:
            for meth, ls, mk in (("icr", "-", "o"), ("sampled", "--", "s")):
                rs = [r for r in rows if r["body"] == bname and r["motion"] == ename and r["method"] == meth]
                pts = [(r["ns_per_eval"], max(r["error"], 1e-17)) for r in rs]
                if pts:
                    ax.loglog(*zip(*pts), ls=ls, marker=mk, color=colors[ename], label=f"{meth}, ICR {ename}")
        ax.set_xlabel("cost per evaluation (ns)")
        ax.set_ylabel("relative error of (F, tau/R)")
        ax.set_title(bname, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Area friction: error vs cost per evaluation (solid: ICR quadrature, dashed: sampled elements)",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path
