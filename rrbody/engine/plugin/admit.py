"""A body's entry into :class:`rrbody.engine.plugin.plane.PlaneFriction`: the checks ``add`` makes, the row
of the kernel's ``bodies`` array it writes (columns :mod:`rrbody.contact.columns`), and the half kick
a newly added body gets at its first step (the staggered scheme's start, docs/engine.md).

These are the plugin's own steps, kept apart from its membership and stepping: each is a function of
the body and the numbers it is given, so that the plugin decides only where the row goes.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.contact.feet import feet_step
from rrbody.engine.plugin.footprints import Footprints
from rrbody.model.laws import LAW_TABLE, PLUGIN_AREA, Law, check_area, check_law_params, law_coded, law_named
from rrbody.physics import contact as C
from rrbody.physics.footprint import Footprint

__all__ = ["FRICTION_METHODS", "not_finite", "check_body", "add_law", "check_law", "body_row", "half_kick"]

#: ``add``'s friction_method: each step's exact wrench (a disk, a ring, a Hertz patch: its table), or the
#: footprint's wrench table
FRICTION_METHODS: tuple[str, ...] = ("auto", "table")


def not_finite(position: tuple[float, float] | None, angle: float, velocity: tuple[float, float],
               spin: float) -> str:
    """``"<quantity> must be finite (<unit>), got <value>"`` for the first non-finite one, else ``""``. The
    angle first: pymunk derives the position it reports from it (an infinite angle reads as a NaN position)."""
    for what, unit, val in (("angle", "rad", angle), ("position", "m", position), ("velocity", "m/s", velocity),
                            ("angular_velocity", "rad/s", spin)):
        if val is not None and not all(map(math.isfinite, val if isinstance(val, tuple) else (val,))):
            return f"{what} must be finite ({unit}), got {val!r}"
    return ""


def check_body(body: Any, space: Any, name: Callable[[Any], str]) -> None:
    """Raise ValueError unless ``body`` is a dynamic pymunk.Body in ``space`` with a positive, finite mass
    (kg) and moment (kg m^2) and a finite position (m), angle (rad), velocity (m/s) and spin (rad/s);
    ``name(body)`` names it in the messages."""
    import pymunk

    if not isinstance(body, pymunk.Body):
        raise ValueError(f"body must be a pymunk.Body, got {body!r}")
    if body.body_type != pymunk.Body.DYNAMIC:
        raise ValueError(f"body must be a dynamic pymunk.Body (kinematic and static bodies do not slide), "
                         f"got body_type {body.body_type!r}")
    if body.space is not space:
        raise ValueError("body must be added to the PlaneFriction's space first (space.add(body, *shapes))")
    m, moment = float(body.mass), float(body.moment)
    if not (0.0 < m < math.inf and 0.0 < moment < math.inf):
        raise ValueError(f"body {name(body)}: mass and moment must be positive and finite (kg, kg m^2), "
                         f"got mass {m!r}, moment {moment!r}: give its shapes a density or mass, or set "
                         f"body.mass/moment")
    p, v, a, w = body.position, body.velocity, body.angle, body.angular_velocity
    if not math.isfinite(p.x + p.y + v.x + v.y + a + w):  # one test on the common path (a huge sum: no error)
        bad = not_finite((p.x, p.y), a, (v.x, v.y), w)
        if bad:
            raise ValueError(f"body {name(body)}: {bad}")


def add_law(law: object, params: object, method: str, mu_static: object) -> tuple[Law, tuple[tuple[str, float], ...]]:
    """``add``'s friction law checked, and its parameters (:func:`rrbody.model.laws.check_law_params`): a law of
    the law table whose coefficient is a friction coefficient mu (a load-scaled law: dry), with a form for a
    footprint (:func:`rrbody.model.laws.check_area`); ``method`` "table" (the footprint's wrench table) holds
    dry friction's wrench only, and ``mu_static`` applies to a law that sticks. Each a ValueError naming the
    law (and the method or parameter), before the body is added."""
    spec = law_named(law, label="law")
    if not spec.load_scaled:
        ok = ", ".join(repr(x.name) for x in LAW_TABLE if x.load_scaled)
        raise ValueError(f"law must be one with a friction coefficient mu ({ok}) for add, got {law!r}: its "
                         f"coefficient is {spec.coeff_unit or 'none'}, not mu g (rrbody.engine.attach binds any law)")
    check_area(spec.name, PLUGIN_AREA, where="add integrates the body's footprint")
    if method == "table" and spec.name != "dry":
        raise ValueError(f"friction_method 'table' holds dry friction's wrench; friction {spec.name!r} has no form "
                         f"for it: use 'auto'")
    if mu_static is not None and not spec.sticks:
        sticky = ", ".join(repr(x.name) for x in LAW_TABLE if x.sticks)
        raise ValueError(f"mu_static applies to a law that sticks ({sticky}), got friction {spec.name!r}")
    return spec, check_law_params(spec.name, {} if params is None else params)


def check_law(law: float, coeff: float, params: tuple[float, ...]) -> Law:
    """The declaration of the LAW column's ``law`` (a code of the law table, :data:`K.LAW_CODE`), checked for
    the plugin: ValueError naming the law and the plugin's area method if the law has no form for a footprint
    (:func:`rrbody.model.laws.check_area`), naming the code if no law has it, and for ``params`` (the law's
    further parameters per unit mass) of another count than the law declares, or a coefficient under "none"."""
    spec = law_coded(law)
    check_area(spec.name, PLUGIN_AREA, where="the plugin integrates each body's footprint")
    if len(params) != len(spec.params):
        raise ValueError(f"params must be {len(spec.params)} numbers for friction {spec.name!r} "
                         f"({', '.join(q.name for q in spec.params) or 'none'}), got {params!r}")
    if spec.name == "none" and coeff != 0.0:
        raise ValueError(f"coeff must be 0 for friction 'none' (no friction), got {coeff!r}")
    return spec


def body_row(body: Any, *, law: float, coeff: float, footprint: Footprint, snap: bool,
             history: tuple[float, float, float, float] | None, v_eps: float, staggered: bool,
             static: float | None, g_plane: tuple[float, float], feet: Footprints, tabulate: bool,
             params: tuple[float, ...] = ()) -> np.ndarray:
    """The kernel's row (:mod:`rrbody.contact.columns`) of ``body`` with this friction law and footprint,
    before its footprint is placed (:meth:`Footprints.place` fills SHAPE_FIRST, SHAPE_END). ``law``: a code of the law
    table (:data:`K.LAW_CODE`), checked (:func:`check_law`: a ValueError, before any kernel runs);
    ``coeff``: mu g cos(tilt) for dry friction or gamma (1/s) for viscous; ``params``: the law's further
    parameters per unit mass (:func:`rrbody.model.laws.bound_params`); ``static``: mu_static g cos(tilt)
    (m/s^2; None: coeff for a law that sticks, dry friction, none for viscous); ``g_plane``: gravity's pull
    along the plane (m/s^2, world frame); ``history`` (vx, vy, spin, gap) when the caller has made the half
    kick; ``feet``: the plugin's footprint store, which gives a dry body its wrench table (``tabulate``: the
    footprint's own)."""
    spec = check_law(law, coeff, params)
    shapes, geo, reach, (gx, gy), jj = footprint
    m, moment = float(body.mass), float(body.moment)
    row = np.zeros(K.N_BODY)
    row[[K.MASS, K.INERTIA_PER_MASS, K.LAW, K.FRICTION_COEFF, K.REACH, K.REST_RULE, K.SLIP_EPS, K.LOAD_MEAN_X,
         K.LOAD_MEAN_Y, K.LOAD_SPREAD, K.STAGGERED]] = \
        m, moment / m, law, coeff, reach, 1.0 if snap else 0.0, v_eps, gx, gy, jj, 1.0 if staggered else 0.0
    row[[K.STATIC_COEFF, K.TILT_GX, K.TILT_GY]] = ((coeff if spec.sticks else 0.0) if static is None else static,
                                                   *g_plane)
    row[K.LAW_PARAMS:K.LAW_PARAMS + len(params)] = params
    row[K.HELD] = -1.0  # no load tested yet
    # two or more point feet: a foot at rest is held by static friction (rrbody.contact.feet)
    # (dry friction only: the other feet slide under dry friction's own kernel while one is held)
    row[K.FEET] = 1.0 if law == K.LAW_DRY and shapes.shape[0] > 1 and bool(np.all(shapes[:, C.KIND] == C.POINT)) \
        else 0.0
    if law == K.LAW_DRY:  # dry friction's wrench tables (the viscous law is linear: exact and cheap without one)
        row[K.TABLE_KIND], row[K.TABLE_START] = feet.friction_table(shapes, geo, tabulate)
    if history is not None:
        row[[K.PREV_VX, K.PREV_VY, K.PREV_SPIN, K.PREV_GAP]] = history
    return row


def half_kick(body: Any, j: int, dt: float, g_plane: tuple[float, float], bodies: np.ndarray, shapes: np.ndarray,
              geo: np.ndarray, tables: np.ndarray) -> None:
    """The half kick of a newly added body (row ``j`` of the kernel's arrays): its velocity (m/s, rad/s,
    world frame) becomes the one at t + dt/2 under friction and gravity's pull along the plane
    (``g_plane``, m/s^2), and its row keeps the velocity at t as the step's history (dt in s)."""
    v = body.velocity
    vx, vy, w = float(v.x), float(v.y), float(body.angular_velocity)
    if (vx, vy, w) != (0.0, 0.0, 0.0):
        gx, gy = g_plane  # gravity along a tilted plane: half a kick of it too
        row = bodies[j]
        alpha = float(body.angle)
        foot = -1
        if row[K.FEET] > 0.0 and row[K.STATIC_COEFF] > 0.0 and row[K.REST_RULE] > 0.0 and law_coded(row[K.LAW]).sticks:
            # on feet, launched with a foot at rest (or arriving there in the half step): held
            # (the kicked velocity moves the pose in the first step: its lever halfway through it)
            foot, ax, ay, tq = feet_step(shapes, int(row[K.SHAPE_FIRST]), int(row[K.SHAPE_END]), alpha,
                                         alpha + 0.5 * w * dt, alpha, vx, vy, w, vx, vy, w, gx, gy, 0.0,
                                         row[K.FRICTION_COEFF], row[K.STATIC_COEFF], row[K.INERTIA_PER_MASS],
                                         row[K.SLIP_EPS], 0.5 * dt, row[K.REACH], -1)
            aw, s = tq / row[K.INERTIA_PER_MASS], 1.0
            row[K.PINNED_FOOT] = foot + 1.0 if foot >= 0 else 0.0
        if foot == -1:
            ax, ay, aw, s = K.limited(j, math.cos(alpha), math.sin(alpha), vx, vy, w, vx, vy, w, 0.5 * dt,
                                      bodies, shapes, geo, tables, gx, gy, 0.0)
        h = 0.5 * dt * s
        body.velocity = (vx + h * ax + 0.5 * dt * gx, vy + h * ay + 0.5 * dt * gy)
        body.angular_velocity = w + h * aw
    bodies[j, [K.PREV_VX, K.PREV_VY, K.PREV_SPIN, K.PREV_GAP]] = vx, vy, w, 0.5 * dt
