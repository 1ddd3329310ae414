"""Start-up: what one `rrbody flip-time` process costs, and how much of it is numba's own start-up.

Measured as wall time of fresh processes (best of 5, after one warm-up run that fills the numba
cache): (1) `rrbody flip-time --H 0.2 --k 0.05 --omega 0.6 --json`; (2) a Python process that only
imports numba and calls a one-line cached @njit function (the floor any numba-based command pays);
(3) `python -c "import numpy"` (the interpreter and numpy alone). The solve itself is in the ODE study.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "startup"
TITLE = "Start-up: one CLI call vs numba's per-process floor"

_TRIVIAL = '''
from numba import njit

@njit(cache=True)
def f(x):
    return x + 1.0

f(1.0)
'''


def _best_wall(cmd: list[str], repeats: int, cwd: str | None = None) -> float:
    subprocess.run(cmd, check=True, capture_output=True, cwd=cwd)  # warm-up: fills the numba cache
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True, cwd=cwd)
        best = min(best, time.perf_counter() - t0)
    return best


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    repeats = 2 if quick else 5
    rrbody_cmd = [sys.executable, "-m", "rrbody.cli", "flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6",
                  "--json"]
    with tempfile.TemporaryDirectory(prefix="rrbody-startup-") as tmp:
        script = Path(tmp) / "trivial_numba.py"
        script.write_text(_TRIVIAL)
        cli = _best_wall(rrbody_cmd, repeats)
        floor = _best_wall([sys.executable, str(script)], repeats, cwd=tmp)
    numpy_only = _best_wall([sys.executable, "-c", "import numpy"], repeats)
    rows = [{"process": "rrbody flip-time (phixtpm, --json)", "best_wall_s": cli},
            {"process": "numba import + one cached one-line @njit call", "best_wall_s": floor},
            {"process": "python -c 'import numpy'", "best_wall_s": numpy_only}]
    files = [str(write_csv(out / "startup.csv", rows))]
    targets = [Target("`rrbody flip-time` process, after the first (compiling) run", "well under 1 s (issue 2)",
                      f"{fmt(cli)} s; numba's per-process floor {fmt(floor)} s", cli < 0.8,
                      "the solve takes ~1 ms; the rest is interpreter, numpy/numba import and numba's target set-up")]
    md = [f"## {TITLE}", "", machine_text(), "", __doc__.split("\n\n", 1)[1].strip(), "",
          md_table(["process", "best wall (s)"], [(r["process"], r["best_wall_s"]) for r in rows]), "",
          "Data: `startup.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    return res
