"""``rrbody active`` and ``rrbody active-ensemble``: the active-bodies box study
(:mod:`rrbody.analysis.active_study`) from the command line.

``active``: one run (a :class:`~rrbody.analysis.active_study.Box`), its summary as JSON (``--out``, and on
stdout with ``--json``), optionally filmed (``--movie``, ``--rerun``: only established episodes in red,
:mod:`rrbody.render.active_film`). ``active-ensemble``: every combination of lists of packings,
activities and seeds (:func:`~rrbody.analysis.active_study.ensemble`: local processes, ``--workers``),
resumable from ``<out>.checkpoint.jsonl`` (``--resume``), a table (CSV or JSON) and optionally the
figure (``--plot``). Every value is checked by ``Box`` itself, each output path before anything runs;
bad input is one line naming the option, exit 2, nothing written.
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from dataclasses import fields
from pathlib import Path
from typing import Any

from rrbody.cli.active_options import rename
from rrbody.cli.args import CliError, check_options, emit, given, integer, number, option_help, option_message, ranged
from rrbody.model.active import MAX_SEED

__all__ = ["add_parser", "cmd_active", "cmd_active_ensemble", "BOX_OPTIONS"]

#: Box's parameter -> option
BOX_OPTIONS = {"n": "--n", "packing": "--packing", "activity": "--activity", "mix": "--mix", "seed": "--seed",
               "t_end": "--t-end", "every": "--every", "dt": "--dt"}
_LISTS = ("packing", "activity", "seed")  # lists in active-ensemble
_HELP = {"n": "bodies in the box", "packing": "area fraction the bodies cover",
         "activity": "propulsion over the dry friction, F / (mu m g)", "mix": "fraction of L-shapes (the rest: disks)",
         "seed": "placement and noise (the same seed, the same run)", "t_end": "the run's length",
         "every": "steps between samples (the episodes' resolution)", "dt": "time step"}


def _box_defaults() -> dict[str, Any]:
    from rrbody.analysis.active_study import Box

    return {f.name: f.default for f in fields(Box)}


def _box_valid(name: str) -> str:
    """A Box parameter's range as the help and the messages show it (Box's own table)."""
    from rrbody.analysis.active_study import BOX_INTEGERS, BOX_RANGES
    from rrbody.model.checks import range_text

    lo, hi, lo_open, unit = BOX_RANGES[name]
    if name in BOX_INTEGERS:
        return f"an integer in [{int(lo)}, {'2^63 - 1' if hi == MAX_SEED else int(hi)}]{' ' + unit if unit else ''}"
    return range_text(lo, hi, lo_open, unit=unit)


def _box_options(p: argparse.ArgumentParser, *, lists: bool) -> None:
    from rrbody.analysis.active_study import BOX_INTEGERS

    g = p.add_argument_group("box (docs: Active bodies)")
    defaults = _box_defaults()
    for name, opt in BOX_OPTIONS.items():
        listed = lists and name in _LISTS
        valid = _box_valid(name)
        # in the parser's message: '--n must be an integer in [2, ...]', '--packing must be a finite number in ...'
        shown = valid.removeprefix("an integer") if name in BOX_INTEGERS else " " + valid
        one = (integer if name in BOX_INTEGERS else number)(opt, shown)
        what = f"{_HELP[name]}: a comma-separated list, each {valid}" if listed else f"{_HELP[name]}, {valid}"
        d = defaults[name]
        ranged(g.add_argument(opt, type=_list(opt, one) if listed else one, default=None,
                              metavar="V1,V2,..." if listed else None,
                              help=f"{what}; default {d:.6g}" if isinstance(d, float) else f"{what}; default {d}"),
               valid)


def _list(option: str, parse_one: Any) -> Any:
    def parse(text: str) -> tuple[Any, ...]:
        parts = [v for v in text.split(",") if v.strip()]
        if not parts:
            raise argparse.ArgumentTypeError(f"{option} must be a comma-separated list of values, got {text!r}")
        return tuple(parse_one(v) for v in parts)

    parse.__name__ = "list"
    return parse


def _outputs(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", action="store_true", help="overwrite existing output files (regular files only)")
    p.add_argument("--json", action="store_true", help="print one JSON object (the summary)")


def add_parser(sub: Any) -> None:
    """Register ``active`` and ``active-ensemble``."""
    a = sub.add_parser("active", help="one run of the active-bodies box study: its episodes, summary, movie",
                       description="Chiral active bodies (L-shapes and disks) in a walled box: reverse-rotation "
                                   "episodes and the collisions that begin them (docs: Active bodies). Example: "
                                   "rrbody active --n 100 --packing 0.3 --t-end 20 --out run.json --movie run.mp4")
    _box_options(a, lists=False)
    o = a.add_argument_group("outputs")
    o.add_argument("--out", help="the run's summary (.json): parameters, per body its episodes, per species the "
                                 "statistics")
    o.add_argument("--movie", help="an MP4 of the run (.mp4): red only inside an established episode, blue turning "
                                   "with the orbit, grey neither")
    o.add_argument("--fps", type=number("--fps"), default=None, help=option_help("fps", "movie frame rate", 20))
    o.add_argument("--movie-speed", type=number("--movie-speed"), default=None,
                   help=option_help("movie_speed", "simulated seconds per second of movie", 1))
    o.add_argument("--rerun", help="a rerun recording (.rrd), coloured as the movie")
    ranged(o.add_argument("--rerun-every", type=integer("--rerun-every", " in [1, 1000000]"), default=None,
                          help="keep every N-th sample in the rerun recording, an integer in [1, 1000000]; default 1"),
           "an integer in [1, 1000000]")
    _outputs(a)
    a.set_defaults(func=cmd_active)

    e = sub.add_parser("active-ensemble", help="the active-bodies box study over packings, activities and seeds",
                       description="Every combination of --packing, --activity and --seed (lists), each a run of "
                                   "`rrbody active`, on local processes; the statistics per run and species, and "
                                   "their mean and sd over the seeds. Resumable: finished runs are kept in "
                                   "OUT.checkpoint.jsonl. Example: rrbody active-ensemble --n 100 --packing "
                                   "0.1,0.2,0.3 --activity 1.5,3 --seed 0,1,2 --t-end 30 --out ens.csv --plot ens.png")
    _box_options(e, lists=True)
    o = e.add_argument_group("output and execution")
    o.add_argument("--out", required=True, help="the table, .csv (a row per run and species) or .json (the runs "
                                                "and the mean over seeds); a regular file or absent")
    o.add_argument("--plot", help="PNG of the statistics against packing (mean +- sd over the seeds)")
    o.add_argument("--workers", type=integer("--workers"), default=None,
                   help=option_help("workers", "local processes (default: the core count; never more than the runs)"))
    o.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://127.0.0.1:8786, instead "
                                                     "of local processes (its form, then that it answers, checked "
                                                     "before anything is written)")
    o.add_argument("--resume", action="store_true", help="continue an interrupted ensemble from its checkpoint "
                                                         "(not with --force)")
    _outputs(e)
    e.set_defaults(func=cmd_active_ensemble)


# ---- shared checks -----------------------------------------------------------------------------
def _box(values: dict[str, Any]) -> Any:
    """A Box from parameter values; CliError naming the option."""
    from rrbody.analysis.active_study import Box

    try:
        return Box(**values)
    except ValueError as e:
        raise CliError(rename(str(e), BOX_OPTIONS)) from None


def _given_box(args: argparse.Namespace) -> dict[str, Any]:
    return {name: getattr(args, name) for name in BOX_OPTIONS if getattr(args, name) is not None}


def _check_paths(paths: dict[str, str], suffixes: dict[str, tuple[str, ...]], *, force: bool,
                 needs: tuple[tuple[str, str], ...] = ()) -> None:
    """Each output writable (absent or a regular file; existing: --force), with its writer's suffix and
    that writer installed, no two of them one file, and the extras the run needs (``needs``: (module,
    purpose)): before anything runs (:func:`rrbody.model.outputs.preflight`)."""
    from rrbody.model.outputs import preflight

    preflight({opt: (path, suffixes[opt]) for opt, path in paths.items()}, force=force, needs=needs)


#: the run itself steps pymunk: its extra is named before anything is written
_ENGINE = (("pymunk", "the active bodies' run"),)


def _only_with(args: argparse.Namespace, pairs: tuple[tuple[str, str], ...]) -> None:
    for opt, needs in pairs:
        if given(args, opt) and getattr(args, needs[2:].replace("-", "_")) is None:
            raise CliError(f"{opt} applies only with {needs}: add {needs} FILE or drop {opt}")


# ---- rrbody active -----------------------------------------------------------------------------
def cmd_active(args: argparse.Namespace) -> int:
    """Handler of ``rrbody active``: one run, its summary and films."""
    box = _box(_given_box(args))
    _only_with(args, (("--fps", "--movie"), ("--movie-speed", "--movie"), ("--rerun-every", "--rerun")))
    check_options(args, ("--fps", "--movie-speed"))
    every = 1 if args.rerun_every is None else args.rerun_every
    if args.rerun_every is not None:
        from rrbody.model.checks import check_int

        every = check_int("--rerun-every", every, 1, 1_000_000)
    paths = {o: getattr(args, o[2:]) for o in ("--out", "--movie", "--rerun") if getattr(args, o[2:]) is not None}
    _check_paths(paths, {"--out": (".json",), "--movie": (".mp4",), "--rerun": (".rrd",)}, force=args.force,
                 needs=_ENGINE)
    from rrbody.model.io import check_writable
    from rrbody.model.outlock import claimed

    with claimed(paths.items()):
        for opt, path in paths.items():  # what changed between the checks above and the claim
            check_writable(path, force=args.force, name=opt)
        return _run_active(args, box, every)


def _run_active(args: argparse.Namespace, box: Any, rerun_every: int) -> int:
    from rrbody.analysis.active_study import summary
    from rrbody.model.io import atomic_write_text
    from rrbody.model.trajectory import jsonable
    from rrbody.render.active_film import run_filmed, write_movie, write_rerun

    res, rec, rrd = run_filmed(box, movie=bool(args.movie), rerun_every=rerun_every if args.rerun else None,
                               progress=not args.json and sys.stderr.isatty())
    out = jsonable(summary(res))
    written: dict[str, str] = {}
    if args.out:
        from rrbody._version import __version__

        atomic_write_text(args.out, json.dumps({**out, "rrbody_version": __version__}, indent=1) + "\n",
                          force=args.force, name="--out")
        written["out"] = args.out
    if args.movie:
        show = not args.json and sys.stderr.isatty()
        written["movie"] = str(write_movie(res, rec, args.movie, fps=20.0 if args.fps is None else args.fps,
                                           speed=1.0 if args.movie_speed is None else args.movie_speed,
                                           force=args.force, progress=show))
    if args.rerun:
        written["rerun"] = str(write_rerun(res, rrd, args.rerun, rerun_every=rerun_every, force=args.force))
    st = out["stats"]
    text = (f"active box: {box.n} bodies, packing {box.packing:g}, activity {box.activity:g}, side "
            f"{out['side']:.4g} m, {res['t'][-1]:.6g} s, seed {box.seed}")
    for sp, s in st.items():
        if s.get("bodies"):
            text += (f"\n  {sp}: {s['bodies']} bodies, {s['episodes']} episodes "
                     f"({s['episodes_per_body_per_min']:.3g} per body per min)"
                     + (f", {s['fraction_at_collision']:.0%} begun at a collision (by chance "
                        f"{s['chance_at_collision']:.0%})" if s["episodes"] else ""))
    for v in written.values():
        text += f"\nwrote {v}"
    emit(args, {**out, "written": written}, text)
    return 0


# ---- rrbody active-ensemble --------------------------------------------------------------------
def _points(args: argparse.Namespace) -> list[Any]:
    """Every combination of the lists (packing slowest, seed fastest), each a checked Box."""
    defaults = _box_defaults()
    lists: dict[str, tuple[Any, ...]] = {}
    for name in _LISTS:
        v = getattr(args, name)
        vals = (defaults[name],) if v is None else (v if isinstance(v, tuple) else (v,))
        for x in vals:
            if vals.count(x) > 1:
                raise CliError(f"{BOX_OPTIONS[name]} lists {x!r} twice; give each value once")
        lists[name] = vals
    fixed = {k: v for k, v in _given_box(args).items() if k not in _LISTS}
    return [_box({**fixed, "packing": p, "activity": a, "seed": s})
            for p, a, s in itertools.product(lists["packing"], lists["activity"], lists["seed"])]


def cmd_active_ensemble(args: argparse.Namespace) -> int:
    """Handler of ``rrbody active-ensemble``."""
    from rrbody.analysis.sweep_store import checkpoint_path
    from rrbody.model.io import check_writable
    from rrbody.model.outlock import claimed

    points = _points(args)
    check_options(args, ("--workers",))
    if args.resume and args.force:
        raise CliError("--resume and --force contradict each other: --resume continues the checkpoint, --force "
                       "discards it and starts afresh; give one of them")
    paths = {o: getattr(args, o[2:]) for o in ("--out", "--plot") if getattr(args, o[2:]) is not None}
    ck = checkpoint_path(args.out)
    _check_paths({**paths, "--out: checkpoint": str(ck)},
                 {"--out": (".csv", ".json"), "--plot": (".png",), "--out: checkpoint": (".jsonl",)},
                 force=True, needs=_ENGINE)  # (existing outputs: below, once the lock is held)
    if args.scheduler is not None:
        from rrbody.analysis.pool import check_scheduler_address
        from rrbody.cli.sweep import quiet_dask
        from rrbody.model.extras import require

        try:
            check_scheduler_address(args.scheduler)
        except ValueError as e:
            raise CliError(option_message(str(e))) from None
        require("distributed", purpose="a Dask scheduler (--scheduler)")
        quiet_dask()
    with claimed([*paths.items(), ("--out: checkpoint", ck)]):
        for opt, path in paths.items():
            check_writable(path, force=args.force or args.resume, name=opt)
        if ck.exists() and not (args.resume or args.force):
            raise CliError(f"--out: checkpoint {str(ck)!r} exists from an earlier run; pass --resume to continue "
                           "it or --force to start afresh")
        if ck.exists() and args.force:
            ck.unlink()
        return _run_ensemble(args, points, ck)


def _run_ensemble(args: argparse.Namespace, points: list[Any], ck: Path) -> int:
    from rrbody.analysis.active_study import ensemble, seed_table
    from rrbody.analysis.pool import ExecutorFault
    from rrbody.analysis.sweep_store import count_rows

    try:
        rows = ensemble(points, workers=args.workers, checkpoint=ck, scheduler=args.scheduler,
                        progress=not args.json and sys.stderr.isatty())
    except ValueError as e:  # no scheduler answers at the address (before anything is written), or a
        # checkpoint of other runs (kept)
        raise CliError(option_message(str(e))) from None
    except KeyboardInterrupt:
        print(f"rrbody active-ensemble: interrupted: {count_rows(ck)} of {len(points)} runs are saved in "
              f"{str(ck)!r}; run the same command with --resume to compute the rest", file=sys.stderr)
        return 130
    except (ExecutorFault, OSError) as e:
        what = str(e) if isinstance(e, ExecutorFault) else f"{e.strerror or e}" + (f": {e.filename!r}"
                                                                                  if e.filename else "")
        print(f"rrbody active-ensemble: error: {what}; {count_rows(ck)} of {len(points)} runs are saved in "
              f"{str(ck)!r}; finish with the same command and --resume", file=sys.stderr)
        return 1
    table = seed_table(rows)
    _write_table(args.out, rows, table, force=True)
    written = {"out": args.out}
    if args.plot:
        from rrbody.render.active_film import ensemble_figure

        p0 = points[0]
        ensemble_figure(table, args.plot, force=True,
                        title=f"{p0.n} bodies, mix {p0.mix:g}, {p0.t_end:g} s; mean +- sd over "
                              f"{len({p.seed for p in points})} seeds")
        written["plot"] = args.plot
    ck.unlink()
    text = f"{len(points)} runs; wrote " + " and ".join(written.values())
    emit(args, {"points": len(points), "written": written, "table": table}, text)
    return 0


def _write_table(out: str, rows: list[dict[str, Any]], table: list[dict[str, Any]], *, force: bool) -> None:
    """``.json``: the runs (as :func:`~rrbody.analysis.active_study.ensemble` returns them) and the mean over
    seeds; ``.csv``: a row per run and species (its parameters, then the statistics; empty: undefined),
    after a ``# rrbody-active-ensemble: {json}`` line (columns, version). Written atomically."""
    import csv

    from rrbody._version import __version__
    from rrbody.analysis.active_study import STAT_KEYS, Box
    from rrbody.model.io import atomic_path, atomic_write_text
    from rrbody.model.trajectory import jsonable

    params = [f.name for f in fields(Box)]
    if out.lower().endswith(".json"):
        atomic_write_text(out, json.dumps(jsonable({"rrbody_version": __version__, "runs": rows,
                                                     "mean_over_seeds": table}), indent=1) + "\n",
                          force=force, name="--out")
        return
    cols = ["i", *params, "species", *STAT_KEYS]

    def cell(v: Any) -> str:
        return "" if v is None else repr(float(v)) if isinstance(v, float) else str(v)

    with atomic_path(out, force=force, name="--out") as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        fh.write("# rrbody-active-ensemble: " + json.dumps({"columns": cols, "rrbody_version": __version__}) + "\n")
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            for sp, st in r["stats"].items():
                w.writerow([cell(r[c]) for c in ["i", *params]] + [sp] + [cell(st.get(k)) for k in STAT_KEYS])
