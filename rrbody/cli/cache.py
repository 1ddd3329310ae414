"""``rrbody cache info|clear|build``: the one folder where rrbody keeps compiled kernels and quadrature
tables (``rrbody._cache``; ``RRBODY_CACHE_DIR`` moves it); ``clear`` removes what rrbody wrote there
and nothing else, ``build`` compiles every kernel into it now (:mod:`rrbody.cli.prebuild`), as the
install does."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import sys
from pathlib import Path
from typing import Any

from rrbody._cache import ENV, cache_dir, entries, kernels_dir, shipped_kernels_dir

__all__ = ["add_parser", "cmd_cache", "cache_report", "clear"]


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
            # the plugin's wrench tables live beside the kernels they belong to (rrbody.engine.plugin.footprints.stored)
            "wrench_tables": {"count": len(list((current / "tables").glob("*.npz"))),
                              "bytes": _size(current / "tables")},
            "installed_kernels": {"path": str(shipped_kernels_dir()), "bytes": _size(shipped_kernels_dir())}}


def _mb(n: int) -> str:
    return f"{n / 1e6:.1f} MB"


def _bytes(path: Path) -> int:
    """Bytes of the entry ``path``: a folder's regular files, a file's (or a link's own) size; 0 if gone."""
    try:
        return _size(path) if path.is_dir() and not path.is_symlink() else path.lstat().st_size
    except FileNotFoundError:
        return 0


def _held(lock: Path) -> bool:
    """Whether a process holds the lock file ``lock`` (an rrbody of an earlier version writing its
    output: its lock file must stay, or a second writer would not meet it)."""
    import fcntl

    try:
        fd = os.open(lock, os.O_RDONLY | os.O_CLOEXEC | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:
        return True
    finally:
        os.close(fd)
    return False


def _remove(path: Path, failed: list[tuple[Path, str]]) -> None:
    """Remove ``path`` (a folder whole, a file or a link, never what a link points to); what cannot be
    removed is added to ``failed`` as (path, the system's reason)."""
    def note(_func: Any, where: str, exc: Any) -> None:
        e = exc if isinstance(exc, BaseException) else exc[1]
        failed.append((Path(where), getattr(e, "strerror", None) or str(e)))

    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, **({"onexc": note} if sys.version_info >= (3, 12) else {"onerror": note}))
    else:
        try:
            path.unlink()
        except FileNotFoundError:
            pass
        except OSError as e:
            failed.append((path, e.strerror or str(e)))


def clear(root: Path | None = None) -> dict[str, Any]:
    """Remove what rrbody wrote in the cache folder ``root`` (default: the cache folder), and nothing
    else (:func:`rrbody._cache.entries`): its kernel folders, its tables, the lock files of earlier
    versions that no process holds; then its own folders if that leaves them empty. Returns the folder,
    what was removed (paths relative to it), what was kept (not rrbody's, or a lock in use), what could
    not be removed (path and reason) and the bytes freed."""
    root = cache_dir() if root is None else root
    ours, foreign = entries(root)
    removed: list[str] = []
    kept = [str(p.relative_to(root)) for p in foreign]
    failed: list[tuple[Path, str]] = []
    freed = 0
    for p in ours:
        if p.parent.name == "locks" and _held(p):
            kept.append(str(p.relative_to(root)) + " (a lock in use)")
            continue
        size = _bytes(p)
        n_failed = len(failed)
        _remove(p, failed)
        freed += size - _bytes(p)
        if not os.path.lexists(p):
            removed.append(str(p.relative_to(root)))
        elif len(failed) == n_failed:  # a survivor no removal reported (a file written into it meanwhile)
            failed.append((p, "still there"))
    for name in {p.relative_to(root).parts[0] for p in ours}:
        with contextlib.suppress(OSError):  # its own folders, if now empty (not: foreign files are in it)
            (root / name).rmdir()
    return {"path": str(root), "removed": removed, "kept": kept, "freed_bytes": freed,
            "failed": [{"path": str(f), "reason": why} for f, why in failed]}


def _cmd_clear(args: argparse.Namespace) -> int:
    """``rrbody cache clear``: say what was removed and what was kept; a path that could not be removed
    is one line on stderr naming it, exit 1."""
    rep = clear()
    if args.json:
        print(json.dumps(rep))
    n = len(rep["removed"])
    if rep["failed"]:
        first, more = rep["failed"][0], len(rep["failed"]) - 1
        print(f"rrbody cache: error: could not remove {first['path']} ({first['reason']})"
              + (f" nor {more} more path{'s' if more > 1 else ''}" if more else "")
              + f"; removed {n} of rrbody's entries ({_mb(rep['freed_bytes'])} freed); check the folder's "
                f"permissions, or set {ENV} to a writable folder", file=sys.stderr)
        return 1
    if args.json:
        return 0
    groups: dict[str, int] = {}
    for r in rep["removed"]:
        groups[Path(r).parts[0]] = groups.get(Path(r).parts[0], 0) + 1
    what = ", ".join(f"{top}/ ({k} {'entry' if k == 1 else 'entries'})" for top, k in sorted(groups.items()))
    text = (f"cleared {rep['path']}: removed {what} ({_mb(rep['freed_bytes'])} freed)" if n else
            f"cleared {rep['path']}: nothing of rrbody's was there")
    if rep["kept"]:
        shown = ", ".join(rep["kept"][:5]) + (f" and {len(rep['kept']) - 5} more" if len(rep["kept"]) > 5 else "")
        text += f"; kept what rrbody did not write: {shown}"
    print(text + ("; the next command loads or compiles rrbody's kernels again" if n else ""))
    return 0


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
    if args.action == "clear":
        return _cmd_clear(args)
    rep = cache_report()
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
          f"({_mb(b) if (b := rep['installed_kernels']['bytes']) else 'none for these sources'}; "
          "copied into the cache folder on first use)")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``rrbody cache`` on the CLI's subparsers."""
    c = sub.add_parser("cache", help="show, clear or fill rrbody's cache folder (compiled kernels, tables)",
                       description="rrbody keeps its compiled kernels (numba) and quadrature tables "
                                   f"in one user cache folder (~/.cache/rrbody on Linux; the environment variable "
                                   f"{ENV} moves it). Kernels compiled from other sources are never loaded. "
                                   "'info' shows the folder and its size; 'clear' removes what rrbody wrote in "
                                   "it, and nothing else (the next command loads the kernels compiled at install "
                                   "again, or compiles them); 'build' "
                                   "compiles every kernel into it now, as the install does (useful after "
                                   "editing a checkout).")
    c.add_argument("action", choices=("info", "clear", "build"),
                   help="info: where and how big; clear: remove what rrbody wrote there; build: compile every "
                        "kernel now")
    c.add_argument("--json", action="store_true", help="print one JSON object")
    c.set_defaults(func=cmd_cache)
