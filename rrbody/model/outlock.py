"""One writer per output: an advisory lock per output path, held for the life of the writing process.

Two rrbody processes that aim at one output (a sweep and its checkpoint, a trajectory CSV, a movie)
must never both run: the second is refused at once, naming the first, whatever ``--force`` or
``--resume`` say. The lock is the operating system's (``fcntl.flock``) on a small hidden file beside
the output, ``.NAME.rrbody-lock`` in the output's own folder (:func:`lock_path`): every process that
writes the output meets it there, whatever cache folder (``RRBODY_CACHE_DIR``) it uses, and a user
with two shells or a scheduler that gives each job its own cache cannot have two writers. The file
exists only while its output is written (removed at release). The kernel releases a lock when its
holder exits, however it exits (``kill -9`` included): a lock left by a dead process is simply free,
and the next writer takes it over and removes its file. The file records the holder's process id and
command line, for the refusal message; a file of that name that is not one of these (a folder, a
link, another program's file) is never replaced: the claim is refused, naming it.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import fcntl
import os
import stat
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path

__all__ = ["OutputBusy", "claim", "release", "claimed", "lock_key", "lock_path", "LOCK_SUFFIX"]

#: what the lock file's name adds to the output's (after a leading dot): ``.NAME.rrbody-lock``
LOCK_SUFFIX = ".rrbody-lock"
#: how a lock file written by rrbody begins (its holder line); an empty one (or one cut short) is a claim
#: that was being made
_HOLDER_PREFIX = b"process "


class OutputBusy(ValueError):
    """The output is being written by another rrbody process (a ``ValueError``: bad input, exit 2)."""


#: path key -> (open lock file descriptor, lock file), for this process's claims
_HELD: dict[str, tuple[int, Path]] = {}


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


def lock_path(path: str | os.PathLike[str]) -> Path:
    """The lock file of the output ``path``: ``.NAME.rrbody-lock`` in the output's real folder (the
    folder of :func:`lock_key`, so that every spelling of one output, and a link to it, meet at one file)."""
    key = Path(lock_key(path))
    return key.parent / f".{key.name}{LOCK_SUFFIX}"


def _holder(fd: int) -> str:
    try:
        text = os.pread(fd, 4096, 0).decode(errors="replace").strip()
    except OSError:
        return "another rrbody process"
    return text.splitlines()[0] if text else "another rrbody process"


def _not_ours(name: str, path: str | os.PathLike[str], f: Path, what: str) -> ValueError:
    return ValueError(f"{name}: {str(f)!r}, where rrbody keeps the lock of {str(path)!r} while writing it, is "
                      f"{what}; remove it or choose another path")


def _open_lock(f: Path, name: str, path: str | os.PathLike[str]) -> int:
    """Open (or create) the lock file ``f`` without following a link; refused (``ValueError`` naming
    ``name``) when something else is in its place or the folder does not take it."""
    try:
        fd = os.open(f, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | getattr(os, "O_NOFOLLOW", 0), 0o644)
    except IsADirectoryError:
        raise _not_ours(name, path, f, "a folder") from None
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise _not_ours(name, path, f, "a symbolic link") from None
        raise ValueError(f"{name}: cannot create the lock file {str(f)!r} beside the output ({e.strerror})") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):  # a FIFO or a device opens without blocking in read-write mode
        os.close(fd)
        raise _not_ours(name, path, f, "not a regular file")
    return fd


def claim(path: str | os.PathLike[str], *, name: str = "out") -> None:
    """Take the output lock on ``path`` for this process (until :func:`release` or exit).

    Raises :class:`OutputBusy` naming ``name``, the path and the holding process when another
    process holds it; claiming a path this process already holds is a no-op. The lock file is
    :func:`lock_path`, beside the output (its folder must exist and be writable, as for the output
    itself); a file of that name that rrbody did not write (a folder, a link, another program's file),
    or a folder where it cannot be created, is a ``ValueError`` naming it."""
    key = lock_key(path)
    if key in _HELD:
        return
    f = lock_path(path)
    while True:
        fd = _open_lock(f, name, path)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            holder = _holder(fd)
            os.close(fd)
            if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise OutputBusy(f"{name}: {str(path)!r} is being written by {holder}; wait for it to finish "
                                 "or choose another path (--force and --resume do not override this)") from None
            raise
        # the holder before us may have unlinked the file after we opened it: then our lock is on
        # a file nobody else can see, and we must lock the one at the path instead
        try:
            same = os.stat(f, follow_symlinks=False).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    head = os.pread(fd, len(_HOLDER_PREFIX), 0)
    if not _HOLDER_PREFIX.startswith(head):  # not a lock rrbody wrote: never truncated, never removed
        os.close(fd)
        raise _not_ours(name, path, f, "a file rrbody did not write")
    prog = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python"
    if prog in ("__main__.py", "-m"):  # `python -m rrbody.cli ...`: name the command as a user types it
        prog = "rrbody"
    argv = " ".join([prog, *sys.argv[1:]])[:300]
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"process {os.getpid()} ({argv})\n{key}\n".encode(errors="replace"), 0)
    _HELD[key] = (fd, f)


def release(path: str | os.PathLike[str]) -> None:
    """Give up this process's lock on ``path`` (no-op if not held); the lock file is removed."""
    _drop(lock_key(path))


def _drop(key: str) -> None:
    held = _HELD.pop(key, None)
    if held is None:
        return
    fd, f = held
    # unlink while still holding the lock, so a waiter that opened it sees a stale inode and retries
    with contextlib.suppress(OSError):
        if os.stat(f, follow_symlinks=False).st_ino == os.fstat(fd).st_ino:
            os.unlink(f)
    os.close(fd)


@contextlib.contextmanager
def claimed(paths: Iterable[tuple[str, str | os.PathLike[str]]]) -> Iterator[None]:
    """Claim every ``(name, path)`` (all or none: a refusal releases the ones already taken), yield,
    then release them."""
    taken: list[str] = []
    try:
        for name, path in paths:
            key = lock_key(path)
            if key in _HELD:
                continue  # held by an outer claim: that claim releases it
            claim(path, name=name)
            taken.append(key)
        yield
    finally:
        for key in taken:
            _drop(key)


def _forget_in_child() -> None:
    """In a forked child, close the copies of this process's lock descriptors and forget them.

    ``flock`` belongs to the open file, which ``fork`` shares: without this a lock would outlive a
    killed parent for as long as its last child (a sweep's workers), and a ``--resume`` at once would
    be refused; a child's exit would also remove the parent's lock files. Closing a copy does not
    release the parent's lock."""
    for fd, _ in _HELD.values():
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()


os.register_at_fork(after_in_child=_forget_in_child)


@atexit.register
def _release_all() -> None:
    """Remove this process's lock files on a normal exit (a killed process leaves its file, unlocked)."""
    for key in list(_HELD):
        _drop(key)
