"""Where rrbody keeps what it computes once and reuses: one user cache folder, never the package.

Layout (``cache_dir()``, by default the platform's user cache folder, ``~/.cache/rrbody`` on Linux;
``RRBODY_CACHE_DIR`` overrides it)::

    kernels/<version>-<sources>/   numba's compiled kernels for this exact source tree
    tables/                        quadrature rules (``.npz``), keyed by their own parameters
    locks/                         output locks of earlier rrbody versions (they now live beside
                                   each output: rrbody.model.outlock); nothing new is written here

``<sources>`` hashes every ``.py`` file of the layers that hold kernels and of those below them
(``KERNEL_LAYERS``: a kernel inlines only what it imports, and imports go only downward, which
``tests/test_layers.py`` enforces), so a kernel compiled from other sources (another version, an
edited checkout) is never loaded: numba keys a cached function only by its own file's time stamp
and would miss an edit to a kernel it inlines from another file. The same hash is the stamp numba
checks in each index, so kernels compiled from a source tree load from an installed copy of it.

Kernels compiled at install: the build backend compiles every kernel once
(:mod:`rrbody.cli.prebuild`) into the package's ``_kernels/<version>-<sources>/``; the first use of
rrbody copies that folder into the cache folder (``seed_kernels``), where numba loads it like
kernels of its own (its version, the CPU and every function's bytecode are still checked: a kernel
that does not match is compiled again, never used). A folder begun before them (``make demo``'s
part, a first use) is completed function by function at the next start. The first run of new sources
removes the kernel folders of other sources beyond the four newest that have gone unused for an hour.
``rrbody cache clear`` removes what rrbody wrote there (:data:`LAYOUT`, :func:`entries`) and nothing else:
the folder may be one other programs use too (``RRBODY_CACHE_DIR=~/.cache``); ``rrbody cache info`` shows it.

A damaged or foreign file in the folder (truncated, garbage, a folder in a file's place) is rebuilt:
numba's files of a kernel it cannot read are removed and the kernel compiled again (``_guard_numba``),
and so are tables (``stored_arrays``); one that cannot be removed raises :class:`CacheDamaged`.

The package folder is never written to: an installed rrbody leaves its files as pip put them.
This module is imported by the layers that hold kernels (physics, integrate, engine) before they
define any, and it imports numba only there, so ``import rrbody`` stays cheap.
"""

from __future__ import annotations

import errno
import functools
import hashlib
import os
import re
import sys
from pathlib import Path
from typing import Any

from rrbody._private import private_allowed
from rrbody._version import __version__

__all__ = ["ENV", "BUILD_FILE", "cache_dir", "kernels_dir", "shipped_kernels_dir", "tables_dir", "stored_arrays",
           "locks_dir", "source_hash", "use_for_kernels", "kernel_sources", "KERNEL_LAYERS", "prune_kernels",
           "seed_kernels", "built_by_numba", "NO_SEED", "CacheDamaged", "remove_damaged", "LAYOUT", "entries"]

#: the environment variable that moves the cache folder
ENV = "RRBODY_CACHE_DIR"
_PKG = Path(__file__).resolve().parent


def cache_dir() -> Path:
    """The cache folder (absolute; not created here): ``$RRBODY_CACHE_DIR``, else the user cache folder."""
    env = os.environ.get(ENV, "")
    if env:
        return Path(env).expanduser().resolve()
    import platformdirs

    return Path(platformdirs.user_cache_dir("rrbody", appauthor=False))


class CacheDamaged(OSError):
    """A damaged cache file that cannot be removed: the command line prints its ``strerror`` (which says
    ``rrbody cache clear``) and ``filename`` on one line and exits with status 1, as for any OSError."""


def remove_damaged(path: Path) -> None:
    """Remove the damaged cache entry ``path`` (a file, a link, or a folder in a file's place), for what
    it held to be rebuilt. Raises :class:`CacheDamaged` naming it if it cannot be."""
    import shutil

    try:
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink(missing_ok=True)
    except OSError:
        raise CacheDamaged(errno.EIO, "a damaged file in rrbody's cache folder could not be removed; run "
                                      "`rrbody cache clear`", str(path)) from None


#: the sub-packages the kernels are compiled from: those that define kernels (physics, integrate, engine)
#: and the one below them (model); an edit in analysis, render or cli (no kernel there) compiles nothing
KERNEL_LAYERS = ("model", "physics", "integrate", "contact", "engine", "mujoco_adapter")
#: modules at the package root that the kernel layers import
KERNEL_ROOT_FILES = ("_cache.py", "_private.py", "_version.py")


def kernel_sources() -> list[Path]:
    """The ``.py`` files the kernels are compiled from (see ``KERNEL_LAYERS``), sorted."""
    files = [f for f in _PKG.rglob("*.py")
             if f.relative_to(_PKG).parts[0] in KERNEL_LAYERS or f.relative_to(_PKG).as_posix() in KERNEL_ROOT_FILES]
    return sorted(files)


@functools.lru_cache(maxsize=1)
def source_hash() -> str:
    """A short hash of the kernels' sources (path and bytes of every file of ``kernel_sources``): about 2 ms."""
    h = hashlib.sha256(__version__.encode() + (b"" if private_allowed() else b"+no-private"))
    for f in kernel_sources():
        h.update(f.relative_to(_PKG).as_posix().encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


#: kernel folders of other sources kept (the newest), so that switching between a few versions or
#: branches does not recompile; older ones are removed once unused for PRUNE_AGE_S
KEEP_KERNEL_FOLDERS = 4
PRUNE_AGE_S = 3600.0


def kernels_dir() -> Path:
    """The folder of numba's compiled kernels for these sources: ``kernels/<version>-<hash>``."""
    return cache_dir() / "kernels" / f"{__version__}-{source_hash()}"


def shipped_kernels_dir() -> Path:
    """Where an install keeps the kernels it compiled for these sources (may not exist):
    ``<package>/_kernels/<version>-<hash>``."""
    return _PKG / "_kernels" / kernels_dir().name


#: the file, in a kernel folder compiled at install, that names the numba that compiled it
BUILD_FILE = "BUILD.json"


#: set (to anything) by ``rrbody.cli.prebuild --force`` in its jobs: compile, do not copy what an install holds
NO_SEED = "RRBODY_NO_SEED"


def built_by_numba(folder: Path) -> str | None:
    """The numba version a kernel folder compiled by :mod:`rrbody.cli.prebuild` names (its
    ``BUILD.json``), or None."""
    import json

    try:
        return json.loads((folder / BUILD_FILE).read_text()).get("numba")
    except (OSError, ValueError, AttributeError):
        return None


def _fill_in(shipped: Path, target: Path) -> bool:
    """Complete a kernel folder numba began before the install's kernels existed (a source tree used
    before its prebuild finished): each function it lacks gets the install's files, each copied and
    renamed (never seen half-written); numba's own stay. The build file, last, marks it complete."""
    import shutil

    copied = False
    for nbi in shipped.rglob("*.nbi"):
        rel = nbi.relative_to(shipped)
        if (target / rel).exists():
            continue
        stem = nbi.name[:-len(".nbi")]
        (target / rel.parent).mkdir(parents=True, exist_ok=True)
        # the index last: numba looks a function up by its index, then loads the data it names
        for f in [*sorted(nbi.parent.glob(stem + ".*.nbc")), nbi]:
            dest = target / rel.parent / f.name
            tmp = dest.with_name(f".seed-{os.getpid()}-{f.name}")
            try:
                shutil.copyfile(f, tmp)
                os.replace(tmp, dest)
            except OSError:
                tmp.unlink(missing_ok=True)
                return copied
        copied = True
    try:
        shutil.copyfile(shipped / BUILD_FILE, target / BUILD_FILE)
    except OSError:
        pass
    return copied


def seed_kernels() -> bool:
    """Copy the kernels compiled at install into the cache folder, if it has none for these sources
    yet. Atomic (a copy in a temporary folder, renamed): of two processes seeding at once, one wins.
    A folder numba began before them is completed function by function (:func:`_fill_in`). Kernels
    of another numba (pip's build environment may hold a newer one) would all be refused by numba:
    not copied, and a RuntimeWarning says how to compile them once (``rrbody cache build``).
    Returns whether this call seeded (never under ``RRBODY_NO_SEED``)."""
    import shutil
    import tempfile

    target = kernels_dir()
    shipped = shipped_kernels_dir()
    if not shipped.is_dir() or os.environ.get(NO_SEED) or (target / BUILD_FILE).exists():
        return False
    import numba

    built_by = built_by_numba(shipped)
    if built_by != numba.__version__:
        if target.is_dir():  # said on these sources' first run only (this runs at each start until complete)
            return False
        import warnings

        warnings.warn(f"rrbody's kernels were compiled at install by numba {built_by}, this is numba "
                      f"{numba.__version__}: each is compiled on first use instead (15-30 s); "
                      "'rrbody cache build' compiles them all now", RuntimeWarning, stacklevel=2)
        return False
    if target.is_dir():
        return _fill_in(shipped, target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".seed-", dir=target.parent))
    try:
        shutil.copytree(shipped, tmp, dirs_exist_ok=True)
        os.rename(tmp, target)  # replaces nothing but an empty folder
    except OSError:
        shutil.rmtree(tmp, ignore_errors=True)
        return False
    return True


def _ready_kernels() -> None:
    """At a process's start: these sources' kernel folder, absent or not complete (begun by a first use or
    ``make demo``'s part), gets the install's kernels (:func:`seed_kernels`); a complete one costs one look."""
    target = kernels_dir()
    if (target / BUILD_FILE).exists():
        return
    try:
        if not target.is_dir():
            prune_kernels()
        seed_kernels()
    except OSError:
        pass


def prune_kernels(now: float | None = None) -> list[Path]:
    """Remove kernel folders of other sources beyond the KEEP_KERNEL_FOLDERS newest, if untouched for
    PRUNE_AGE_S seconds (a process of another version may be using a recent one). Returns them."""
    import shutil
    import time

    current = kernels_dir()
    others = []
    for p in (current.parent.iterdir() if current.parent.is_dir() else ()):
        if p.is_dir() and p != current:
            try:
                others.append((p.stat().st_mtime, p))
            except OSError:
                continue
    others.sort(reverse=True)
    now = time.time() if now is None else now
    removed = []
    for mtime, p in others[KEEP_KERNEL_FOLDERS:]:
        if now - mtime > PRUNE_AGE_S:
            shutil.rmtree(p, ignore_errors=True)
            removed.append(p)
    return removed


def tables_dir() -> Path:
    """The folder of precomputed tables (quadrature rules): ``tables/``."""
    return cache_dir() / "tables"


def stored_arrays(path: Path, build: Any, *, valid: Any = None) -> tuple[Any, ...]:
    """The arrays ``build()`` returns (a tuple of numpy arrays), read from the ``.npz`` file ``path`` if it
    holds them (stamped with its own place in the cache folder, and ``valid(arrays)``), else built and
    stored there for the next process, through a temporary file renamed (two processes may build the
    same arrays at once); a folder that cannot be written only costs the build. A file that cannot be
    read for any reason (truncated, garbage, a folder in its place, another table's) is built again."""
    import tempfile

    import numpy as np

    try:  # (outside the cache folder, the file's name)
        stamp = path.resolve().relative_to(cache_dir().resolve()).as_posix()
    except ValueError:
        stamp = path.name
    try:
        with np.load(path, allow_pickle=False) as z:
            if "stamp" in z.files and str(z["stamp"][()]) == stamp:
                arrays = tuple(z[f"a{i}"] for i in range(len(z.files) - 1))
                if arrays and (valid is None or valid(arrays)):
                    return arrays
    except Exception:  # noqa: BLE001 (whatever a missing or damaged file makes numpy raise: built again)
        pass
    arrays = tuple(build())
    if path.is_dir() and not path.is_symlink():
        remove_damaged(path)  # (a file is replaced by the rename below)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return arrays
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, stamp=np.array(stamp), **{f"a{i}": a for i, a in enumerate(arrays)})
        os.replace(tmp, path)
    except OSError:
        Path(tmp).unlink(missing_ok=True)
    return arrays


def locks_dir() -> Path:
    """The folder where rrbody versions before the locks moved beside the outputs kept them: ``locks/``
    (read by ``rrbody cache clear`` only)."""
    return cache_dir() / "locks"


#: what rrbody writes in the cache folder: each folder of its own, and the names (regular expressions)
#: of what rrbody puts in it. The writers: :func:`kernels_dir` (``<version>-<16 hex digits>``) and
#: :func:`seed_kernels`'s temporary copies (``.seed-``); :func:`stored_arrays` in :func:`tables_dir`
#: (``.npz``, through ``tmp*.tmp``); earlier versions' output locks (a hash, ``.lock``).
LAYOUT: dict[str, tuple[str, ...]] = {
    "kernels": (r".+-[0-9a-f]{16}", r"\.seed-.+"),
    "tables": (r".+\.npz", r"tmp[a-z0-9_]+\.tmp"),
    "locks": (r"[0-9a-f]{32}\.lock",),
}


def entries(root: Path | None = None) -> tuple[list[Path], list[Path]]:
    """What of the cache folder ``root`` (default :func:`cache_dir`) rrbody wrote, and what it did not:
    ``(ours, foreign)``. Ours: the entries of :data:`LAYOUT`'s folders whose names it gives (a kernel
    folder whole); foreign: everything else at the top and in those folders, including a file, or a
    link, in the place of one of them (rrbody makes folders there)."""
    root = cache_dir() if root is None else root
    ours: list[Path] = []
    foreign: list[Path] = []
    for top in sorted(root.iterdir()) if root.is_dir() else ():
        names = LAYOUT.get(top.name)
        if names is None or not top.is_dir() or top.is_symlink():
            foreign.append(top)
            continue
        for p in sorted(top.iterdir()):
            (ours if any(re.fullmatch(n, p.name) for n in names) else foreign).append(p)
    return ours, foreign


@functools.lru_cache(maxsize=1)
def use_for_kernels() -> None:
    """Make numba cache rrbody's kernels (and only rrbody's) in :func:`kernels_dir`.

    numba picks a cache folder per function through a list of *locators*; a locator placed first
    that answers only for functions defined in this package's files sends them here, and leaves
    every other program's numba functions (and ``NUMBA_CACHE_DIR``) as they were. Idempotent."""
    if not private_allowed():  # RRBODY_NO_PRIVATE: numba's own locators (rrbody._private)
        return
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    base = caching._SourceFileBackedLocatorMixin

    class _Locator(base, caching._CacheLocator):  # type: ignore[misc, name-defined]
        """numba's source-file locator, rooted in rrbody's versioned kernel folder."""

        def __init__(self, py_func: object, py_file: str) -> None:
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno  # type: ignore[attr-defined]
            rel = Path(py_file).resolve().parent.relative_to(_PKG)
            self._cache_path = str(kernels_dir().joinpath(*rel.parts))

        def get_cache_path(self) -> str:
            return self._cache_path

        def get_source_stamp(self) -> str:
            # the hash of the kernels' sources, not this file's time stamp: an installed copy of a source tree
            # (new time stamps) loads the kernels compiled from it, an edited tree never does
            return source_hash()

        @classmethod
        def from_function(cls, py_func: object, py_file: str) -> object:
            try:
                Path(py_file).resolve().relative_to(_PKG)
            except ValueError:
                return None  # not one of ours: numba's own locators decide
            self = cls(py_func, py_file)
            try:
                self.ensure_cache_path()
            except OSError:
                try:  # a file where a folder of the path belongs (damage): removed, then once more
                    _clear_way(Path(self._cache_path))
                    self.ensure_cache_path()
                except OSError:  # an unwritable cache folder: a private temporary one, never numba's next
                    import tempfile  # choice (which would be the package folder itself)

                    self._cache_path = os.path.join(tempfile.gettempdir(), f"rrbody-{os.getuid()}",
                                                    Path(self._cache_path).relative_to(cache_dir()))
            return self

    _guard_numba(caching, _Locator)
    _ready_kernels()
    _Locator.__name__ = _Locator.__qualname__ = "RrbodyCacheLocator"
    impl._locator_classes.insert(0, _Locator)
    # keep the class reachable by name for pickling and debugging
    sys.modules[__name__].RrbodyCacheLocator = _Locator  # type: ignore[attr-defined]


def _clear_way(folder: Path) -> None:
    """Remove what is not a folder on the way from the cache folder down to ``folder`` (damage)."""
    root = p = cache_dir()
    for part in folder.relative_to(root).parts if folder.is_relative_to(root) else ():
        p = p / part
        if (p.is_symlink() or p.exists()) and not p.is_dir():
            remove_damaged(p)


def _guard_numba(caching: Any, locator: type) -> None:
    """Make a file of an rrbody kernel that numba cannot read (truncated, garbage, a folder in its place,
    another program's) a cache miss rather than the end of the command (numba raises from deep in its
    loader, an UnpicklingError from ``IndexDataCacheFile._load_index``, say): the function's index and
    data files are removed, and numba compiles and saves it afresh; a failed save is retried once after
    the same removal (a second failure is the system's: raised). Other programs' caches are untouched."""
    cls = caching.Cache
    if getattr(cls, "_rrbody_guarded", False):
        return

    def discard(cache: Any) -> None:
        index = Path(cache._cache_file._index_path)
        base = index.name[:-len("nbi")]
        for p in [index, *(q for q in (index.parent.iterdir() if index.parent.is_dir() else ())
                           if q.name.startswith(base) and q.name.endswith(".nbc"))]:
            remove_damaged(p)

    def guarded(method: Any, otherwise: Any) -> Any:
        def call(self: Any, sig: Any, arg: Any) -> Any:
            if not isinstance(self._impl.locator, locator):
                return method(self, sig, arg)
            try:
                return method(self, sig, arg)
            except Exception:  # noqa: BLE001 (whatever numba's loader raises on a damaged file)
                discard(self)
                return otherwise(self, sig, arg)
        return call

    cls.load_overload = guarded(cls.load_overload, lambda *_: None)  # a miss: numba compiles it
    cls.save_overload, cls._rrbody_guarded = guarded(cls.save_overload, cls.save_overload), True  # retried once
