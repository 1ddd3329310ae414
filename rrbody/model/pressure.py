"""Normal-pressure distributions of a contact: how a body's weight is spread over the plane.

A distribution is plain validated data; where its load goes is in the body frame, from the body's
centre of gravity, in metres. Friction is linear in the pressure, so each distribution is a sum of
parts whose dry-friction wrench is exact (:mod:`rrbody.physics.contact`):

- :func:`uniform` (the default): each shape's weight spread evenly over its own area, centred on the
  centre of gravity (linear where a centre of gravity set by hand needs it:
  :mod:`rrbody.physics.loads`);
- :func:`ring`: all of it on a circle (a cup's rim, a curling stone's running band);
- :func:`annulus`: spread evenly between two circles (a disk minus a disk);
- :func:`hertz`: p proportional to sqrt(1 - r^2/a^2) on a disk of radius a (a sphere, a rounded foot);
- :func:`points`: feet, each carrying its share of the weight (a finite sum of point contacts);
- :func:`field`: any p(x, y) >= 0 you give, sampled on the footprint.

In a static body on a level plane the centre of pressure lies under the centre of gravity: the
default sees to it from the shapes' masses and the centre of gravity (or refuses a body that would
tip); the other profiles are taken as given, which the centred ones (``centre=(0, 0)``, the default)
and symmetric feet satisfy; placing them elsewhere is allowed and means a moment the plane supplies.
Where the load must lie on the body (a ring inside its footprint, feet on it) is checked where the
footprint is known (:func:`rrbody.physics.footprint.apply_pressure`).

Text form (the command line's ``--pressure``): ``uniform``, ``ring:R``, ``annulus:RIN,ROUT``,
``hertz:A``, ``points:X,Y,SHARE;X,Y,SHARE;...`` (:func:`parse_pressure`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from dataclasses import field as _field

from rrbody.model.checks import MAX_LENGTH, MIN_LENGTH, check_choice, number_rows, range_text

__all__ = ["Pressure", "uniform", "ring", "annulus", "hertz", "points", "field", "parse_pressure", "as_pressure",
           "pressure_from_description",
           "PRESSURE_KINDS"]

PRESSURE_KINDS: tuple[str, ...] = ("uniform", "ring", "annulus", "hertz", "points", "field")


def _length(name: str, value: object, *, zero_ok: bool = False) -> float:
    """A radius (m): finite, in [MIN_LENGTH, MAX_LENGTH] (or 0 where allowed)."""
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        v = math.nan
    if not ((zero_ok and v == 0.0) or MIN_LENGTH <= v <= MAX_LENGTH):
        raise ValueError(f"{name} must be {range_text(MIN_LENGTH, MAX_LENGTH, zero_ok=zero_ok, unit='m')}, "
                         f"got {value!r}")
    return v


def _coord(name: str, value: object) -> float:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        v = math.nan
    if not abs(v) <= MAX_LENGTH:
        raise ValueError(f"{name} must be in [-{MAX_LENGTH:g}, {MAX_LENGTH:g}] m, got {value!r}")
    return v


def _centre(centre: object) -> tuple[float, float]:
    try:
        x, y = centre  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"centre must be a pair (x, y) in m (body frame, from the centre of gravity), "
                         f"got {centre!r}") from None
    return _coord("centre x", x), _coord("centre y", y)


@dataclass(frozen=True)
class Pressure:
    """A pressure distribution (build it with the functions of this module).

    ``kind`` is one of :data:`PRESSURE_KINDS`; ``radii`` its radii (m: ring (R,), annulus
    (inner, outer), hertz (a,)); ``centre`` its centre (m, body frame from the centre of gravity);
    ``feet`` rows (x, y, share) with shares summing to 1; ``density`` the user's p(x, y) and
    ``samples`` how many area elements sample it."""

    kind: str = "uniform"
    radii: tuple[float, ...] = ()
    centre: tuple[float, float] = (0.0, 0.0)
    feet: tuple[tuple[float, float, float], ...] = ()
    density: Callable[..., object] | None = _field(default=None, compare=False)
    samples: int = 0

    def __post_init__(self) -> None:
        check_choice("pressure", self.kind, PRESSURE_KINDS)

    @property
    def is_uniform(self) -> bool:
        return self.kind == "uniform"

    def describe(self) -> dict[str, object]:
        """Plain data for metadata and JSON (a user's p(x, y) by name only)."""
        out: dict[str, object] = {"kind": self.kind}
        if self.radii:
            out["radii"] = list(self.radii)
        if self.kind in ("ring", "annulus", "hertz"):
            out["centre"] = list(self.centre)
        if self.feet:
            out["feet"] = [list(f) for f in self.feet]
        if self.density is not None:
            out["density"] = getattr(self.density, "__name__", repr(self.density))
            out["samples"] = self.samples
        return out

    def text(self) -> str:
        """The command line's form (:func:`parse_pressure` reads it back); a p(x, y) has none."""
        if self.kind == "uniform":
            return "uniform"
        if self.kind == "points":
            return "points:" + ";".join(",".join(f"{v:g}" for v in f) for f in self.feet)
        if self.kind == "field":
            raise ValueError("a pressure field p(x, y) has no text form: pass it in Python (rrbody.pressure.field)")
        return f"{self.kind}:" + ",".join(f"{r:g}" for r in self.radii)


def uniform() -> Pressure:
    """The default: each shape's (part's) weight spread evenly over its own area (by area where the
    shapes carry no masses), its centre of pressure at the centre of gravity (linear where a centre of
    gravity set by hand needs it: :mod:`rrbody.physics.loads`)."""
    return Pressure()


def ring(radius: float, centre: Sequence[float] = (0.0, 0.0)) -> Pressure:
    """All the weight spread evenly on the circle of ``radius`` (m) about ``centre``."""
    return Pressure("ring", (_length("ring radius", radius),), _centre(centre))


def annulus(inner: float, outer: float, centre: Sequence[float] = (0.0, 0.0)) -> Pressure:
    """The weight spread evenly between the circles of radius ``inner`` and ``outer`` (m); inner = 0
    is a full disk."""
    rin = _length("annulus inner radius", inner, zero_ok=True)
    rout = _length("annulus outer radius", outer)
    if not rin < rout:
        raise ValueError(f"annulus inner radius must be in [0, {rout:g}) m (below the outer radius), got {inner!r}")
    return Pressure("annulus", (rin, rout), _centre(centre))


def hertz(a: float, centre: Sequence[float] = (0.0, 0.0)) -> Pressure:
    """Hertz's contact of a sphere: p proportional to sqrt(1 - r^2 / a^2) on the disk of radius ``a`` (m)."""
    return Pressure("hertz", (_length("hertz radius a", a),), _centre(centre))


def points(feet: Sequence[Sequence[float]]) -> Pressure:
    """Feet ``[(x, y, share), ...]`` (m, m, > 0): point contacts carrying shares of the weight, which
    are normalised to sum to 1 (give them as fractions, or as loads)."""
    try:
        rows = [tuple(f) for f in feet]
    except TypeError:
        raise ValueError(f"feet must be a list of (x, y, share), got {feet!r}") from None
    if not rows:
        raise ValueError("feet must hold at least one (x, y, share), got none")
    out = []
    for i, f in enumerate(rows):
        if len(f) != 3:
            raise ValueError(f"feet[{i}] must be (x, y, share), got {f!r}")
        x, y = _coord(f"feet[{i}] x", f[0]), _coord(f"feet[{i}] y", f[1])
        try:
            s = float(f[2])
        except (TypeError, ValueError):
            s = math.nan
        if not 0.0 < s < math.inf:
            raise ValueError(f"feet[{i}] share must be in (0, inf) (a fraction or a load), got {f[2]!r}")
        out.append((x, y, s))
    total = sum(f[2] for f in out)
    return Pressure("points", feet=tuple((x, y, s / total) for x, y, s in out))


def field(density: Callable[..., object], samples: int = 4096) -> Pressure:
    """Any pressure ``density(x, y) >= 0`` (x, y arrays in m, body frame from the centre of gravity;
    any units: it is normalised), sampled on the footprint by about ``samples`` area elements
    (a Gauss rule on each part: spectrally accurate for a smooth p)."""
    if not callable(density):
        raise ValueError(f"density must be a callable p(x, y), got {density!r}")
    if isinstance(samples, bool) or not isinstance(samples, int) or not 16 <= samples <= 10**6:
        raise ValueError(f"samples must be an integer in [16, 1e6], got {samples!r}")
    return Pressure("field", density=density, samples=samples)


def as_pressure(value: object) -> Pressure:
    """A :class:`Pressure` as given, or read from its text form (:func:`parse_pressure`)."""
    if isinstance(value, Pressure):
        return value
    if isinstance(value, str):
        return parse_pressure(value)
    raise ValueError(f"pressure must be a rrbody.pressure distribution (uniform(), ring(R), annulus(RIN, ROUT), "
                     f"hertz(A), points(FEET), field(P)) or its text form such as 'ring:0.05', got {value!r}")


def pressure_from_description(desc: dict[str, object] | None) -> Pressure:
    """Inverse of :meth:`Pressure.describe` (None: uniform). A user's p(x, y) cannot be rebuilt from
    its name: ValueError."""
    if desc is None:
        return uniform()
    kind = desc.get("kind")
    if kind == "points":
        return points(desc["feet"])  # type: ignore[arg-type]
    if kind in ("ring", "annulus", "hertz"):
        return {"ring": ring, "annulus": annulus, "hertz": hertz}[kind](*desc["radii"], centre=desc["centre"])  # type: ignore
    if kind == "uniform":
        return uniform()
    raise ValueError(f"pressure {kind!r} cannot be rebuilt from a description (a p(x, y) is code): pass it again")


def parse_pressure(text: str) -> Pressure:
    """The command line's ``--pressure``: ``uniform``, ``ring:R``, ``annulus:RIN,ROUT``, ``hertz:A`` or
    ``points:X,Y,SHARE;...`` (metres)."""
    kind, _, args = str(text).strip().partition(":")
    usage = "uniform, ring:R, annulus:RIN,ROUT, hertz:A or points:X,Y,SHARE;X,Y,SHARE;..."
    if kind == "uniform" and not args:
        return uniform()
    try:
        if kind == "points":
            feet = number_rows(args)
        else:
            nums = [float(v) for v in args.split(",")] if args else []
    except ValueError:
        raise ValueError(f"pressure must be one of {usage}, got {text!r}") from None
    need = {"ring": 1, "annulus": 2, "hertz": 1}
    if kind != "points" and (kind not in need or len(nums) != need[kind]):
        raise ValueError(f"pressure must be one of {usage}, got {text!r}")
    try:
        return points(feet) if kind == "points" else {"ring": ring, "annulus": annulus, "hertz": hertz}[kind](*nums)
    except ValueError as e:  # name the option's value too: "pressure 'ring:-1': ring radius must be ..."
        raise ValueError(f"pressure {text!r}: {e}") from None
