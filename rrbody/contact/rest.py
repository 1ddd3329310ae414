"""The operator of the plane step (:mod:`rrbody.contact.kernel`, the force pass): what acts on a body
between its loads and its friction, as REBOUNDx separates operators from forces. The rest rule (a
body every point of which friction stops within the step is stopped exactly, its rounding residue
zeroed the step after) and static friction (a body at rest stays exactly at rest while its load lies
in the contact's limit surface, :func:`rrbody.physics.limit.at_rest`; else it breaks away with the
maximum-dissipation wrench). All compiled; units SI, loads per unit mass in m/s^2 (torque m^2/s^2),
``out`` rows in N and N m (world frame).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact.columns import *  # noqa: F403 (the columns of the bodies array)
from rrbody.contact.lean import NO_REFCOUNT
from rrbody.model.laws import LAW_TABLE
from rrbody.physics.effects.laws import one_of
from rrbody.physics.limit import at_rest

__all__ = ["law_sticks", "is_static", "modes", "evaluated", "may_hold", "slow_enough", "stop", "held", "hold_or_break",
           "no_held", "no_break"]


#: law_sticks(law): whether the LAW column's ``law`` sticks (rrbody.model.laws.Law.sticks: dry, Stribeck): its force
#: stays finite at zero speed, so the rest rule and static friction act on a body under it
law_sticks = one_of(tuple(LAW_CODE[law.name] for law in LAW_TABLE if law.sticks))


@njit(cache=True, inline="always")
def is_static(j: int, bodies: np.ndarray) -> bool:
    """Whether static friction acts on body j: a law that sticks (dry), and governed by the rest rule
    (not a driven body: its joint holds it)."""
    return bodies[j, STATIC_COEFF] > 0.0 and bodies[j, REST_RULE] > 0.0 and law_sticks(bodies[j, LAW])


@njit(cache=True, inline="always")
def modes(i: int, j: int, got: np.ndarray, bodies: np.ndarray) -> tuple[bool, float, bool, bool]:
    """Body j's (row i of the read) standing in this step: whether static friction acts on it
    (:func:`is_static`), its rest-rule flag STOP, whether it is at rest (velocity and spin read exactly
    zero) and whether it turns on a held foot (:mod:`rrbody.contact.feet`; after a stop the rest rule
    zeroes the residue first)."""
    static = is_static(j, bodies)
    was = bodies[j, STOP]
    resting = got[i, 1] == 0.0 and got[i, 2] == 0.0 and got[i, 3] == 0.0
    feet = static and bodies[j, FEET] > 0.0 and was == 0.0 and not resting
    return static, was, resting, feet


@njit(cache=True, inline="always")
def evaluated(i: int, j: int, got: np.ndarray, bodies: np.ndarray) -> bool:
    """Whether :func:`_friction` evaluates body j's friction at its extrapolated velocity: not at rest
    (kinetic friction has no direction) nor turning on a held foot."""
    _, _, resting, feet = modes(i, j, got, bodies)
    return not (resting or feet)


@njit(cache=True, inline="always")
def may_hold(j: int, bodies: np.ndarray, fx: float, fy: float) -> bool:
    """False if static friction cannot hold the load force (fx, fy) (N, world) on dry body j: its
    magnitude per unit mass is above mu_s g cos(tilt) (STATIC_COEFF), the largest force static friction gives
    (:func:`rrbody.physics.limit.at_rest` tests the same before its limit-set test, on the body-frame
    components). The margin 1e-12 covers the rotation's rounding (a few ulps), so a False here is a
    False there: the test is skipped, with its deferral, only where its answer is known. Active bodies
    whose propulsion beats static friction then never wait for it (in a jammed cluster, half of
    1,000 bodies were deferred every step)."""
    m = bodies[j, MASS]
    lx = fx / m
    ly = fy / m
    mus = bodies[j, STATIC_COEFF]
    return lx * lx + ly * ly <= mus * mus * (1.0 + 1e-12)


@njit(cache=True, inline="always")
def slow_enough(i: int, j: int, vx: float, vy: float, w: float, dt: float, bodies: np.ndarray,
                 out: np.ndarray) -> bool:
    """The rest rule's test: every point of body j slower than the deceleration friction leaves along
    the motion (mu g, less the pull of the other forces in ``out[i]`` along it: a tilt's, the user's)
    times dt. Evaluated only where the limiter already cut the friction impulse."""
    speed = math.hypot(vx, vy)
    decel = bodies[j, FRICTION_COEFF]
    if speed > 0.0:  # (the direction first: m * speed underflows to 0 for a subnormal speed)
        decel -= (out[i, 0] * (vx / speed) + out[i, 1] * (vy / speed)) / bodies[j, MASS]
    return speed + abs(w) * bodies[j, REACH] <= decel * dt


@njit(cache=True, inline="always")
def stop(i: int, j: int, was: float, static: bool, vx: float, vy: float, w: float, dt: float, bodies: np.ndarray,
          out: np.ndarray) -> None:
    """The rest rule stops body j (row i of the read) in this step, its load held if ``static``: the
    positions still move with this step's velocity (as the exact motion would, to O(mu g dt^2)); the
    impulse cancels it, and the next step (``was`` > 0) sets the rounding residue exactly to zero."""
    if static:  # the load is held: at rest, no force but the stopping impulse
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
    if was > 0.0:
        bodies[j, STOP] = ZEROED
        bodies[j, PREV_VX] = 0.0
        bodies[j, PREV_VY] = 0.0
        bodies[j, PREV_SPIN] = 0.0
        return
    bodies[j, STOP] = STOPPING
    out[i, 0] -= bodies[j, MASS] * vx / dt
    out[i, 1] -= bodies[j, MASS] * vy / dt
    out[i, 2] -= bodies[j, MASS] * bodies[j, INERTIA_PER_MASS] * w / dt


@njit(cache=True)
def held(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
          out: np.ndarray) -> bool:
    """Whether static friction holds the load in ``out[i]`` (every force but friction: the user's,
    the tilt's) on dry body j at rest at angle alpha: it lies in the contact's limit surface
    (:func:`rrbody.physics.limit.at_rest`). The answer for the last load is kept: the same load at
    the same angle needs no new test."""
    m = bodies[j, MASS]
    lx = out[i, 0] / m
    ly = out[i, 1] / m
    lt = out[i, 2] / m
    if lx == bodies[j, HELD_LOAD_X] and ly == bodies[j, HELD_LOAD_Y] and lt == bodies[j, HELD_LOAD_TORQUE] \
            and alpha == bodies[j, HELD_ANGLE] \
            and bodies[j, HELD] >= 0.0:
        return bodies[j, HELD] > 0.0
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    _, _, _, held = at_rest(shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), ca * lx + sa * ly,
                            -sa * lx + ca * ly, lt, bodies[j, INERTIA_PER_MASS], bodies[j, STATIC_COEFF], 0.0)
    bodies[j, HELD] = 1.0 if held else 0.0
    bodies[j, HELD_LOAD_X] = lx
    bodies[j, HELD_LOAD_Y] = ly
    bodies[j, HELD_LOAD_TORQUE] = lt
    bodies[j, HELD_ANGLE] = alpha
    return held


@njit(cache=True)
def hold_or_break(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
                   out: np.ndarray) -> None:
    """Dry body j at rest under the load in ``out[i]``: static friction cancels it while it is held
    (the body stays exactly at rest), else ``out[i]`` becomes the break-away wrench of the
    maximum-dissipation rule (:func:`rrbody.physics.limit.at_rest`, kinetic friction). A load whose
    force alone is beyond static friction (:func:`may_hold`) breaks away without the limit-set test,
    whose answer is known (as in :func:`_friction`)."""
    if may_hold(j, bodies, out[i, 0], out[i, 1]) and held(i, j, alpha, bodies, shapes, geo, out):
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
        return
    m = bodies[j, MASS]
    ca = math.cos(alpha)
    sa = math.sin(alpha)
    lx = out[i, 0] / m
    ly = out[i, 1] / m
    ax, ay, aw, _ = at_rest(shapes, geo, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), ca * lx + sa * ly,
                            -sa * lx + ca * ly, out[i, 2] / m, bodies[j, INERTIA_PER_MASS], 0.0,
                            bodies[j, FRICTION_COEFF])
    out[i, 0] = m * (ca * ax - sa * ay)
    out[i, 1] = m * (sa * ax + ca * ay)
    out[i, 2] = m * bodies[j, INERTIA_PER_MASS] * aw


@njit(cache=True, **NO_REFCOUNT)
def no_held(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
             out: np.ndarray) -> bool:
    """:func:`_sweep`'s stand-in for :func:`held` (it defers the bodies that would call it)."""
    return False


@njit(cache=True, **NO_REFCOUNT)
def no_break(i: int, j: int, alpha: float, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
              out: np.ndarray) -> None:
    """:func:`_sweep`'s stand-in for :func:`hold_or_break`."""
    return
