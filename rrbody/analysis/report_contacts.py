"""Report sections of the contact scenes: pressure distributions, the tilted plane with
static friction, and polygon bodies.

Each ``section_*(L, res)`` appends Markdown lines to ``L`` from ``res/<scene>/summary.json``: a
heading, a table with the exact value beside rrbody's, and the figure; a scene that has not been
run is reported as *(not run)*. Units: s, m, rad, rad/s, rad/s^2, m/s^2.

:func:`rrbody.analysis.report.write_report` calls these; both are written with the small pieces of
:mod:`rrbody.analysis.report_parts`.
"""

from __future__ import annotations

from pathlib import Path

from rrbody.analysis.report_parts import fmt as _f
from rrbody.analysis.report_parts import heading as _heading
from rrbody.analysis.report_parts import img as _img
from rrbody.analysis.report_parts import read_summary

__all__ = ["section_pressure", "section_incline", "section_polygon"]


#: the frictionless H_c, root of 2H K(4H/(H+1)^2) = pi (H+1) (rrbody.analysis.flip.frictionless_critical_h)
HC0 = 0.7927262347097797
PROFILE_LEVER = {"uniform": "2R/3", "ring": "R", "annulus": "(2/3)(Ro^3-Ri^3)/(Ro^2-Ri^2)", "hertz": "3 pi R/16"}


def _figure(L: list[str], scene: str, res: Path) -> None:
    """The scene's figure (``<scene>/<scene>.png``), closing its section."""
    L.extend([_img(scene, scene, res), ""])


def _table(L: list[str], rows: list[tuple[str, str, str]]) -> None:
    L.append("| quantity | exact | rrbody |")
    L.append("|---|---|---|")
    L.extend(f"| {q} | {e} | {r} |" for q, e, r in rows)
    L.append("")


def _few(n: int, k: int = 5) -> list[int]:
    """Up to k indices spread evenly over range(n), first and last included."""
    return list(range(n)) if n <= k else sorted({round(i * (n - 1) / (k - 1)) for i in range(k)})


def section_pressure(L: list[str], res: Path) -> None:
    s = read_summary(res, "pressure")
    if not _heading(L, "## pressure: spin-down per pressure profile, the stop ratio of washers", s):
        return
    L.append("(a) A disk (pymunk Circle, I/m = R^2/2) spinning in place in the plugin decelerates at "
             "alpha = mu g lever / (I/m), the lever the profile's mean distance from the centre. rrbody: a linear "
             "fit of the plugin's omega(t) before the stop.")
    L.append("")
    rows = [(f"alpha, {name} (lever {PROFILE_LEVER.get(name, '?')}) (rad/s^2)", _f(d["alpha_exact"], ".10g"),
             f"{_f(d['alpha_measured'], '.10g')} (rel. err. {_f(d['rel_err'], '.1e')})")
            for name, d in s["spin_down"].items()]
    rows += [("stop ratio v/(R Omega), disk (f = 0)", "0.653 (Farkas et al. 2003)",
              f"{_f(s['disk_ratio'], '.6f')} (kernel fixed point)"),
             ("stop ratio v/(R Omega), hoop on its rim (f = 1)", "1",
              f"{_f(s['hoop_ratio'], '.15f')} (kernel fixed point)")]
    _table(L, rows)
    sr = s["stop_ratio"]
    exact = dict(zip(sr["f"], sr["eps_exact"]))
    L.append("(b) Washers of inner radius Ri = f R (uniform pressure on their area, I/m = (Ri^2 + R^2)/2) sliding "
             "and spinning: the ratio eps = v/(R Omega) moves toward eps*(f), where slide and spin stop together "
             "(root of F(eps) = eps T(eps)/kappa from the kernel). The plugin's ratio just before the stop "
             "(launched at eps0, Omega0 = 20 rad/s): the approach is slow, so it lies between eps0 and eps*.")
    L.append("")
    L.append("| f | eps* (exact) | eps0 | eps just before the stop (plugin) |")
    L.append("|---|---|---|---|")
    for r in sr["sim"]:
        L.append(f"| {r['f']:g} | {_f(exact.get(r['f']), '.6f')} | {r['eps0']:g} | {_f(r['eps_last'], '.6f')} |")
    L.append("")
    _figure(L, "pressure", res)


def section_incline(L: list[str], res: Path) -> None:
    s = read_summary(res, "incline")
    if not _heading(L, "## incline: a tilted plane and static friction", s):
        return
    a, inv, br, held, acc = s["alpha"], s["invariant"], s["breakaway"], s["held"], s["downhill_accel"]
    L.append(f"Plane tilted at alpha = {a:.6g} rad. With mu = tan(alpha) a point mass launched at theta0 from "
             "downhill keeps v (1 + cos theta) = v0 (1 + cos theta0) (ODE path) and tends to v0 (1 + cos theta0)/2 "
             "(once theta is small it falls exponentially, at the rate g sin(alpha) / v).")
    L.append("")
    rows, end = [], f" (t = {inv['t_max']:g} s)" if "t_max" in inv else ""
    for th, drift, vf, vl in zip(inv["theta0_deg"], inv["max_drift"], inv["v_final_over_v0"], inv["v_limit_over_v0"]):
        rows.append((f"theta0 = {th:g} deg: max relative drift of v (1 + cos theta)", "0", _f(drift, ".1e")))
        rows.append((f"theta0 = {th:g} deg: v/v0 at the end of the run{end}", f"{_f(vl, '.15f')} (t -> inf)",
                     _f(vf, ".15f")))
    rows += [("slid downhill, mu = 0.3: acceleration (m/s^2)", f"g (sin a - mu cos a) = {_f(acc['exact'], '.12g')}",
              f"plugin {_f(acc['plugin'], '.12g')}; ODE {_f(acc['ode'], '.12g')}"),
             ("level plane, push growing by a step each time step: push at break-away / (mu_s m g)",
              f"1 (to one step, {_f(br['step_over_limit'], 'g')})",
              f"{_f(br['push_at_break_over_limit'], '.6f')} (the first push above the limit)"
              + {True: "; not moved before it", False: "; MOVED before it", None: ""}[br.get("still_before")]),
             (f"released at rest on the slope, mu < tan(alpha) < mu_s: motion after {held['steps']:,} steps", "none",
              "none: position, angle and velocity bit-identical" if held["bit_identical"] else "moved")]
    _table(L, rows)
    _figure(L, "incline", res)


def section_polygon(L: list[str], res: Path) -> None:
    s = read_summary(res, "polygon")
    if not _heading(L, "## polygon: flip times and critical geometry of polygon bodies", s):
        return
    tf, hc = s["t_f"], s["Hc"]
    bodies = list(tf)
    L.append(f"Flip time t_f (s) at l = {_f(s['l'], 'g')} m, k = {_f(s['k'], 'g')} s^-2, for a few omega (rad/s); "
             "n/a: no reverse rotation, so no flip:")
    L.append("")
    L.append("| omega | " + " | ".join(bodies) + " |")
    L.append("|---" * (len(bodies) + 1) + "|")
    for i in _few(len(s["omega"])):
        L.append(f"| {s['omega'][i]:g} | " + " | ".join(_f(tf[b][i], ".5g") for b in bodies) + " |")
    L.append("")
    shapes = [b for b in hc if b != "k"]
    L.append("Critical geometry H_c at a few k (s^-2); the rod-mass body for reference:")
    L.append("")
    L.append("| k | rod mass | " + " | ".join(shapes) + " |")
    L.append("|---" * (len(shapes) + 2) + "|")
    for i in _few(len(hc["k"])):
        L.append(f"| {hc['k'][i]:g} | {_f(s['Hc_rod_mass'][i], '.5g')} | "
                 + " | ".join(_f(hc[b][i], ".5g") for b in shapes) + " |")
    L.append("")
    c, rows = s["box_spin_check"], []
    if 0.0 in hc["k"]:  # frictionless, a driven body's phi obeys the rod-mass equation with its H
        i = hc["k"].index(0.0)
        got = [hc[b][i] for b in shapes if hc[b][i] is not None]
        rows.append(("H_c(0), every body (no friction)", f"{HC0:.8f}",
                     f"{_f(min(got), '.8f')} to {_f(max(got), '.8f')}" if got else "n/a"))
    rows.append(("square spinning in place: spin-down rate mu g (sqrt 2 + ln(1 + sqrt 2))/a (rad/s^2)",
                 _f(c["alpha_exact"], ".12g"),
                 f"{_f(c['alpha_ode'], '.12g')} (ODE path, rel. err. {_f(c['rel_err'], '.1e')})"))
    _table(L, rows)
    _figure(L, "polygon", res)
