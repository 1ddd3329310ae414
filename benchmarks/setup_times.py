"""Set-up timings: ``make demo`` and ``make test`` from a clean clone, step by step -> ``setup.json``.

Usage (from the repository root; each target takes minutes and both cores)::

    python -m benchmarks.setup_times                    # make demo, then make test
    python -m benchmarks.setup_times --target demo      # one of them; setup.json keeps the other's record

Each target runs in a fresh ``git clone`` of this repository's HEAD (committed work only: the record
names the commit), with an empty rrbody cache folder (``RRBODY_CACHE_DIR``) and no ``PYTHONPATH``,
exactly as the README's two set-up commands. uv's own download cache stays the machine's: packages an
earlier install downloaded are not downloaded again (the record says so; a machine that must
download them takes longer). The Makefile announces each long step with a line ``==> STEP: ...``;
every line of make's output is timestamped as it arrives, and a step's time runs from its line to the
next step's line (or to the end). Written to ``setup.json``: per target the date, the commit, the
load average before and after (the machine may be shared), the total wall time, each step's time and
the tests each pytest run passed. ``python -m benchmarks.quotes`` then writes the figures the
docs, the CHANGELOG and the Makefile's own step lines quote (``setup.TARGET.STEP``).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .common import write_text

__all__ = ["TARGETS", "STEP", "parse_steps", "record", "main"]

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = Path(__file__).resolve().parent / "results"
TARGETS = ("demo", "test")
#: the Makefile's announcement of a step: ``==> kernels: compiling rrbody's kernels ...``
STEP = re.compile(r"^==> (?P<step>[a-z][a-z-]*): ")
#: pytest's last line, e.g. ``= 1012 passed, 3 skipped in 201.5s =`` or ``40 passed in 30.1s``
PASSED = re.compile(r"(\d+) passed")
#: a line of pytest's --durations table: ``35.12s call     tests/test_readme.py::test_x``
DURATION = re.compile(r"^\s*(?P<s>\d+(?:\.\d+)?)s (?P<when>call|setup|teardown)\s+(?P<node>tests/\S+)")
#: what a record says about where the packages came from
UV_CACHE = ("uv's download cache as the machine had it (packages earlier installs downloaded are not "
            "downloaded again)")


def parse_steps(lines: Sequence[tuple[float, str]], end: float
                ) -> tuple[dict[str, float], dict[str, int], dict[str, float]]:
    """(seconds per step, tests passed per step, the slowest tests pytest listed) from make's
    timestamped output lines ``(t, text)``, ``t`` in s from make's start; ``end``: when make ended. A
    step runs from its ``==>`` line to the next one (or ``end``); what came before the first (make's
    own start) is ``start``. A step name announced twice (never, in the Makefile) adds up. The slowest
    tests: the main suite's ``--durations`` table, ``"WHEN NODE"`` -> s."""
    steps: dict[str, float] = {}
    passed: dict[str, int] = {}
    slowest: dict[str, float] = {}
    name, since = "start", 0.0
    for t, text in lines:
        m = STEP.match(text)
        if m:
            steps[name] = steps.get(name, 0.0) + (t - since)
            name, since = m["step"], t
            continue
        d = DURATION.match(text)
        if d and name == "suite":
            slowest[f"{d['when']} {d['node']}"] = float(d["s"])
        p = PASSED.search(text)
        if p and ("=" in text or " in " in text) and name.startswith("suite"):
            passed[name] = int(p.group(1))
    steps[name] = steps.get(name, 0.0) + (end - since)
    if steps.get("start", 0.0) < 0.05:
        steps.pop("start", None)  # nothing ran before the first announced step
    return steps, passed, slowest


def _commit() -> tuple[str, bool]:
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True)
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT, capture_output=True,
                           text=True, check=True)
    return head.stdout.strip(), bool(dirty.stdout.strip())


def _load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def record(target: str) -> dict[str, Any]:
    """Run ``make TARGET`` in a fresh clone of HEAD and return its record (raises if make fails)."""
    commit, dirty = _commit()
    tmp = Path(tempfile.mkdtemp(prefix="rrbody-setup-"))
    try:
        clone = tmp / "rrbody"
        subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "RRBODY_CACHE_DIR")}
        env["RRBODY_CACHE_DIR"] = str(tmp / "cache")  # empty: as on a machine that never ran rrbody
        date = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
        before = _load()
        t0 = time.perf_counter()
        lines: list[tuple[float, str]] = []
        proc = subprocess.Popen(["make", target], cwd=clone, env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, bufsize=1)
        assert proc.stdout is not None
        for text in proc.stdout:
            t = time.perf_counter() - t0
            lines.append((t, text.rstrip("\n")))
            print(f"[{t:7.1f} s] {text}", end="", flush=True)  # the run, as it goes
        code = proc.wait()
        end = time.perf_counter() - t0
        if code != 0:
            raise RuntimeError(f"make {target} exited {code} in the clone (see its output above); nothing recorded")
        steps, passed, slowest = parse_steps(lines, end)
        return {"command": f"make {target}", "date_utc": date, "commit": commit, "uncommitted_changes": dirty,
                "load_avg_before": before, "load_avg_after": _load(), "total_s": round(end, 1),
                "steps_s": {k: round(v, 1) for k, v in steps.items()}, "tests_passed": passed,
                "slowest_tests_s": slowest,
                "packages": UV_CACHE, "cache": "an empty RRBODY_CACHE_DIR"}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main(argv: Sequence[str] | None = None) -> int:
    """Record the set-up targets' timings into ``OUT/setup.json`` (the other targets' records kept)."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks.setup_times", description=__doc__.split("\n\n")[0])
    ap.add_argument("--target", action="append", choices=TARGETS, help="make target to time (repeatable; default both)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="results folder (default: %(default)s)")
    args = ap.parse_args(argv)
    path = args.out / "setup.json"
    data = json.loads(path.read_text(encoding="utf-8")) if path.exists() else {}
    data["about"] = __doc__.split("\n\n", 1)[0]
    data["recorded_by"] = "python -m benchmarks.setup_times"
    for target in args.target or TARGETS:
        print(f"== make {target} in a clean clone", flush=True)
        data.setdefault("targets", {})[target] = record(target)
        write_text(path, json.dumps(data, indent=1) + "\n")  # each target as soon as it is done
        rec = data["targets"][target]
        print(f"== make {target}: {rec['total_s']:.0f} s; " + ", ".join(f"{k} {v:.0f} s" for k,
                                                                        v in rec["steps_s"].items()),
              flush=True)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
