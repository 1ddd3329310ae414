"""``rrbody cache info|clear|build``: the one folder where rrbody keeps compiled kernels, quadrature
tables and output locks (``rrbody._cache``; ``RRBODY_CACHE_DIR`` moves it); ``build`` compiles every
kernel into it now (:mod:`rrbody.cli.prebuild`), as the install does."""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path
from typing import Any

from rrbody._cache import ENV, cache_dir, kernels_dir, shipped_kernels_dir

__all__ = ["add_parser", "cmd_cache", "cache_report"]


def _size(path: Path) -> int:
    """Bytes of the regular files under ``path`` (0 if absent)."""
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file() and not f.is_symlink()) if path.is_dir() else 0


def cache_report() -> dict[str, Any]:
    """The cache folder, its size in bytes per part, and the kernel folders of other sources (stale)."""
    root = cache_dir()
    current = kernels_dir()
    kernels = sorted(p for p in (root / "kernels").glob("*") if p.is_dir())
    return {"path": str(root), "env": ENV, "exists": root.is_dir(), "bytes": _size(root),
            "kernels": {"current": str(current), "current_bytes": _size(current),
                        "stale": [str(p) for p in kernels if p != current],
                        "stale_bytes": sum(_size(p) for p in kernels if p != current)},
            "tables_bytes": _size(root / "tables"),
            # the plugin's wrench tables live beside the kernels they belong to (rrbody.contact.footprints.stored)
            "wrench_tables": {"count": len(list((current / "tables").glob("*.npz"))),
                              "bytes": _size(current / "tables")},
            "installed_kernels": {"path": str(shipped_kernels_dir()), "bytes": _size(shipped_kernels_dir())}}


def _mb(n: int) -> str:
    return f"{n / 1e6:.1f} MB"


def cmd_cache(args: argparse.Namespace) -> int:
    """Handler of ``rrbody cache``."""
    if args.action == "build":
        from rrbody.cli.prebuild import build

        if not args.json:
            print("rrbody: compiling every kernel into the cache folder ...", flush=True)
        where = build(None, quiet=args.json)
        if args.json:
            print(json.dumps({"path": str(where), "bytes": _size(where)}))
        return 0
    rep = cache_report()
    if args.action == "clear":
        root = Path(rep["path"])
        if root.is_dir():
            # the locks folder stays: a running rrbody may hold a lock in it, and its files are empty;
            # only what is no lock file goes (a folder or a link in one's place: damage no process holds)
            for part in root.iterdir():
                if part.name == "locks" and part.is_dir() and not part.is_symlink():
                    for f in part.iterdir():
                        if f.is_dir() and not f.is_symlink():
                            shutil.rmtree(f, ignore_errors=True)
                        elif f.is_symlink():
                            f.unlink(missing_ok=True)
                    continue
                if part.is_dir() and not part.is_symlink():
                    shutil.rmtree(part, ignore_errors=True)
                else:
                    part.unlink(missing_ok=True)
        freed = rep["bytes"]
        if args.json:
            print(json.dumps({"path": rep["path"], "freed_bytes": freed}))
        else:
            print(f"cleared {rep['path']} ({_mb(freed)} freed); the next command loads or compiles rrbody's kernels again")
        return 0
    if args.json:
        print(json.dumps(rep))
        return 0
    k = rep["kernels"]
    print(f"rrbody cache: {rep['path']} ({_mb(rep['bytes'])}; set {ENV} to move it)\n"
          f"  kernels for this version: {k['current']} ({_mb(k['current_bytes'])})\n"
          f"  kernels of other versions or sources: {len(k['stale'])} folder(s), {_mb(k['stale_bytes'])} "
          "(never loaded; `rrbody cache clear` removes them)\n"
          f"  quadrature tables: {_mb(rep['tables_bytes'])}\n"
          f"  the plugin's wrench tables (in the kernels' folder): {rep['wrench_tables']['count']}, "
          f"{_mb(rep['wrench_tables']['bytes'])}\n"
          f"  kernels compiled at install: {rep['installed_kernels']['path']} "
          f"({_mb(rep['installed_kernels']['bytes']) if rep['installed_kernels']['bytes'] else 'none for these sources'}; "
          "copied into the cache folder on first use)")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``rrbody cache`` on the CLI's subparsers."""
    c = sub.add_parser("cache", help="show, clear or fill rrbody's cache folder (compiled kernels, tables)",
                       description="rrbody keeps its compiled kernels (numba), quadrature tables and output locks "
                                   f"in one user cache folder (~/.cache/rrbody on Linux; the environment variable "
                                   f"{ENV} moves it). Kernels compiled from other sources are never loaded. "
                                   "'info' shows the folder and its size; 'clear' empties it (the next command "
                                   "loads the kernels compiled at install again, or compiles them); 'build' "
                                   "compiles every kernel into it now, as the install does (useful after "
                                   "editing a checkout).")
    c.add_argument("action", choices=("info", "clear", "build"),
                   help="info: where and how big; clear: remove its contents; build: compile every kernel now")
    c.add_argument("--json", action="store_true", help="print one JSON object")
    c.set_defaults(func=cmd_cache)
