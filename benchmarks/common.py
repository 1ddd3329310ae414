"""Shared helpers for the benchmark studies: machine description, timing, output files, summaries.

Every study module exposes ``run(out: Path, *, quick: bool) -> StudyResult``. The runner
(:mod:`benchmarks.run`) writes each study's summary to ``<out>/<name>_summary.md`` and assembles
``SUMMARY.md`` from whichever study summaries exist, so ``--only NAME`` refreshes one section.
All files are written through :func:`rrbody.io.atomic_path` (a crash never leaves a half file).
"""

from __future__ import annotations

import csv
import datetime as _dt
import importlib
import math
import os
import platform
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from rrbody.model.io import atomic_path, atomic_write_text

__all__ = ["Target", "StudyResult", "machine_info", "machine_text", "best_time", "best_wall_cpu", "write_csv",
           "write_text",
           "md_table", "fmt", "module_available", "save_figure", "loglog_slope"]

T = TypeVar("T")


@dataclass
class Target:
    """One speed/accuracy target and its measured outcome.

    ``met`` is True/False, or None when the measurement could not be made (the note says why) or
    when there is no bound to judge (a ``target`` in parentheses, "(no bound)": then "reported").
    """

    name: str
    target: str
    measured: str
    met: bool | None
    note: str = ""

    @property
    def verdict(self) -> str:
        if self.met is None and self.target.startswith("("):
            return "reported"
        return {True: "met", False: "not met", None: "not measured"}[self.met]


@dataclass
class StudyResult:
    """What a study hands back to the runner: its targets, a Markdown section and the files it wrote."""

    name: str
    title: str
    targets: list[Target] = field(default_factory=list)
    markdown: str = ""
    files: list[str] = field(default_factory=list)
    skipped: str | None = None
    wall_s: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)


def module_available(name: str) -> tuple[bool, str]:
    """Whether ``name`` imports; on failure the reason (printed by studies that skip)."""
    try:
        importlib.import_module(name)
    except Exception as e:  # noqa: BLE001 - any import failure means "not available yet"
        return False, f"{type(e).__name__}: {e}"
    return True, ""


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _version(mod: str) -> str:
    try:
        m = importlib.import_module(mod)
    except Exception:  # noqa: BLE001
        return "not installed"
    return str(getattr(m, "__version__", None) or getattr(m, "version", None) or getattr(m, "VERSION", "?"))


def machine_info() -> dict[str, Any]:
    """Machine, load and package versions at the time of the call (for every study's header)."""
    try:
        load = os.getloadavg()
    except OSError:
        load = (math.nan, math.nan, math.nan)
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count() or 1
    return {
        "date_utc": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "nproc": usable,
        "cpu": _cpu_model(),
        "load_avg_1_5_15": tuple(round(x, 2) for x in load),
        "python": platform.python_version(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "numba": _version("numba"),
        "pymunk": _version("pymunk"),
        "rrbody": _version("rrbody"),
    }


def machine_text(info: dict[str, Any] | None = None) -> str:
    """One Markdown line describing the machine (quoted at the top of each study)."""
    i = machine_info() if info is None else info
    return (f"Machine: {i['nproc']} cores ({i['cpu']}), load average {i['load_avg_1_5_15']} at start "
            f"(shared machine: expect timing noise); Python {i['python']}, numpy {i['numpy']}, scipy {i['scipy']}, "
            f"numba {i['numba']}, pymunk {i['pymunk']}, rrbody {i['rrbody']}; {i['date_utc']}.")


def best_time(fn: Callable[[], T], *, min_total: float = 0.05, max_repeats: int = 5,
              max_total: float = 5.0) -> tuple[float, T]:
    """Best-of-n wall time (s) of ``fn()`` and its last result.

    Repeats until ``min_total`` seconds were spent or ``max_repeats`` calls were made (at least
    one; never beyond ``max_total`` seconds). The minimum is the least noisy estimate on a shared
    machine: noise only ever adds time.
    """
    best = math.inf
    spent = 0.0
    result: T
    n = 0
    while True:
        t0 = time.perf_counter()
        result = fn()
        dt = time.perf_counter() - t0
        best = min(best, dt)
        spent += dt
        n += 1
        if n >= max_repeats or spent >= max_total or (spent >= min_total and n >= 1):
            break
    return best, result


def best_wall_cpu(fn: Callable[[], T], *, repeats: int = 3) -> tuple[float, float, T]:
    """Best wall time and best CPU time (s, this process) over ``repeats`` calls, and the last result.

    On a shared machine the CPU time is the cost of the code itself; the wall time adds waiting
    for a core. Both are reported where a target is stated in seconds.
    """
    wall = cpu = math.inf
    result: T
    for _ in range(max(1, repeats)):
        c0 = time.process_time()
        t0 = time.perf_counter()
        result = fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu, result


def write_csv(path: Path, rows: Sequence[dict[str, Any]], header: Sequence[str] | None = None) -> Path:
    """Write ``rows`` (dicts) as CSV atomically; the columns are ``header`` or the first row's keys."""
    cols = list(header) if header is not None else (list(rows[0].keys()) if rows else [])
    with atomic_path(path, force=True, name="csv") as tmp, open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: _csv_value(r.get(k)) for k in cols})
    return path


def _csv_value(v: Any) -> Any:
    if isinstance(v, float):
        return repr(v)
    return "" if v is None else v


def write_text(path: Path, text: str) -> Path:
    return atomic_write_text(path, text, force=True, name="text")


def save_figure(fig: Any, path: Path) -> Path:
    """Save a matplotlib figure atomically as PNG."""
    with atomic_path(path, force=True, name="figure") as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path


def fmt(x: Any, digits: int = 3) -> str:
    """Compact number formatting for tables (None/nan -> '-')."""
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if math.isnan(x):
            return "-"
        if math.isinf(x):
            return "inf"
        if x == 0.0:
            return "0"
        if 1e-3 <= abs(x) < 1e5:
            return f"{x:.{digits}g}"
        return f"{x:.{max(digits - 1, 1)}e}"
    return str(x)


def md_table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A Markdown table (cells formatted with :func:`fmt`)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for r in rows:
        lines.append("| " + " | ".join(c if isinstance(c, str) else fmt(c) for c in r) + " |")
    return "\n".join(lines)


def loglog_slope(x: Sequence[float], y: Sequence[float]) -> float:
    """Least-squares slope of log y against log x (the observed power-law exponent)."""
    import numpy as np

    lx = np.log(np.asarray(x, dtype=float))
    ly = np.log(np.asarray(y, dtype=float))
    ok = np.isfinite(lx) & np.isfinite(ly)
    if ok.sum() < 2:
        return math.nan
    return float(np.polyfit(lx[ok], ly[ok], 1)[0])
