"""The pre-flight check of a run's outputs: every output's writer is known and installed and its path
writable, before anything is computed or written.

A run that computes for minutes and then finds that it cannot write its result (the extra that
writes NetCDF is missing, the folder does not exist) has wasted the minutes, and may leave a
checkpoint behind that blocks the same command later. So every command, and every Python entry
point that writes, checks all of its outputs first with :func:`preflight`:

- the format is known: the path ends in a suffix the output accepts (:data:`WRITERS` names each
  suffix's writer);
- the writer is installed: the packages it imports are importable, else
  :class:`~rrbody.model.extras.MissingExtraError` names the extra to install (an ImportError: one
  line, exit 2, on the command line);
- the path is writable (:func:`rrbody.model.io.check_writable`: absent or a regular file, ``force``
  for an existing one, its folder existing and writable), and no two outputs, nor an output and an
  input, are one file (:func:`rrbody.model.io.check_distinct`).

Messages name each output as the caller does: an option (``--out``) or a parameter (``out``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from rrbody.model.extras import require
from rrbody.model.io import check_distinct, check_writable

__all__ = ["Writer", "WRITERS", "Output", "writer_of", "require_writer", "check_output", "preflight"]


@dataclass(frozen=True)
class Writer:
    """What writes one kind of file: ``what`` it holds (for messages) and the optional packages it
    imports (top-level module names; none for the core's own writers)."""

    what: str
    modules: tuple[str, ...] = ()


#: file suffix -> its writer. The core writes CSV, JSON and checkpoints; the rest need an extra
#: (:data:`rrbody.model.extras.EXTRA_OF` maps each module onto it)
WRITERS: dict[str, Writer] = {
    ".csv": Writer("a CSV table"),
    ".json": Writer("a JSON file"),
    ".jsonl": Writer("a checkpoint"),
    ".nc": Writer("a NetCDF table", ("xarray",)),
    ".mp4": Writer("a movie", ("matplotlib", "imageio_ffmpeg")),
    ".png": Writer("a figure", ("matplotlib",)),
    ".svg": Writer("a figure", ("matplotlib",)),
    ".rrd": Writer("a rerun recording", ("rerun",)),
}


def writer_of(path: str | os.PathLike[str]) -> Writer | None:
    """The writer of ``path``'s suffix (case ignored), or None for a suffix rrbody does not know."""
    return WRITERS.get(Path(os.fspath(path)).suffix.lower())


def require_writer(writer: Writer, *, name: str) -> None:
    """Raise :class:`~rrbody.model.extras.MissingExtraError` (an ImportError naming the extra to
    install) unless every package ``writer`` imports is importable; ``name`` is the output's option
    or parameter, shown in the message (``a movie (--movie) needs the optional package ...``)."""
    for module in writer.modules:
        require(module, purpose=f"{writer.what} ({name})")


def check_output(path: str | os.PathLike[str], *, name: str, suffixes: Sequence[str] | None = None,
                 force: bool = False, writer: Writer | None = None) -> Path:
    """One output before any work: the path writable, its suffix one of ``suffixes`` (None: any; then
    ``writer``, else the suffix's own writer, if it has one, writes it), that writer installed.
    Returns the path to write (:func:`~rrbody.model.io.check_writable`). ``ValueError`` naming
    ``name`` for a bad suffix or path; ``MissingExtraError`` for a missing writer."""
    final = check_writable(path, force=force, name=name)  # first: an empty path is that, not a bad suffix
    text = os.fspath(path)
    if suffixes is not None and not text.lower().endswith(tuple(s.lower() for s in suffixes)):
        raise ValueError(f"{name} must end in {' or '.join(suffixes)}, got {text!r}")
    chosen = writer if writer is not None else writer_of(text)
    if chosen is not None:
        require_writer(chosen, name=name)
    return final


#: one output for :func:`preflight`: (path or None, accepted suffixes or None) or, for a file that one
#: writer writes whatever its suffix, (path or None, None, that writer)
Output = tuple[str | os.PathLike[str] | None, Sequence[str] | None] | tuple[
    str | os.PathLike[str] | None, Sequence[str] | None, Writer]


def preflight(outputs: Mapping[str, Output], *, force: bool = False,
              inputs: Mapping[str, str | os.PathLike[str] | None] | None = None,
              needs: Iterable[tuple[str, str]] = ()) -> dict[str, Path]:
    """Check a run's outputs before anything is computed or written; return the given ones by name.

    ``outputs`` maps a name (``--out``) to ``(path, suffixes)`` or ``(path, suffixes, writer)``: path
    None (not asked for) is skipped; suffixes and writer as :func:`check_output`. ``inputs`` are files
    being read (an output may not be one of them). ``needs`` lists further ``(module, purpose)`` a
    run imports that is no file's writer (pymunk for the engine, rerun for a live viewer). Raises as
    :func:`check_output`."""
    checked: dict[str, Path] = {}
    for name, spec in outputs.items():
        path, suffixes = spec[0], spec[1]
        if path is not None:
            check_output(path, name=name, suffixes=suffixes, force=force, writer=spec[2] if len(spec) > 2 else None)
            checked[name] = Path(os.fspath(path))
    check_distinct(dict(checked), inputs or {})
    for module, purpose in needs:
        require(module, purpose=purpose)
    return checked
