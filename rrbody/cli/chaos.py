"""``rrbody lyapunov`` and ``rrbody poincare``: the Lyapunov exponents of a driven scene and its Poincare
sections (:mod:`rrbody.analysis.chaos`), written as CSV and drawn as figures."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from rrbody.cli.args import CliError, angle, emit, integer, number, option_help, option_message
from rrbody.cli.options import add_scene_options, echo_typed, scene_from_args

__all__ = ["add_parser", "cmd_lyapunov", "cmd_poincare", "OUTPUTS"]

#: output options and the suffix their writer needs
OUTPUTS = {"--out": ".csv", "--plot": ".png"}


def add_parser(sub: Any) -> None:
    """Register ``lyapunov``."""
    p = sub.add_parser("lyapunov", help="Lyapunov exponents of a driven scene (tangent or two-trajectory estimate)",
                       description="Lyapunov exponents of a driven scene by Benettin's method: the spectrum from the "
                                   "variational equations (smooth friction: none, viscous) or the maximal exponent "
                                   "from two nearby trajectories (any friction, dry included). Example: rrbody "
                                   "lyapunov --H 0.2 --k 0.05 --omega 0.6 --friction viscous --t-max 2000 --json")
    add_scene_options(p)
    g = p.add_argument_group("estimate")
    g.add_argument("--estimate", choices=("auto", "tangent", "two"), default="auto",
                   help="tangent: the spectrum from the variational equations (no or viscous friction); two: the "
                        "maximal exponent from two trajectories d0 apart; auto (default): tangent unless the friction "
                        "is dry")
    g.add_argument("--renorm", type=number("--renorm"), default=None,
                   help=option_help("renorm", "seconds between renormalisations (default: one driving period)"))
    g.add_argument("--d0", type=number("--d0"), default=1e-8,
                   help=option_help("d0", "--estimate two: the trajectories' separation in (phi, phi')", "1e-8"))
    g.add_argument("--rtol", type=number("--rtol"), default=1e-10,
                   help=option_help("rtol", "ODE relative tolerance", "1e-10"))
    g.add_argument("--t-max", type=number("--t-max"), default=None,
                   help=option_help("t_max", "the run's length (required; the exponents are averages over it)"))
    p.add_argument("--out", help="CSV of the running estimates: t (s), lambda_1 (1/s)[, lambda_2]")
    p.add_argument("--plot", help="PNG of the running estimates against time (their convergence)")
    p.add_argument("--force", action="store_true", help="overwrite existing output files (regular files only)")
    p.add_argument("--json", action="store_true", help="print one JSON object (exponents, method, renorm, ...)")
    p.set_defaults(func=cmd_lyapunov)

    q = sub.add_parser("poincare", help="a Poincare section of a driven scene (theta = theta_s, or stroboscopic)",
                       description="Points of a Poincare section of a driven scene: the crossings of theta = phi - "
                                   "omega t + pi = THETA_S (mod 2 pi) in one direction, each located to the "
                                   "integrator's accuracy, or the state once per driving period. Example: rrbody "
                                   "poincare --H 0.2 --omega 0.6 --friction none --points 500 --direction down "
                                   "--out sec.csv --plot sec.png")
    add_scene_options(q)
    g = q.add_argument_group("section")
    g.add_argument("--kind", choices=("theta", "strobe"), default="theta",
                   help="theta (default): the crossings of theta = --theta-s; strobe: once per driving period")
    g.add_argument("--points", type=integer("--points"), default=1000,
                   help=option_help("points", "points wanted", 1000))
    g.add_argument("--theta-s", type=angle("--theta-s"), default=0.0,
                   help=option_help("theta_s", "--kind theta: the surface's theta ('pi/2', '90deg')", 0))
    g.add_argument("--direction", choices=("up", "down"), default="up",
                   help="--kind theta: the crossings counted, theta' > 0 (up, default) or < 0 (down: an orbit "
                        "that turns back against the drive crosses only downwards)")
    g.add_argument("--rtol", type=number("--rtol"), default=1e-10,
                   help=option_help("rtol", "ODE relative tolerance", "1e-10"))
    g.add_argument("--t-max", type=number("--t-max"), default=None,
                   help=option_help("t_max", "a cap on the run (default: 100 driving periods per point)"))
    q.add_argument("--out", help="CSV of the points: t (s), phi (rad), phi_dot (rad/s), theta and the drive phase "
                                 "omega t (rad, in [0, 2 pi))")
    q.add_argument("--plot", help="PNG of the section: phi' against theta (strobe) or the drive phase (theta)")
    q.add_argument("--force", action="store_true", help="overwrite existing output files (regular files only)")
    q.add_argument("--json", action="store_true", help="print one JSON object (points found, kind, ...)")
    q.set_defaults(func=cmd_poincare)


def _outputs(args: argparse.Namespace) -> dict[str, str]:
    """The output paths by option, checked before anything runs or the analysis is loaded
    (:func:`rrbody.model.outputs.preflight`: writable, their suffix, distinct, the figure's extra)."""
    from rrbody.model.outputs import preflight

    checked = preflight({opt: (getattr(args, opt[2:]), (suffix,)) for opt, suffix in OUTPUTS.items()},
                        force=args.force)
    return {opt: getattr(args, opt[2:]) for opt in checked}


def cmd_lyapunov(args: argparse.Namespace) -> int:
    scene = scene_from_args(args, required=("--t-max",))
    if not scene.driven:
        raise CliError("--no-drive: Lyapunov exponents are computed for driven scenes (drop --no-drive)")
    paths = _outputs(args)
    from rrbody.analysis.chaos import auto_method, lyapunov

    method = args.estimate
    dry = auto_method(scene) == "two"  # one rule for the command and the sweep quantity chaos
    if method == "tangent" and dry:
        raise CliError("--estimate tangent needs a smooth right-hand side, and dry friction has a kink where the "
                       "contact stops sliding: use --estimate two (or auto)")
    if method == "auto":
        method = "two" if dry else "tangent"
    try:
        res = lyapunov(scene, t_max=scene.t_max, renorm=args.renorm, rtol=args.rtol, method=method, d0=args.d0,
                       progress=not args.json and _tty())
    except ValueError as e:
        raise CliError(option_message(str(e))) from None
    written = {}
    if "--out" in paths:
        written["out"] = str(_write_csv(res, paths["--out"], force=args.force))
    if "--plot" in paths:
        written["plot"] = str(_plot(res, scene, paths["--plot"], force=args.force))
    d = {**res.to_dict(), **echo_typed(args, scene), "omega": scene.omega, "tilt": scene.tilt,
         "friction": scene.friction.law, "body": scene.body.kind, "written": written}
    text = ("lambda = " + ", ".join(f"{x:.6g}" for x in res.exponents)
            + f" 1/s  ({method}, {len(res.times)} renormalisations")
    text += f"; divergence {res.divergence:.6g} 1/s)" if res.divergence is not None else ")"
    emit(args, d, text)
    return 0


def cmd_poincare(args: argparse.Namespace) -> int:
    scene = scene_from_args(args)
    if not scene.driven:
        raise CliError("--no-drive: the sections are those of a driven scene (drop --no-drive)")
    paths = _outputs(args)
    from rrbody.analysis.chaos import poincare

    try:
        sec = poincare(scene, points=args.points, kind=args.kind, theta_s=args.theta_s,
                       direction=1 if args.direction == "up" else -1, t_max=args.t_max, rtol=args.rtol)
    except ValueError as e:
        raise CliError(option_message(str(e))) from None
    written = {}
    if "--out" in paths:
        import numpy as np

        from rrbody.model.io import atomic_path

        with atomic_path(paths["--out"], force=args.force, name="--out") as tmp:
            with open(tmp, "w", encoding="utf-8") as fh:
                fh.write("# " + json.dumps({**sec.to_dict(), "direction": args.direction}) + "\n")
                fh.write("t_s,phi_rad,phi_dot_rad_per_s,theta_rad,drive_phase_rad\n")
                np.savetxt(fh, np.column_stack([sec.t, sec.phi, sec.phi_dot, sec.theta, sec.drive_phase]),
                           delimiter=",", fmt="%.17g")
        written["out"] = paths["--out"]
    if "--plot" in paths:
        written["plot"] = str(_section_plot(sec, scene, paths["--plot"], force=args.force))
    d = {**sec.to_dict(), "direction": args.direction, **echo_typed(args, scene), "omega": scene.omega,
         "tilt": scene.tilt, "friction": scene.friction.law, "written": written}
    emit(args, d, f"{len(sec.t)} points of the {args.kind} section"
                  + (f" (fewer than {args.points}: the run's cap came first)" if len(sec.t) < args.points else ""))
    return 0


def _section_plot(sec: Any, scene: Any, path: str, *, force: bool) -> Any:
    """phi' against theta at the section's points."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    # the section's own coordinates: (theta, phi') once per period; (drive phase, phi') on theta = theta_s
    strobe = sec.kind == "strobe"
    x = sec.theta if strobe else sec.drive_phase
    ax.plot(x, sec.phi_dot, ".", ms=2, color="k")
    what = "once per driving period" if strobe else f"theta = {sec.theta_s:.3g} (mod 2 pi)"
    xlabel = "theta = phi - omega t + pi (rad, mod 2 pi)" if strobe else "drive phase omega t (rad, mod 2 pi)"
    ax.set(xlabel=xlabel, ylabel="phi' (rad/s)", xlim=(0, 2 * math.pi),
           title=f"Poincare section, {what}: H={scene.H:.3g}, k={scene.k:.3g}, omega={scene.omega:.3g} rad/s, "
                 f"tilt={math.degrees(scene.tilt):.3g} deg; {len(sec.t)} points")
    ax.title.set_fontsize(8)
    return _save_png(fig, path, force=force)


def _tty() -> bool:
    import sys

    return sys.stderr.isatty()


def _write_csv(res: Any, path: str, *, force: bool) -> Any:
    import numpy as np

    from rrbody.model.io import atomic_path

    cols = ["t_s"] + [f"lambda_{i + 1}_per_s" for i in range(res.running.shape[1])]
    with atomic_path(path, force=force, name="--out") as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write("# " + json.dumps(res.to_dict()) + "\n")
            fh.write(",".join(cols) + "\n")
            np.savetxt(fh, np.column_stack([res.times, res.running]), delimiter=",", fmt="%.17g")
    return path


def _plot(res: Any, scene: Any, path: str, *, force: bool) -> Any:
    """The running estimates against time, log time axis: a converged exponent is a flat line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    for i in range(res.running.shape[1]):
        ax.plot(res.times, res.running[:, i], lw=1.2, label=f"lambda_{i + 1} = {res.exponents[i]:.4g} 1/s")
    if res.divergence is not None:
        ax.axhline(res.divergence, color="0.5", ls=":", lw=1, label=f"divergence {res.divergence:.4g} 1/s (the sum)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set(xscale="log", xlabel="t (s)", ylabel="running estimate (1/s)",
           title=f"Lyapunov exponents ({res.method}): H={scene.H:.3g}, k={scene.k:.3g}, "
                 f"omega={scene.omega:.3g} rad/s, tilt={math.degrees(scene.tilt):.3g} deg")
    ax.title.set_fontsize(9)
    ax.legend(fontsize=8)
    return _save_png(fig, path, force=force)


def _save_png(fig: Any, path: str, *, force: bool) -> str:
    """``--plot``: the figure as a byte-reproducible PNG, written to a temporary sibling and renamed."""
    import matplotlib.pyplot as plt

    from rrbody.model.io import atomic_path
    from rrbody.render.figures import savefig_reproducible

    with atomic_path(path, force=force, name="--plot") as tmp:
        savefig_reproducible(fig, tmp, fmt="png", dpi=150)
    plt.close(fig)
    return path
