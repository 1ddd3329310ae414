"""Safe output: every file is written to a temporary sibling and renamed into place.

A crash or Ctrl-C mid-write leaves any previous file intact, and an existing file is never
clobbered unless ``force=True``.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_path", "atomic_write_text", "check_writable"]


def check_writable(path: str | os.PathLike[str], *, force: bool = False, name: str = "out") -> Path:
    """Validate an output path before any work is done: its folder must exist and, unless
    ``force``, the file must not. Raises ``ValueError`` naming the option."""
    p = Path(path)
    if p.exists() and not force:
        raise ValueError(f"{name}: {str(p)!r} already exists (pass force=True / --force to overwrite)")
    if p.exists() and p.is_dir():
        raise ValueError(f"{name}: {str(p)!r} is a directory")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"{name}: folder {str(parent)!r} does not exist")
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
