"""Safe output: every file is written to a temporary sibling and renamed into place.

A crash or Ctrl-C mid-write leaves any previous file intact, and an existing file is never
clobbered unless ``force=True``.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_path", "atomic_write_text", "check_writable"]


_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _kind(mode: int) -> str:
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def check_writable(path: str | os.PathLike[str], *, force: bool = False, name: str = "out") -> Path:
    """Validate an output path before any work is done; return the path to write (a symbolic link
    to a regular file resolves to its target, so the link survives and the target is replaced).

    The path must be absent or a regular file (never a directory, FIFO, device, socket, or a link
    to one, nor a dangling link: ``force`` does not change that); an existing file needs
    ``force``; the folder must exist and be writable. Raises ``ValueError`` naming ``name``."""
    p = Path(path)
    if p.is_symlink():
        try:
            target = p.resolve(strict=True)
        except (OSError, RuntimeError):
            raise ValueError(f"{name}: {str(p)!r} is a dangling or looping symbolic link; refusing to write "
                             "through it") from None
        st = target.stat()
        if not stat.S_ISREG(st.st_mode):
            raise ValueError(f"{name}: {str(p)!r} is a symbolic link to {_kind(st.st_mode)}; rrbody writes only "
                             "regular files, with or without --force")
        p = target
    elif p.exists() or os.path.lexists(p):
        mode = p.lstat().st_mode
        if not stat.S_ISREG(mode):
            raise ValueError(f"{name}: {str(p)!r} is {_kind(mode)}; rrbody writes only regular files, with or "
                             "without --force")
    if p.exists() and not force:
        raise ValueError(f"{name}: {str(p)!r} already exists (pass force=True / --force to overwrite)")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"{name}: folder {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: folder {str(parent)!r} is not writable")
    return p


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], *, force: bool = False, name: str = "out") -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success it is renamed onto ``path``.

    On any exception (including KeyboardInterrupt) the temporary file is removed and ``path``
    is left as it was.
    """
    final = check_writable(path, force=force, name=name)
    fd, tmp = tempfile.mkstemp(prefix=f".{final.name}.", suffix=".part" + final.suffix, dir=final.parent or ".")
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        if not force and final.exists():
            raise ValueError(f"{name}: {str(final)!r} appeared while writing (pass --force to overwrite)")
        if os.path.lexists(final) and not stat.S_ISREG(final.lstat().st_mode):
            raise ValueError(f"{name}: {str(final)!r} became {_kind(final.lstat().st_mode)} while writing; "
                             "left it alone")
        # mkstemp creates 0600 files; give the result the permissions a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)
        os.replace(tmp_path, final)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str, *, force: bool = False, name: str = "out") -> Path:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path, force=force, name=name) as tmp:
        tmp.write_text(text)
    return Path(path)


def atomic_write_with(path: str | os.PathLike[str], writer: Callable[[IO[Any]], None], *, force: bool = False,
                      name: str = "out", mode: str = "w") -> Path:
    """Open a temporary file, let ``writer`` fill it, then rename it onto ``path``."""
    with atomic_path(path, force=force, name=name) as tmp, open(tmp, mode) as fh:
        writer(fh)
    return Path(path)
