"""One writer per output: an advisory lock per output path, held for the life of the writing process.

Two rrbody processes that aim at one output (a sweep and its checkpoint, a trajectory CSV, a movie)
must never both run: the second is refused at once, naming the first, whatever ``--force`` or
``--resume`` say. The lock is the operating system's (``fcntl.flock``) on a small file in rrbody's
cache folder (``locks/``, one file per output, named by a hash of the output's absolute path), so
nothing appears beside the user's outputs. The kernel releases a lock when its holder exits, however
it exits (``kill -9`` included): a lock left by a dead process is simply free, and the next writer
takes it over. The file records the holder's process id and command line, for the refusal message.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import fcntl
import hashlib
import os
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path

from rrbody._cache import locks_dir, remove_damaged

__all__ = ["OutputBusy", "claim", "release", "claimed", "lock_key"]


class OutputBusy(ValueError):
    """The output is being written by another rrbody process (a ``ValueError``: bad input, exit 2)."""


#: path key -> open lock file descriptor, for this process's claims
_HELD: dict[str, int] = {}


def lock_key(path: str | os.PathLike[str]) -> str:
    """The absolute, normalised path a lock is taken on: the real folder (links resolved) plus the name,
    so two spellings of one output share a lock. A link to a regular file locks its target."""
    p = Path(path).expanduser()
    if p.is_symlink():
        with contextlib.suppress(OSError, RuntimeError):
            p = p.resolve(strict=True)
    parent = p.parent if str(p.parent) else Path(".")
    try:
        parent = parent.resolve(strict=False)
    except (OSError, RuntimeError):
        parent = Path(os.path.abspath(parent))
    return str(parent / p.name)


def _lock_file(key: str) -> Path:
    return locks_dir() / (hashlib.sha256(key.encode()).hexdigest()[:32] + ".lock")


def _holder(f: Path) -> str:
    try:
        text = f.read_text(errors="replace").strip()
    except OSError:
        return "another rrbody process"
    return text.splitlines()[0] if text else "another rrbody process"


def claim(path: str | os.PathLike[str], *, name: str = "out") -> None:
    """Take the output lock on ``path`` for this process (until :func:`release` or exit).

    Raises :class:`OutputBusy` naming ``name``, the path and the holding process when another
    process holds it; claiming a path this process already holds is a no-op. The lock file is
    created in ``rrbody._cache.locks_dir()`` (``RRBODY_CACHE_DIR`` moves it); a folder that cannot be
    written is a ``ValueError`` naming it."""
    key = lock_key(path)
    if key in _HELD:
        return
    f = _lock_file(key)
    if (f.parent.exists() or f.parent.is_symlink()) and not f.parent.is_dir():
        remove_damaged(f.parent)  # a file in the lock folder's place (damage)
    try:
        f.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ValueError(f"{name}: cannot create rrbody's lock folder {str(f.parent)!r} ({e.strerror}); set "
                         f"RRBODY_CACHE_DIR to a writable folder") from None
    while True:
        try:
            fd = os.open(f, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except IsADirectoryError:  # a folder in the lock file's place (damage; no process can hold it)
            remove_damaged(f)
            continue
        except OSError as e:
            raise ValueError(f"{name}: cannot open the lock file {str(f)!r} ({e.strerror}); set RRBODY_CACHE_DIR "
                             "to a writable folder") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            os.close(fd)
            if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise OutputBusy(f"{name}: {str(path)!r} is being written by {_holder(f)}; wait for it to finish "
                                 "or choose another path (--force and --resume do not override this)") from None
            raise
        # the holder before us may have unlinked the file after we opened it: then our lock is on
        # a file nobody else can see, and we must lock the one at the path instead
        try:
            same = os.stat(f).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    prog = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python"
    if prog in ("__main__.py", "-m"):  # `python -m rrbody.cli ...`: name the command as a user types it
        prog = "rrbody"
    argv = " ".join([prog, *sys.argv[1:]])[:300]
    os.ftruncate(fd, 0)
    os.write(fd, f"process {os.getpid()} ({argv})\n{key}\n".encode(errors="replace"))
    _HELD[key] = fd


def release(path: str | os.PathLike[str]) -> None:
    """Give up this process's lock on ``path`` (no-op if not held); the lock file is removed."""
    key = lock_key(path)
    fd = _HELD.pop(key, None)
    if fd is None:
        return
    # unlink while still holding the lock, so a waiter that opened it sees a stale inode and retries
    with contextlib.suppress(OSError):
        os.unlink(_lock_file(key))
    os.close(fd)


@contextlib.contextmanager
def claimed(paths: Iterable[tuple[str, str | os.PathLike[str]]]) -> Iterator[None]:
    """Claim every ``(name, path)`` (all or none: a refusal releases the ones already taken), yield,
    then release them."""
    taken: list[str | os.PathLike[str]] = []
    try:
        for name, path in paths:
            if lock_key(path) in _HELD:
                continue  # held by an outer claim: that claim releases it
            claim(path, name=name)
            taken.append(path)
        yield
    finally:
        for path in taken:
            release(path)


def _forget_in_child() -> None:
    """In a forked child, close the copies of this process's lock descriptors and forget them.

    ``flock`` belongs to the open file, which ``fork`` shares: without this a lock would outlive a
    killed parent for as long as its last child (a sweep's workers), and a ``--resume`` at once would
    be refused; a child's exit would also remove the parent's lock files. Closing a copy does not
    release the parent's lock."""
    for fd in _HELD.values():
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()


os.register_at_fork(after_in_child=_forget_in_child)


@atexit.register
def _release_all() -> None:
    """Remove this process's lock files on a normal exit (a killed process leaves its file, unlocked)."""
    for key in list(_HELD):
        release(key)
