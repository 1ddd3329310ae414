"""Start-up: 1,000 quick answers from one `rrbody flip-time --batch` process vs one single call.

Both are fresh processes, timed as wall time and interleaved in one run (batch, single, batch,
single, ...; best of N each, after one warm-up run of each that fills the numba cache):
(1) `rrbody flip-time --batch FILE` on 1,000 lines, rod-mass scenes around phixtpm (H 0.15-0.3,
k 0.03-0.1, omega 0.5-0.7, dry friction, the default accuracy); (2) one single
`rrbody flip-time --H 0.2 --k 0.05 --omega 0.6 --json`. For scale, (3) a Python process that imports
numba and calls one cached one-line @njit function (the floor any numba process pays) and (4)
`python -c "import numpy"`. The batch's answers are checked against single calls with the same
options, field by field (all but `wall_s`, a timing) on an evenly spaced subset of the lines.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "startup"
TITLE = "Start-up: 1,000 lines of `flip-time --batch` vs one single call"

_TRIVIAL = '''
from numba import njit

@njit(cache=True)
def f(x):
    return x + 1.0

f(1.0)
'''
RRBODY = [sys.executable, "-m", "rrbody.cli"]
SINGLE = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"]


def _lines(n: int) -> list[dict[str, float]]:
    rng = np.random.default_rng(13)  # fixed: the same 1,000 scenes in every run
    return [{"H": round(float(h), 4), "k": round(float(k), 4), "omega": round(float(w), 4)}
            for h, k, w in zip(rng.uniform(0.15, 0.3, n), rng.uniform(0.03, 0.1, n), rng.uniform(0.5, 0.7, n))]


def _wall(cmd: list[str], cwd: str | None = None) -> tuple[float, str]:
    t0 = time.perf_counter()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=cwd)
    return time.perf_counter() - t0, p.stdout


def _strip(d: dict[str, object]) -> dict[str, object]:
    return {k: v for k, v in d.items() if k != "wall_s"}


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    repeats = 2 if quick else 5
    n_lines = 1000
    n_check = 5 if quick else 20
    lines = _lines(n_lines)
    with tempfile.TemporaryDirectory(prefix="rrbs") as tmp:
        batch_file = Path(tmp) / "lines.jsonl"
        batch_file.write_text("".join(json.dumps(d) + "\n" for d in lines))
        script = Path(tmp) / "trivial_numba.py"
        script.write_text(_TRIVIAL)
        batch_cmd = [*RRBODY, "flip-time", "--batch", str(batch_file)]
        single_cmd = [*RRBODY, *SINGLE]
        floor_cmd = [sys.executable, str(script)]
        numpy_cmd = [sys.executable, "-c", "import numpy"]
        cmds = {"batch": batch_cmd, "single": single_cmd, "floor": floor_cmd, "numpy": numpy_cmd}
        for c in cmds.values():  # warm-up: fills the numba caches
            _wall(c, cwd=tmp)
        best = {k: float("inf") for k in cmds}
        batch_out = ""
        for _ in range(repeats):  # interleaved: a load change hits every process alike
            for k, c in cmds.items():
                w, so = _wall(c, cwd=tmp)
                best[k] = min(best[k], w)
                if k == "batch":
                    batch_out = so
        answers = [json.loads(s) for s in batch_out.splitlines()]
        idx = np.linspace(0, n_lines - 1, n_check).astype(int)
        mismatches = 0
        for i in idx:
            argv = [x for kv in lines[i].items() for x in (f"--{kv[0]}", repr(kv[1]))]
            _, so = _wall([*RRBODY, "flip-time", *argv, "--json"], cwd=tmp)
            mismatches += _strip(json.loads(so)) != _strip(answers[i])
    ratio = best["batch"] / best["single"]
    rows = [{"process": f"rrbody flip-time --batch ({n_lines} lines)", "best_wall_s": best["batch"]},
            {"process": "rrbody flip-time (one single call, phixtpm, --json)", "best_wall_s": best["single"]},
            {"process": "numba import + one cached one-line @njit call", "best_wall_s": best["floor"]},
            {"process": "python -c 'import numpy'", "best_wall_s": best["numpy"]}]
    files = [str(write_csv(out / "startup.csv", rows))]
    equal = mismatches == 0 and len(answers) == n_lines
    targets = [Target(f"{n_lines} lines of `flip-time --batch` vs one single `flip-time` call",
                      "< 3x, results equal the single calls'",
                      f"{fmt(ratio)}x ({fmt(best['batch'])} s vs {fmt(best['single'])} s); "
                      f"{n_check - mismatches} of {n_check} checked lines equal to single calls",
                      ratio < 3.0 and equal,
                      f"per line {fmt((best['batch'] - best['single']) / n_lines * 1e3)} ms beyond one call's "
                      f"start-up; numba's per-process floor is {fmt(best['floor'])} s")]
    md = [f"## {TITLE}", "", machine_text(), "", __doc__.split("\n\n", 1)[1].strip(), "",
          md_table(["process", "best wall (s)"], [(r["process"], r["best_wall_s"]) for r in rows]), "",
          f"Ratio batch / single: {fmt(ratio)}. Lines checked against single calls: {n_check} "
          f"(mismatches: {mismatches}).", "", "Data: `startup.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    return res
