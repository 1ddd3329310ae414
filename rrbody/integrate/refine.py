"""Locating an event inside a step by re-stepping from the step's start, each iterate a fresh step,
so that an event has the order of the solution rather than that of an interpolant.

- for the one stepping loop (its sibling :mod:`rrbody.integrate.loop`, compiled): one trial step of
  whichever method is current (:func:`method_step`: DOP853, RODAS4 or Radau IIA; the loop's dense
  output re-steps with it too), and Newton's method on the step size for a driven body's event
  (:func:`refine_event`: a local minimum of phi, T_1, a crossing of a Poincare section);
- for the run of a body on feet (:mod:`rrbody.integrate.pivot`, in Python): the Illinois method on
  the step's length for the release of a pivoting foot (:func:`illinois_on_step`), each iterate a
  fresh integration by the loop from the step's start.

Times in s, angles in rad, rates in rad/s; ``y`` the state (phi, phi', ...), ``f`` = y' at the
step's start, ``K`` the method's stage rows (row 12: f at the step's end), ``scale`` the error scales.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from numba import literally, njit

from rrbody.integrate.dop853 import trial_step
from rrbody.integrate.radau import radau_step
from rrbody.integrate.rodas import ros_step

__all__ = ["method_step", "refine_event", "illinois_on_step"]


@njit(cache=True, inline="always")
def method_step(meth, system, t, y, f, h, p, S, J, fx, K, ynew, ytmp, scale, A, B, C, E3, E5, boost, rtol):  # noqa: ANN001
    """One trial step of the current method (0 DOP853, 1 RODAS4, 2 Radau IIA); returns its error
    norm (RODAS4's divided by ``boost``: its tolerance is raised to the floor
    :data:`rrbody.integrate.loop.STIFF_RTOL_FLOOR`).

    Both fill ``ynew`` and K[12] = f(t + h, ynew). DOP853 leaves the state of its last stage (at
    t + h) in ``ytmp``, which the stiffness detector reads. Inlined into the loop."""
    if meth == 0:
        return trial_step(system, t, y, f, h, p, S, A, B, C, E3, E5, K, ynew, ytmp, scale)
    if meth == 2:
        return radau_step(system, t, y, f, h, p, S, J, K, ynew, ytmp, scale, rtol)
    return ros_step(system, t, y, f, h, p, S, J, fx, K, ynew, ytmp, scale) / boost


@njit(cache=True)
def refine_event(meth, system, t, y, f, h0, hmax, which, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5,
            omega, target, rtol):  # noqa: ANN001
    """Newton on h in (0, hmax] for the event `which` (1: phi' = 0; 2: theta = target); every
    iterate is a fresh step of the current method from the step start. Returns the event's step
    size and phi (rad) and phi' (rad/s) there.

    Each step at h gives the event function g and its slope g', hence the Newton update
    d = -g / g' and, from the curvature g'', the error of the updated iterate h + d, about
    |g'' / (2 g')| d^2. The iteration stops once that error, or d itself, is below rtol * hmax (or
    a few ulps of t): the event time is then known to the accuracy the step itself has. It returns
    the updated iterate h + d without a further step, with phi carried there by its Taylor
    polynomial, phi(h) + phi'(h) d + phi''(h) d^2 / 2 (for a minimum, phi(h) - g^2 / (2 g'); exact
    to O(d^3)). The g'' of a minimum is the third derivative of phi, estimated from phi'' at the
    two ends of the step (f and K2[12]); that of T_1 is phi'' itself."""
    literally(system)
    h = min(max(h0, 0.0), hmax)
    htol = max(rtol * hmax, 4e-16 * (abs(t) + abs(hmax)) + 1e-300)
    for _ in range(12):
        method_step(meth, system, t, y, f, h, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, 1.0, rtol)
        if which == 1:
            g = y2[1]
            dg = K2[12, 1]
            ddg = (dg - f[1]) / h if h > 0.0 else 0.0
        else:
            g = y2[0] - omega * (t + h) + math.pi - target
            dg = y2[1] - omega
            ddg = K2[12, 1]
        if dg == 0.0:
            return h, y2[0], y2[1]
        hn = min(max(h - g / dg, 0.0), hmax)
        d = hn - h
        # the curvature is estimated roughly (to first order across the step): a safety factor of 10
        if abs(d) <= htol or 10.0 * abs(ddg / (2.0 * dg)) * d * d <= htol:
            return hn, y2[0] + d * (y2[1] + 0.5 * K2[12, 1] * d), y2[1] + d * K2[12, 1]
        h = hn
    method_step(meth, system, t, y, f, h, p, S, J, fx, K2, y2, ytmp, scale, A, B, C, E3, E5, 1.0, rtol)
    return h, y2[0], y2[1]


def illinois_on_step(h: float, ga: float, gb: float, redo: Callable[[float], float], t0: float, gtol: float) -> None:
    """The step of length ``h`` (s) from time ``t0`` took the event function g from ``ga`` <= 0 to
    ``gb`` > 0: the Illinois method on the step's length, ``redo(s)`` putting the state back at the
    step's start, integrating ``s`` seconds from there and returning g at its end. It ends where g
    is zero to ``gtol`` (on either side of the zero), or at the crossed end (g > 0) of a bracket a
    few ulps of t wide; the state is that of the last ``redo``."""
    a, b = 0.0, h
    side = 0
    at = b
    for _ in range(60):
        if b - a <= 4e-16 * (abs(t0) + b) or gb - ga == 0.0:
            break
        s = b - gb * (b - a) / (gb - ga)
        if not a < s < b:
            s = 0.5 * (a + b)
        gs = redo(s)
        at = s
        if gs > 0.0:
            b, gb = s, gs
            if side == 1:
                ga *= 0.5
            side = 1
        else:
            a, ga = s, gs
            if side == -1:
                gb *= 0.5
            side = -1
        if abs(gs) <= gtol:
            return  # at the zero to rounding: end here (on either side of it)
    if at != b:
        redo(b)
