"""Cold start: a new user's first answer, with an empty cache folder, beside the same call warm.

Every run is a fresh process (``python -m rrbody.cli ...`` or a short Python program), timed as
wall time. A *cold* run gets a new, empty ``RRBODY_CACHE_DIR``: it finds the kernels compiled when
the package was installed (``rrbody/_kernels``, docs/compile.md) and copies them into that folder;
the *warm* run that follows repeats the same command on the filled folder. The scenarios are
interleaved (cold, warm, next scenario, ...) and the whole round repeated; best of the repeats each.
Beside them, once per scenario (each costs tens of seconds), the *compile* column: the same command cold
from a copy of the package's sources without its install-time kernels (an install with
``RRBODY_BUILD_KERNELS=0``, or a checkout just edited), where numba compiles every kernel the
command uses. Scenarios (the cold-start targets, "the first answer in seconds"):

1. ``rrbody flip-time`` of the rod-mass body under dry friction (phixtpm's H 0.2, k 0.05, omega 0.6);
2. the first ``PlaneFriction.step`` of a program with one box (timed inside the program, around
   that call, and as the whole process);
3. ``rrbody simulate`` of an ellipse (docs/cli.md's: R0 0.3, delta 0.9, l 0.2, k 0.0033, 10 s);
4. a stiff flip time (k = 1e4 s^-2, where the automatic mode switches to Radau IIA);
5. one effect added to a scene run before: the cache filled by scenario 1 (dry friction), then the
   same body under viscous friction, a combination not compiled yet.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from .common import StudyResult, Target, fmt, machine_text, md_table, write_csv

NAME = "coldstart"
TITLE = "Cold start: the first answer with an empty cache, beside the same call warm"

RRBODY = [sys.executable, "-m", "rrbody.cli"]
FLIP = ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"]
#: a user's first plugin program: one box, one step, the step's wall time printed
PLUGIN_PROGRAM = """
import time, pymunk
from rrbody.plugin import PlaneFriction
space = pymunk.Space()
pf = PlaneFriction(space, g=9.81)
box = pymunk.Body()
shape = pymunk.Poly.create_box(box, (0.2, 0.1))
shape.density = 800.0
space.add(box, shape)
box.velocity, box.angular_velocity = (1.5, -0.4), -12.0
pf.add(box, mu=0.5)
t0 = time.perf_counter()
pf.step(1 / 240)
print(time.perf_counter() - t0)
"""
#: scenario -> (the command, the target's bound on its cold time in s)
SCENARIOS: dict[str, tuple[list[str], float]] = {
    "flip-time, rod-mass, dry": ([*RRBODY, *FLIP], 3.0),
    "first PlaneFriction.step": ([sys.executable, "-c", PLUGIN_PROGRAM], 1.5),
    "simulate, ellipse, 10 s": ([*RRBODY, "simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.9", "--l",
                                 "0.2", "--k", "0.0033", "--omega", "0.6", "--t-max", "10", "--json"], 5.0),
    "flip-time, stiff (k = 1e4)": ([*RRBODY, "flip-time", "--H", "0.2", "--k", "1e4", "--omega", "0.6", "--json"],
                                   4.0),
}
ADDED = [*RRBODY, *FLIP, "--friction", "viscous"]
ADDED_BOUND = 2.0


def _run(cmd: list[str], cache: Path, cwd: str, sources: Path | None = None) -> tuple[float, str]:
    """(wall s, stdout) of ``cmd`` in a fresh process whose cache folder is ``cache``; ``sources``: a
    folder holding a copy of the package to import instead of the installed one."""
    env = {**os.environ, "RRBODY_CACHE_DIR": str(cache), "MPLBACKEND": "Agg"}
    if sources is not None:
        env["PYTHONPATH"] = str(sources)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=cwd, env=env)
    return time.perf_counter() - t0, p.stdout


def run(out: Path, *, quick: bool = False) -> StudyResult:
    t0 = time.perf_counter()
    repeats = 1 if quick else 3
    names = [*SCENARIOS, "one effect added (dry -> viscous)"]
    best: dict[str, dict[str, float]] = {n: {"cold": float("inf"), "warm": float("inf")} for n in names}
    inner: dict[str, float] = {"cold": float("inf"), "warm": float("inf")}  # the plugin's first step itself
    compile_s: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="rrbc") as tmp:
        import rrbody

        sources = Path(tmp) / "sources"  # the package's .py files alone: no install-time kernels
        shutil.copytree(Path(rrbody.__file__).parent, sources / "rrbody",
                        ignore=shutil.ignore_patterns("_kernels", "__pycache__"))
        for i, (name, (cmd, _)) in enumerate(SCENARIOS.items()):
            compile_s[name], _ = _run(cmd, Path(tmp) / f"jit-{i}", tmp, sources)
        compile_s[names[-1]], _ = _run(ADDED, Path(tmp) / "jit-0", tmp, sources)
        for rep in range(repeats):
            for i, (name, (cmd, _)) in enumerate(SCENARIOS.items()):
                cache = Path(tmp) / f"cache-{rep}-{i}"  # new and empty: the cold run compiles everything
                for kind in ("cold", "warm"):
                    wall, so = _run(cmd, cache, tmp)
                    best[name][kind] = min(best[name][kind], wall)
                    if name.startswith("first PlaneFriction"):
                        inner[kind] = min(inner[kind], float(so.strip().splitlines()[-1]))
            # one effect added: the first scenario's cache (rod-mass, dry) already holds its kernels
            cache = Path(tmp) / f"cache-{rep}-0"
            added = names[-1]
            for kind in ("cold", "warm"):
                wall, so = _run(ADDED, cache, tmp)
                json.loads(so)  # an answer, not an error
                best[added][kind] = min(best[added][kind], wall)
    rows: list[dict[str, Any]] = []
    targets = []
    bounds = {**{n: b for n, (_, b) in SCENARIOS.items()}, names[-1]: ADDED_BOUND}
    for n in names:
        cold, warm = best[n]["cold"], best[n]["warm"]
        judged = inner["cold"] if n.startswith("first PlaneFriction") else cold
        rows.append({"scenario": n, "cold_s": cold, "warm_s": warm, "cold_over_warm": cold / warm,
                     "target_s": bounds[n], "judged_s": judged, "compile_s": compile_s[n]})
        what = "the first step itself" if n.startswith("first PlaneFriction") else "the whole process"
        cache = "the cache of the dry run" if n == names[-1] else "empty cache"
        targets.append(Target(f"cold {n} ({cache})", f"<= {fmt(bounds[n])} s",
                              f"{fmt(judged)} s ({what}; process cold {fmt(cold)} s, warm {fmt(warm)} s)",
                              judged <= bounds[n], "best of the repeats, interleaved with warm runs"))
    files = [str(write_csv(out / "coldstart.csv", rows))]
    md = [f"## {TITLE}", "", machine_text(), "", __doc__.split("\n\n", 1)[1].strip(), "",
          md_table(["scenario", "cold (s)", "warm (s)", "cold / warm", "judged (s)", "target (s)",
                    "compile, no install-time kernels (s)"],
                   [(r["scenario"], r["cold_s"], r["warm_s"], r["cold_over_warm"], r["judged_s"], r["target_s"],
                     r["compile_s"]) for r in rows]), "",
          f"The plugin's first step itself: {fmt(inner['cold'])} s cold, {fmt(inner['warm'])} s warm. "
          f"Best of {repeats}. Data: `coldstart.csv`."]
    res = StudyResult(NAME, TITLE, targets, "\n".join(md), files)
    res.wall_s = time.perf_counter() - t0
    return res
