"""One source for every benchmark figure the docs quote: ``benchmarks/results/``.

A quoted figure sits between two HTML comments, invisible on GitHub and in the Sphinx site (MyST
passes inline and block HTML through as raw HTML, and a browser shows no comment)::

    1,000 lines cost <!--q:head.startup.1-->1.83x<!--/q--> one single call

``python -m benchmarks.quotes`` rewrites the text between every such pair from the recorded results
(the ``*_targets.json``, ``*.csv`` and ``SUMMARY.md`` files that ``make bench`` writes), so two
pages can no longer quote two different runs; ``--check`` only reports the spans that differ (exit
status 1), which is what ``tests/test_quotes.py`` asserts. Run it after ``make bench``.

Quote names:

- ``target.STUDY.N``: the N-th target's (1-based) measured text of ``STUDY_targets.json``, whole;
  ``head.STUDY.N`` its leading figure (before the first `` (``, ``;`` or `` over``);
  ``paren.STUDY.N`` the text of its first parentheses; ``verdict.STUDY.N``: met / not met;
- ``table.targets`` (every target, as in ``SUMMARY.md``), ``table.targets-brief`` (without the
  notes), ``table.plugin`` (``engine_plugin.csv``), ``table.rhs`` (``core_rhs.csv``), ``table.mujoco``
  and ``table.mujoco-cost`` (``mujoco.csv``, ``mujoco_cost.csv``): block quotes,
  a table with a blank line either side;
- ``setup.TARGET.KEY``: ``make TARGET``'s record in ``setup.json`` (``python -m benchmarks.setup_times``:
  a clean clone, step by step): KEY a step the Makefile announces (``kernels``, ``suite``, ...), or
  ``total``, ``set-up`` (every step but the suite's and the demo's own), ``date``, ``load`` (the load
  average before and after), ``passed`` (the
  main suite's tests), ``slowest.FILE`` (the longest of tests/FILE.py's tests in pytest's list of the
  slowest); ``?`` while that target has no record;
- the named quotes of :data:`NAMED` (figures read from one file each, documented there).

Besides README.md and docs/*.md, the CHANGELOG's entries and the Makefile's step lines quote figures
(:func:`quoted_files`).
"""

from __future__ import annotations

import argparse
import csv
import json
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from .common import Target, fmt, md_table, write_text
from .run import DEFAULT_OUT, STUDIES

__all__ = ["MARKER", "PLACEHOLDER", "NAMED", "QuoteError", "quote", "rewrite", "quoted_files", "stale_spans", "main"]

ROOT = Path(__file__).resolve().parent.parent

#: one quoted span: the name, then the quoted text (possibly several lines, for tables); every name
#: has a dot (``head.startup.1``), so a page may show the syntax itself, ``<!--q:NAME-->...<!--/q-->``
MARKER = re.compile(r"<!--q:(?P<name>[A-Za-z0-9_\-]+\.[A-Za-z0-9_.\-]+)-->(?P<body>.*?)<!--/q-->", re.DOTALL)
PLACEHOLDER = "<!--q:NAME-->"  # the syntax shown, not a quote


class QuoteError(ValueError):
    """A quote name that names nothing, or a result file that does not hold what it should."""


def quoted_files(root: Path = ROOT) -> list[Path]:
    """The files whose figures must come from the results: README.md, docs/*.md, CHANGELOG.md and
    the Makefile (the time each set-up step announces)."""
    return [root / "README.md", *sorted((root / "docs").glob("*.md")), root / "CHANGELOG.md", root / "Makefile"]


# ----------------------------------------------------------------------------------- readers


def _targets(results: Path, study: str) -> list[Target]:
    path = results / f"{study}_targets.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise QuoteError(f"no recorded results for study {study!r} ({path} is missing: run make bench)") from None
    return [Target(**t) for t in data["targets"]]


def _target(results: Path, study: str, n: str) -> Target:
    targets = _targets(results, study)
    if not n.isdigit() or not 1 <= int(n) <= len(targets):
        raise QuoteError(f"study {study!r} has targets 1..{len(targets)}, not {n!r}")
    return targets[int(n) - 1]


def _rows(results: Path, name: str) -> list[dict[str, str]]:
    with open(results / name, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def _find(pattern: str, text: str, what: str) -> str:
    m = re.search(pattern, text)
    if m is None:
        raise QuoteError(f"{what}: {pattern!r} not found in {text!r}")
    return m.group(1)


def _head(measured: str) -> str:
    """The leading figure of a measured text: ``1.83x (1.08 s vs 0.591 s); ...`` -> ``1.83x``."""
    return re.split(r" \(|;| over ", measured, maxsplit=1)[0].strip()


# ------------------------------------------------------------------------------------ tables


def _targets_table(results: Path, *, notes: bool) -> str:
    """Every study's targets, in run order, as ``benchmarks.run.assemble_summary`` tabulates them."""
    rows = []
    for study in STUDIES:
        if not (results / f"{study}_targets.json").exists():
            continue
        for t in _targets(results, study):
            rows.append((study, t.name, t.target, t.measured, t.verdict, *((t.note,) if notes else ())))
    head = ["study", "target", "wanted", "measured", "verdict", *(["note"] if notes else [])]
    return md_table(head, rows)


def _plugin_table(results: Path) -> str:
    rows = [(int(r["bodies"]), float(r["bare_us"]), float(r["tank_us"]), float(r["plugin_us"]),
             float(r["plugin_over_tank"]), float(r["plugin_us_per_body"])) for r in _rows(results, "engine_plugin.csv")]
    return md_table(["N bodies (half circles, half boxes)", "bare `space.step` (us)", "tank-example joints (us)",
                     "PlaneFriction (us)", "PlaneFriction / tank", "PlaneFriction us per body"], rows)


def _rhs_table(results: Path) -> str:
    rows = _rows(results, "core_rhs.csv")
    point = float(next(r["ns_per_eval"] for r in rows if r["body"] == "point mass"))
    return md_table(["body (method)", "nodes per panel", "ns per right-hand side", "x point mass"],
                    [(r["body"], int(r["nodes_per_panel"]), float(r["ns_per_eval"]), float(r["ns_per_eval"]) / point)
                     for r in rows])


def _coldstart_table(results: Path) -> str:
    """The cold-start study's processes, cold (empty cache: the install's kernels) and warm, beside
    the cold-start bound, and the same call compiling its kernels (no install-time kernels)."""
    return md_table(["first call (a fresh process)", "cold (s)", "warm (s)", "bound, cold (s)",
                     "compiling, without the install's kernels (s)"],
                    [(r["scenario"], float(r["cold_s"]), float(r["warm_s"]), float(r["target_s"]),
                      float(r["compile_s"]))
                     for r in _rows(results, "coldstart.csv")])


def _mujoco_table(results: Path) -> str:
    """MuJoCo's own plane friction and the adapter's: spin-down over the exact rate, the disk's stop ratio."""
    def num(x: str, digits: str) -> str:
        return "-" if x in ("", "nan") else format(float(x), digits)

    return md_table(["friction", "body", "spin-down / exact", "stop ratio v/(R Omega) (exact 0.653)"],
                    [(r["friction"], r["body"], num(r["spin-down / exact"], ".4f"), num(r["stop ratio v/(R Omega)"],
                                                                                        ".4g"))
                     for r in _rows(results, "mujoco.csv")])


def _mujoco_cost_table(results: Path) -> str:
    return md_table(["100 bodies", "MuJoCo's own step (us)", "with the adapter (us)", "ratio"],
                    [(r["phase"], float(r["mujoco_step_us"]), float(r["adapter_step_us"]), float(r["ratio"]))
                     for r in _rows(results, "mujoco_cost.csv")])


# ------------------------------------------------------------------------------ named quotes


def _summary_date(results: Path) -> str:
    return _find(r"(\d{4}-\d\d-\d\d \d\d:\d\d UTC)", (results / "SUMMARY.md").read_text(encoding="utf-8"),
                 "SUMMARY.md date")


def _startup(results: Path, prefix: str) -> str:
    row = next(r for r in _rows(results, "startup.csv") if r["process"].startswith(prefix))
    return f"{fmt(float(row['best_wall_s']))} s"


def _ode_wall(results: Path, name: str, case: str, method: str, rtol: float) -> float:
    """One recorded wall time (s) of ode_rrbody.csv (t_f run) or ode_scipy.csv (its t_f measure)."""
    for r in _rows(results, name):
        if (r["case"], r["method"], float(r["rtol"])) == (case, method, rtol) and r.get("measure", "tf") == "tf":
            return float(r["wall_tf_s"] if "wall_tf_s" in r else r["wall_s"])
    raise QuoteError(f"{name} has no {method} run of case {case!r} at rtol {rtol:g}")


def _fast_1e8_ms(results: Path) -> str:
    return f"{1e3 * _ode_wall(results, 'ode_rrbody.csv', 'fast', 'rrbody', 1e-8):.1f} ms"


def _scipy_fast_1e6(results: Path) -> str:
    return f"{fmt(_ode_wall(results, 'ode_scipy.csv', 'fast', 'DOP853', 1e-6))} s"


def _old_worst_now(results: Path) -> str:
    """scipy DOP853's fast rtol 1e-6 run over rrbody's rtol 1e-8 run: the match that was the worst."""
    ratio = _ode_wall(results, "ode_scipy.csv", "fast", "DOP853", 1e-6) / _ode_wall(
        results, "ode_rrbody.csv", "fast", "rrbody", 1e-8)
    return f"{ratio:.0f}x"


def _stiff(results: Path, old: bool) -> str:
    rows = [r for r in _rows(results, "core_stiff.csv") if r["method"].startswith("rrbody")
            and ("DOP853 only" in r["method"]) == old]
    walls = [float(r["wall_s"]) for r in rows]
    if old:
        steps = [int(r["steps"]) for r in rows]
        return f"{min(walls):.2g}-{max(walls):.2g} s ({min(steps) / 1e3:.0f}k-{max(steps) / 1e3:.0f}k steps)"
    worst = max(float(r["err"]) for r in rows)
    return f"{1e3 * min(walls):.2g}-{1e3 * max(walls):.2g} ms for errors of {worst:.2g}"


def _core3(pattern: str) -> Callable[[Path], str]:
    return lambda results: _find(pattern, _target(results, "core", "3").measured, "core target 3")


def _default_max_cpu(results: Path) -> str:
    cpus = [float(_find(r"in (\S+) s CPU", t.measured, "ode default run")) for t in _targets(results, "ode")
            if t.name.startswith("default `flip-time`")]
    return f"{fmt(max(cpus))} s"


def _point_ns(results: Path) -> str:
    row = next(r for r in _rows(results, "core_rhs.csv") if r["body"] == "point mass")
    return f"{float(row['ns_per_eval']):.0f} ns"


def _ellipse_table_gain(results: Path) -> str:
    """How many times cheaper an ellipse's right-hand side is with its table than with the quadrature."""
    ns = {r["body"]: float(r["ns_per_eval"]) for r in _rows(results, "core_rhs.csv")}
    return f"{ns['ellipse R0 0.1 delta 0.5 (icr)'] / ns['ellipse R0 0.1 delta 0.5 (table)']:.0f}x"


def _step_ns(results: Path) -> str:
    rows = _rows(results, "core_step.csv")
    lean = next(float(r["ns_per_step"]) for r in rows if r["what"].startswith("lean"))
    ours = next(float(r["ns_per_step"]) for r in rows if r["what"].startswith("rrbody"))
    return f"{ours:.0f} vs {lean:.0f} ns"


def _summary_minutes(results: Path) -> str:
    """The studies' wall times added up (each ``*_targets.json``): what ``make bench`` costs."""
    total = sum(json.loads((results / f"{s}_targets.json").read_text(encoding="utf-8"))["wall_s"]
                for s in STUDIES if (results / f"{s}_targets.json").exists())
    return f"{total / 60:.0f} minutes"


def _coldstart_compile(results: Path) -> str:
    """The range of the cold-start study's compile column: a first call without install-time kernels."""
    walls = [float(r["compile_s"]) for r in _rows(results, "coldstart.csv")]
    return f"{min(walls):.0f}-{max(walls):.0f} s"


def _study_date(study: str) -> Callable[[Path], str]:
    """When one study last ran (its own section's machine line; ``--only`` re-runs one study)."""
    return lambda results: _find(r"(\d{4}-\d\d-\d\d \d\d:\d\d UTC)",
                                 (results / f"{study}_summary.md").read_text(encoding="utf-8"), f"{study} date")


def _mujoco(own: bool, bodies: tuple[str, ...], digits: int) -> Callable[[Path], str]:
    """The range of spin-down / exact over mujoco.csv's rows of MuJoCo's own friction (``own``) or the
    adapter's, for ``bodies``: "1.35 to 1.83", or one figure when the range is one."""
    def read(results: Path) -> str:
        vals = [float(r["spin-down / exact"]) for r in _rows(results, "mujoco.csv")
                if r["friction"].startswith("MuJoCo") == own and r["body"] in bodies]
        if not vals:
            raise QuoteError(f"mujoco.csv has no rows for {bodies}")
        lo, hi = f"{min(vals):.{digits}f}", f"{max(vals):.{digits}f}"
        return lo if lo == hi else f"{lo} to {hi}"
    return read


#: the steps of a target that are its purpose, not its set-up (``setup.TARGET.set-up`` leaves them out)
_NOT_SET_UP = ("suite", "suite-lowest", "suite-public", "demo")


def _setup(results: Path, target: str, key: str) -> str:
    """One figure of ``make TARGET``'s record in setup.json (``?`` while the target has none)."""
    path = results / "setup.json"
    rec = json.loads(path.read_text(encoding="utf-8")).get("targets", {}).get(target) if path.exists() else None
    if rec is None:
        return "?"
    steps = rec["steps_s"]
    if key == "date":
        return rec["date_utc"][:10]
    if key == "load":  # the 1-minute load averages before and after: how shared the 2 cores were
        lo, hi = sorted((rec["load_avg_before"][0], rec["load_avg_after"][0]))
        return f"{lo:.1f}-{hi:.1f}" if f"{lo:.1f}" != f"{hi:.1f}" else f"{lo:.1f}"
    if key == "passed":
        return str(rec["tests_passed"]["suite"])
    if key.startswith("slowest."):  # the longest listed test of one file: slowest.test_readme
        node = f"tests/{key.partition('.')[2]}.py::"
        times = [v for k, v in rec.get("slowest_tests_s", {}).items() if k.split(" ", 1)[1].startswith(node)]
        if not times:
            raise QuoteError(f"make {target}'s record lists no slow test of {node[:-2]}")
        return f"{max(times):.0f} s"
    if key == "total":
        s = rec["total_s"]
    elif key == "set-up":
        s = sum(v for k, v in steps.items() if k not in _NOT_SET_UP)
    elif key in steps:
        s = steps[key]
    else:
        raise QuoteError(f"make {target}'s record has no step {key!r} (steps: {', '.join(steps)}; or total, "
                         f"set-up, date, passed)")
    return f"{s:.0f} s"


#: name -> figure, each read from one recorded file
NAMED: dict[str, Callable[[Path], str]] = {
    "summary.date": _summary_date,                                   # SUMMARY.md: when make bench ran
    "startup.batch": lambda r: _startup(r, "rrbody flip-time --batch"),   # startup.csv
    "startup.single": lambda r: _startup(r, "rrbody flip-time (one"),     # startup.csv
    "startup.per-line": lambda r: _find(r"per line (\S+ ms)", _target(r, "startup", "1").note, "startup note"),
    "ode.fast-1e-8": _fast_1e8_ms,                                   # ode_rrbody.csv
    "ode.scipy-fast-1e-6": _scipy_fast_1e6,                          # ode_scipy.csv
    "ode.old-worst-now": _old_worst_now,                             # both
    "ode.default-max-cpu": _default_max_cpu,                         # ode_targets.json
    "core.step-ns": _step_ns,                                        # core_step.csv
    "core.point-ns": _point_ns,                                      # core_rhs.csv
    "core.ellipse-table-gain": _ellipse_table_gain,                  # core_rhs.csv
    "core.ellipse-auto": _core3(r"the quadrature\) (\S+x)"),         # core_targets.json
    "core.disk-table": _core3(r"table \(its default\) (\S+x)"),
    "core.disk-icr": _core3(r"icr (\S+x)"),
    "stiff.old": lambda r: _stiff(r, True),                          # core_stiff.csv
    "stiff.auto": lambda r: _stiff(r, False),
    "summary.minutes": _summary_minutes,                             # every *_targets.json
    "coldstart.compile": _coldstart_compile,                         # coldstart.csv
    "coldstart.date": _study_date("coldstart"),                      # coldstart_summary.md
    # mujoco.csv: MuJoCo's own friction on a smooth disk (a prism) and a plate; on its cylinder geom
    # (which hops); the adapter on those and on the cylinder
    "mujoco.own-smooth": _mujoco(True, ("disk (prism)", "plate (box)"), 2),
    "mujoco.own-cylinder": _mujoco(True, ("disk (cylinder)",), 2),
    "mujoco.adapter-smooth": _mujoco(False, ("disk (prism)", "plate (box)"), 4),
    "mujoco.adapter-cylinder": _mujoco(False, ("disk (cylinder)",), 2),
}

_TABLES: dict[str, Callable[[Path], str]] = {
    "table.targets": lambda r: _targets_table(r, notes=True),
    "table.targets-brief": lambda r: _targets_table(r, notes=False),
    "table.plugin": _plugin_table,
    "table.rhs": _rhs_table,
    "table.coldstart": _coldstart_table,
    "table.mujoco": _mujoco_table,
    "table.mujoco-cost": _mujoco_cost_table,
}

_OF_TARGET: dict[str, Callable[[Target], str]] = {
    "target": lambda t: t.measured,
    "head": lambda t: _head(t.measured),
    "paren": lambda t: _find(r"\(([^)]*)\)", t.measured, t.name),
    "verdict": lambda t: t.verdict,
}


def quote(name: str, results: Path = DEFAULT_OUT) -> str:
    """The text the span named ``name`` must hold, from the results in ``results``."""
    if name in NAMED:
        return NAMED[name](results)
    if name in _TABLES:
        return "\n\n" + _TABLES[name](results) + "\n\n"  # blank lines: the table is its own block
    kind, _, rest = name.partition(".")
    if kind == "setup" and rest.partition(".")[0] in ("demo", "test") and rest.partition(".")[2]:
        return _setup(results, *rest.split(".", 1))
    study, _, n = rest.partition(".")
    if kind in _OF_TARGET and study in STUDIES:
        return _OF_TARGET[kind](_target(results, study, n))
    raise QuoteError(f"unknown quote {name!r}: use target|head|paren|verdict.STUDY.N (STUDY one of "
                     f"{', '.join(STUDIES)}), setup.demo|test.KEY, {', '.join(_TABLES)} or one of {', '.join(NAMED)}")


def rewrite(text: str, results: Path = DEFAULT_OUT) -> str:
    """``text`` with every quoted span's body replaced by what the results say."""
    return MARKER.sub(lambda m: f"<!--q:{m['name']}-->{quote(m['name'], results)}<!--/q-->", text)


def stale_spans(path: Path, results: Path = DEFAULT_OUT) -> list[tuple[str, str, str]]:
    """(name, written, recorded) for every span of ``path`` that differs from the results."""
    return [(m["name"], m["body"], want) for m in MARKER.finditer(path.read_text(encoding="utf-8"))
            if m["body"] != (want := quote(m["name"], results))]


def main(argv: Sequence[str] | None = None) -> int:
    """Rewrite (or ``--check``) the quoted figures of :func:`quoted_files`."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks.quotes", description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="change nothing; list stale spans, exit 1 if any")
    ap.add_argument("--results", type=Path, default=DEFAULT_OUT, help="the recorded results (default: %(default)s)")
    args = ap.parse_args(argv)
    stale = 0
    try:
        for path in quoted_files():
            spans = stale_spans(path, args.results)
            stale += len(spans)
            for name, old, new in spans:
                print(f"{path.relative_to(ROOT)}: {name}: {old.strip()!r} -> {new.strip()!r}")
            if spans and not args.check:
                write_text(path, rewrite(path.read_text(encoding="utf-8"), args.results))
    except QuoteError as e:
        print(f"python -m benchmarks.quotes: error: {e}", file=sys.stderr)
        return 2
    if args.check:
        return 1 if stale else 0
    print(f"{stale} quoted figure(s) rewritten from {args.results}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
