"""Compile rrbody's kernels once, ahead of use: at install (the build backend runs this module,
``setup.py``) or on demand (``rrbody cache build``). docs/compile.md explains the design.

The compiled code depends only on a scene's *kind* (driven or free) and, for a driven body, its
friction law, never on its other effects (area method, geometry, numbers: all read at run time;
:func:`rrbody.physics.effects.compiled_code`), so a fixed workload compiles everything a user can
reach: the driven loop for each law and the free-body loop, the area methods, the quadrature
tables, the stiff methods, and the plugin's kernels. The workload (:mod:`rrbody.cli.workload`)
runs the user's own entry points (the command line's commands, the plugin's ``step``) with tiny
horizons: first the jobs of a part's first pass, each in a process of its own, two at a time (two
cores); then, for the whole (the part ``all``), all of the workload in one process, which compiles
what those left out and whatever a race between two processes lost (two processes adding overloads
to one index file: the last save wins).

The part ``demo`` (``--part demo``, ``make demo``) compiles only what ``rrbody demo`` needs (Movie
S1) into the user's cache folder, which it leaves incomplete: every other kernel is compiled where
it is first used, or copied in from the install's kernels once they exist (``make test`` compiles
them into ``rrbody/_kernels``; :mod:`rrbody._cache`), or compiled there by ``rrbody cache build``.

Kernels go to numba's cache in a fresh cache folder (``RRBODY_CACHE_DIR``), and the folder
``kernels/<version>-<sources>`` is moved to ``--into`` (the package's ``_kernels`` folder at install)
or stays in the user's cache folder (``rrbody cache build``). :mod:`rrbody._cache` seeds the user's
cache from the package's folder on first use; numba's own checks (its version, the CPU, each
function's bytecode and signature) still decide whether a kernel loads.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["N_LOOPS", "PARTS", "build", "main"]

#: the workload's jobs that each compile a stepping loop: the first N_LOOPS commands of
#: :data:`rrbody.cli.workload.COMMANDS`, in their order
N_LOOPS = 4
_LOOPS = ("the stepping loop under dry friction", "the free bodies' stepping loop",
          "the stepping loop under viscous friction", "the stepping loop without friction")

#: the parts of the workload the prebuild compiles: the jobs of each one's first pass, (what it
#: compiles, the workload's arguments: :mod:`rrbody.cli.workload`), processes of their own, two at a
#: time, in this order. "all": the plugin's kernels and the stand-alone right-hand sides (the longest
#: job: first, so that the other worker compiles the loops beside it), then the jobs that compile a
#: stepping loop; the rest of the workload mostly loads those, in the one process of the second pass
#: (``--all``), which also compiles whatever a race between two processes lost. "demo": what ``rrbody
#: demo`` computes before it draws, one job (no race, no second pass)
PARTS: dict[str, tuple[tuple[str, list[str]], ...]] = {
    "all": (("the plugin's kernels and the right-hand sides", ["--extras"]),
            *((_LOOPS[i], ["--job", str(i)]) for i in range(N_LOOPS))),
    "demo": (("the kernels Movie S1 needs: a driven body under dry friction, its flip time and run", ["--movie-s1"]),),
}


def _run_jobs(jobs: list[list[str]], env: dict[str, str] | None, cwd: str, workers: int, *,
              names: list[str] | None = None, what: str | None = None, first: int = 0, of: int | None = None,
              t0: float | None = None) -> None:
    """Run the jobs, ``workers`` at a time; the first failure is raised with its command and error.
    ``what``: a line on stderr as each job ends, ``rrbody: WHAT [k/of] NAME done (T s)``, k counted
    from ``first``, T the time since ``t0`` (a plain line, terminal or log: the build's only output
    for a minute or two, and a bar redrawn in place would be lost in a log)."""
    import threading
    from concurrent.futures import ThreadPoolExecutor, as_completed

    failed = threading.Event()  # set before the failure is reported: no job starts after it
    names = names if names is not None else [" ".join(cmd[2:]) for cmd in jobs]
    of = len(jobs) if of is None else of
    t0 = time.perf_counter() if t0 is None else t0

    def one(cmd: list[str]) -> None:
        if failed.is_set():
            return
        p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            failed.set()
            tail = p.stderr.strip().splitlines()[-1:] or ["(no message)"]
            raise RuntimeError(f"prebuild: '{' '.join(cmd[2:])}' exited {p.returncode}: {tail[0]}")

    pool = ThreadPoolExecutor(max_workers=workers)
    futures = {pool.submit(one, cmd): name for cmd, name in zip(jobs, names)}
    try:
        for done, fut in enumerate(as_completed(futures), first + 1):
            fut.result()
            if what is not None:
                print(f"rrbody: {what} [{done}/{of}] {futures[fut]} done ({time.perf_counter() - t0:.0f} s)",
                      file=sys.stderr, flush=True)
    except BaseException:
        failed.set()  # a failure (or Ctrl-C) stops the jobs not yet started
        for fut in futures:
            fut.cancel()
        raise
    finally:
        pool.shutdown(wait=True)  # the running ones end (each is short): no process is left behind


def build(into: Path | None = None, *, jobs: int = 2, quiet: bool = False, force: bool = False,
          part: str = "all") -> Path:
    """Compile every kernel (``part="all"``), or only those of a part of the workload
    (:data:`PARTS`: ``"demo"``, what ``rrbody demo`` needs); returns the kernel
    folder. ``into``: move the folder ``<version>-<sources>`` there (replacing the folders of other
    sources); None: fill the user's cache. ``jobs`` processes at a time, then (the whole only) the
    workload once more in one process: that pass compiles what a race between two processes lost, and
    nothing else. A folder ``into`` already holds for these sources is complete (it is moved there only
    at the end, and the workload is part of the sources): kept as it is unless ``force``. Unless
    ``force``, a wheel built from a source tree whose own ``rrbody/_kernels`` holds these sources'
    kernels, compiled by this numba (an editable install, ``make test``), gets a copy of them instead
    of a second compilation. A part goes to the user's cache only (a package carries every kernel),
    and is not marked complete there; it is skipped where the cache folder is complete or the
    install's kernels (which a first use copies in) serve."""
    import numba

    from rrbody._cache import BUILD_FILE, ENV, NO_SEED, built_by_numba, cache_dir, kernels_dir, shipped_kernels_dir

    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError(f"jobs must be an integer >= 1 (processes at a time), got {jobs!r}")
    if part not in PARTS:
        raise ValueError(f"part must be one of {', '.join(PARTS)}, got {part!r}")
    whole = part == "all"
    if not whole and into is not None:
        raise ValueError(f"part {part!r} compiles into the cache folder only (into=None): a package carries "
                         "every kernel")
    t0 = time.perf_counter()
    name = kernels_dir().name  # these sources; the jobs must find the same (no edit during a build)
    if into is not None and (into / name).is_dir() and not force:
        if not quiet:
            print(f"rrbody: the kernels of these sources are already compiled: {into / name}", file=sys.stderr)
        return into / name
    mine = shipped_kernels_dir()  # this source tree's own kernels (the tree this module runs from)
    if not whole and not force and ((kernels_dir() / BUILD_FILE).exists()
                                    or (mine.is_dir() and built_by_numba(mine) == numba.__version__)):
        where = kernels_dir() if (kernels_dir() / BUILD_FILE).exists() else mine
        if not quiet:
            print(f"rrbody: every kernel of these sources is compiled already (a first use copies them in): {where}",
                  file=sys.stderr)
        return where
    if into is not None and not force and mine.is_dir() and built_by_numba(mine) == numba.__version__ \
            and mine.resolve() != (into / name).resolve():
        result = _place(mine, into, copy=True)
        if not quiet:
            print(f"rrbody: copied the kernels this source tree compiled for these sources: {result}", file=sys.stderr)
        return result
    work = Path(tempfile.mkdtemp(prefix="rrbody-kernels-")) if into is not None else cache_dir()
    env = dict(os.environ, **{ENV: str(work)})
    if force:
        env[NO_SEED] = "1"  # compile: the jobs must not copy what an install already holds
    # the jobs import rrbody from where this process did (the source tree during a build)
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["MPLBACKEND"] = "Agg"
    run = [sys.executable, "-m", "rrbody.cli.workload"]
    first = PARTS[part]
    of = len(first) + whole
    what = None if quiet else "compiling"
    try:
        with tempfile.TemporaryDirectory(prefix="rrbody-prebuild-") as cwd:  # any file a job writes
            if not quiet:
                print(f"rrbody: compiling every kernel: {len(first)} jobs, {jobs} at a time, then the whole "
                      "workload once more in one process (a line as each ends)" if whole else
                      f"rrbody: compiling the part {part!r} of the kernels ({len(first)} job{'s' * (len(first) > 1)}; "
                      "the others compile where they are first used, or all at once: rrbody cache build)",
                      file=sys.stderr, flush=True)
            _run_jobs([[*run, *args] for _, args in first], env, cwd, jobs, names=[n for n, _ in first],
                      what=what, of=of, t0=t0)
            if whole:
                _run_jobs([[*run, "--all"]], env, cwd, 1, names=["the whole workload in one process"], what=what,
                          first=len(first), of=of, t0=t0)
        src = work / "kernels" / name
        if not src.is_dir():
            raise RuntimeError(f"prebuild: no kernels were written to {src} (were the sources edited during the "
                               "build?)")
        if whole:
            # which numba compiled them: a first use under another numba does not copy them (rrbody._cache);
            # the file also marks the folder complete (a part leaves it for the install's kernels to fill in)
            import json
            import platform

            for t in (src / "tables").glob("footprint-*.npz"):  # the workload's own shapes' tables: no user's
                t.unlink()
            (src / BUILD_FILE).write_text(json.dumps({"numba": numba.__version__, "python": platform.python_version(),
                                                      "machine": platform.machine()}))
        result = src if into is None else _place(src, into, copy=False)
    finally:
        if into is not None:
            shutil.rmtree(work, ignore_errors=True)
    if not quiet:
        done = "every kernel" if whole else f"the part {part!r}"
        print(f"rrbody: compiled {done} in {time.perf_counter() - t0:.0f} s -> {result}", file=sys.stderr)
    return result


def _place(src: Path, into: Path, *, copy: bool) -> Path:
    """Move (or copy) the kernel folder ``src`` into ``into`` under its own name, replacing the
    folders of other sources there (a package carries the kernels of its own sources only)."""
    into.mkdir(parents=True, exist_ok=True)
    result = into / src.name
    shutil.rmtree(result, ignore_errors=True)
    if copy:
        shutil.copytree(src, result)
    else:
        shutil.move(str(src), str(result))
    for old in into.iterdir():
        if old != result and old.is_dir():
            shutil.rmtree(old, ignore_errors=True)
    return result


def _positive_int(text: str) -> int:
    """``--jobs``: an integer >= 1 (argparse turns the ValueError into its usage error, exit 2)."""
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"--jobs must be an integer >= 1, got {text!r}")
    return n


def main(argv: list[str] | None = None) -> int:
    """``python -m rrbody.cli.prebuild [--into DIR] [--jobs N] [--force] [--part PART]`` (the build
    backend's call; ``make demo`` runs ``--part demo``)."""
    ap = argparse.ArgumentParser(prog="python -m rrbody.cli.prebuild", description=__doc__.split("\n\n")[0])
    ap.add_argument("--into", type=Path, default=None, help="move the kernel folder here (default: the user cache)")
    ap.add_argument("--jobs", type=_positive_int, default=2, help="processes at a time, 1 or more (default 2)")
    ap.add_argument("--force", action="store_true", help="compile again even if --into holds these sources' kernels")
    ap.add_argument("--part", choices=tuple(PARTS), default="all",
                    help="all: every kernel (default); demo: only what `rrbody demo` needs, into the cache folder")
    args = ap.parse_args(argv)
    if args.part != "all" and args.into is not None:
        ap.error(f"--part {args.part} compiles into the cache folder: no --into (a package carries every kernel)")
    build(args.into, jobs=args.jobs, force=args.force, part=args.part)
    return 0


if __name__ == "__main__":
    sys.exit(main())
