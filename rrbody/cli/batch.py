"""Batch mode: many quick answers from one process (``flip-time``, ``critical-h``, ``simulate --json``).

``rrbody flip-time --batch FILE`` (``-``: stdin) reads one JSON object of options per line, keys being
the long option names without dashes (``{"H": 0.2, "k": 0.05, "omega": 0.6}``; ``phi-dot0`` and
``phi_dot0`` both work), and writes one JSON result per line, in order, flushed as it goes, so a
caller can feed lines through a pipe and read each answer at once. A value is what the option takes:
a number, a string (``"pi/2"``, ``"180deg"``, ``"dry"``), ``true``/``false`` for a flag, a list for
``v0``; ``null`` leaves the default. Options given on the command line are defaults for every line.

Each line runs exactly the code of a single call with the same options, so its result is the same
JSON, bit for bit (only ``wall_s``, a timing, differs). A bad line yields
``{"error": "<the one-line message of a single call>", "line": N}`` (N counts from 1, blank lines and
``#`` comments included, which produce no output) and the other lines still run; so does a run
that fails for another reason (its error names the exception). Exit status: 0, or 2 if any line
failed. The process pays its start-up (interpreter, numba, kernels) once.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Iterator
from typing import IO

from rrbody.cli.args import CliError

__all__ = ["run_batch", "line_argv"]

_FORBIDDEN = {"batch", "help", "h", "version"}


def line_argv(obj: object) -> list[str]:
    """The command-line tokens that a JSON object of options stands for."""
    if not isinstance(obj, dict):
        raise CliError(f"a batch line must be a JSON object of options, got {type(obj).__name__}")
    out: list[str] = []
    for key, value in obj.items():
        name = str(key).lstrip("-").replace("_", "-")
        if name in _FORBIDDEN:
            raise CliError(f"--{name} is not allowed in a batch line")
        opt = f"--{name}"
        if value is None or value is False:
            continue
        if value is True:
            out.append(opt)
        elif isinstance(value, (list, tuple)):
            out.append(f"{opt}={','.join(_token(v, opt) for v in value)}")
        else:
            out.append(f"{opt}={_token(value, opt)}")
    return out


def _token(v: object, opt: str) -> str:
    if isinstance(v, bool) or isinstance(v, (dict, list)):
        raise CliError(f"{opt} must be a number or a string, got {json.dumps(v)}")
    if isinstance(v, float):
        return repr(v)  # shortest repr: float(repr(x)) == x, so a line and a single call see the same float
    return str(v)


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


def _lines(path: str) -> Iterator[str]:
    if path == "-":
        yield from iter(sys.stdin.readline, "")
        return
    try:
        fh: IO[str] = open(path)
    except OSError as e:
        raise CliError(f"--batch: cannot read {path!r}: {e.strerror}") from None
    with fh:
        yield from fh


def run_batch(parser: argparse.ArgumentParser, argv: list[str], args: argparse.Namespace,
              parse: Callable[..., argparse.Namespace],
              run_command: Callable[[argparse.Namespace], int]) -> int:
    """Run every line of ``args.batch`` as the command ``args.command`` with those options, through
    the same ``parse`` and ``run_command`` as a single call (passed in: cli.main imports this module)."""
    command = args.command
    if command == "simulate" and not args.json:
        raise CliError("--batch needs --json for simulate (one JSON summary per line)")
    base = [command, *_without_batch(argv[1:]), "--json"]
    failed = False
    for n, raw in enumerate(_lines(args.batch), start=1):
        text = raw.strip()
        if not text or text.startswith("#"):
            continue
        try:
            try:
                obj = json.loads(text)
            except json.JSONDecodeError as e:
                raise CliError(f"line {n} is not JSON: {e.msg} at column {e.colno}") from None
            line_args = parse(parser, [*base, *line_argv(obj)], repeats=True)
            line_args.batch = None
            line_args.batch_line = True
            run_command(line_args)
        except CliError as e:
            failed = True
            print(json.dumps({"error": str(e), "line": n}), flush=True)
        except BrokenPipeError:
            raise
        except Exception as e:  # noqa: BLE001 - one failing run must not take the other lines down
            failed = True
            print(json.dumps({"error": f"{type(e).__name__}: {e}", "line": n}), flush=True)
    return 2 if failed else 0
