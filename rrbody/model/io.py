"""Safe output: every file is written to a temporary sibling and renamed into place.

A crash or Ctrl-C mid-write leaves any previous file intact, and an existing file is never
clobbered unless ``force=True``. The temporary sibling (``.NAME.XXXXXXXX.part.SUFFIX``) is written
under the output's lock (:mod:`rrbody.model.outlock`), so one that a killed process left behind is
known to be stale by the next writer of the same output, which removes it; a writer that does not
get the lock (another process writes the output) is refused and removes nothing. Every output path
is checked before any work is done (:func:`check_writable`: a regular file or absent, not empty, not
too long for the file system), and the outputs of one run are checked to be distinct files, none of
them an input (:func:`check_distinct`).

Messages name the output as the caller calls it: an option (``--out``), whose hints speak the
command line's words (``pass --force``), or a Python parameter (``out``: ``pass force=True``).
"""

from __future__ import annotations

import contextlib
import os
import re
import stat
import tempfile
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_path", "atomic_write_text", "atomic_write_with", "check_writable", "check_distinct", "same_file",
           "NAME_RESERVE"]

#: bytes of a file name kept free for what rrbody writes beside an output: its temporary sibling
#: ``.NAME.XXXXXXXX.part.SUFFIX``, its lock file ``.NAME.rrbody-lock`` and a sweep's
#: ``NAME.checkpoint.jsonl`` (whose own temporary name is the longest, NAME plus 38 bytes)
NAME_RESERVE = 48
#: the limits assumed where the file system does not say (POSIX NAME_MAX and Linux PATH_MAX), bytes
_NAME_MAX, _PATH_MAX = 255, 4096


_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _kind(mode: int) -> str:
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def _force_hint(name: str) -> str:
    """How to overwrite, in the caller's words: ``--force`` for an option, ``force=True`` in Python."""
    return "--force" if name.startswith("--") else "force=True"


def _limits(folder: str) -> tuple[int, int]:
    """(longest file name, longest path) in bytes in ``folder``'s file system, asked of the nearest
    existing folder (the POSIX/Linux defaults where the system does not say)."""
    d = os.path.abspath(folder)
    while not os.path.isdir(d) and os.path.dirname(d) != d:
        d = os.path.dirname(d)
    out = []
    for key, default in (("PC_NAME_MAX", _NAME_MAX), ("PC_PATH_MAX", _PATH_MAX)):
        try:
            v = os.pathconf(d, key)
        except (OSError, ValueError, AttributeError):  # no pathconf (Windows) or no such limit
            v = -1
        out.append(v if v and v > 0 else default)
    return out[0], out[1]


def _check_spelling(path: str | os.PathLike[str], name: str) -> str:
    """The path as text, refused (``ValueError`` naming ``name``) when empty, holding a NUL byte,
    not encodable for the file system, or longer than the file system allows (a component longer
    than NAME_MAX less :data:`NAME_RESERVE`, the whole longer than PATH_MAX less the reserve): the
    system's raw 'File name too long' would otherwise come mid-run, after the work."""
    try:
        text = os.fspath(path)
    except TypeError:
        raise ValueError(f"{name} must be a file path, got {path!r}") from None
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    if not text.strip():
        raise ValueError(f"{name} must be a file path, got {text!r} (an empty path does not mean 'no output': "
                         f"omit {name} for that)")
    if "\x00" in text:
        raise ValueError(f"{name}: {text!r} holds a NUL character, which no file name may contain")
    try:
        raw = os.fsencode(text)
    except UnicodeError:
        raise ValueError(f"{name}: {text!r} cannot be encoded as a file name on this system") from None
    folder = os.path.dirname(text) or "."
    name_max, path_max = _limits(folder)
    *folders, last = raw.split(os.fsencode(os.sep))
    for part, most in [*((f, name_max) for f in folders), (last, name_max - NAME_RESERVE)]:
        if len(part) > most:
            shown = os.fsdecode(part)
            why = ("the file system's limit" if most == name_max else
                   f"the file system takes {name_max}, and rrbody writes a temporary sibling with a longer name")
            raise ValueError(f"{name}: the name {shown[:40] + '...' if len(shown) > 40 else shown!r} is "
                             f"{len(part)} bytes long; at most {most} bytes are allowed here ({why})")
    if len(raw) > path_max - NAME_RESERVE:
        raise ValueError(f"{name}: the path is {len(raw)} bytes long; at most {path_max - NAME_RESERVE} bytes are "
                         f"allowed here (the system takes {path_max})")
    return text


def check_writable(path: str | os.PathLike[str], *, force: bool = False, name: str = "out") -> Path:
    """Validate an output path before any work is done; return the path to write (a symbolic link
    to a regular file resolves to its target, so the link survives and the target is replaced).

    The path must be a non-empty path of a length the file system takes (see
    :data:`NAME_RESERVE`), absent or a regular file (never a directory, FIFO, device, socket, or a
    link to one, nor a dangling link: ``force`` does not change that); an existing file needs
    ``force``; the folder must exist and be writable. Raises ``ValueError`` naming ``name`` (an
    option such as ``--out``, or a Python parameter such as ``out``: the hint follows suit)."""
    p = Path(_check_spelling(path, name))
    if p.is_symlink():
        try:
            target = p.resolve(strict=True)
        except (OSError, RuntimeError):
            raise ValueError(f"{name}: {str(p)!r} is a dangling or looping symbolic link; refusing to write "
                             "through it") from None
        st = target.stat()
        if not stat.S_ISREG(st.st_mode):
            raise ValueError(f"{name}: {str(p)!r} is a symbolic link to {_kind(st.st_mode)}; rrbody writes only "
                             f"regular files, with or without {_force_hint(name)}")
        p = target
    elif p.exists() or os.path.lexists(p):
        mode = p.lstat().st_mode
        if not stat.S_ISREG(mode):
            raise ValueError(f"{name}: {str(p)!r} is {_kind(mode)}; rrbody writes only regular files, with or "
                             f"without {_force_hint(name)}")
    if p.exists() and not force:
        raise ValueError(f"{name}: {str(p)!r} already exists; pass {_force_hint(name)} to overwrite it")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"{name}: folder {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: folder {str(parent)!r} is not writable")
    return p


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """True when ``a`` and ``b`` name one file: the same device and inode where both exist (hard
    links, symbolic links, any spelling), else the same absolute path with links resolved."""
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):  # one of them does not exist (yet), or is no valid path
        pass
    try:
        return os.path.normcase(os.path.realpath(a)) == os.path.normcase(os.path.realpath(b))
    except (OSError, ValueError):
        return False


def check_distinct(outputs: Mapping[str, str | os.PathLike[str] | None],
                   inputs: Mapping[str, str | os.PathLike[str] | None] | None = None) -> None:
    """Refuse outputs that are one file, or an output that is an input, before anything is written.

    ``outputs`` and ``inputs`` map a name (``--out``, ``movie``) to a path (None: not given). Raises
    ``ValueError`` naming both: two outputs to one file would leave only the last one written (``--out
    o.mp4 --movie o.mp4``), and an output onto an input would replace the input while it is read
    (``--batch in.jsonl --out in.jsonl --force``). Comparison by :func:`same_file`."""
    def shown(pa: str | os.PathLike[str], pb: str | os.PathLike[str]) -> str:
        a, b = os.fspath(pa), os.fspath(pb)
        return repr(a) if a == b else f"{a!r} and {b!r} are one file"

    outs = [(n, p) for n, p in outputs.items() if p is not None]
    ins = [(n, p) for n, p in (inputs or {}).items() if p is not None]
    for i, (na, pa) in enumerate(outs):
        for nb, pb in outs[i + 1:]:
            if same_file(pa, pb):
                raise ValueError(f"{na} and {nb} name the same file ({shown(pa, pb)}); give each output its own "
                                 "path")
        for nb, pb in ins:
            if same_file(pa, pb):
                raise ValueError(f"{na} is the input of {nb} ({shown(pa, pb)}); writing it would replace what is "
                                 "being read: choose another path")


#: the temporary siblings this process is writing now (their names): never taken for stale ones
_WRITING: set[str] = set()


def _part_affixes(final: Path) -> tuple[str, str]:
    """The prefix and suffix of ``final``'s temporary siblings (``tempfile.mkstemp`` puts eight
    characters of its own between them)."""
    return f".{final.name}.", ".part" + final.suffix


def _remove_stale_parts(final: Path) -> None:
    """Remove the temporary siblings of ``final`` that an earlier writer left (killed mid-write).
    Called with ``final``'s lock held, so no other process is writing one of them; this process's
    own (another thread's) are kept. Other files, links and folders are never touched."""
    prefix, suffix = _part_affixes(final)
    mine = re.compile(re.escape(prefix) + r"[a-z0-9_]{8}" + re.escape(suffix) + r"\Z")
    try:
        names = os.listdir(final.parent)
    except OSError:
        return
    for n in names:
        if mine.match(n) and n not in _WRITING:
            p = final.parent / n
            with contextlib.suppress(OSError):
                if stat.S_ISREG(p.lstat().st_mode):
                    p.unlink()


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], *, force: bool = False, name: str = "out") -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success it is renamed onto ``path``.

    On any exception (including KeyboardInterrupt) the temporary file is removed and ``path``
    is left as it was. The output's lock (:func:`rrbody.model.outlock.claimed`) is held from
    before the temporary file exists until it is renamed or removed (already held by a command
    that claimed its outputs first: kept), and the stale temporary siblings an earlier, killed
    writer left are removed under it. Another process writing ``path`` raises
    :class:`~rrbody.model.outlock.OutputBusy` (a ``ValueError`` naming ``name``).
    """
    from rrbody.model.outlock import claimed

    final = check_writable(path, force=force, name=name)
    with claimed([(name, final)]):
        _remove_stale_parts(final)
        prefix, suffix = _part_affixes(final)
        fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=suffix, dir=final.parent or ".")
        os.close(fd)
        tmp_path = Path(tmp)
        _WRITING.add(tmp_path.name)
        try:
            yield tmp_path
            if not force and final.exists():
                raise ValueError(f"{name}: {str(final)!r} appeared while writing; pass {_force_hint(name)} to "
                                 "overwrite it")
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
        finally:
            _WRITING.discard(tmp_path.name)


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
