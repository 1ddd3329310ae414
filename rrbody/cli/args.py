"""Argument helpers shared by every ``rrbody`` subcommand: the parser class, value parsers, the map
from option names onto the model's parameter names, and the rewriting of messages.

Ranges and units are not kept here: every numeric option names a parameter of
:data:`rrbody.model.checks.LIMITS`, whose range and unit appear in the option's help and whose check
runs with the option's name as the label. Imports stay light (argparse, difflib, the model's
checks): ``rrbody --help`` and the flip-time path pay for nothing else.
"""

from __future__ import annotations

import argparse
import difflib
import math
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

from rrbody.model.angles import parse_number
from rrbody.model.checks import LIMITS, check
from rrbody.model.laws import LAW_PARAMS

__all__ = ["CliError", "Parser", "OPTION_PARAMS", "emit", "ranged", "number", "integer", "angle", "float_list",
           "option_help", "check_options", "option_message", "preprocess_argv", "suggest", "commands", "subparser",
           "parse", "check_repeats", "given", "plain_text", "_angle", "_finite", "_float_list", "warn_later",
           "flush_warnings", "drop_warnings"]

#: warnings about values that parsed (a bare number that looks like degrees), held until the command has
#: checked all of its input (:func:`flush_warnings`): a command refused for bad input prints its one error
#: line and nothing else (:func:`drop_warnings`), whichever option was wrong
_PENDING: list[str] = []


def warn_later(text: str) -> None:
    """Hold the warning ``text`` until the command's input is checked (:func:`flush_warnings`)."""
    _PENDING.append(text)


def flush_warnings() -> None:
    """Print the held warnings, one line each on stderr (the command's input is good)."""
    for text in _PENDING:
        print(f"rrbody: warning: {text}", file=sys.stderr)
    _PENDING.clear()


def drop_warnings() -> None:
    """Forget the held warnings: the command is refused, and its error is its one line."""
    _PENDING.clear()


class CliError(ValueError):
    """A bad option value (reported as ``rrbody CMD: error: ...``, exit 2)."""


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line and raise :class:`CliError` instead of printing
    the usage and exiting, so that the command's own error path (and batch mode, per line) report
    them. Abbreviated options are off: ``--om`` is a typo to report, not ``--omega`` silently."""

    def __init__(self, *args: Any, **kw: Any) -> None:
        kw.setdefault("allow_abbrev", False)
        super().__init__(*args, **kw)

    def error(self, message: str) -> NoReturn:
        raise CliError(_rewrite_argparse(message))

    def format_help(self) -> str:
        """The help with reST markup made plain: descriptions and help texts may come from docstrings,
        whose ``code`` and :func:`roles` a terminal would show raw."""
        return plain_text(super().format_help())


_ROLE = re.compile(r":[a-z]+(?::[a-z]+)?:`~?([^`]+)`")
_DOUBLE = re.compile(r"``(.+?)``", re.S)  # help text is wrapped: a literal may span a line break
_SINGLE = re.compile(r"`([^`\n]+)`")


def plain_text(text: str) -> str:
    """``text`` without reST markup: roles (:func: and the like) and double backquotes are dropped, a
    single-backquoted word is put in plain quotes."""
    return _SINGLE.sub(r"'\1'", _DOUBLE.sub(r"\1", _ROLE.sub(r"\1", text)))


def _rewrite_argparse(message: str) -> str:
    """argparse says 'argument --H: ...'; rrbody says '--H ...' (option first, like every other error)."""
    if message.startswith("argument "):
        head, _, rest = message[len("argument "):].partition(": ")
        opt = head.split("/")[-1]
        return rest if rest.startswith(opt) else f"{opt}: {rest}"
    if message.startswith("the following arguments are required: "):
        return "missing required options: " + message.split(": ", 1)[1]
    return message


#: CLI option -> parameter of rrbody.model.checks.LIMITS (its range, unit and check)
OPTION_PARAMS: dict[str, str] = {
    "--H": "H", "--l": "l", "--R0": "R0", "--delta": "delta", "--omega": "omega", "--d": "d", "--k": "k",
    "--mu": "mu", "--g": "g", "--phi0": "phi0", "--phi-dot0": "phi_dot0", "--v0": "v0", "--spin0": "spin0",
    "--samples": "samples", "--rtol": "rtol", "--dt": "dt", "--iterations": "iterations",
    "--max-steps": "max_steps", "--t-max": "t_max", "--dt-out": "dt_out", "--tol": "tol", "--fps": "fps",
    "--movie-speed": "movie_speed", "--workers": "workers", "--batch-size": "batch_size",
    "--tilt": "tilt", "--downhill": "downhill", "--mu-static": "mu_static", "--sides": "sides",
    "--renorm": "renorm", "--d0": "d0", "--points": "points", "--theta-s": "theta_s",
    "--transient": "settle_periods",
}
#: parameter names in library messages -> the option a user typed
_PARAM_OPTIONS: dict[str, str] = {**{p: o for o, p in OPTION_PARAMS.items()}, "R": "--R0", "v0[0]": "--v0",
                                  "v0[1]": "--v0", "friction coefficient": "--k", "speed": "--movie-speed",
                                  "out": "--out", "movie": "--movie", "rerun": "--rerun", "body": "--body",
                                  "friction": "--friction", "friction_method": "--friction-method",
                                  "orientation": "--orientation", "accuracy": "--accuracy", "method": "--method",
                                  "quantity": "--quantity", "batch": "--batch", "resume": "--resume",
                                  "n_scan": "--n-scan", "stepper": "--stepper", "scheduler": "--scheduler",
                                  "pressure": "--pressure", "vertices": "--vertices", "polygon": "--body polygon",
                                  "transient": "--transient", "estimate": "--estimate",
                                  "t_max and periods": "--t-max",
                                  **{q: "--" + q.replace("_", "-") for q in LAW_PARAMS}}  # the law table's


def option_help(param: str, text: str, default: object = None) -> str:
    """Help text with the unit and the valid range of ``param`` (and the default, when one is set)."""
    d = "" if default is None else f"; default {default}"
    return f"{text}; {LIMITS[param].text()}{d}"


def _valid(option: str) -> str:
    """' in [lo, hi] unit' for an option with a range in the model's table, else ''."""
    param = OPTION_PARAMS.get(option)
    return f" {LIMITS[param].text()}" if param else ""


def ranged(action: argparse.Action, valid: str) -> argparse.Action:
    """Mark an option whose range is not the model's table (:data:`OPTION_PARAMS`) but another checked
    table's (a study's parameters): ``valid`` ('in [0, 1] m') is its range as its help shows it."""
    action.valid = valid  # type: ignore[attr-defined]
    return action


def number(option: str, valid: str | None = None) -> Callable[[str], float]:
    """argparse type: a finite float written as a decimal literal, finite as written (``1e400`` is
    refused, not read as inf) and not a nonzero literal that underflows to 0 (``1e-400``); range
    checks come later, from the model's table (or the table ``valid``, ' in [0, 1] m', comes from)."""
    def parse(text: str) -> float:
        try:
            return parse_number(text, name=option, valid=_valid(option) if valid is None else valid)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None

    parse.__name__ = "number"
    return parse


_INT = re.compile(r"^\s*[+-]?\d+\s*$", re.ASCII)


def integer(option: str, valid: str | None = None) -> Callable[[str], int]:
    """argparse type: an integer written as one (``1e3`` and ``1.0`` count, ``1.5`` does not); ``valid``
    as for :func:`number`."""
    def parse(text: str) -> int:
        if _INT.match(text):
            try:
                return int(text)  # exact, however many digits (up to Python's limit)
            except ValueError:
                pass
        try:
            v = parse_number(text, name=option)
        except ValueError:
            v = math.nan
        if not (math.isfinite(v) and v.is_integer()):
            raise argparse.ArgumentTypeError(f"{option} must be an integer"
                                             f"{_valid(option) if valid is None else valid}, got {text!r}")
        return int(v)

    parse.__name__ = "integer"
    return parse


def angle(option: str) -> Callable[[str], float]:
    """argparse type: an angle in rad (``pi/2``, ``-0.5*pi``, ``180deg``); warns on stderr when a
    bare number beyond 2 pi is a whole number, most likely degrees without the ``deg`` suffix (once the
    command's input is checked: :func:`warn_later`)."""
    def parse(text: str) -> float:
        from rrbody.model.angles import maybe_degrees, parse_angle

        try:
            v = parse_angle(text, name=option)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None
        param = OPTION_PARAMS.get(option)
        if param is not None and not _plain(text):
            # an expression ('100deg', '3pi/4') out of range is reported as typed, with its value in rad:
            # the range check further on sees only the number (1.7453292519943295)
            try:
                check(param, v, label=option)
            except ValueError:
                raise argparse.ArgumentTypeError(f"{option} must be {LIMITS[param].text()}, got {text.strip()} "
                                                 f"({v:.6g} rad)") from None
        if maybe_degrees(text, v):
            warn_later(f"{option} {text} is read as {v:g} rad ({v / (2 * math.pi):.3g} turns); for degrees "
                       f"write {text}deg")
        return v

    parse.__name__ = "angle"
    return parse


def _plain(text: str) -> bool:
    """True when ``text`` is a plain decimal number (its value is what was typed)."""
    try:
        parse_number(text, name="value")
    except ValueError:
        return False
    return True


def float_list(option: str, n: int) -> Callable[[str], tuple[float, ...]]:
    """argparse type: ``n`` comma-separated finite numbers."""
    def parse(text: str) -> tuple[float, ...]:
        parts = [s for s in text.replace(" ", "").split(",") if s]
        if len(parts) != n:
            raise argparse.ArgumentTypeError(f"{option} must be {n} finite comma-separated numbers, got {text!r}")
        try:
            return tuple(parse_number(s, name=option) for s in parts)
        except ValueError as e:
            raise argparse.ArgumentTypeError(f"{option} must be {n} finite comma-separated numbers, got {text!r}"
                                             f"{_reason(str(e))}") from None

    parse.__name__ = "list"
    return parse


def _reason(message: str) -> str:
    """The ': why' tail of a parse_number message ('' when there is none)."""
    head, sep, tail = message.rpartition("': ")
    return f": {tail}" if sep else ""


# names kept for callers of the old helpers
_finite = number
_float_list = float_list
_angle = angle("--phi0")


def check_options(args: argparse.Namespace, options: Sequence[str]) -> None:
    """Check every given numeric option against the model's table, named as the user typed it."""
    for opt in options:
        v = getattr(args, opt.lstrip("-").replace("-", "_"), None)
        if v is None:
            continue
        param = OPTION_PARAMS[opt]
        for x in (v if isinstance(v, (tuple, list)) else (v,)):
            check(param, x, label=opt)


#: a library hint ``force=True`` (also ``force=True / --force``, ``resume=True (--resume)``)
_KEYWORD = re.compile(r"\b([a-z_]+)=True(?: \((--[a-z-]+)\)| / (--[a-z-]+))?")


def shell_words(msg: str) -> str:
    """A library message's Python hints in the words of the command line: ``pass force=True`` becomes
    ``pass --force`` (a shell user has no keyword arguments)."""
    return _KEYWORD.sub(lambda m: m[2] or m[3] or "--" + m[1].replace("_", "-"), msg)


def option_message(msg: str, *, extended: bool = False) -> str:
    """Rewrite a library message '<name> must ...' so that it names the CLI option (and says --force
    where the library says force=True)."""
    msg = shell_words(msg)
    for name in sorted(_PARAM_OPTIONS, key=len, reverse=True):
        for sep in (" ", ": "):
            if msg.startswith(name + sep):
                opt = _PARAM_OPTIONS[name]
                if name == "H" and extended:
                    return "--l, --R0, --delta, --d: " + msg
                return opt + msg[len(name):]
    return msg


def suggest(word: str, choices: Sequence[str]) -> str:
    """' (did you mean --omega?)' for the closest choice, or ''."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]}?)" if close else ""


def preprocess_argv(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """Join ``--opt VALUE`` into ``--opt=VALUE`` when VALUE starts with '-' (``--phi0 -pi/2``,
    ``--phi0 -0.5*pi``, ``--k -1``): argparse would take such a value for an option and report
    'expected one argument'. A following token that is itself an option of the command is left alone."""
    takes_value: set[str] = set()
    known: set[str] = set()
    for a in parser._actions:  # argparse keeps no public list of a parser's options
        known.update(a.option_strings)
        if a.option_strings and a.nargs is None and not isinstance(a, argparse._StoreConstAction):
            takes_value.update(a.option_strings)
    out: list[str] = []
    i = 0
    while i < len(argv):
        tok = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if tok in takes_value and nxt is not None and nxt.startswith("-") and nxt.split("=")[0] not in known:
            out.append(f"{tok}={nxt}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def subparser(parser: argparse.ArgumentParser, name: str | None) -> argparse.ArgumentParser | None:
    """The parser of subcommand ``name`` (None if there is none)."""
    for a in parser._actions:  # argparse has no public accessor for its subparsers
        if isinstance(a, argparse._SubParsersAction):
            return a.choices.get(name) if name else None
    return None


def commands(parser: argparse.ArgumentParser) -> list[str]:
    """The names of the parser's subcommands (empty without any)."""
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            return list(a.choices)
    return []


def check_repeats(sp: argparse.ArgumentParser, argv: list[str]) -> None:
    """A single-valued option given twice in ``argv`` is an error, not 'the last one wins' in silence."""
    once = {o: a for a in sp._actions for o in a.option_strings
            if not isinstance(a, (argparse._AppendAction, argparse._HelpAction))}
    seen: set[int] = set()  # ids of the actions already set
    for tok in argv:
        a = once.get(tok.split("=", 1)[0])
        if a is None:
            continue
        if id(a) in seen:
            raise CliError(f"{a.option_strings[-1]} is given twice; give it once")
        seen.add(id(a))


def parse(parser: argparse.ArgumentParser, argv: list[str], *, repeats: bool = False) -> argparse.Namespace:
    """Parse ``argv`` with rrbody's conventions (negative values, did-you-mean, no silent repeats;
    ``repeats=True``: later values win, as batch lines override command-line defaults); raises CliError."""
    if argv and not argv[0].startswith("-") and argv[0] not in commands(parser):
        raise CliError(f"unknown command {argv[0]!r}{suggest(argv[0], commands(parser))}; "
                       f"commands: {', '.join(commands(parser))}")
    sp = subparser(parser, argv[0]) if argv else None
    if sp is not None:
        argv = [argv[0], *preprocess_argv(sp, argv[1:])]
        if not repeats:
            check_repeats(sp, argv[1:])
    args, extra = parser.parse_known_args(argv)
    unknown = [x for x in extra if x.startswith("-")] or extra
    if unknown:
        opts = [o for a in (sp or parser)._actions for o in a.option_strings]
        word = unknown[0].split("=")[0]
        raise CliError(f"unknown option {word}{suggest(word, opts)}" if word.startswith("-")
                       else f"unexpected argument {word!r}")
    if sp is not None:
        names = {o: a.option_strings[-1] for a in sp._actions for o in a.option_strings}
        args._given = frozenset(names[t.split("=", 1)[0]] for t in argv[1:] if t.split("=", 1)[0] in names)
    return args


def given(args: argparse.Namespace, option: str) -> bool:
    """True when ``option`` (as ``--name``) was typed, on the command line or in a batch line, whatever its
    value: a default and an explicit value equal to it differ here (``--g 9.81`` with ``--k`` is a
    contradiction, leaving ``--g`` out is not)."""
    return option in getattr(args, "_given", ())


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> None:
    """Print a command's result: one JSON line with ``--json``, else the text."""
    import json

    if args.json:
        from rrbody.model.trajectory import jsonable

        print(json.dumps(jsonable(payload)), flush=bool(getattr(args, "batch_line", False)))
    else:
        print(text)
