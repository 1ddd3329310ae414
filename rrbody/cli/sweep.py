"""``rrbody sweep``: the command-line front end of :mod:`rrbody.analysis.sweep`, over any scene.

The scene options are those of ``simulate`` and ``flip-time`` (any body: ``--body rod|disk|ellipse``,
``--R0``, ``--delta``, ``--l``, free bodies with ``--no-drive``); ``--axis NAME=...`` varies any
numeric one. Everything (options, every axis value, options that contradict each other, the output
path and whether another process is writing it, ``--workers``, the scheduler's address and that it
answers) is checked before any work starts or any file is written: bad input is one line, exit 2. A
fault (a worker process that dies, a lost Dask scheduler, a full disk) is one line too, exit 1,
saying how many points are saved and the exact command that finishes the sweep (``--resume``).
This module imports the sweep engine only when the command runs, so other commands never load it.
"""

from __future__ import annotations

import argparse
import inspect
import json
import logging
import math
import re
import shlex
import sys
from typing import Any

from rrbody.cli.args import CliError, check_options, given, integer, number, option_help, option_message, suggest
from rrbody.cli.options import (
    SCENE_OPTIONS,
    add_accuracy_options,
    add_scene_options,
    check_contradictions,
    scene_params,
)

__all__ = ["add_parser", "cmd_sweep", "QUANTITY_NAMES", "quiet_dask"]

#: the sweep engine's quantities (tests check this equals rrbody.analysis.sweep_spec.QUANTITIES)
QUANTITY_NAMES = ("flip_time", "critical_h", "rr", "rest", "chaos")
#: options of --quantity chaos only (option -> the quantity's option name)
_CHAOS_OPTIONS = {"--transient": "transient", "--estimate": "estimate", "--d0": "d0", "--plot": None}
_ALWAYS = ("phi0", "d", "friction")  # written into every sweep's base, as before any-scene sweeps


def _values(name: str, text: str) -> list[float]:
    """Axis values: a list v1,v2,... or start:stop:num[:log]; angle expressions for phi0."""
    from rrbody.model.angles import parse_angle, parse_number

    def num(t: str) -> float:
        # finite at every step, as on the command line (1e400 is refused, not read as inf)
        return parse_angle(t, name=name) if name == "phi0" else parse_number(t, name=f"--axis {name}")

    if ":" in text:
        parts = text.split(":")
        if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3] != "log"):
            raise ValueError
        start, stop = num(parts[0]), num(parts[1])
        n = float(parts[2])
        if not (n.is_integer() and 1 <= n <= 1_000_000):
            raise ValueError
        log = len(parts) == 4
        if log and (start <= 0 or stop <= 0):
            raise ValueError
        import numpy as np

        vals = np.geomspace(start, stop, int(n)) if log else np.linspace(start, stop, int(n))
        return [float(v) for v in vals]
    return [num(v) for v in text.split(",") if v.strip()]


def parse_axes(items: list[str]) -> dict[str, tuple[float, ...]]:
    """The ``--axis`` options, in order; a repeated or unknown name is an error naming ``--axis``."""
    from rrbody.model.scene import NUMERIC_SCENE_PARAMS

    axes: dict[str, tuple[float, ...]] = {}
    for text in items:
        name, sep, rest = text.partition("=")
        name = name.strip().replace("-", "_")
        if not sep or not name or not rest.strip():
            raise CliError(f"--axis must be NAME=v1,v2,... or NAME=start:stop:num[:log], got {text!r}")
        if name not in NUMERIC_SCENE_PARAMS:
            raise CliError(f"--axis {name}: not a scene parameter{suggest(name, NUMERIC_SCENE_PARAMS)}; "
                           f"axes: {', '.join(NUMERIC_SCENE_PARAMS)}")
        if name in axes:
            raise CliError(f"--axis {name} is given twice; give each axis once (two axes make a 2-D grid)")
        try:
            vals = _values(name, rest)
        except (ValueError, IndexError) as e:
            if str(e).startswith(f"--axis {name}"):  # a value the number parser refused: its own words
                raise CliError(str(e)) from None
            raise CliError(f"--axis must be NAME=v1,v2,... or NAME=start:stop:num[:log] (1 <= num <= 1e6, log "
                           f"needs start, stop > 0), got {text!r}") from None
        if not vals or not all(math.isfinite(v) for v in vals):
            raise CliError(f"--axis {name}: values must be finite numbers, got {rest!r}")
        axes[name] = tuple(vals)
    return axes


def add_parser(sub: Any) -> None:
    """Register ``rrbody sweep`` on the CLI's subparsers."""
    s = sub.add_parser("sweep", help="flip time / H_c / RR / free-body rest over a grid or list of any scene's "
                                     "parameters",
                       description="Sweep any scene. Examples: rrbody sweep --H 0.25 --k 7.5 --axis "
                                   "omega=0.1:100:40:log --out tf.csv; rrbody sweep --body ellipse --R0 0.3 --l 0.2 "
                                   "--k 0.0033 --omega 0.6 --axis delta=-0.9:0.9:7 --out e.csv (2-D: two --axis; "
                                   "--out x.nc for NetCDF)")
    s.add_argument("--quantity", choices=QUANTITY_NAMES, default="flip_time",
                   help="flip_time (default), critical_h (rod: H_c over k, omega, phi0), rr (reverse rotation "
                        "yes/no), rest (free body: stop time, distance, turn; needs --no-drive and --t-max), "
                        "chaos (maximal Lyapunov exponent and fraction of time in reverse rotation; see the group "
                        "'chaos')")
    s.add_argument("--axis", action="append", required=True, metavar="NAME=VALUES",
                   help="NAME=v1,v2,... or NAME=start:stop:num[:log]; NAME is any numeric scene option (H, l, R0, "
                        "delta, omega, d, k, mu, g, phi0, phi_dot0, samples, spin0, tilt, downhill, mu_static, sides); "
                        "each value is checked against "
                        "that option's range, and an axis the quantity does not depend on is refused (H with "
                        "critical_h); repeat for a 2-D grid")
    s.add_argument("--list", dest="zip_axes", action="store_true", help="zip the axes (one point per index)")
    add_scene_options(s)
    g = s.add_argument_group("analysis")
    add_accuracy_options(g)
    g.add_argument("--t-max", type=number("--t-max"), default=None,
                   help=option_help("t_max", "flip_time: horizon cap; rest: horizon (required); chaos: the span "
                                             "the exponent is averaged over, at every point (default 200 driving "
                                             "periods of each point)"))
    g.add_argument("--tol", type=number("--tol"), default=None, help=option_help("tol", "critical_h tolerance on H"))
    c = s.add_argument_group("chaos (--quantity chaos only; its span: --t-max, default 200 driving periods per "
                                 "point; rtol: --rtol, default 1e-10, not --accuracy)")
    c.add_argument("--transient", type=number("--transient"), default=None,
                   help=option_help("settle_periods", "driving periods run first and discarded, per point", 20))
    c.add_argument("--estimate", choices=("auto", "tangent", "two"), default=None,
                   help="tangent (variational equations), two (two trajectories) or auto (default: tangent unless "
                        "the friction is dry)")
    c.add_argument("--d0", type=number("--d0"), default=None,
                   help=option_help("d0", "two trajectories' separation in (phi, phi')", "1e-8"))
    c.add_argument("--plot", default=None,
                   help="PNG of the two maps, lambda_max and the RR fraction (a 2-D grid: two --axis, no --list)")
    o = s.add_argument_group("output and execution")
    o.add_argument("--out", required=True, help="output .csv or .nc (2-D grids); a regular file or absent")
    o.add_argument("--resume", action="store_true", help="continue an interrupted sweep from its checkpoint "
                                                         "(not with --force)")
    o.add_argument("--force", action="store_true", help="overwrite an existing output (regular file) / start afresh "
                                                        "(never an output another rrbody process is writing)")
    o.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://127.0.0.1:8786 (its form, "
                                                     "then that it answers, checked before anything is written)")
    o.add_argument("--workers", type=integer("--workers"), default=None,
                   help=option_help("workers", "local processes (default: the core count; never more than the "
                                               "batches; a warning above the core count)"))
    o.add_argument("--batch-size", type=integer("--batch-size"), default=None,
                   help=option_help("batch_size", "points per task (default: ~4 tasks per process, <= 256)"))
    o.add_argument("--json", action="store_true", help="print one JSON object (out, points, shape)")
    # the options in the order of --help, for the --resume command a fault prints
    options = tuple((a.dest, a.option_strings[-1], a.nargs == 0) for a in s._actions
                    if a.option_strings and a.dest != "help")
    s.set_defaults(func=cmd_sweep, _sweep_options=options)


def _resume_command(args: argparse.Namespace) -> str:
    """The command that finishes this sweep: the options typed, --force dropped, --resume added."""
    def text(v: Any) -> str:
        if isinstance(v, (tuple, list)):
            return ",".join(text(x) for x in v)
        return repr(v) if isinstance(v, float) else str(v)

    words = ["rrbody", "sweep"]
    for dest, opt, flag in getattr(args, "_sweep_options", ()):
        if not given(args, opt) or dest in ("force", "resume"):
            continue
        v = getattr(args, dest)
        for one in (v if dest == "axis" else [v]):
            if flag:
                words.append(opt)
            else:
                t = text(one)
                words += [f"{opt}={t}"] if t.startswith("-") else [opt, t]
    return shlex.join([*words, "--resume"])


def _contradictions(args: argparse.Namespace, axes: dict[str, Any]) -> None:
    """Options that cannot both hold, named both: --resume with --force; an option typed that is also a
    swept axis; and those of every scene command (:func:`check_contradictions`), where an axis counts
    as its option typed (``--friction none`` with ``--axis k=...`` ignores the axis as it would ``--k``)."""
    if args.resume and args.force:
        raise CliError("--resume and --force contradict each other: --resume continues the checkpoint, --force "
                       "discards it and starts afresh; give one of them")
    opts = {name: "--" + name.replace("_", "-") for name in axes}
    for name, opt in opts.items():
        if given(args, opt):
            raise CliError(f"{opt} and --axis {name}=... contradict each other: the axis sets {name} at every "
                           f"point; drop {opt} or the axis")
    typed = frozenset(getattr(args, "_given", ())) | set(opts.values())
    try:
        check_contradictions(argparse.Namespace(**{**vars(args), "_given": typed}))
    except CliError as e:  # name an axis as the user typed it, not as the option it stands for
        msg = str(e)
        for name, opt in opts.items():
            if not given(args, opt):
                msg = re.sub(rf"{re.escape(opt)}\b(?!-)", f"--axis {name}=...", msg)
        raise CliError(msg) from None


def _base(args: argparse.Namespace, axes: dict[str, Any]) -> dict[str, Any]:
    """The fixed scene parameters: those given, and the defaults the sweep's metadata always shows."""
    from rrbody.model.scene import scene_from_params

    defaults = {k: p.default for k, p in inspect.signature(scene_from_params).parameters.items()}
    kw = scene_params(args)
    kw.pop("t_max", None)  # an analysis option here, not a scene parameter
    base = {k: v for k, v in kw.items() if k in _ALWAYS or v != defaults.get(k)}
    for k in axes:
        base.pop(k, None)
    if "v0" in base:
        base["v0"] = list(base["v0"])
    return base


def quiet_dask() -> None:
    """Silence Dask's loggers: it logs a lost connection as tracebacks on stderr, and the command
    reports the fault in one line. Importing it here reports a missing extra before any file."""
    from rrbody.model.extras import require

    require("distributed", purpose="a Dask scheduler (--scheduler)")

    for name in ["distributed", *logging.root.manager.loggerDict]:
        if name == "distributed" or name.startswith("distributed."):  # several have their own level
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)


def _chaos_checks(args: argparse.Namespace, axes: dict[str, Any]) -> str | None:
    """The chaos options only with --quantity chaos, --accuracy not with it; --plot a writable .png of
    a 2-D grid (checked before any work). Returns the --plot path."""
    if args.quantity != "chaos":
        typed = [opt for opt in _CHAOS_OPTIONS if given(args, opt)]
        if typed:
            raise CliError(f"{typed[0]} applies only to --quantity chaos, got --quantity {args.quantity}")
        return None
    if given(args, "--accuracy"):
        raise CliError("--accuracy does not apply to --quantity chaos: give --rtol (default 1e-10)")
    if args.plot is None:
        return None
    if args.zip_axes or len(axes) != 2:
        raise CliError(f"--plot draws a 2-D map: give two --axis and no --list, got {len(axes)} --axis"
                       f"{' with --list' if args.zip_axes else ''}")
    from rrbody.model.outputs import preflight

    preflight({"--plot": (args.plot, (".png",)), "--out": (args.out, None)}, force=True)  # (--out: below)
    from rrbody.model.io import check_writable

    check_writable(args.plot, force=args.force or args.resume, name="--plot")
    return str(args.plot)


def _check_out(args: argparse.Namespace) -> None:
    """--out, its checkpoint and sidecar before the sweep engine is even loaded: the suffix, its writer
    installed (.nc: the data extra), the folder (:func:`rrbody.analysis.sweep_store.check_outputs`; what
    another process could change is checked again under the output's lock)."""
    from rrbody.analysis.sweep_store import check_outputs

    try:
        check_outputs(args.out, grid=not args.zip_axes, resume=args.resume, force=args.force, existing=False,
                      name="--out")
    except ValueError as e:
        raise CliError(option_message(str(e))) from None


def cmd_sweep(args: argparse.Namespace) -> int:
    """Handler of ``rrbody sweep``."""
    check_options(args, (*SCENE_OPTIONS, "--rtol", "--t-max", "--tol", "--workers", "--batch-size", "--d0",
                         "--transient"))
    axes = parse_axes(args.axis)
    _contradictions(args, axes)
    base = _base(args, axes)
    plot = _chaos_checks(args, axes)
    options: dict[str, Any] = {} if args.quantity == "chaos" else {"accuracy": args.accuracy}
    if args.rtol is not None:
        options["rtol"] = args.rtol
    if args.quantity == "chaos":
        options.update({name: getattr(args, name) for name in _CHAOS_OPTIONS.values()
                        if name is not None and getattr(args, name) is not None})
    if args.t_max is not None and args.quantity in ("flip_time", "rest", "chaos"):
        options["t_max"] = args.t_max
    if args.tol is not None and args.quantity == "critical_h":
        options["tol"] = args.tol
    _check_out(args)
    from rrbody.analysis.sweep import SweepFault, SweepStopped, run_sweep
    from rrbody.analysis.sweep_spec import Sweep
    from rrbody.model.checks import MissingParameters

    extended = args.body != "rod"
    try:
        sweep = Sweep(base=base, axes=axes, quantity=args.quantity, mode="list" if args.zip_axes else "grid",
                      options=options)
    except MissingParameters as e:
        given = set(axes)
        names = [f"--{n.replace('_', '-')} (or --axis {n}=...)" for n in e.names if n not in given]
        raise CliError(f"missing required options: {', '.join(names)}") from None
    except ValueError as e:
        msg = str(e)
        if msg.startswith("axis "):
            name, _, rest = msg[5:].partition(": ")
            raise CliError(f"--axis {name}: {option_message(rest, extended=extended)}") from None
        raise CliError(option_message(msg, extended=extended)) from None
    if args.scheduler is not None:
        quiet_dask()
    try:
        out = run_sweep(sweep, args.out, resume=args.resume, force=args.force, scheduler=args.scheduler,
                        workers=args.workers, batch_size=args.batch_size,
                        progress=not args.json and sys.stderr.isatty())
    except SweepStopped as e:
        print(f"rrbody sweep: interrupted: {e.done} of {e.total} points are saved in {str(e.checkpoint)!r}; "
              "run the same command with --resume to compute the rest", file=sys.stderr)
        return 130
    except SweepFault as e:
        print(f"rrbody sweep: error: {e.what}; {e.done} of {e.total} points are saved in {str(e.checkpoint)!r}; "
              f"finish with: {_resume_command(args)}", file=sys.stderr)
        return 1
    except ValueError as e:
        raise CliError(option_message(str(e), extended=extended)) from None
    if plot is not None:
        from rrbody.render.chaos_map import plot_chaos_map

        plot_chaos_map(out, plot, force=args.force or args.resume)
    if args.json:
        print(json.dumps({"out": str(out), "points": sweep.size, "shape": list(sweep.shape),
                          **({"plot": plot} if plot is not None else {})}))
    else:
        print(f"wrote {out} ({sweep.size} points, shape {sweep.shape})" + (f" and {plot}" if plot else ""))
    return 0
