"""Where a cold start's compile time goes: numba's compile events of one first call, per function.

``python -m benchmarks.compile_profile`` runs, in a fresh process with an empty cache folder, the
first ``flip_time`` of the rod-mass body under dry friction (the cold-start study's first scenario)
with a listener on numba's ``numba:compile`` events, and writes
``benchmarks/results/compile_profile.csv``: per compiled function, the number of compilations and
the seconds between its compile's start and end. The times are *inclusive* (a function's compile
contains the compiles of the functions it calls for the first time), so they do not add up; they
show which units are large and which are compiled although the run never calls them. Also written:
the process's CPU seconds of the whole first call and with numba's LLVM optimisation off
(``NUMBA_OPT=0``), which says how much of the time is LLVM's.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from .common import write_csv

_CHILD = r"""
import collections, json, time
from numba.core import event
rec = event.RecordingListener()
from rrbody import flip_time, rod_mass_scene
scene = rod_mass_scene(H=0.2, k=0.05, omega=0.6)
c0 = time.process_time()
with event.install_listener("numba:compile", rec):
    flip_time(scene)
cpu = time.process_time() - c0
start, total, count = {}, collections.Counter(), collections.Counter()
for ts, ev in rec.buffer:
    d = ev.data.get("dispatcher") if ev.data else None
    key = d.py_func.__qualname__ if d is not None else str(ev.data)[:60]
    if ev.is_start:
        start[key] = ts
    else:
        total[key] += ts - start.pop(key, ts)
        count[key] += 1
print(json.dumps({"cpu_s": cpu, "functions": [[k, count[k], v] for k, v in total.most_common()]}))
"""


def profile(opt: str | None = None) -> dict:
    """The child's report, in a fresh process with an empty cache folder (``opt``: NUMBA_OPT)."""
    with tempfile.TemporaryDirectory(prefix="rrbp") as tmp:
        env = {**os.environ, "RRBODY_CACHE_DIR": tmp}
        if opt is not None:
            env["NUMBA_OPT"] = opt
        p = subprocess.run([sys.executable, "-c", _CHILD], check=True, capture_output=True, text=True, env=env)
    return json.loads(p.stdout.strip().splitlines()[-1])


def main(argv: Sequence[str] | None = None) -> int:
    from .run import DEFAULT_OUT

    ap = argparse.ArgumentParser(prog="python -m benchmarks.compile_profile", description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output folder (default: benchmarks/results)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    full = profile()
    no_llvm_opt = profile("0")
    rows = [{"function": "(whole first call, CPU s)", "compilations": "", "inclusive_s": full["cpu_s"]},
            {"function": "(whole first call with NUMBA_OPT=0, CPU s)", "compilations": "",
             "inclusive_s": no_llvm_opt["cpu_s"]}]
    rows += [{"function": f, "compilations": n, "inclusive_s": s} for f, n, s in full["functions"]]
    path = write_csv(args.out / "compile_profile.csv", rows)
    for r in rows[:25]:
        print(f"{r['inclusive_s']:8.2f}  {r['compilations']!s:>3}  {r['function']}")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
