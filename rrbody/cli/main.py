"""The ``rrbody`` command. Every subcommand has ``--help``; ``--json`` prints one JSON object.

Error contract: bad input (an option's value, a missing or misspelled option, an output path that
is not a regular file) prints one line, ``rrbody COMMAND: error: <option> ...``, on stderr, writes
nothing and exits with status 2; never a traceback. Ctrl-C or SIGTERM exits 130 (sweeps say how to
resume); a closed stdout (``| head``) ends quietly with status 141, like a command killed by SIGPIPE.
Heavy modules are imported inside the handlers, so a command imports only what it uses.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
from collections.abc import Sequence
from typing import Any

from rrbody._version import __version__
from rrbody.cli.active_options import add_active_options, with_active
from rrbody.cli.args import (
    CliError,
    Parser,
    check_options,
    commands,
    drop_warnings,
    emit,
    flush_warnings,
    number,
    option_help,
    option_message,
    parse,
)
from rrbody.cli.cache import add_parser as add_cache_parser
from rrbody.cli.options import (
    SIMULATE_OUTPUTS,
    add_accuracy_options,
    add_drive_option,
    add_friction_options,
    add_integrator_options,
    add_scene_options,
    check_contradictions,
    check_simulate_outputs,
    echo_typed,
    number_text,
    scene_from_args,
    stepper_option,
    typed,
)

__all__ = ["main", "entry", "build_parser", "scene_from_args", "run_command"]

EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130
EXIT_BROKEN_PIPE = 141
INTERRUPTED = "rrbody: interrupted; no partial output was left behind"


def _progress(args: argparse.Namespace) -> bool:
    return bool(getattr(args, "progress", True)) and not args.json and sys.stderr.isatty()


# ---- subcommands -----------------------------------------------------------------------------
def cmd_simulate(args: argparse.Namespace) -> int:
    check_options(args, ("--dt-out", "--fps", "--movie-speed"))
    scene = with_active(scene_from_args(args, required=("--t-max",)), args)
    stepper = stepper_option(args)
    paths = check_simulate_outputs(args)  # and the writers' extras: before anything runs or is written
    pictures = bool(args.movie or args.rerun or args.rerun_spawn)
    from rrbody.model.io import check_writable
    from rrbody.model.outlock import claimed

    # one writer per output: another rrbody process aiming at one of these paths is refused here, before
    # the run (the lock is held until the outputs are written)
    with claimed(paths.items()):
        for opt, path in paths.items():  # what changed between the checks above and the claim
            check_writable(path, force=args.force, name=opt)
        flush_warnings()  # the input is checked: the warnings held while parsing it, before the run
        return _simulate(args, scene, stepper, pictures)


def _simulate(args: argparse.Namespace, scene: Any, stepper: dict[str, str], pictures: bool) -> int:
    """The run and the writing of simulate, its outputs checked and claimed."""
    from rrbody.analysis.simulate import simulate

    opts: dict[str, Any] = {"max_steps": args.max_steps}
    if args.method == "ode":
        opts.update(rtol=args.rtol, accuracy=args.accuracy, **stepper)
    else:
        opts.update({k: v for k, v in (("dt", args.dt), ("iterations", args.iterations)) if v is not None})
    try:
        traj = simulate(scene, method=args.method, dt_out=args.dt_out, progress=_progress(args), **opts)
    except ValueError as e:  # (run_command names the option; a hint at Python's method= is --method here)
        raise ValueError(str(e).replace("method='engine'", "--method engine")) from None
    if "warning" in traj.meta:
        print(f"rrbody simulate: warning: {traj.meta['warning']}; the trajectory is partial", file=sys.stderr)
    written: dict[str, str] = {}
    if args.out is not None:
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
               "t_stop": ev.get("t_stop"), "distance": ev.get("distance"), "turn": ev.get("turn"),
               "meta": {k: v for k, v in traj.meta.items() if k != "scene"}, "written": written}
    if scene.driven:
        summary["scene"].update(echo_typed(args, scene))
    if "pivots" in ev:  # a free body on point feet (the ODE path): its pivots on a foot
        summary["pivots"] = ev["pivots"]
    if flip is not None:
        summary["flip"] = {"status": flip.status, "t_f": flip.t_f, "in_span": flip.in_span(float(traj.t[0]),
                                                                                             float(traj.t[-1])),
                           "caption": flip.caption(float(traj.t[0]), float(traj.t[-1]))}
    text = (f"simulated {scene.body.kind} body, H={scene.H:.6g}, k={scene.k:.6g}, omega={scene.omega:.6g} rad/s "
            f"for {traj.t[-1]:.6g} s with {args.method}: {len(traj)} samples; lowest phi in this span "
            f"{number_text(ev.get('phi_min'))} rad at t={number_text(ev.get('t_phi_min'))} s"
            if scene.driven else
            f"simulated free {scene.body.kind} body for {traj.t[-1]:.6g} s: {len(traj)} samples; "
            + (f"stop time {ev['t_stop']:.6g} s" if ev.get("t_stop") is not None
               else f"still moving at t = {traj.t[-1]:.6g} s (no stop time)"))
    if flip is not None:
        text += f"\npictures: {flip.caption(float(traj.t[0]), float(traj.t[-1]))}"
    for k, v in written.items():
        text += f"\nwrote {v} ({SIMULATE_OUTPUTS['--' + k][1]})"
    emit(args, summary, text)
    return 0


def cmd_flip_time(args: argparse.Namespace) -> int:
    scene = scene_from_args(args)
    if not scene.driven:
        raise CliError("--no-drive: a free body has no flip time (use `rrbody simulate`)")
    stepper = stepper_option(args)
    flush_warnings()  # the input is checked
    if args.method == "engine":
        from rrbody.analysis.flip import without_phantom_minimum
        from rrbody.engine import engine_flip_time

        opts = {k: v for k, v in (("dt", args.dt), ("iterations", args.iterations)) if v is not None}
        res = without_phantom_minimum(engine_flip_time(scene, t_max=args.t_max, max_steps=args.max_steps,
                                                       progress=_progress(args), **opts))
    else:
        from rrbody.analysis.flip import flip_time

        res = flip_time(scene, rtol=args.rtol, accuracy=args.accuracy, t_max=args.t_max, max_steps=args.max_steps,
                        progress=_progress(args), **stepper)
    d = res.as_dict()
    d.update(**echo_typed(args, scene), omega=scene.omega, phi0=scene.phi0, friction=scene.friction.law,
             body=scene.body.kind, method=args.method)
    if res.t_f is not None:
        text = f"t_f = {res.t_f:.10g} s  (phi_min = {res.phi_min:.10g} rad)  [{res.regime}]"
    elif math.isnan(res.phi_min):
        text = f"t_f: none  (phi has had no minimum, so there is no phi_min)  [{res.regime}]"
    else:
        text = f"t_f: none  [{res.regime}]"
    emit(args, d, text)
    return 0


def cmd_critical_h(args: argparse.Namespace) -> int:
    check_options(args, ("--k", "--mu", "--g", "--d", "--omega", "--phi0", "--tol", "--rtol"))
    missing = [o for o, v in (("--k (or --mu)", args.k if args.k is not None else args.mu), ("--omega", args.omega))
               if v is None and not (o.startswith("--k") and args.friction == "none")]
    if missing:
        raise CliError(f"missing required options: {', '.join(missing)}")
    check_contradictions(args)
    from rrbody.analysis.flip import critical_h
    from rrbody.model.friction import Friction

    try:  # the model's friction constructors check k (or mu, g, d) once, as for every scene
        fr = Friction("none") if args.friction == "none" else (
            Friction.from_k(args.friction, args.k, args.d) if args.k is not None
            else Friction.from_mu(args.friction, args.mu, args.g, args.d))
        k = fr.k(args.d)
        flush_warnings()  # the options are checked
        Hc = critical_h(k, args.omega, phi0=args.phi0, friction=args.friction, tol=args.tol, rtol=args.rtol,
                        accuracy=args.accuracy)
    except CliError:
        raise
    except ValueError as e:
        raise CliError(option_message(str(e))) from None
    emit(args, {"H_c": Hc, "k": typed(args, "k", k), "omega": args.omega, "phi0": args.phi0, "friction": args.friction,
                "tol": args.tol},
         f"H_c = {Hc:.10g}  (k={k:g}, omega={args.omega:g} rad/s, {args.friction} friction)")
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    """The main job: the Movie S1 scene (movies/movie_s1.mp4 and results/movie-s1/)."""
    from rrbody.cli.scenes import run_scene

    run_scene("movie-s1", force=True)
    return 0


def cmd_scene(args: argparse.Namespace) -> int:
    from rrbody.cli.scenes import check_scene, list_scenes, output_root, run_scene

    if args.list or args.name is None:
        scenes = list_scenes()
        width = max((len(n) for n, _ in scenes), default=0)  # one column, however long the longest name
        for n, doc in scenes:
            print(f"{n:{width}s}  {doc}")
        return 0
    names = [n for n, _ in list_scenes()] if args.name == "all" else [args.name]
    for n in names:  # every scene's extras and folders before the first one computes anything
        check_scene(n)
    import time

    t0 = time.perf_counter()
    for n in names:
        run_scene(n, force=args.force, report=(args.name == "all"))
    if args.name == "all":
        from rrbody.analysis.report import write_report

        wall = time.perf_counter() - t0  # printed, never stored: tracked files hold no timings
        print(f"all scenes: {wall:.1f} s; wrote {write_report(output_root() / 'results')}")
    return 0


def _batch_option(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument("--batch", metavar="FILE", default=None,
                   help=f"read one JSON object of options per line from FILE ('-': stdin), e.g. "
                        f"{{\"H\": 0.2, \"k\": 0.05, \"omega\": 0.6}}; write one JSON {what} per line, in order "
                        "(options on the command line are defaults for every line). A line obeys the command "
                        "line's rules (one value per option, of its type, each option once), must be UTF-8 and "
                        "at most 1 MiB; a bad line gives {\"error\": ..., \"line\": N} and the others still run")


def build_parser() -> Parser:
    p = Parser(prog="rrbody", description=__doc__.split("\n")[0] if __doc__ else "rrbody",
               epilog="Run `rrbody COMMAND --help` for each command's options.")
    p.add_argument("--version", action="version", version=f"rrbody {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)

    s = sub.add_parser("simulate", help="integrate one scene and write its trajectory (CSV), movie or recording",
                       description="Integrate one scene. Example: rrbody simulate --H 0.2 --k 0.05 --omega 0.6 "
                                   "--phi0 pi --t-max 60 --out traj.csv")
    add_scene_options(s)
    add_active_options(s)
    add_integrator_options(s)
    s.add_argument("--dt-out", type=number("--dt-out"), default=None,
                   help=option_help("dt_out", "output interval (default: 1/64 of the fastest period)"))
    s.add_argument("--out", help="trajectory CSV (JSON metadata in the first line); a regular file or absent")
    s.add_argument("--movie", help="render an MP4 of the run to this path")
    s.add_argument("--movie-speed", type=number("--movie-speed"), default=1.0,
                   help=option_help("movie_speed", "simulated seconds per second of movie", 1))
    s.add_argument("--fps", type=number("--fps"), default=30.0, help=option_help("fps", "movie frame rate", 30))
    s.add_argument("--movie-arrows", action="store_true",
                   help="draw the CM velocity and the friction force as arrows in the movie")
    s.add_argument("--rerun", help="write a rerun recording (.rrd) of the run")
    s.add_argument("--rerun-spawn", action="store_true", help="open the rerun viewer (needs a screen)")
    s.add_argument("--force", action="store_true", help="overwrite existing output files (regular files only)")
    s.add_argument("--json", action="store_true", help="print one JSON object summarising the run")
    _batch_option(s, "summary (needs --json)")
    s.set_defaults(func=cmd_simulate)

    f = sub.add_parser("flip-time", help="flip time t_f: time of the global minimum of phi",
                       description="Flip time (the time of the global minimum of phi). Example: rrbody flip-time "
                                   "--H 0.2 --k 0.05 --omega 0.6 --phi0 pi --json")
    add_scene_options(f)
    add_integrator_options(f)
    f.add_argument("--json", action="store_true", help="print one JSON object (t_f, phi_min, reverse_rotation, ...)")
    _batch_option(f, "result")
    f.set_defaults(func=cmd_flip_time)

    c = sub.add_parser("critical-h", help="critical geometry H_c(k) for the rod-mass body",
                       description="H_c: first RR/no-RR boundary as H grows. Example: rrbody critical-h --k 0.01 "
                                   "--omega 0.3 --json")
    for opt, text in (("--k", "friction k = mu g / d (viscous: gamma in 1/s)"),
                      ("--mu", "friction coefficient (with --g, --d)"), ("--g", None),
                      ("--d", "driving radius, with --mu"), ("--omega", None),
                      ("--phi0", "initial angle (number, 'pi/2', '180deg', ...)")):
        add_drive_option(c, opt, text)  # the scene's declarations, their help worded for H_c
    add_friction_options(c)
    c.add_argument("--tol", type=number("--tol"), default=1e-9, help=option_help("tol", "tolerance on H_c", "1e-9"))
    add_accuracy_options(c)
    c.add_argument("--json", action="store_true", help="print one JSON object (H_c, k, omega, ...)")
    _batch_option(c, "result")
    c.set_defaults(func=cmd_critical_h)

    sc = sub.add_parser("scene", help="run a named scene (paper figure or movie); --list lists them",
                        description="Run a scene script of scenes/ by name; outputs go to results/NAME/ "
                                    "(movies to movies/). 'all' runs every scene and writes results/REPORT.md.")
    sc.add_argument("name", nargs="?", help="scene name (see --list), or 'all'")
    sc.add_argument("--list", action="store_true", help="list the scenes with one line each")
    sc.add_argument("--force", action="store_true", default=True, help=argparse.SUPPRESS)
    sc.set_defaults(func=cmd_scene, json=False)

    from rrbody.analysis.report import add_parser as add_report_parser
    from rrbody.cli.sweep import add_parser as add_sweep_parser

    add_sweep_parser(sub)
    add_report_parser(sub)
    add_cache_parser(sub)
    from rrbody.cli.chaos import add_parser as add_chaos_parser

    add_chaos_parser(sub)
    from rrbody.cli.active import add_parser as add_active_parser

    add_active_parser(sub)

    dm = sub.add_parser("demo", help="the main job (what `make demo` runs): Movie S1",
                        description="Run the Movie S1 scene: movies/movie_s1.mp4 and results/movie-s1/. No options.")
    dm.set_defaults(func=cmd_demo, json=False)
    return p


def run_command(args: argparse.Namespace) -> int:
    """Run a parsed command; bad input becomes CliError naming the option."""
    try:
        return int(args.func(args) or 0)
    except CliError:
        raise
    except ValueError as e:
        raise CliError(option_message(str(e), extended=getattr(args, "body", "rod") != "rod")) from None


def _terminate(signum: int, frame: Any) -> None:
    raise KeyboardInterrupt  # SIGTERM ends like Ctrl-C: temporary files removed, pools stopped


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: Any = None, line: str | None = None) -> None:
    print(f"rrbody: warning: {option_message(str(message))}", file=sys.stderr)  # one line, no source excerpt


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    command = argv[0] if argv and argv[0] in commands(parser) else None
    drop_warnings()  # (an earlier call's, in a program that calls main more than once)
    try:
        args = parse(parser, argv)
        command = getattr(args, "command", None)
        if not command:
            parser.print_help()
            return 0
        if command in ("flip-time", "critical-h", "simulate"):
            from rrbody.cli.lean import preload_cython_blas

            preload_cython_blas()
        if getattr(args, "batch", None) is not None:
            from rrbody.cli.batch import run_batch

            return run_batch(parser, argv, args, parse, run_command)
        return run_command(args)
    except CliError as e:
        drop_warnings()  # bad input is one line: the error's
        print(f"rrbody{' ' + command if command else ''}: error: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except ImportError as e:  # a missing optional extra: one line naming it, exit 2
        from rrbody.model.extras import missing_extra_message

        msg = missing_extra_message(e)
        if msg is None:
            raise
        drop_warnings()
        print(f"rrbody{' ' + command if command else ''}: error: {msg}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        raise
    except OSError as e:  # the system refused (disk full, permissions changed mid-run): one line, no traceback
        where = f": {e.filename}" if e.filename else ""
        print(f"rrbody{' ' + command if command else ''}: error: {e.strerror or e}{where}", file=sys.stderr)
        return 1
    finally:
        flush_warnings()  # the input was good: what a command did not print once it had checked it


def entry(argv: Sequence[str] | None = None) -> int:
    """The ``rrbody`` console command: :func:`main` plus one-line warnings and quiet ends on SIGTERM
    and closed pipes (process-wide settings, so not made by :func:`main`, which tests call in-process)."""
    import threading
    import warnings

    warnings.showwarning = _show_warning
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminate)
    try:
        code = main(argv)
        sys.stdout.flush()
    except BrokenPipeError:
        # the reader went away (`| head`): say nothing; point stdout at /dev/null so that the
        # interpreter's final flush cannot raise again
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    return code


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(entry())
