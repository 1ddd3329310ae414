"""One body's step of the plane step (:mod:`rrbody.contact.kernel` runs it over all bodies): its loads
(a tilt's pull, the active load), its friction at the predicted angle and the extrapolated velocity
(:mod:`rrbody.contact.accel`, with the limiter), the operator where it applies (:mod:`rrbody.contact.rest`:
the rest rule, static friction, feet), and its state for the next step (velocity history, a driven
body's driver). Compiled and inlined into the kernel's loops (a call would pass its arrays on the
stack for every body). Units SI; ``out`` rows are forces (N) and torques (N m) in the world frame,
``bodies`` rows are :mod:`rrbody.contact.columns`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.contact import rest as R
from rrbody.contact.accel import limited, limited_at
from rrbody.contact.columns import *  # noqa: F403 (the columns of the bodies array)
from rrbody.contact.feet import feet_step
from rrbody.physics.effects import active as act
from rrbody.physics.effects.drive_circular import sincos_reduced

__all__ = ["extrapolated", "load", "settle", "step_one", "friction", "evaluate", "commit", "driver", "idle",
           "same_bits"]


@njit(cache=True, inline="always")
def extrapolated(i: int, j: int, got: np.ndarray, bodies: np.ndarray, dt: float) -> tuple[float, float, float]:
    """The velocity (m/s, world) and spin (rad/s) friction and the active drag are evaluated at for body
    j (row i of the read): the staggered scheme's extrapolation to the half step from the last two
    steps, or the velocity read (no history yet, or the plain scheme)."""
    vx = got[i, 1]
    vy = got[i, 2]
    w = got[i, 3]
    gap = bodies[j, PREV_GAP]
    if gap > 0.0 and bodies[j, STAGGERED] > 0.0:
        g = 0.5 * dt / gap
        return (vx + g * (vx - bodies[j, PREV_VX]), vy + g * (vy - bodies[j, PREV_VY]),
                w + g * (w - bodies[j, PREV_SPIN]))
    return vx, vy, w


@njit(cache=True, inline="always")
def load(i, j, got, bodies, dt, out, active, noise):  # noqa: ANN001, ANN202
    """Add the loads on plugin body j (row i of the read) to ``out[i]``, which holds its own force and
    torque: the tilt's pull and the active load. Returns the angle friction and the active load are
    evaluated at (rad), its cosine and sine, and the velocity friction and the drag act at
    (:func:`extrapolated`)."""
    # a tilted plane: gravity's in-plane part acts at the centre of gravity in every step
    out[i, 0] += bodies[j, MASS] * bodies[j, TILT_GX]
    out[i, 1] += bodies[j, MASS] * bodies[j, TILT_GY]
    # the angle friction and the active load are evaluated at (pymunk moves the pose first)
    alpha = got[i, 0] + got[i, 3] * dt
    sa, ca = sincos_reduced(alpha)  # (one range reduction for both: cheaper than the library's pair, to 2 ulp)
    ex, ey, ew = extrapolated(i, j, got, bodies, dt)  # the velocity friction and the drag act at
    if active.shape[0] > 0:  # self-propulsion, a medium's drag and noise: a load as well
        fa, fb, fc = act.load(j, ca, sa, ex, ey, ew, bodies[j, MASS], bodies[j, INERTIA_PER_MASS], dt, active, noise)
        out[i, 0] += fa
        out[i, 1] += fb
        out[i, 2] += fc
    return alpha, ca, sa, ex, ey, ew


@njit(cache=True, inline="always")
def settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break, defer,  # noqa: ANN001, ANN202
            alpha, ca, sa, ex, ey, ew, have, ax, ay, aw):
    """Body j's friction on top of the loads in ``out[i]`` (:func:`friction`; with ``have``, its
    evaluation at (ex, ey, ew) is (ax, ay, aw) already); the friction added is kept (FRICTION_FX, FRICTION_FY,
    FRICTION_TORQUE). Returns 1 if the rest rule stops it, DEFER if it was deferred (nothing kept), else 0."""
    lx = out[i, 0]
    ly = out[i, 1]
    lt = out[i, 2]
    n = friction(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break, defer, alpha, ca, sa,
                  ex, ey, ew, have, ax, ay, aw)
    if n == DEFER:
        return n
    # what friction added to the load is the friction this step applies
    bodies[j, LOAD_FX] = lx
    bodies[j, LOAD_FY] = ly
    bodies[j, LOAD_TORQUE] = lt
    bodies[j, FRICTION_FX] = out[i, 0] - lx
    bodies[j, FRICTION_FY] = out[i, 1] - ly
    bodies[j, FRICTION_TORQUE] = out[i, 2] - lt
    return n


@njit(cache=True, inline="always")
def step_one(i, j, got, bodies, shapes, geo, tables, t, dt, out, active, noise):  # noqa: ANN001, ANN202
    """One plugin body's whole step in the limit-set loop (row ``i`` of the read, row ``j`` of
    ``bodies``), ``out[i]`` holding its own force and torque: the tilt's pull and the active load are
    added, then friction, static friction's limit-set test included (:func:`~rrbody.contact.rest.held`,
    :func:`~rrbody.contact.rest.hold_or_break`); the friction added is kept (FRICTION_FX, FRICTION_FY, FRICTION_TORQUE).
    Returns 1 if the rest rule stops it."""
    alpha, ca, sa, ex, ey, ew = load(i, j, got, bodies, dt, out, active, noise)
    return settle(i, j, got, bodies, shapes, geo, tables, t, dt, out, R.held, R.hold_or_break, False, alpha, ca, sa,
                   ex, ey, ew, False, 0.0, 0.0, 0.0)


@njit(cache=True, inline="always")
def friction(i, j, got, bodies, shapes, geo, tables, t, dt, out, held, hold_or_break,  # noqa: ANN001, ANN202
              defer, alpha, ca, sa, ex, ey, ew, have, ax0, ay0, aw0):
    """Add this step's friction on plugin body ``j`` (row ``i`` of the space's read) to ``out[i]``, which
    holds the load (the user's force and torque, and a tilt's pull); 1 if the rest rule stops it.
    Inlined (a call would pass its arrays on the stack for every body); ``held`` and ``hold_or_break``
    are :func:`~rrbody.contact.rest.held` and :func:`~rrbody.contact.rest.hold_or_break` (the limit-set loop,
    :func:`step_one`) or, with ``defer``,
    :func:`rrbody.contact.kernel._sweep`'s stand-ins; ``alpha`` (rad) is the angle friction is evaluated at, ``ca``,
    ``sa`` its
    cosine and sine, (ex, ey, ew) the velocity (:func:`extrapolated`); with ``have``, the friction there
    is (ax0, ay0, aw0) already. With ``defer`` (the lean sweep, which hands the bodies at rest under
    static friction to the limit-set loop itself, before their loads), a body about to stop under a load
    static friction may hold, or on a held foot whose spin runs out in this step, returns DEFER having
    changed nothing, for the caller to step it again without ``defer``. A body on feet otherwise takes
    its step here: turning on a held foot, or sliding (measured, 1,000 sliding disks on three point feet:
    3.3x the cost of uniform disks per step while every such body was deferred, 1.7x since)."""
    static, was, resting, feet = R.modes(i, j, got, bodies)
    vx = got[i, 1]
    vy = got[i, 2]
    w = got[i, 3]
    m0 = bodies[j, MASS]
    ax = ay = aw = 0.0
    s = 1.0
    stop = False
    # on feet: a foot at rest is held by static friction while the body turns about it. Everything up
    # to commit() changes no state (feet_step and the evaluation read none of what it writes), so a body
    # that needs the limit-set test can still be deferred, and the same numbers come out either way
    if not (resting or feet):
        ax, ay, aw, s, stop = evaluate(i, j, ca, sa, vx, vy, w, ex, ey, ew, dt, was, bodies, shapes, geo,
                                        tables, out, have, ax0, ay0, aw0)
        if stop and static and defer and R.may_hold(j, bodies, out[i, 0], out[i, 1]):
            return DEFER  # (a load static friction cannot hold needs no test: the body slides on, below)
    foot = -1
    fx = fy = tq = 0.0
    runs_out = False
    if feet:
        # near the spin's stop the extrapolated spin passes zero before the spin does: the current one then
        fex, fey, few = (vx, vy, w) if ew * w <= 0.0 else (ex, ey, ew)
        # (pymunk moves the pose with the velocity read, from got[i, 0] to alpha, then updates the
        # velocity, which moves the pose in the next step: its lever halfway through that one)
        foot, fx, fy, tq = feet_step(shapes, int(bodies[j, SHAPE_FIRST]), int(bodies[j, SHAPE_END]), alpha,
                                     alpha + 0.5 * w * dt, got[i, 0] + 0.5 * w * dt, vx, vy, w, fex, fey, few,
                                     out[i, 0] / m0, out[i, 1] / m0, out[i, 2] / m0,
                                     bodies[j, FRICTION_COEFF], bodies[j, STATIC_COEFF], bodies[j, INERTIA_PER_MASS],
                                     bodies[j, SLIP_EPS], dt, bodies[j, REACH], int(bodies[j, PINNED_FOOT]) - 1)
        # held, its spin runs out in this step: the whole body at rest where static friction holds its
        # load (the limit-set test), else, on a tilt, it swings back (the usual friction below)
        runs_out = foot >= 0 and w * (w + dt * (out[i, 2] / m0 + tq) / bodies[j, INERTIA_PER_MASS]) <= 0.0
        if runs_out and defer:
            return DEFER
        if runs_out or foot == -1:
            ax, ay, aw, s, stop = evaluate(i, j, ca, sa, vx, vy, w, fex, fey, few, dt, was, bodies, shapes, geo,
                                            tables, out, False, 0.0, 0.0, 0.0)
            # (the same test as in the branch above; one test after both branches compiled the L-shapes'
            # table look-up differently: results one ulp apart, measured)
            if stop and static and defer and R.may_hold(j, bodies, out[i, 0], out[i, 1]):
                return DEFER
    commit(j, bodies, vx, vy, w, alpha, ew, t, dt)
    if resting:
        # at rest: kinetic friction has no direction; static friction holds the load or lets go
        if static:
            hold_or_break(i, j, got[i, 0], bodies, shapes, geo, out)
        return 0
    if feet:
        if runs_out:
            bodies[j, PINNED_FOOT] = 0.0
            if held(i, j, got[i, 0], bodies, shapes, geo, out):
                R.stop(i, j, was, static, vx, vy, w, dt, bodies, out)
                return 1
        elif foot != -1:
            bodies[j, PINNED_FOOT] = foot + 1.0 if foot >= 0 else 0.0
            out[i, 0] += m0 * fx
            out[i, 1] += m0 * fy
            out[i, 2] += m0 * tq
            return 0
        bodies[j, PINNED_FOOT] = 0.0
    if stop and (not static or held(i, j, got[i, 0], bodies, shapes, geo, out)):
        # every point slower than decel dt: friction stops the body within this step (if a load
        # acts, only where static friction then holds it; else it slides on)
        R.stop(i, j, was, static, vx, vy, w, dt, bodies, out)
        return 1
    m = bodies[j, MASS] * s
    out[i, 0] += m * ax
    out[i, 1] += m * ay
    out[i, 2] += m * bodies[j, INERTIA_PER_MASS] * aw
    return 0


@njit(cache=True, inline="always")
def evaluate(i, j, ca, sa, vx, vy, w, ex, ey, ew, dt, was, bodies, shapes, geo, tables, out,  # noqa: ANN001, ANN202
              have, ax0, ay0, aw0):
    """Friction (ax, ay, alpha_dot) of body j at the velocity (ex, ey, ew), its limiter's factor s
    (:func:`limited`, under the load in ``out[i]``) and whether the rest rule may stop the body in this
    step: every point slower than the deceleration friction leaves, where the limiter cut the impulse
    or, the step after a stop, where what is left is rounding (friction, in its dead band, may then
    give no impulse to limit). With ``have``, (ax0, ay0, aw0) is the friction at (ex, ey, ew) already.
    Changes no state."""
    m0 = bodies[j, MASS]
    if have:
        ax, ay, aw, s = limited_at(ax0, ay0, aw0, j, ca, sa, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo, tables,
                                   out[i, 0] / m0, out[i, 1] / m0, out[i, 2] / (m0 * bodies[j, INERTIA_PER_MASS]))
    else:
        ax, ay, aw, s = limited(j, ca, sa, vx, vy, w, ex, ey, ew, dt, bodies, shapes, geo, tables, out[i, 0] / m0,
                                out[i, 1] / m0, out[i, 2] / (m0 * bodies[j, INERTIA_PER_MASS]))
    stop = (s < 1.0 or was == STOPPING) and bodies[j, REST_RULE] > 0.0 and R.law_sticks(bodies[j, LAW]) \
        and R.slow_enough(i, j, vx, vy, w, dt, bodies, out)
    return ax, ay, aw, s, stop


@njit(cache=True, inline="always")
def commit(j: int, bodies: np.ndarray, vx: float, vy: float, w: float, alpha: float, ew: float, t: float,
            dt: float) -> None:
    """Body j's state for the next step: this step's velocity (the history the next extrapolates
    from), the angle and spin friction is evaluated at, and a driven body's driver."""
    bodies[j, STOP] = 0.0
    bodies[j, PREV_VX] = vx
    bodies[j, PREV_VY] = vy
    bodies[j, PREV_SPIN] = w
    bodies[j, PREV_GAP] = dt
    bodies[j, EVAL_ANGLE] = alpha
    bodies[j, EVAL_SPIN] = ew
    if bodies[j, DRIVEN] > 0.0:
        driver(j, bodies, t, dt)


@njit(cache=True)
def driver(j: int, bodies: np.ndarray, t: float, dt: float) -> None:
    """The kinematic driver's position and velocity for the step from t to t + dt (s): its position
    update lands it exactly on P(t + dt) = d (cos, sin)(omega (t + dt)); its velocity, which the joint
    gives P, is P'(t + dt/2 + dt/2) plus the centripetal term w^2 dt/2 (P - CM) that pymunk's straight
    drift of a rotating body omits (staggered scheme), or P'(t + dt) (plain)."""
    t1 = t - bodies[j, DRIVE_T0] + dt
    w = bodies[j, DRIVE_OMEGA]
    d = bodies[j, DRIVE_D]
    c1 = math.cos(w * t1)
    s1 = math.sin(w * t1)
    if bodies[j, STAGGERED] > 0.0:
        th = w * (t1 + 0.5 * dt)
        ca = math.cos(bodies[j, EVAL_ANGLE])
        sa = math.sin(bodies[j, EVAL_ANGLE])
        c = 0.5 * dt * bodies[j, EVAL_SPIN] * bodies[j, EVAL_SPIN]
        vx = -d * w * math.sin(th) + c * (ca * bodies[j, ANCHOR_X] - sa * bodies[j, ANCHOR_Y])
        vy = d * w * math.cos(th) + c * (sa * bodies[j, ANCHOR_X] + ca * bodies[j, ANCHOR_Y])
    else:
        vx = -d * w * s1
        vy = d * w * c1
    bodies[j, DRIVE_VX] = vx
    bodies[j, DRIVE_VY] = vy
    bodies[j, DRIVE_PX] = d * c1 - dt * vx
    bodies[j, DRIVE_PY] = d * s1 - dt * vy


@njit(cache=True, inline="always")
def same_bits(x: float, y: float) -> bool:
    """x and y are the same float64, sign of a zero included (never for a NaN)."""
    return x == y and math.copysign(1.0, x) == math.copysign(1.0, y)


@njit(cache=True, inline="always")
def idle(i: int, j: int, got: np.ndarray, bodies: np.ndarray, dt: float) -> bool:
    """Whether :func:`step_one` would leave plugin body j (row i of the read) exactly as it is and apply no
    force (the limit-set loop is where :func:`rrbody.contact.kernel.plane_step` steps a body at rest under
    static friction): at rest (velocity and spin exactly zero) under static friction, no driver, no
    stop pending, the load (its own force and torque, a tilt's pull; no active load, which the caller
    checks) held by static friction by the answer kept for that load at that angle
    (:func:`~rrbody.contact.rest.held`), and every number :func:`commit` and :func:`settle` would write
    already there, bit for bit. The conditions are the branches step_one takes for such a body, written
    out; False wherever any of them does not hold."""
    static, was, resting, _ = R.modes(i, j, got, bodies)
    if (not (static and resting) or not same_bits(was, 0.0) or bodies[j, DRIVEN] > 0.0
            or not same_bits(bodies[j, DEFERRED], 0.0)):
        return False
    m = bodies[j, MASS]
    lx = got[i, 4] + m * bodies[j, TILT_GX]  # the load as load() makes it (no active load)
    ly = got[i, 5] + m * bodies[j, TILT_GY]
    lt = got[i, 6]
    # held(): its kept answer for this load at this angle (the test it would otherwise run writes the rows)
    if not (R.may_hold(j, bodies, lx, ly) and lx / m == bodies[j, HELD_LOAD_X] and ly / m == bodies[j, HELD_LOAD_Y]
            and lt / m == bodies[j, HELD_LOAD_TORQUE] and got[i, 0] == bodies[j, HELD_ANGLE] and bodies[j, HELD] > 0.0):
        return False
    _, _, ew = extrapolated(i, j, got, bodies, dt)
    # commit()'s history and settle()'s friction kept (held: out becomes 0, the friction minus the load)
    return (same_bits(bodies[j, PREV_VX], got[i, 1]) and same_bits(bodies[j, PREV_VY], got[i, 2])
            and same_bits(bodies[j, PREV_SPIN], got[i, 3]) and same_bits(bodies[j, PREV_GAP], dt)
            and same_bits(bodies[j, EVAL_ANGLE], got[i, 0] + got[i, 3] * dt) and same_bits(bodies[j, EVAL_SPIN], ew)
            and same_bits(bodies[j, FRICTION_FX], 0.0 - lx) and same_bits(bodies[j, FRICTION_FY], 0.0 - ly)
            and same_bits(bodies[j, FRICTION_TORQUE], 0.0 - lt))
