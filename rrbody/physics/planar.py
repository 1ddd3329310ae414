"""The dry-friction wrench of planar contacts, for many bodies in one call (``rrbody.planar``).

A body's *footprint* is the union of its parts on the plane: circles, ellipses, convex polygons
(boxes), points; its normal load is spread over them as a pressure distribution says
(:mod:`rrbody.pressure`: uniform by default, a ring, an annulus, a Hertz patch, feet, any p(x, y)).
Geometry is in the body frame, from the body's centre of gravity, in metres. Each part may carry
its ``mass`` (kg): then each presses with its own weight over its own area, and a centre of gravity
(the origin) off the parts' centre of mass gets the linear pressure that centres the load on it
(:mod:`rrbody.physics.loads`); parts without masses share the load by area, as placed. :class:`Footprints`
stacks n bodies once; :meth:`Footprints.wrench` then takes their angles, velocities and spins and
returns the Coulomb friction force and torque of each, exact (the kernel of the pymunk plugin and of
the ODE path, :func:`rrbody.physics.contact.footprint_wrench`, in one compiled loop)::

    import numpy as np
    from rrbody import planar

    feet = planar.Footprints([
        [planar.circle(0.1)],                                        # a disk of radius 0.1 m
        [planar.box(0.2, 0.1)],                                      # a 0.2 m x 0.1 m box
        [planar.circle(0.05, (-0.1, 0.0)), planar.circle(0.05, (0.1, 0.0))],  # two disks, one body
    ])
    force, torque = feet.wrench(angle=[0.0, 0.3, 0.0],              # rad, body frame from world
                                velocity=[[1.0, 0.0], [0.0, 0.5], [0.2, 0.0]],  # m/s, world frame
                                spin=[10.0, 0.0, -3.0],              # rad/s, counter-clockwise
                                mu=0.5, load=[9.81, 4.9, 2.0])       # -, N
    # force: (3, 2) N, world frame, at each centre of gravity; torque: (3,) N m about it

Frames and units: velocities are the centres of gravity's, in the world frame (m/s); ``angle`` turns
each body frame (where its parts were given) to the world frame (rad, counter-clockwise); the force
comes back in the world frame (N) and the torque about the centre of gravity (N m, counter-clockwise
positive). ``load`` is the normal force pressing each body on the plane (N: m g on a level plane).
Without slip (velocity and spin zero) kinetic friction has no direction and the wrench is zero.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from rrbody.model.bodies import Polygon
from rrbody.model.checks import check_nonnegative, check_positive, check_real
from rrbody.model.pressure import Pressure, as_pressure
from rrbody.physics import contact as C
from rrbody.physics.batch import batch_wrench, stack
from rrbody.physics.footprint import ICR_NODES, Part, apply_pressure, ellipse_part, point_part, polygon_part

__all__ = ["circle", "ellipse", "box", "polygon", "point", "Footprints", "Part", "is_part", "masses_given"]


def _xy(name: str, value: object) -> tuple[float, float]:
    try:
        x, y = value  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (x, y) in m, got {value!r}") from None
    return check_real(f"{name}[0]", x), check_real(f"{name}[1]", y)


def _massed(part: Part, mass: float | None) -> Part:
    """``part`` carrying ``mass`` (kg, > 0; None: none) in its row's LOAD_SHARE
    (:func:`rrbody.physics.loads.shares`)."""
    if mass is not None:
        part[0][C.LOAD_SHARE] = check_positive("mass", mass, unit="kg")
    return part


def circle(radius: float, centre: Sequence[float] = (0.0, 0.0), *, mass: float | None = None) -> Part:
    """A disk of ``radius`` (m, > 0) centred at ``centre`` (m, body frame from the centre of gravity);
    ``mass`` (kg, > 0) its own weight's mass, or None."""
    r = check_positive("radius", radius, unit="m")
    cx, cy = _xy("centre", centre)
    return _massed(ellipse_part(cx, cy, r, r, 0.0, ICR_NODES), mass)


def ellipse(a: float, b: float, centre: Sequence[float] = (0.0, 0.0), angle: float = 0.0, *,
            mass: float | None = None) -> Part:
    """An ellipse with semi-axes ``a`` (along ``angle``, rad from the body x axis) and ``b`` (m, > 0);
    ``mass`` (kg, > 0) or None."""
    cx, cy = _xy("centre", centre)
    return _massed(ellipse_part(cx, cy, check_positive("a", a, unit="m"), check_positive("b", b, unit="m"),
                                check_real("angle", angle), ICR_NODES), mass)


def polygon(vertices: Sequence[Sequence[float]], *, mass: float | None = None) -> Part:
    """A convex polygon, ``vertices`` (m, body frame from the centre of gravity, either orientation);
    ``mass`` (kg, > 0) or None."""
    Polygon(vertices=tuple(map(tuple, vertices)))  # type: ignore[arg-type]  # validates: ValueError naming vertices
    return _massed(polygon_part(np.array(vertices, dtype=float)), mass)


def box(width: float, height: float, centre: Sequence[float] = (0.0, 0.0), angle: float = 0.0, *,
        mass: float | None = None) -> Part:
    """A rectangle ``width`` x ``height`` (m, > 0), ``width`` along ``angle`` (rad from the body x axis);
    ``mass`` (kg, > 0) or None."""
    w = 0.5 * check_positive("width", width, unit="m")
    h = 0.5 * check_positive("height", height, unit="m")
    cx, cy = _xy("centre", centre)
    a = check_real("angle", angle)
    c, s = math.cos(a), math.sin(a)
    corners = [(w, -h), (w, h), (-w, h), (-w, -h)]
    return _massed(polygon_part(np.array([(cx + c * x - s * y, cy + s * x + c * y) for x, y in corners])), mass)


def point(x: float, y: float, *, mass: float | None = None) -> Part:
    """All of the part's load at one point (m, body frame): a foot, a point mass; ``mass`` (kg, > 0) or None."""
    return _massed(point_part(check_real("x", x), check_real("y", y)), mass)


def masses_given(parts: Sequence[Part]) -> bool:
    """Whether every part of one body carries a mass (True) or none does (False); ValueError when only
    some do (the others' share of the weight would be unknown; the caller names the body)."""
    has = [p[0][C.LOAD_SHARE] > 0.0 for p in parts]
    if any(has) and not all(has):
        raise ValueError(f"mass must be given for every part of a body or for none, got masses on {sum(has)} of "
                         f"{len(has)} parts (part {has.index(False)} has none)")
    return all(has)


def _column(name: str, value: object, n: int, unit: str, *, lo: float = -math.inf) -> np.ndarray:
    """``value`` as a float array of shape (n,) (a scalar is broadcast), finite and >= lo."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of {n} numbers ({unit}), got {value!r}") from None
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) ({unit}, one per body) or be a number, got shape {a.shape}")
    bad = ~(np.isfinite(a) & (a >= lo))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        valid = "finite" if lo == -math.inf else f"finite and >= {lo:g}"
        raise ValueError(f"{name}[{i}] must be {valid} ({unit}), got {a[i]!r}")
    return np.ascontiguousarray(a)


class Footprints:
    """The footprints of n bodies, stacked once for :meth:`wrench`.

    Parameters
    ----------
    bodies : sequence
        One entry per body: a part (:func:`circle`, :func:`box`, ...) or a list of parts (their
        union; overlapping parts count twice), body frame from the centre of gravity (m).
    pressure : Pressure, str or sequence of them
        How each body's load is spread (:mod:`rrbody.pressure`, or its text form ``"ring:0.05"``):
        one for all or one per body; default uniform: each part's own weight over its area where
        the parts carry masses (centred on the origin, the centre of gravity, by a linear pressure if
        their centre of mass is elsewhere), else by area (parts without area, points, share it equally).
    """

    def __init__(self, bodies: Sequence[Part | Sequence[Part]], pressure: Pressure | str | Sequence[Pressure | str]
                 = "uniform") -> None:
        bodies = list(bodies)
        if not bodies:
            raise ValueError("bodies must list at least one body (a part or a list of parts), got none")
        if isinstance(pressure, (Pressure, str)):
            pressures = [as_pressure(pressure)] * len(bodies)
        else:
            pressures = [as_pressure(p) for p in pressure]
            if len(pressures) != len(bodies):
                raise ValueError(f"pressure must be one profile or one per body ({len(bodies)}), got {len(pressures)}")
        feet = []
        for i, (parts, p) in enumerate(zip(bodies, pressures)):
            parts = [parts] if is_part(parts) else list(parts)  # type: ignore[list-item]
            if not parts or not all(is_part(q) for q in parts):
                raise ValueError(f"bodies[{i}] must be a part or a non-empty list of parts (rrbody.planar.circle, "
                                 f"box, polygon, ellipse, point), got {parts!r}")
            try:
                shapes, geo, *_ = apply_pressure(parts, p, balance=masses_given(parts))
            except ValueError as e:
                raise ValueError(f"bodies[{i}]: {e}") from None
            feet.append((shapes, geo))
        self.n = len(feet)
        self._shapes, self._geo, self._ranges = stack(feet)

    def wrench(self, angle: object, velocity: object, spin: object, *, mu: object = 1.0, load: object = 1.0,
               v_eps: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """(force, torque) of Coulomb friction on every body: force shape (n, 2) (N, world frame, at
        the centre of gravity), torque shape (n,) (N m about it, counter-clockwise positive).

        ``angle`` (rad), ``spin`` (rad/s), ``mu`` (>= 0) and ``load`` (N, >= 0) are arrays of shape
        (n,) or numbers for all; ``velocity`` (m/s, world frame, of the centres of gravity) has shape
        (n, 2). Elements of the footprint slower than ``v_eps`` (m/s, >= 0) feel no friction. Raises
        ValueError naming the argument, the entry and the valid range."""
        n = self.n
        try:
            v = np.asarray(velocity, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"velocity must be an array of shape ({n}, 2) (m/s), got {velocity!r}") from None
        if v.shape != (n, 2):
            raise ValueError(f"velocity must have shape ({n}, 2) (m/s, world frame, one row per body), "
                             f"got shape {v.shape}")
        a = _column("angle", angle, n, "rad")
        vx = _column("velocity[:, 0]", v[:, 0], n, "m/s")
        vy = _column("velocity[:, 1]", v[:, 1], n, "m/s")
        w = _column("spin", spin, n, "rad/s")
        scale = _column("mu", mu, n, "dimensionless", lo=0.0) * _column("load", load, n, "N", lo=0.0)
        eps = check_nonnegative("v_eps", v_eps, unit="m/s")
        out = np.empty((n, 3))
        batch_wrench(self._shapes, self._geo, self._ranges, a, vx, vy, w, eps, out)
        return out[:, :2] * scale[:, None], out[:, 2] * scale


def is_part(p: object) -> bool:
    """A part as :mod:`rrbody.physics.footprint` makes them: (row, geo, area, reach, mean, spread)."""
    return isinstance(p, tuple) and len(p) == 6 and isinstance(p[0], np.ndarray) and p[0].ndim == 1
