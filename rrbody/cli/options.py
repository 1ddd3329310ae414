"""The option groups that several subcommands share (scene, integrator) and the one function that
turns parsed options into a Scene (through :func:`rrbody.model.scene.scene_from_params`)."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from typing import Any

from rrbody.cli.args import (
    CliError,
    angle,
    check_options,
    float_list,
    given,
    integer,
    number,
    option_help,
    option_message,
    ranged,
)
from rrbody.model.checks import number_rows
from rrbody.model.laws import LAW_PARAMS, LAW_TABLE, LAWS
from rrbody.model.scene import FRICTION_METHODS, SCENE_PARAMS

__all__ = ["add_scene_options", "add_friction_options", "add_integrator_options", "add_accuracy_options",
           "scene_from_args", "scene_params",
           "SCENE_OPTIONS", "INTEGRATOR_OPTIONS", "STEPPERS", "stepper_option", "check_contradictions",
           "SIMULATE_OUTPUTS", "check_simulate_outputs", "typed", "echo_typed", "number_text", "DRIVE_OPTIONS",
           "add_drive_option"]

#: simulate's outputs: option -> (the suffix its writer needs, what the file holds)
SIMULATE_OUTPUTS = {"--out": ("", "trajectory CSV"), "--movie": (".mp4", "movie"),
                    "--rerun": (".rrd", "rerun recording")}
#: the numeric scene options (each names a parameter of the model's table)
SCENE_OPTIONS = ("--H", "--l", "--R0", "--delta", "--omega", "--d", "--k", "--mu", "--g", "--phi0", "--phi-dot0",
                 "--samples", "--v0", "--spin0")
#: --stepper's values: the keys of rrbody.integrate.loop.STEP_METHODS (tests/test_cli_stepper.py checks they
#: agree; spelled out here so that parsing the command line does not load the compiled core)
STEPPERS = ("auto", "dop853", "radau", "rodas")
INTEGRATOR_OPTIONS = ("--rtol", "--dt", "--iterations", "--max-steps", "--t-max")
#: the drive's, the friction's and the start's options, which critical-h takes too: option -> (its argparse
#: type's maker, default, help text, default as the help shows it)
DRIVE_OPTIONS: dict[str, tuple[Callable[[str], Callable[[str], float]], float | None, str, object]] = {
    "--omega": (number, None, "driving rate (required)", None),
    "--d": (number, 1.0, "driving radius", 1),
    "--k": (number, None, "friction k = mu g / d (viscous: gamma in 1/s); required unless --mu or --friction none",
            None),
    "--mu": (number, None, "friction coefficient (with --g and --d, instead of --k)", None),
    "--g": (number, 9.81, "gravity, with --mu", 9.81),
    "--phi0": (angle, math.pi, "initial angle of CM -> P: a number (rad) or 'pi', 'pi/2', '3pi/4', '-0.5*pi', "
                               "'180deg'", "pi"),
}


def add_drive_option(g: Any, opt: str, text: str | None = None) -> None:
    """Declare one of :data:`DRIVE_OPTIONS` on ``g`` (a parser or a group): its type, default, unit and
    range; ``text`` replaces its help's words where a command words it its own way."""
    kind, default, words, shown = DRIVE_OPTIONS[opt]
    g.add_argument(opt, type=kind(opt), default=default, help=option_help(opt[2:], text or words, shown))


def add_scene_options(p: argparse.ArgumentParser, *, free_bodies: bool = True) -> None:
    """Body, drive, friction and initial state (every option with its unit and range)."""
    g = p.add_argument_group("scene")
    g.add_argument("--body", choices=("rod", "disk", "ellipse", "box", "polygon"), default="rod",
                   help="rod: point mass on a massless rod (default); disk; ellipse; box (half-sides R0 (1 + delta) "
                        "and R0 (1 - delta)); polygon (--sides with circumradius --R0, or --vertices): exact friction")
    g.add_argument("--sides", type=integer("--sides"), default=None,
                   help=option_help("sides",
                                    "--body polygon: a regular polygon inscribed in the circle of radius --R0"))
    g.add_argument("--vertices", default=None, metavar="X,Y;X,Y;...",
                   help="--body polygon: the vertices of a convex polygon (m; the centroid becomes the CM)")
    g.add_argument("--H", type=number("--H"), help=option_help("H", "rod-mass geometry H = l/d (required for "
                                                                "--body rod unless --l); extended bodies derive H"))
    g.add_argument("--l", type=number("--l"), help=option_help("l", "distance CM -> P (rod: the rod length; "
                                                                "extended bodies: default 0, P at the centre)"))
    g.add_argument("--R0", type=number("--R0"), help=option_help("R0", "disk radius / ellipse mean semi-axis "
                                                                  "(required for --body disk, ellipse)"))
    g.add_argument("--delta", type=number("--delta"), default=0.0,
                   help=option_help("delta", "ellipse: R_A = R0 (1 + delta), R_B = R0 (1 - delta)", 0))
    g.add_argument("--orientation", choices=("x", "y"), default="x",
                   help="initial direction of the R_A semi-axis (default x)")
    for opt in ("--omega", "--d", "--k", "--mu", "--g"):
        add_drive_option(g, opt)
    add_friction_options(g, params=True)
    add_drive_option(g, "--phi0")
    g.add_argument("--phi-dot0", type=number("--phi-dot0"), default=None,
                   help=option_help("phi_dot0", "initial phi' (default: the impulsive start (omega/H) cos phi0)"))
    g.add_argument("--friction-method", choices=FRICTION_METHODS, default="auto",
                   help="area integration for extended bodies (auto: the wrench table for dry disks, the "
                        "instantaneous-centre quadrature for ellipses; table: the precomputed wrench, built "
                        "once per aspect ratio, seconds for an ellipse)")
    g.add_argument("--samples", type=integer("--samples"), default=4096,
                   help=option_help("samples", "area elements for --friction-method sampled", 4096))
    g.add_argument("--pressure", default=None, metavar="PROFILE",
                   help="how the weight presses on the plane (disk, ellipse; m, from the centre): uniform "
                        "(default), ring:R, annulus:RIN,ROUT, hertz:A (p ~ sqrt(1 - r^2/A^2)) or "
                        "points:X,Y,SHARE;X,Y,SHARE;... (feet); exact (docs: Contacts)")
    g.add_argument("--tilt", type=angle("--tilt"), default=0.0,
                   help=option_help("tilt", "the plane's angle from the horizontal (rad, or e.g. '10deg'): "
                                            "normal load m g cos(tilt), gravity pulls at the CM along it", 0))
    g.add_argument("--downhill", type=angle("--downhill"), default=0.0,
                   help=option_help("downhill", "direction of steepest descent, from the x axis", 0))
    g.add_argument("--mu-static", type=number("--mu-static"), default=None,
                   help=option_help("mu_static", "static friction (dry; default mu): a free body at rest stays "
                                                 "there while it holds the tilt's pull"))
    if free_bodies:
        g.add_argument("--no-drive", action="store_true", help="a free body: no drive, launched with --v0 and --spin0")
        g.add_argument("--v0", type=float_list("--v0", 2), default=(0.0, 0.0),
                       help=option_help("v0", "free body: CM velocity VX,VY (each component)", "0,0"))
        g.add_argument("--spin0", type=number("--spin0"), default=0.0,
                       help=option_help("spin0", "free body: initial spin", 0))


def add_friction_options(g: Any, *, params: bool = False) -> None:
    """``--friction``, its choices the law table's laws (:mod:`rrbody.model.laws`), and with ``params`` an
    option per law parameter the table declares (``--NAME``, with its unit and range)."""
    g.add_argument("--friction", choices=LAWS, default="dry",
                   help="friction law (default dry): " + "; ".join(f"{law.name}: {law.summary}" for law in LAW_TABLE))
    for q in LAW_PARAMS.values() if params else ():
        owners = ", ".join(law.name for law in LAW_TABLE if q in law.params)
        opt = "--" + q.name.replace("_", "-")
        ranged(g.add_argument(opt, type=number(opt, valid=" " + q.limit.text()), default=None,
                              help=f"--friction {owners}: {q.help}, {q.limit.text()}"), q.limit.text())


def add_accuracy_options(g: Any) -> None:
    """``--accuracy`` and ``--rtol`` (every command that integrates the ODE)."""
    g.add_argument("--accuracy", choices=("draft", "default", "paper"), default="default",
                   help="ODE tolerance preset: draft 1e-9, default 1e-13, paper 1e-14 (docs/accuracy.md)")
    g.add_argument("--rtol", type=number("--rtol"), default=None,
                   help=option_help("rtol", "ODE relative tolerance (overrides --accuracy)"))


def add_integrator_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("integrator")
    g.add_argument("--method", choices=("ode", "engine"), default="ode", help="direct ODE (default) or pymunk engine")
    add_accuracy_options(g)
    g.add_argument("--stepper", choices=STEPPERS, default=None,
                   help="ODE stepping method (--method ode only): auto (default) DOP853, switching to the implicit "
                        "Radau IIA (free bodies: RODAS4) where the run is stiff and back where it is not; dop853 "
                        "the explicit DOP853 throughout (slow or failing where stiff); radau the implicit Radau "
                        "IIA (order 5, analytic Jacobian) throughout, driven bodies only; rodas the linearly "
                        "implicit RODAS4 (order 4) throughout, its tolerance raised to at least 1e-11")
    g.add_argument("--dt", type=number("--dt"), default=None,
                   help=option_help("dt", "engine time step (default: from the fastest period)"))
    g.add_argument("--iterations", type=integer("--iterations"), default=None,
                   help=option_help("iterations", "engine constraint-solver iterations"))
    g.add_argument("--max-steps", type=integer("--max-steps"), default=50_000_000,
                   help=option_help("max_steps", "cap on integration steps (runaway guard)", "5e7"))
    g.add_argument("--t-max", type=number("--t-max"), default=None,
                   help=option_help("t_max", "horizon (flip-time: a cap; simulate: required)"))


def stepper_option(a: argparse.Namespace) -> dict[str, str]:
    """``{"stepper": ...}`` for the ODE path ({} if --stepper was not given); CliError if it was given with
    --method engine, which has a fixed time step and no stepping method to choose."""
    stepper = getattr(a, "stepper", None)
    if stepper is None:
        return {}
    if getattr(a, "method", "ode") == "engine":
        raise CliError(f"--stepper {stepper} applies to --method ode only (the engine steps with a fixed --dt); "
                       f"drop --stepper or use --method ode")
    return {"stepper": stepper}


def _value(a: argparse.Namespace, dest: str) -> Any:
    """The parsed value of ``dest`` (None where the command has no such option)."""
    return getattr(a, dest, None)


def check_contradictions(a: argparse.Namespace) -> None:
    """Refuse options that contradict each other, naming both: an option whose value would be ignored
    in silence because of another one (``--friction none`` with ``--k``). Only options typed count
    (:func:`rrbody.cli.args.given`), not defaults; each rule applies where the command has both options.
    Raises CliError."""
    def both(x: str, y: str, why: str, fix: str) -> CliError:
        return CliError(f"{x} and {y} contradict each other: {why}; {fix}")

    friction = _value(a, "friction")
    if friction == "none" and given(a, "--friction"):
        for opt in ("--k", "--mu", "--g"):
            if given(a, opt):
                raise both("--friction none", opt, f"without friction {opt} has no effect",
                           f"drop {opt} or choose --friction {' or '.join(n for n in LAWS if n != 'none')}")
    if given(a, "--k") and given(a, "--mu"):
        raise both("--k", "--mu", "they are alternatives (k = mu g / d)", "give one of them")
    if given(a, "--g") and not given(a, "--mu"):
        raise CliError("--g applies only with --mu (k = mu g / d); with --k, or with neither, it has no effect: "
                       "drop --g or give --mu")
    method = _value(a, "method")
    if method == "ode":
        for opt in ("--dt", "--iterations"):
            if given(a, opt):
                raise both(opt, "--method ode", "the ODE path chooses its own steps",
                           f"drop {opt} or use --method engine")
    elif method == "engine":
        for opt in ("--rtol", "--accuracy"):
            if given(a, opt):
                raise both(opt, "--method engine", "the engine steps with a fixed --dt",
                           f"drop {opt} or use --method ode")
    body = _value(a, "body")
    for opt, kinds in (("--R0", ("disk", "box", "polygon", "ellipse")), ("--delta", ("box", "ellipse")),
                       ("--sides", ("polygon",)), ("--vertices", ("polygon",))):
        if body is not None and body not in kinds and given(a, opt):
            raise both(opt, f"--body {body}" + ("" if given(a, "--body") else " (the default)"),
                       f"{opt} applies to --body {' or '.join(kinds)} only", f"drop {opt} or choose --body {kinds[-1]}")
    if _value(a, "no_drive") is False:
        for opt in ("--v0", "--spin0"):
            if given(a, opt):
                raise CliError(f"{opt} applies to a free body only (with --no-drive); a driven body starts from "
                               f"--phi0 and --phi-dot0: drop {opt} or add --no-drive")
    if hasattr(a, "movie") and not _value(a, "movie"):
        for opt in ("--fps", "--movie-speed", "--movie-arrows"):
            if given(a, opt):
                raise CliError(f"{opt} applies only with --movie: add --movie FILE.mp4 or drop {opt}")


def scene_params(a: argparse.Namespace) -> dict[str, Any]:
    """The parsed scene options as keyword arguments of scene_from_params (None: not given)."""
    kw = {k: getattr(a, k) for k in SCENE_PARAMS if getattr(a, k, None) is not None}
    if "vertices" in kw:
        try:
            kw["vertices"] = tuple(number_rows(kw["vertices"]))
        except ValueError:
            raise CliError(f"--vertices must be X,Y;X,Y;... (numbers, m), got {kw['vertices']!r}") from None
    if "v0" in kw:
        kw["v0"] = tuple(kw["v0"])
    return kw


def scene_from_args(a: argparse.Namespace, *, required: tuple[str, ...] = ()) -> Any:
    """A validated Scene from parsed options. Every option is checked before anything runs; every
    missing required option is named at once; errors name the option as typed."""
    from rrbody.model.checks import MissingParameters
    from rrbody.model.scene import scene_from_params

    check_options(a, [o for o in (*SCENE_OPTIONS, *INTEGRATOR_OPTIONS) if hasattr(a, o[2:].replace("-", "_"))])
    check_contradictions(a)
    missing = [o for o in required if getattr(a, o[2:].replace("-", "_"), None) is None]
    try:
        scene = scene_from_params(**scene_params(a))
    except MissingParameters as e:
        names = [{"k": "--k (or --mu)"}.get(n, "--" + n.replace("_", "-")) for n in e.names] + missing
        raise CliError(f"missing required options: {', '.join(names)}") from None
    except ValueError as e:
        raise CliError(option_message(str(e), extended=getattr(a, "body", "rod") != "rod")) from None
    if missing:
        raise CliError(f"missing required options: {', '.join(missing)}")
    return scene


def typed(args: argparse.Namespace, name: str, computed: float | None) -> float | None:
    """The option ``name`` (``H``, ``k``) as the user gave it, else ``computed`` (the scene's value).

    A scene stores what its parts need and derives the rest: the rod-mass body keeps l = H d and
    gives H = l^2 / (d l) back as 0.20000000000000004 for ``--H 0.2``, and k = mu g / d comes back
    from the friction's coefficient as 0.049999999999999996 for ``--k 0.05 --d 0.7``. An echo of the
    input shows what was typed; a value the user did not give (a disk's H) is the scene's."""
    v = getattr(args, name, None)
    return float(v) if v is not None else computed


def echo_typed(args: argparse.Namespace, scene: Any) -> dict[str, float | None]:
    """H and k of a driven ``scene`` for a JSON echo, each as typed where it was (:func:`typed`)."""
    return {"H": typed(args, "H", scene.H), "k": typed(args, "k", scene.k)}


def check_simulate_outputs(args: argparse.Namespace) -> dict[str, str]:
    """simulate's output paths by option, each checked before anything runs or is written
    (:func:`rrbody.model.outputs.preflight`): writable (a regular file or absent, not empty, not too
    long), the suffix its writer needs, that writer installed, no two of them one file, none of them
    the batch input being read; and the extras the run itself needs (pymunk for --method engine, rerun
    for the viewer)."""
    from rrbody.model.outputs import WRITERS, preflight

    specs: dict[str, Any] = {}
    for opt, (suffix, _) in SIMULATE_OUTPUTS.items():
        path = getattr(args, opt[2:], None)
        # --out is a CSV whatever its suffix (the renderers need theirs)
        specs[opt] = (path, None, WRITERS[".csv"]) if opt == "--out" else (path, (suffix,) if suffix else None)
    needs = []
    if args.rerun_spawn:
        needs.append(("rerun", "the rerun viewer (--rerun-spawn)"))
    if args.method == "engine":
        needs.append(("pymunk", "the engine path (--method engine)"))
    batch_input = getattr(args, "batch_input", None)
    checked = preflight(specs, force=args.force, inputs={"--batch": batch_input} if batch_input else {}, needs=needs)
    return {opt: getattr(args, opt[2:]) for opt in checked}


def number_text(x: float | None) -> str:
    """A number for a sentence (10 significant digits), or 'none'."""
    return "none" if x is None else f"{x:.10g}"
