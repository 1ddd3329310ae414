"""``rrbody sweep``: the command-line front end of :mod:`rrbody.analysis.sweep`."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from rrbody.analysis.sweep import QUANTITIES, Sweep, run_sweep
from rrbody.cli.args import _angle, _finite

__all__ = ["add_parser", "cmd_sweep"]


def _parse_axis(text: str) -> tuple[str, tuple[float, ...]]:
    """NAME=v1,v2,... or NAME=start:stop:num[:log]."""
    name, sep, rest = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"--axis must be NAME=v1,v2,... or NAME=start:stop:num[:log], got {text!r}")
    try:
        if ":" in rest:
            parts = rest.split(":")
            start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
            log = len(parts) > 3 and parts[3] == "log"
            if num < 1 or (log and (start <= 0 or stop <= 0)):
                raise ValueError
            vals = np.geomspace(start, stop, num) if log else np.linspace(start, stop, num)
        else:
            vals = np.asarray([float(v) for v in rest.split(",") if v])
    except (ValueError, IndexError):
        raise argparse.ArgumentTypeError(f"--axis must be NAME=v1,v2,... or NAME=start:stop:num[:log] "
                                         f"(num >= 1, log needs start, stop > 0), got {text!r}") from None
    return name.strip(), tuple(float(v) for v in vals)


def add_parser(sub: Any) -> None:
    """Register ``rrbody sweep`` on the CLI's subparsers."""
    s = sub.add_parser("sweep", help="flip time / H_c / RR over a grid or list of rod-mass parameters",
                       description="Sweep a rod-mass scene. Example: rrbody sweep --quantity flip_time --H 0.25 "
                                   "--k 7.5 --axis omega=0.1:100:40:log --out tf.csv  (2-D: two --axis; "
                                   "--out x.nc for NetCDF)")
    s.add_argument("--quantity", choices=tuple(QUANTITIES), default="flip_time")
    s.add_argument("--axis", action="append", type=_parse_axis, required=True,
                   help="NAME=v1,v2,... or NAME=start:stop:num[:log]; NAME in H, k, omega, phi0, d (repeatable)")
    s.add_argument("--list", dest="zip_axes", action="store_true", help="zip the axes (one point per index)")
    s.add_argument("--H", type=_finite("--H"))
    s.add_argument("--k", type=_finite("--k"))
    s.add_argument("--omega", type=_finite("--omega"))
    s.add_argument("--phi0", type=_angle, default=math.pi)
    s.add_argument("--d", type=_finite("--d"), default=1.0)
    s.add_argument("--friction", choices=("dry", "viscous", "none"), default="dry")
    s.add_argument("--accuracy", choices=("draft", "default", "paper"), default="default")
    s.add_argument("--rtol", type=_finite("--rtol"), default=None)
    s.add_argument("--t-max", type=_finite("--t-max"), default=None, help="flip_time horizon cap (s)")
    s.add_argument("--tol", type=_finite("--tol"), default=None, help="critical_h tolerance on H")
    s.add_argument("--out", required=True, help="output .csv or .nc (2-D grids)")
    s.add_argument("--resume", action="store_true", help="continue an interrupted sweep from its checkpoint")
    s.add_argument("--force", action="store_true", help="overwrite an existing output / start afresh")
    s.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://127.0.0.1:8786")
    s.add_argument("--workers", type=int, default=None, help="local processes (default: all cores)")
    s.add_argument("--batch-size", type=int, default=None, help="points per task")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_sweep)


def cmd_sweep(args: argparse.Namespace) -> int:
    """Handler of ``rrbody sweep``."""
    import sys

    axes = dict(args.axis)
    base: dict[str, Any] = {"phi0": args.phi0, "d": args.d, "friction": args.friction}
    for k in ("H", "k", "omega"):
        v = getattr(args, k)
        if v is not None:
            base[k] = v
    for k in axes:
        base.pop(k, None)
    options: dict[str, Any] = {"accuracy": args.accuracy}
    if args.rtol is not None:
        options["rtol"] = args.rtol
    if args.t_max is not None and args.quantity == "flip_time":
        options["t_max"] = args.t_max
    if args.tol is not None and args.quantity == "critical_h":
        options["tol"] = args.tol
    sweep = Sweep(base=base, axes=axes, quantity=args.quantity, mode="list" if args.zip_axes else "grid",
                  options=options)
    out = run_sweep(sweep, args.out, resume=args.resume, force=args.force, scheduler=args.scheduler,
                    workers=args.workers, batch_size=args.batch_size,
                    progress=not args.json and sys.stderr.isatty())
    if args.json:
        print(json.dumps({"out": str(out), "points": sweep.size, "shape": list(sweep.shape)}))
    else:
        print(f"wrote {out} ({sweep.size} points, shape {sweep.shape})")
    return 0
