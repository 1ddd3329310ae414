"""Start-up: what one `rrbody flip-time` call costs, with and without the warm worker.

Measured as wall time of fresh processes (best of 5, after one warm-up run that fills the numba
cache): (1) `rrbody flip-time --H 0.2 --k 0.05 --omega 0.6 --json` answered by the warm worker
(`rrbody.worker`, started once before timing); (2) the same call in its own process
(`RRBODY_WORKER=off`), and once with an empty numba cache (the first, compiling call); (3) a
Python process that only imports numba and calls a one-line cached @njit function (the floor any
numba-based process pays); (4) `python -c "import numpy"` (the interpreter and numpy alone). The
solve itself is in the ODE study.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "startup"
TITLE = "Start-up: one CLI call, with the warm worker and in its own process"

_TRIVIAL = '''
from numba import njit

@njit(cache=True)
def f(x):
    return x + 1.0

f(1.0)
'''


def _best_wall(cmd: list[str], repeats: int, cwd: str | None = None, env: dict[str, str] | None = None) -> float:
    env = dict(os.environ, RRBODY_WORKER="off") if env is None else env
    subprocess.run(cmd, check=True, capture_output=True, cwd=cwd, env=env)  # warm-up: fills the numba cache
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True, cwd=cwd, env=env)
        best = min(best, time.perf_counter() - t0)
    return best


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    repeats = 2 if quick else 5
    rrbody_cmd = [sys.executable, "-m", "rrbody.cli", "flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6",
                  "--json"]
    with tempfile.TemporaryDirectory(prefix="rrbs") as tmp:
        script = Path(tmp) / "trivial_numba.py"
        script.write_text(_TRIVIAL)
        # the very first call compiles every kernel it needs: an empty numba cache of its own
        first_env = dict(os.environ, RRBODY_WORKER="off", NUMBA_CACHE_DIR=str(Path(tmp) / "numba"))
        t1 = time.perf_counter()
        subprocess.run(rrbody_cmd, check=True, capture_output=True, env=first_env)
        first = time.perf_counter() - t1
        cold = _best_wall(rrbody_cmd, repeats)
        warm_env = dict(os.environ, RRBODY_WORKER="on", RRBODY_WORKER_DIR=str(Path(tmp) / "w"))
        subprocess.run([*rrbody_cmd[:3], "worker", "start"], check=True, capture_output=True, env=warm_env)
        try:
            warm = _best_wall(rrbody_cmd, repeats, env=warm_env)
            status = subprocess.run([*rrbody_cmd[:3], "worker", "status", "--json"], check=True,
                                    capture_output=True, text=True, env=warm_env)
            served = json.loads(status.stdout)["served"]
        finally:
            subprocess.run([*rrbody_cmd[:3], "worker", "stop"], capture_output=True, env=warm_env)
        floor = _best_wall([sys.executable, str(script)], repeats, cwd=tmp)
    numpy_only = _best_wall([sys.executable, "-c", "import numpy"], repeats)
    rows = [{"process": f"rrbody flip-time (phixtpm, --json), warm worker ({served} calls served)",
             "best_wall_s": warm},
            {"process": "rrbody flip-time (phixtpm, --json), own process (RRBODY_WORKER=off)", "best_wall_s": cold},
            {"process": "the same, very first call: empty numba cache, compiles (one run)", "best_wall_s": first},
            {"process": "numba import + one cached one-line @njit call", "best_wall_s": floor},
            {"process": "python -c 'import numpy'", "best_wall_s": numpy_only}]
    files = [str(write_csv(out / "startup.csv", rows))]
    targets = [Target("`rrbody flip-time` call, after the first (compiling) run", "well under 1 s (issue 2)",
                      f"{fmt(warm)} s with the warm worker; {fmt(cold)} s in its own process "
                      f"(numba's per-process floor {fmt(floor)} s)", warm < 0.5,
                      "the solve takes ~1 ms; a process of its own pays interpreter, numba import and target "
                      "set-up, which the worker pays once")]
    md = [f"## {TITLE}", "", machine_text(), "", __doc__.split("\n\n", 1)[1].strip(), "",
          md_table(["process", "best wall (s)"], [(r["process"], r["best_wall_s"]) for r in rows]), "",
          "Data: `startup.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    return res
