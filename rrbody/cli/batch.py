"""Batch mode: many quick answers from one process (``flip-time``, ``critical-h``, ``simulate --json``).

``rrbody flip-time --batch FILE`` (``-``: stdin) reads one JSON object of options per line, keys being
the long option names without dashes (``{"H": 0.2, "k": 0.05, "omega": 0.6}``; ``phi-dot0`` and
``phi_dot0`` both work), and writes one JSON result per line, in order, flushed as it goes, so a
caller can feed lines through a pipe and read each answer at once. Options given on the command
line are defaults for every line.

A line obeys exactly the rules of the command line: one value per option, of that option's type
(a number or a string such as ``"pi/2"``, ``"180deg"`` or ``"dry"`` for a value, ``true``/``false``
for a flag, a list of numbers only for ``v0``), each option once (``t_max`` and ``t-max`` are one
option), ``null`` leaves the default. A number is read from its JSON text exactly as the same text on
the command line (``1e400`` is refused, not read as infinity; ``NaN`` and ``Infinity`` are not numbers).

Each line runs exactly the code of a single call with the same options, so its result is the same
JSON, bit for bit (only ``wall_s``, a timing, differs). A bad line yields
``{"error": "<the one-line message of a single call>", "line": N}`` (N counts from 1, blank lines and
``#`` comments included, which produce no output) and the other lines still run; so does a run
that fails for another reason (its error names the exception). Files and stdin are read as bytes
and decoded line by line: bytes that are not UTF-8 spoil only their line. A line longer than
:data:`MAX_LINE_BYTES` (1 MiB) is an error for that line, skipped with bounded memory; if no end of
line comes within :data:`MAX_SKIP_BYTES` (an endless line, such as ``--batch /dev/zero``) reading
stops there. Exit status: 0, or 2 if any line failed. The process pays its start-up (interpreter,
numba, kernels) once.
"""

from __future__ import annotations

import argparse
import codecs
import json
import os
import re
import sys
from collections.abc import Callable, Iterator, Mapping
from typing import Any

from rrbody.cli.args import CliError, check_repeats, drop_warnings, flush_warnings, subparser

__all__ = ["run_batch", "line_argv", "read_lines", "input_path", "MAX_LINE_BYTES", "MAX_SKIP_BYTES"]

#: the longest batch line, in bytes, its end of line included: a longer line is an error for that line
MAX_LINE_BYTES = 1 << 20
#: how far past the cap an over-long line is skipped looking for its end before reading stops (bytes)
MAX_SKIP_BYTES = 64 << 20
_CHUNK = 1 << 16  # bytes read at a time while skipping

_FORBIDDEN = {"batch", "help", "h", "version"}
_KEY = re.compile(r"^-{0,2}[A-Za-z][A-Za-z0-9_-]*$")


class _Num(str):
    """A JSON number kept as the text it was written as, so that a line passes it to the option's
    parser exactly as a command line would (``0.05``, ``1e400``, ``4096``)."""


def _no_constant(name: str) -> Any:
    raise CliError(f"{name} is not a finite number (JSON's NaN and Infinity are not accepted)")


def _pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object that names each key once (json.loads keeps the last of a repeated key in silence)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise CliError(f"{key!r} is given twice in this line; give each option once")
        out[key] = value
    return out


def parse_line(text: str) -> object:
    """The JSON value of one batch line: numbers kept as their text, each key once, no NaN/Infinity."""
    return json.loads(text, object_pairs_hook=_pairs, parse_float=_Num, parse_int=_Num,
                      parse_constant=_no_constant)


def _json(v: object) -> str:
    """A JSON value as written: numbers as their text."""
    if isinstance(v, _Num):
        return str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_json(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)}: {_json(x)}" for k, x in v.items()) + "}"
    return json.dumps(v)


def _show(v: object) -> str:
    """A JSON value as written, cut short for a message."""
    text = _json(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _kind(action: argparse.Action | None) -> str:
    """What value an option takes: 'flag', 'list' (comma-separated numbers), 'number' (a number or an
    expression), 'text' (a path or a choice), or 'unknown' (no such option: the parser says so)."""
    if action is None:
        return "unknown"
    if action.nargs == 0:
        return "flag"
    name = getattr(action.type, "__name__", "")
    if name == "list":
        return "list"
    if name in ("number", "integer", "angle"):
        return "number"
    return "text"


def line_argv(obj: object, actions: Mapping[str, argparse.Action] | None = None) -> list[str]:
    """The command-line tokens that a JSON object of options stands for, refusing what the command line
    could not say: a list for a one-value option, a number for a path or a choice, a value for a flag,
    one option twice (``t_max`` and ``t-max``). ``actions``: the command's options by option string
    (without it every value passes as text and the parser judges)."""
    if not isinstance(obj, dict):
        raise CliError(f"a batch line must be a JSON object of options, got {type(obj).__name__}")
    out: list[str] = []
    seen: dict[str, str] = {}
    for key, value in obj.items():
        if not _KEY.match(key):
            raise CliError(f"a batch line's keys are option names such as \"omega\" or \"t-max\", got {key!r}")
        name = key.lstrip("-").replace("_", "-")
        if name in _FORBIDDEN:
            raise CliError(f"--{name} is not allowed in a batch line")
        opt = f"--{name}"
        if opt in seen:
            raise CliError(f"{opt} is given twice in this line (as {seen[opt]!r} and {key!r}); give it once")
        seen[opt] = key
        if value is None:
            continue
        kind = _kind(actions.get(opt)) if actions is not None else "any"
        if kind == "flag":
            if not isinstance(value, bool):
                raise CliError(f"{opt} is a flag: give true or false, got {_show(value)}")
            if value:
                out.append(opt)
            continue
        if isinstance(value, bool) and kind != "unknown":
            raise CliError(f"{opt} takes a value, not {_show(value)}")
        if isinstance(value, dict):
            raise CliError(f"{opt} takes one value, not an object {_show(value)}")
        if isinstance(value, list):
            if kind not in ("list", "any") or not value or not all(isinstance(v, _Num) for v in value):
                what = "a list of numbers" if kind == "list" else "one value"
                raise CliError(f"{opt} takes {what}, got {_show(value)}")
            out.append(f"{opt}={','.join(value)}")
            continue
        if kind == "text" and isinstance(value, _Num):
            raise CliError(f"{opt} takes a string, got the number {value}")
        out.append(f"{opt}={value}")
    return out


def _without_batch(argv: list[str]) -> list[str]:
    out: list[str] = []
    skip = False
    for i, tok in enumerate(argv):
        if skip:
            skip = False
            continue
        if tok == "--batch":
            skip = i + 1 < len(argv)
            continue
        if tok.startswith("--batch="):
            continue
        out.append(tok)
    return out


def input_path(spec: str) -> str | None:
    """The file that ``--batch SPEC`` reads, for comparing outputs with it: the path, or for ``-``
    the file behind stdin (``/dev/stdin``, which names it on Linux and macOS; None where there is none)."""
    if spec == "-":
        return "/dev/stdin" if os.path.exists("/dev/stdin") else None
    return spec


def read_lines(readline: Callable[[int], bytes]) -> Iterator[tuple[int, str | None, str | None]]:
    """``(n, text, error)`` for every line that ``readline(limit)`` (a binary stream's) yields, n from 1:
    ``text`` decoded, or ``error`` (the line is not UTF-8, or longer than :data:`MAX_LINE_BYTES` with its
    end of line). Memory stays bounded by the cap: an over-long line is skipped in chunks; one that does
    not end within :data:`MAX_SKIP_BYTES` ends the reading with an error."""
    n = 0
    while True:
        raw = readline(MAX_LINE_BYTES + 1)
        if not raw:
            return
        n += 1
        if len(raw) > MAX_LINE_BYTES:
            size = len(raw)
            while not raw.endswith(b"\n"):
                raw = readline(_CHUNK)
                if not raw:
                    break
                size += len(raw)
                if size > MAX_LINE_BYTES + MAX_SKIP_BYTES:
                    yield n, None, (f"line {n} is longer than {MAX_LINE_BYTES} bytes (1 MiB), the longest a batch "
                                    f"line may be, and no end of line came in {size} bytes; stopped reading")
                    return
            yield n, None, (f"line {n} is {size} bytes long; a batch line may be at most {MAX_LINE_BYTES} bytes "
                            "(1 MiB), its end of line included")
            continue
        if n == 1 and raw.startswith(codecs.BOM_UTF8):
            raw = raw[len(codecs.BOM_UTF8):]
        if raw.lstrip().startswith(b"#"):  # a comment, whatever its bytes: no output
            yield n, "", None
            continue
        try:
            yield n, raw.decode("utf-8"), None
        except UnicodeDecodeError as e:
            yield n, None, (f"line {n} is not UTF-8: byte 0x{raw[e.start]:02x} at byte {e.start + 1} of the line; "
                            "the batch input must be UTF-8 text")


def _open(spec: str) -> tuple[Callable[[int], bytes], Callable[[], None]]:
    """``(readline, close)`` for ``--batch SPEC``: stdin's bytes for ``-``, else the file's."""
    if spec == "-":
        buf = getattr(sys.stdin, "buffer", None)
        if buf is not None:
            return buf.readline, lambda: None
        text_in = sys.stdin  # a text stream without bytes (an embedding program's): encode its lines back
        return (lambda limit: text_in.readline(limit).encode("utf-8", "surrogateescape")), lambda: None
    if not spec:
        raise CliError("--batch must be a file path or '-' (stdin), got ''")
    try:
        fh = open(spec, "rb")  # noqa: SIM115 - closed by the caller, after the last line
    except OSError as e:
        raise CliError(f"--batch: cannot read {spec!r}: {e.strerror}") from None
    except ValueError as e:  # a NUL in the path
        raise CliError(f"--batch: cannot read {spec!r}: {e}") from None
    return fh.readline, fh.close


def _check_command_line(command: str, args: argparse.Namespace) -> None:
    """What the command line alone gets wrong, refused before any line is read: simulate's outputs
    that are one file or the batch input itself (``--batch in.jsonl --out in.jsonl --force``)."""
    if command != "simulate":
        return
    from rrbody.cli.options import SIMULATE_OUTPUTS
    from rrbody.model.io import check_distinct

    outs = {o: getattr(args, o[2:], None) for o in SIMULATE_OUTPUTS}
    src = input_path(args.batch)
    name = "--batch - (standard input)" if args.batch == "-" else "--batch"
    try:
        check_distinct(outs, {name: src} if src else {})
    except ValueError as e:
        raise CliError(str(e)) from None


def run_batch(parser: argparse.ArgumentParser, argv: list[str], args: argparse.Namespace,
              parse: Callable[..., argparse.Namespace],
              run_command: Callable[[argparse.Namespace], int]) -> int:
    """Run every line of ``args.batch`` as the command ``args.command`` with those options, through
    the same ``parse`` and ``run_command`` as a single call (passed in: cli.main imports this module)."""
    command = args.command
    if command == "simulate" and not args.json:
        raise CliError("--batch needs --json for simulate (one JSON summary per line)")
    _check_command_line(command, args)
    sp = subparser(parser, command)
    actions = {o: a for a in sp._actions for o in a.option_strings} if sp is not None else None
    base = [command, *_without_batch(argv[1:]), "--json"]
    src = input_path(args.batch)
    readline, close = _open(args.batch)
    failed = False
    try:
        for n, text, error in read_lines(readline):
            if text is not None:
                text = text.strip()
                if not text or text.startswith("#"):
                    continue
            try:
                if error is not None:
                    raise CliError(error)
                try:
                    obj = parse_line(text or "")
                except json.JSONDecodeError as e:
                    raise CliError(f"line {n} is not JSON: {e.msg} at column {e.colno}") from None
                except RecursionError:
                    raise CliError(f"line {n} is nested too deeply to be an object of options") from None
                tokens = line_argv(obj, actions)
                if sp is not None:
                    check_repeats(sp, tokens)
                line_args = parse(parser, [*base, *tokens], repeats=True)
                line_args.batch = None
                line_args.batch_line = True
                line_args.batch_input = src
                run_command(line_args)
                flush_warnings()
            except CliError as e:
                failed = True
                drop_warnings()  # a bad line's answer is its error
                print(json.dumps({"error": str(e), "line": n}), flush=True)
            except BrokenPipeError:
                raise
            except Exception as e:  # noqa: BLE001 - one failing run must not take the other lines down
                failed = True
                print(json.dumps({"error": f"{type(e).__name__}: {e}", "line": n}), flush=True)
    finally:
        close()
    return 2 if failed else 0
