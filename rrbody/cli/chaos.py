"""``rrbody lyapunov``: the Lyapunov exponents of a driven scene (:mod:`rrbody.analysis.chaos`), with
the running estimates written as CSV and drawn as a figure of their convergence."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from rrbody.cli.args import CliError, number, option_help, option_message
from rrbody.cli.options import add_scene_options, scene_from_args

__all__ = ["add_parser", "cmd_lyapunov", "OUTPUTS"]

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


def cmd_lyapunov(args: argparse.Namespace) -> int:
    from rrbody.model.io import check_distinct, check_writable

    scene = scene_from_args(args, required=("--t-max",))
    if not scene.driven:
        raise CliError("--no-drive: Lyapunov exponents are computed for driven scenes (drop --no-drive)")
    method = args.estimate
    dry = scene.friction.active and scene.friction.law == "dry"
    if method == "tangent" and dry:
        raise CliError("--estimate tangent needs a smooth right-hand side, and dry friction has a kink where the "
                       "contact stops sliding: use --estimate two (or auto)")
    if method == "auto":
        method = "two" if dry else "tangent"
    paths = {opt: getattr(args, opt[2:]) for opt in OUTPUTS if getattr(args, opt[2:]) is not None}
    for opt, path in paths.items():
        check_writable(path, force=args.force, name=opt)
        if not str(path).lower().endswith(OUTPUTS[opt]):
            raise CliError(f"{opt} must end in {OUTPUTS[opt]}, got {path!r}")
    check_distinct(paths, {})
    if "--plot" in paths:  # a missing extra is named before anything runs
        from rrbody.model.extras import require

        require("matplotlib", purpose="a figure (--plot)")
    from rrbody.analysis.chaos import lyapunov

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
    d = {**res.to_dict(), "H": scene.H, "k": scene.k, "omega": scene.omega, "tilt": scene.tilt,
         "friction": scene.friction.law, "body": scene.body.kind, "written": written}
    text = "lambda = " + ", ".join(f"{x:.6g}" for x in res.exponents) + f" 1/s  ({method}, {len(res.times)} renormalisations"
    text += f"; divergence {res.divergence:.6g} 1/s)" if res.divergence is not None else ")"
    from rrbody.cli.main import emit

    emit(args, d, text)
    return 0


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

    from rrbody.model.io import atomic_path
    from rrbody.render.figures import savefig_reproducible

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
    with atomic_path(path, force=force, name="--plot") as tmp:
        savefig_reproducible(fig, tmp, fmt="png", dpi=150)
    plt.close(fig)
    return path
