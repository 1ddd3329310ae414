"""The ``rrbody`` command. Every subcommand has ``--help``; ``--json`` prints one JSON object.

Bad input prints a one-line error naming the option and exits with status 2 (no traceback).
Heavy modules are imported inside the handlers so that ``rrbody --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Sequence
from typing import Any

from rrbody._version import __version__
from rrbody.cli.args import CliError, _angle, _finite, _float_list

__all__ = ["main", "entry", "build_parser", "scene_from_args"]

EXIT_BAD_INPUT = 2
INTERRUPTED = "rrbody: interrupted; no partial output was left behind"


# ---- shared option groups --------------------------------------------------------------------
def add_scene_options(p: argparse.ArgumentParser, *, require_omega: bool = True) -> None:
    g = p.add_argument_group("scene")
    g.add_argument("--body", choices=("rod", "disk", "ellipse"), default="rod",
                   help="rod: point mass on a massless rod (default); disk; ellipse")
    g.add_argument("--H", type=_finite("--H"), help="rod-mass geometry H = l/d (> 0); extended bodies derive H from --l")
    g.add_argument("--l", type=_finite("--l"), help="distance CM -> P in m (extended bodies; default 0: P at the centre)")
    g.add_argument("--R0", type=_finite("--R0"), help="disk radius / ellipse mean semi-axis R0 in m")
    g.add_argument("--delta", type=_finite("--delta"), default=0.0, help="ellipse eccentricity parameter, -1 < delta < 1")
    g.add_argument("--orientation", choices=("x", "y"), default="x", help="initial direction of the R_A semi-axis")
    g.add_argument("--omega", type=_finite("--omega"), required=False, help="driving rate in rad/s (> 0)")
    g.add_argument("--d", type=_finite("--d"), default=1.0, help="driving radius in m (default 1)")
    g.add_argument("--k", type=_finite("--k"), help="friction k = mu g / d in 1/s^2 (viscous: gamma in 1/s)")
    g.add_argument("--mu", type=_finite("--mu"), help="friction coefficient (with --g and --d instead of --k)")
    g.add_argument("--g", type=_finite("--g"), default=9.81, help="gravity in m/s^2 with --mu (default 9.81)")
    g.add_argument("--friction", choices=("dry", "viscous", "none"), default="dry", help="friction law (default dry)")
    g.add_argument("--phi0", type=_angle, default=math.pi,
                   help="initial angle of CM->P: a number or 'pi', 'pi/2', '3pi/4', '-0.5*pi' (default pi)")
    g.add_argument("--phi-dot0", type=_finite("--phi-dot0"), default=None,
                   help="initial phi' in rad/s (default: the impulsive start (omega/H) cos phi0)")
    g.add_argument("--friction-method", choices=("auto", "sampled", "icr"), default="auto",
                   help="area integration for extended bodies (auto: instantaneous centre where it applies)")
    g.add_argument("--samples", type=int, default=4096, help="area elements for --friction-method sampled")
    g.add_argument("--no-drive", action="store_true", help="a free body: no drive, launched with --v0 and --spin0")
    g.add_argument("--v0", type=_float_list("--v0", 2), default=(0.0, 0.0), help="free body: CM velocity VX,VY in m/s")
    g.add_argument("--spin0", type=_finite("--spin0"), default=0.0, help="free body: initial spin in rad/s")


def add_integrator_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("integrator")
    g.add_argument("--method", choices=("ode", "engine"), default="ode", help="direct ODE (default) or pymunk engine")
    g.add_argument("--accuracy", choices=("draft", "default", "paper"), default="default",
                   help="ODE tolerance preset (see README: Accuracy and cost)")
    g.add_argument("--rtol", type=_finite("--rtol"), default=None, help="ODE relative tolerance (overrides --accuracy)")
    g.add_argument("--dt", type=_finite("--dt"), default=None, help="engine time step in s")
    g.add_argument("--iterations", type=int, default=None, help="engine constraint-solver iterations")
    g.add_argument("--max-steps", type=int, default=50_000_000, help="cap on integration steps (runaway guard)")
    g.add_argument("--t-max", type=_finite("--t-max"), default=None, help="horizon in s")


#: valid ranges of numeric options: (low, high, low end open). Checked before anything runs, so an
#: error always names the option the user typed.
_RANGES: dict[str, tuple[float, float, bool]] = {
    "H": (0.0, 1e6, True), "l": (0.0, 1e6, False), "R0": (0.0, 1e6, True), "delta": (-1.0, 1.0, True),
    "omega": (0.0, 1e6, True), "d": (0.0, 1e6, True), "k": (0.0, 1e9, False), "mu": (0.0, 1e3, False),
    "g": (0.0, 1e6, True), "phi0": (-1e6, 1e6, False), "phi_dot0": (-1e6, 1e6, False), "spin0": (-1e6, 1e6, False),
    "rtol": (1e-15, 1e-2, False), "t_max": (0.0, 1e9, True), "dt_out": (0.0, 1e9, True), "dt": (0.0, 1e3, True),
    "tol": (1e-14, 0.1, False), "samples": (1, 10_000_000, False), "max_steps": (1, 10**12, False),
    "iterations": (1, 100_000, False), "movie_speed": (0.0, 1e6, True), "fps": (1.0, 240.0, False),
}


def check_option_ranges(a: argparse.Namespace) -> None:
    """Raise CliError naming the first option whose value lies outside its range."""
    for dest, (lo, hi, lo_open) in _RANGES.items():
        v = getattr(a, dest, None)
        if v is None:
            continue
        ok = (v > lo if lo_open else v >= lo) and v <= hi and math.isfinite(v)
        if dest == "delta":
            ok = lo < v < hi
        if not ok:
            opt = "--" + dest.replace("_", "-")
            interval = f"{'(' if lo_open or dest == 'delta' else '['}{lo:g}, {hi:g}{')' if dest == 'delta' else ']'}"
            raise CliError(f"{opt} must lie in {interval}, got {v!r}")


def scene_from_args(a: argparse.Namespace) -> Any:
    """Build a validated Scene from parsed options (ValueError names the option)."""
    from rrbody.model.bodies import Disk, Ellipse, RodMass
    from rrbody.model.drive import CircularDrive
    from rrbody.model.friction import Friction
    from rrbody.model.scene import Scene

    check_option_ranges(a)
    if a.k is not None and a.mu is not None:
        raise CliError("--k and --mu are alternatives: give one of them")
    d = a.d
    law = a.friction
    if law == "none":
        fric = Friction("none")
    elif a.k is not None:
        if a.k < 0:
            raise CliError(f"--k must be >= 0, got {a.k!r} (valid range: [0, inf))")
        fric = Friction.from_k(law, a.k, d)
    elif a.mu is not None:
        if a.mu < 0:
            raise CliError(f"--mu must be >= 0, got {a.mu!r} (valid range: [0, inf))")
        if a.g <= 0:
            raise CliError(f"--g must be > 0 m/s^2, got {a.g!r} (valid range: (0, inf))")
        fric = Friction.from_mu(law, a.mu, a.g, d)
    else:
        raise CliError("friction needs --k (or --mu with --g and --d), or --friction none")
    drive = None
    if not a.no_drive:
        if a.omega is None:
            raise CliError("--omega is required (rad/s, > 0) unless --no-drive")
        if not 0 < a.omega <= 1e6:
            raise CliError(f"--omega must be > 0 rad/s and <= 1e6, got {a.omega!r} (valid range: (0, 1e6])")
        drive = CircularDrive(omega=a.omega, d=d)
    try:
        if a.body == "rod":
            if a.l is not None and a.H is not None:
                raise CliError("--H and --l are alternatives for the rod-mass body: give one")
            if a.H is None and a.l is None:
                raise CliError("--H is required for the rod-mass body (H = l/d > 0)")
            if a.H is not None and not 0 < a.H <= 1e6:
                raise CliError(f"--H must be > 0 and <= 1e6, got {a.H!r} (valid range: (0, 1e6])")
            if a.l is not None and not a.l > 0:
                raise CliError(f"--l must be > 0 m, got {a.l!r} (valid range: (0, inf))")
            body: Any = RodMass(l=a.H * d if a.H is not None else a.l)
        else:
            if a.H is not None:
                raise CliError("--H is derived for extended bodies: give --l (m) instead; H is shown in the output")
            if a.R0 is None:
                raise CliError(f"--R0 is required for --body {a.body} (m, > 0)")
            l = 0.0 if a.l is None else a.l
            if l < 0:
                raise CliError(f"--l must be >= 0 m, got {l!r} (valid range: [0, inf))")
            if a.body == "disk":
                body = Disk(R=a.R0, l=l, orientation=a.orientation)
            else:
                body = Ellipse(R0=a.R0, delta=a.delta, l=l, orientation=a.orientation)
        return Scene(body=body, drive=drive, friction=fric, phi0=a.phi0, phi_dot0=a.phi_dot0,
                     t_max=a.t_max, friction_method=a.friction_method, samples=a.samples,
                     v0=tuple(a.v0), spin0=a.spin0)
    except CliError:
        raise
    except ValueError as e:
        raise CliError(_option_name(str(e))) from None


_PARAM_TO_OPTION = {"l": "--l", "R": "--R0", "R0": "--R0", "delta": "--delta", "omega": "--omega", "d": "--d",
                    "samples": "--samples", "t_max": "--t-max", "phi0": "--phi0", "phi_dot0": "--phi-dot0",
                    "rtol": "--rtol", "dt": "--dt", "iterations": "--iterations", "max_steps": "--max-steps",
                    "dt_out": "--dt-out", "tol": "--tol", "H": "--H", "k": "--k", "mu": "--mu", "g": "--g",
                    "friction_method": "--friction-method", "v0[0]": "--v0", "v0[1]": "--v0", "spin0": "--spin0"}


def _option_name(msg: str) -> str:
    """Rewrite a library message 'name must ...' to name the CLI option."""
    head, _, rest = msg.partition(" ")
    if head in _PARAM_TO_OPTION:
        return f"{_PARAM_TO_OPTION[head]} {rest}"
    return msg


def _emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> None:
    if args.json:
        from rrbody.model.trajectory import _jsonable

        print(json.dumps(_jsonable(payload)))
    else:
        print(text)


def _progress(args: argparse.Namespace) -> bool:
    return bool(getattr(args, "progress", True)) and not args.json and sys.stderr.isatty()


# ---- subcommands -----------------------------------------------------------------------------
def cmd_simulate(args: argparse.Namespace) -> int:
    from rrbody.model.io import check_writable
    from rrbody.analysis.simulate import simulate

    scene = scene_from_args(args)  # checks every option's range first, --fps and --movie-speed included
    if scene.t_max is None:
        raise CliError("--t-max is required for simulate (s, > 0)")
    for opt in ("out", "movie", "rerun"):
        path = getattr(args, opt, None)
        if path:
            check_writable(path, force=args.force, name=f"--{opt}")
    pictures = bool(args.movie or args.rerun or args.rerun_spawn)
    if pictures:  # a missing extra is reported before anything runs or is written
        from rrbody.render import check_extras

        check_extras(movie=bool(args.movie), rerun=bool(args.rerun or args.rerun_spawn))
    opts: dict[str, Any] = {}
    if args.method == "ode":
        opts.update(rtol=args.rtol, accuracy=args.accuracy, max_steps=args.max_steps)
    else:
        opts.update({k: v for k, v in (("dt", args.dt), ("iterations", args.iterations)) if v is not None})
        opts["max_steps"] = args.max_steps
    traj = simulate(scene, method=args.method, dt_out=args.dt_out, progress=_progress(args), **opts)
    if "warning" in traj.meta:
        print(f"rrbody simulate: warning: {traj.meta['warning']}; the trajectory is partial", file=sys.stderr)
    written: dict[str, str] = {}
    if args.out:
        written["out"] = str(traj.save(args.out, force=args.force))
    flip = None
    if pictures:  # the flip shown is flip_time over the whole run, never the lowest phi of this span
        from rrbody.render.flip import flip_mark

        flip = flip_mark(traj)
    if args.movie:
        from rrbody.render.mp4 import render_movie

        written["movie"] = str(render_movie(traj, args.movie, force=args.force, progress=_progress(args),
                                            fps=args.fps, speed=args.movie_speed, flip=flip,
                                            arrows=args.movie_arrows))
    if args.rerun or args.rerun_spawn:
        from rrbody.render.rerun import record

        written["rerun"] = str(record(traj, args.rerun, spawn=args.rerun_spawn, force=args.force, flip=flip))
    ev = traj.events
    summary = {"scene": scene.describe(), "method": args.method, "n_samples": len(traj), "t_end": float(traj.t[-1]),
               "phi_end": float(traj.phi[-1]), "phi_min": ev.get("phi_min"), "t_phi_min": ev.get("t_phi_min"),
               "meta": {k: v for k, v in traj.meta.items() if k != "scene"}, "written": written}
    if flip is not None:
        summary["flip"] = {"status": flip.status, "t_f": flip.t_f, "in_span": flip.in_span(float(traj.t[0]),
                                                                                             float(traj.t[-1])),
                           "caption": flip.caption(float(traj.t[0]), float(traj.t[-1]))}
    text = (f"simulated {scene.body.kind} body, H={scene.H:.6g}, k={scene.k:.6g}, omega={scene.omega:.6g} rad/s "
            f"for {traj.t[-1]:.6g} s with {args.method}: {len(traj)} samples; phi_min={ev.get('phi_min')} at "
            f"t={ev.get('t_phi_min')} s"
            if scene.driven else
            f"simulated free {scene.body.kind} body for {traj.t[-1]:.6g} s: {len(traj)} samples; "
            f"stop time {ev.get('t_stop')}")
    if flip is not None:
        text += f"\npictures: {flip.caption(float(traj.t[0]), float(traj.t[-1]))}"
    for k, v in written.items():
        text += f"\nwrote {k}: {v}"
    _emit(args, summary, text)
    return 0


def cmd_flip_time(args: argparse.Namespace) -> int:
    scene = scene_from_args(args)
    if not scene.driven:
        raise CliError("--no-drive: a free body has no flip time (use `rrbody simulate`)")
    if args.method == "engine":
        from rrbody.engine import engine_flip_time

        opts = {k: v for k, v in (("dt", args.dt), ("iterations", args.iterations)) if v is not None}
        res = engine_flip_time(scene, t_max=args.t_max, max_steps=args.max_steps, progress=_progress(args), **opts)
    else:
        from rrbody.analysis.flip import flip_time

        res = flip_time(scene, rtol=args.rtol, accuracy=args.accuracy, t_max=args.t_max, max_steps=args.max_steps,
                        progress=_progress(args))
    d = res.as_dict()
    d.update(H=scene.H, k=scene.k, omega=scene.omega, phi0=scene.phi0, friction=scene.friction.law,
             body=scene.body.kind, method=args.method)
    if res.t_f is not None:
        text = f"t_f = {res.t_f:.10g} s  (phi_min = {res.phi_min:.10g} rad)  [{res.regime}]"
    else:
        text = f"t_f: none  [{res.regime}]"
    _emit(args, d, text)
    return 0


def cmd_critical_h(args: argparse.Namespace) -> int:
    from rrbody.analysis.flip import critical_h

    check_option_ranges(args)
    if args.k is not None and args.mu is not None:
        raise CliError("--k and --mu are alternatives: give one of them")
    if args.k is None and args.mu is None:
        raise CliError("--k is required (1/s^2, >= 0), or --mu with --g and --d")
    k = args.k if args.k is not None else args.mu * args.g / args.d
    if not k >= 0:
        raise CliError(f"--k must be >= 0, got {k!r} (valid range: [0, inf))")
    if args.omega is None or not args.omega > 0:
        raise CliError(f"--omega must be > 0 rad/s, got {args.omega!r} (valid range: (0, inf))")
    try:
        Hc = critical_h(k, args.omega, phi0=args.phi0, friction=args.friction, tol=args.tol, rtol=args.rtol,
                        accuracy=args.accuracy)
    except ValueError as e:
        raise CliError(_option_name(str(e))) from None
    _emit(args, {"H_c": Hc, "k": k, "omega": args.omega, "phi0": args.phi0, "friction": args.friction, "tol": args.tol},
          f"H_c = {Hc:.10g}  (k={k:g}, omega={args.omega:g} rad/s, {args.friction} friction)")
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    """The main job: the Movie S1 scene (movies/movie_s1.mp4 and results/movie-s1/)."""
    from rrbody.cli.scenes import run_scene

    run_scene("movie-s1", force=True)
    return 0


def cmd_scene(args: argparse.Namespace) -> int:
    from rrbody.cli.scenes import list_scenes, run_scene, scenes_dir

    if args.list or args.name is None:
        for n, doc in list_scenes():
            print(f"{n:24s} {doc}")
        return 0
    names = [n for n, _ in list_scenes()] if args.name == "all" else [args.name]
    import time

    t0 = time.perf_counter()
    for n in names:
        run_scene(n, force=args.force, report=(args.name == "all"))
    if args.name == "all":
        from rrbody.analysis.report import write_report

        wall = time.perf_counter() - t0  # printed, never stored: tracked files hold no timings
        print(f"all scenes: {wall:.1f} s; wrote {write_report(scenes_dir().parent / 'results')}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rrbody", description=__doc__.split("\n")[0] if __doc__ else "rrbody",
                                epilog="Run `rrbody COMMAND --help` for each command's options.")
    p.add_argument("--version", action="version", version=f"rrbody {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    s = sub.add_parser("simulate", help="integrate one scene and write its trajectory (CSV), movie or recording",
                       description="Integrate one scene. Example: rrbody simulate --H 0.2 --k 0.05 --omega 0.6 "
                                   "--phi0 pi --t-max 60 --out traj.csv")
    add_scene_options(s)
    add_integrator_options(s)
    s.add_argument("--dt-out", type=_finite("--dt-out"), default=None,
                   help="output interval in s (default: 1/64 of the fastest period)")
    s.add_argument("--out", help="trajectory CSV (JSON metadata in the first line)")
    s.add_argument("--movie", help="render an MP4 of the run to this path")
    s.add_argument("--movie-speed", type=_finite("--movie-speed"), default=1.0,
                   help="simulated seconds per second of movie (default 1: real time)")
    s.add_argument("--fps", type=_finite("--fps"), default=30.0, help="movie frames per second (default 30)")
    s.add_argument("--movie-arrows", action="store_true",
                   help="draw the CM velocity and the friction force as arrows in the movie")
    s.add_argument("--rerun", help="write a rerun recording (.rrd) of the run")
    s.add_argument("--rerun-spawn", action="store_true", help="open the rerun viewer (needs a screen)")
    s.add_argument("--force", action="store_true", help="overwrite existing output files")
    s.add_argument("--json", action="store_true", help="print one JSON object summarising the run")
    s.set_defaults(func=cmd_simulate)

    f = sub.add_parser("flip-time", help="flip time t_f: time of the global minimum of phi",
                       description="Flip time (SPEC section 4). Example: rrbody flip-time --H 0.2 --k 0.05 "
                                   "--omega 0.6 --phi0 pi --json")
    add_scene_options(f)
    add_integrator_options(f)
    f.add_argument("--json", action="store_true", help="print one JSON object (t_f, phi_min, reverse_rotation, ...)")
    f.set_defaults(func=cmd_flip_time)

    c = sub.add_parser("critical-h", help="critical geometry H_c(k) for the rod-mass body",
                       description="H_c: first RR/no-RR boundary as H grows. Example: rrbody critical-h --k 0.01 "
                                   "--omega 0.3 --json")
    c.add_argument("--k", type=_finite("--k"), help="friction k = mu g / d in 1/s^2 (viscous: gamma in 1/s)")
    c.add_argument("--mu", type=_finite("--mu"), help="friction coefficient (with --g, --d)")
    c.add_argument("--g", type=_finite("--g"), default=9.81)
    c.add_argument("--d", type=_finite("--d"), default=1.0)
    c.add_argument("--omega", type=_finite("--omega"), help="driving rate in rad/s (> 0)")
    c.add_argument("--phi0", type=_angle, default=math.pi, help="initial angle (default pi)")
    c.add_argument("--friction", choices=("dry", "viscous", "none"), default="dry")
    c.add_argument("--tol", type=_finite("--tol"), default=1e-9, help="absolute tolerance on H_c (default 1e-9)")
    c.add_argument("--accuracy", choices=("draft", "default", "paper"), default="default")
    c.add_argument("--rtol", type=_finite("--rtol"), default=None)
    c.add_argument("--json", action="store_true")
    c.set_defaults(func=cmd_critical_h)

    sc = sub.add_parser("scene", help="run a named scene (paper figure or movie); --list lists them")
    sc.add_argument("name", nargs="?", help="scene name, or 'all'")
    sc.add_argument("--list", action="store_true", help="list the scenes")
    sc.add_argument("--force", action="store_true", default=True, help=argparse.SUPPRESS)
    sc.set_defaults(func=cmd_scene, json=False)

    from rrbody.analysis.report import add_parser as add_report_parser
    from rrbody.cli.sweep import add_parser as add_sweep_parser

    add_sweep_parser(sub)
    add_report_parser(sub)

    dm = sub.add_parser("demo", help="the main job (what `make demo` runs)")
    dm.set_defaults(func=cmd_demo, json=False)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "command", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except ValueError as e:  # includes CliError: bad input, named
        print(f"rrbody {args.command}: error: {_option_name(str(e))}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except ImportError as e:  # a missing optional extra: one line naming it, exit 2
        from rrbody.model.extras import missing_extra_message

        msg = missing_extra_message(e)
        if msg is None:
            raise
        print(f"rrbody {args.command}: error: {msg}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return 130


def entry(argv: Sequence[str] | None = None) -> int:
    """The ``rrbody`` console command."""
    return main(argv)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(entry())
