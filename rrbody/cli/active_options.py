"""``rrbody simulate``'s active-body options: a free body's self-propulsion, its medium's drag and noise
(:class:`rrbody.model.active.Active`, docs/active.md), given to the Scene as its ``active``.

Every value is checked where it enters, by :class:`~rrbody.model.active.Active` itself (one rule for
Python and the command line), its message naming the option as typed. Options that would be ignored
in silence are refused, naming both: an active option on a driven body, ``--active-angle`` or
``--active-point`` without ``--active-force``, ``--seed`` without noise.
"""

from __future__ import annotations

import argparse
import dataclasses
import re
from typing import Any

from rrbody.cli.args import CliError, angle, float_list, given, integer, number, ranged
from rrbody.model.active import MAX_DIFFUSION, MAX_FORCE, MAX_SEED
from rrbody.model.checks import MAX_FRICTION, MAX_LENGTH, check_int, range_text

__all__ = ["add_active_options", "with_active", "ACTIVE_OPTIONS", "rename"]

#: option -> Active's parameter
ACTIVE_OPTIONS = {"--active-force": "force", "--active-angle": "angle", "--active-point": "point",
                  "--drag": "drag", "--rot-drag": "rot_drag", "--diffusion": "diffusion",
                  "--rot-diffusion": "rot_diffusion"}


def add_active_options(p: argparse.ArgumentParser) -> None:
    """The active group (free bodies, with --no-drive); each option's unit and range in its help
    (Active's own, :func:`rrbody.cli.args.ranged`)."""
    g = p.add_argument_group("active body (free bodies, with --no-drive; docs: Active bodies)")

    def add(opt: str, kind: Any, valid: str, text: str, **kw: Any) -> None:
        ranged(g.add_argument(opt, type=kind, default=None, help=f"{text}, {valid}" + kw.pop("tail", ""), **kw),
               valid)

    v = range_text(0, MAX_FORCE, unit="N")
    add("--active-force", number("--active-force", f" {v}"), v, "propulsion F fixed in the body frame")
    add("--active-angle", angle("--active-angle"), "any finite value", "its direction in the body frame, rad "
        "from the body's x axis ('pi/2', '90deg')", tail="; default 0 (with --active-force)")
    add("--active-point", float_list("--active-point", 2), f"each component {range_text(-MAX_LENGTH, MAX_LENGTH)} m",
        "where it acts, body frame from the centre of gravity (off the line through it, it torques the body)",
        metavar="X,Y", tail="; default 0,0 (with --active-force)")
    for opt, what in (("--drag", "the medium's translational drag rate gamma_t (force -m gamma_t v)"),
                      ("--rot-drag", "the medium's rotational drag rate gamma_r (torque -I gamma_r w)")):
        v = range_text(0, MAX_FRICTION, unit="1/s")
        add(opt, number(opt, f" {v}"), v, what, tail="; default 0")
    for opt, what, unit, drag in (("--diffusion", "translational noise D_t", "m^2/s", "--drag"),
                                  ("--rot-diffusion", "rotational noise D_r", "rad^2/s", "--rot-drag")):
        v = range_text(0, MAX_DIFFUSION, unit=unit)
        add(opt, number(opt, f" {v}"), v, what, tail=f"; default 0 (none); needs {drag} > 0")
    v = "an integer in [0, 2^63 - 1]"
    add("--seed", integer("--seed", " in [0, 2^63 - 1]"), v, "the noise's seed (with --diffusion or "
        "--rot-diffusion; the same seed gives the same run)")


def rename(msg: str, names: dict[str, str], *, anywhere: tuple[str, ...] = ()) -> str:
    """A library message in the command line's words: its leading parameter name (``names``' keys)
    becomes the option, and so does every occurrence of the names in ``anywhere``."""
    for name in sorted(names, key=len, reverse=True):
        if re.match(rf"{re.escape(name)}(?![\w\[-])", msg):
            msg = names[name] + msg[len(name):]
            break
    for name in sorted(anywhere, key=len, reverse=True):
        msg = re.sub(rf"(?<![\w-]){re.escape(name)}(?![\w-])", names[name], msg)
    return msg


_ACTIVE_NAMES = {**{p: o for o, p in ACTIVE_OPTIONS.items()}, "point[0]": "--active-point",
                 "point[1]": "--active-point"}


def _active_message(msg: str) -> str:
    return rename(msg, _ACTIVE_NAMES, anywhere=("drag", "rot_drag", "diffusion", "rot_diffusion"))


def with_active(scene: Any, a: argparse.Namespace) -> Any:
    """``scene`` with the typed active options as its ``active`` (and ``--seed`` as its ``seed``); the
    scene unchanged when none is typed. Raises CliError naming the option."""
    typed = [o for o in ACTIVE_OPTIONS if given(a, o)]
    if not typed:
        if given(a, "--seed"):
            raise CliError("--seed applies only with --diffusion or --rot-diffusion (it seeds their noise): drop "
                           "--seed or add the noise")
        return scene
    if scene.drive is not None:
        raise CliError(f"{typed[0]} applies to a free body only (with --no-drive): a driven body's pivot holds it; "
                       f"add --no-drive or drop {typed[0]}")
    if not given(a, "--active-force"):
        for opt in ("--active-angle", "--active-point"):
            if given(a, opt):
                raise CliError(f"{opt} applies only with --active-force (it places the propulsion): add "
                               f"--active-force N or drop {opt}")
    kw = {p: getattr(a, o[2:].replace("-", "_")) for o, p in ACTIVE_OPTIONS.items() if given(a, o)}
    kw.setdefault("force", 0.0)  # a medium alone (drag, noise) is a body without propulsion
    from rrbody.model.active import Active

    try:
        act = Active(**kw)
    except ValueError as e:
        raise CliError(_active_message(str(e))) from None
    extra: dict[str, Any] = {}
    if given(a, "--seed"):
        seed = a.seed
        try:
            seed = check_int("--seed", seed, 0, MAX_SEED)
        except ValueError as e:
            raise CliError(str(e)) from None
        if not act.noisy:
            raise CliError("--seed applies only with --diffusion or --rot-diffusion > 0 (it seeds their noise): "
                           "drop --seed or add the noise")
        extra["seed"] = seed
    try:
        return dataclasses.replace(scene, active=act, **extra)
    except ValueError as e:  # the Scene's own rules for an active body (the path that runs its noise)
        raise CliError(_active_message(str(e))) from None
