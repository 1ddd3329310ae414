"""The one event detector and what a run's events mean, shared by every integrator path.

Events (times in s, angles in rad):

- local minima of phi (phi' crosses 0 upwards): every one is recorded (up to a buffer size); the
  lowest is the flip candidate;
- T_1, the first time theta = phi - omega t + pi has fallen by 2 pi (the RR test, docs/physics.md,
  "Definitions rrbody fixes");
- the stop rules: flip settled, RR decided (:func:`stop_reached`);
- rest of a free body under dry friction (:func:`rest_reached` and the step rules that approach it).

The compiled stepping loop (:mod:`rrbody.integrate.loop`) calls :func:`crossings`,
:func:`record_minimum` and :func:`stop_reached`, locating each event by re-stepping; a path that
cannot re-step (the engine) calls :func:`on_step` once per step. :func:`classify_flip` then turns
the lowest minimum, T_1 and the way the run ended into the reported flip by one set of rules, so
every path reports the same events with the same meaning.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numba import njit

from rrbody.model.scene import Scene

__all__ = ["FlipResult", "classify_flip", "rr_from_T1"]


def rr_from_T1(T1: float, omega: float) -> bool:
    """Reverse rotation exists iff T_1 exists and omega T_1 < 2 pi (the mean phi' over the first
    backward revolution of theta is negative)."""
    return math.isfinite(T1) and omega * T1 < 2.0 * math.pi


@dataclass
class FlipResult:
    """Outcome of :func:`flip_time` (s, rad). ``t_f`` is None when there is no flip to report."""

    t_f: float | None
    phi_min: float
    t_phi_min: float
    reverse_rotation: bool
    T1: float | None
    settled: bool
    regime: str
    t_stop: float
    n_steps: int
    n_minima: int
    rtol: float
    wall_s: float
    minima: np.ndarray

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("minima")
        return d


def classify_flip(scene: Scene, *, status: str, has_min: bool, phi_min: float, t_min: float, T1: float,
                  t_end: float) -> tuple[float | None, str, bool, bool, float]:
    """Turn a run's lowest minimum into the reported flip: (t_f, regime, RR exists, settled, phi_min).

    Shared by both integrator paths, so the ODE and the engine report flips by the same rules:
    ``t_f`` is the time of the lowest minimum when the run settled and phi fell below phi0;
    otherwise None, with the regime saying why. Without friction there is never a flip (the run
    only answers the RR question) and ``phi_min`` is passed through as the run found it.
    """
    rr = rr_from_T1(T1, scene.omega)
    if not scene.friction.active:
        regime = ("no friction: reverse rotation is perennial, there is no flip" if rr
                  else "no friction: no reverse rotation")
        return None, regime, rr, False, phi_min
    settled = status == "flip settled"
    turned_back = has_min and phi_min < scene.phi0
    t_f: float | None = None
    if not settled:
        where = "" if " at t=" in status else f" at t={t_end:.6g} s"
        regime = (f"not settled: {status}{where}; " +
                  (f"the lowest minimum so far is at t={t_min:.6g} s, so t_f >= that" if has_min
                   else "phi has had no minimum yet"))
    elif not turned_back:
        regime = "no reverse rotation: phi never falls below phi0 (normal rotation from the start)"
    elif rr:
        regime = "reverse rotation (theta made a full backward turn in the first period), then normal rotation"
        t_f = t_min
    else:
        regime = (f"incomplete reverse rotation: phi fell by {scene.phi0 - phi_min:.4g} rad before turning "
                  "forward (no full backward turn of theta in the first period)")
        t_f = t_min
    return t_f, regime, rr, settled, (phi_min if has_min else scene.phi0)


# ------------------------------------------------------------------------------------------------
# The compiled event detector: one set of rules for every path (ODE loop, free bodies, engine)
# ------------------------------------------------------------------------------------------------
# Event state ``ev`` (float64 vector, made by new_event_state): lowest minimum so far, T_1, rest.
E_PHIMIN, E_TMIN, E_HAVEMIN, E_THETA0, E_T1, E_NMIN, E_TSTOP, E_SECTION, E_SECDIR = range(9)
EV_SIZE = 9
#: stop rules: run to the horizon, until the flip is settled, until RR is decided, until rest
STOP_T_END, STOP_FLIP, STOP_RR, STOP_REST = 0, 1, 2, 3
#: what :func:`stop_reached` / :func:`on_step` return (0: keep going)
GO_ON, FLIP_SETTLED, RR_DECIDED = 0, 1, 2

__all__ += ["new_event_state", "crossings", "record_minimum", "stop_reached", "on_step", "hermite",
            "E_PHIMIN", "E_TMIN", "E_HAVEMIN", "E_THETA0", "E_T1", "E_NMIN", "E_TSTOP", "E_SECTION", "E_SECDIR",
            "EV_SIZE",
            "section_crossings", "section_gap",
            "STOP_T_END", "STOP_FLIP", "STOP_RR", "STOP_REST", "GO_ON", "FLIP_SETTLED", "RR_DECIDED"]


def new_event_state(phi0: float, phi_dot0: float) -> np.ndarray:
    """Event state at t = 0 for a driven body starting at (phi0 rad, phi_dot0 rad/s).

    If phi rises from the start, t = 0 is the first minimum candidate (phi0 itself); the rotating
    frame angle theta = phi - omega t + pi starts at phi0 + pi (T_1 is its first fall by 2 pi)."""
    ev = np.zeros(EV_SIZE)
    ev[E_PHIMIN] = np.nan
    ev[E_TMIN] = np.nan
    ev[E_T1] = np.nan
    ev[E_TSTOP] = np.nan
    ev[E_SECTION] = np.nan  # no Poincare section (its theta_s, rad, turns it on: section_crossings)
    ev[E_SECDIR] = 1.0  # its crossings: 1 upwards (theta' > 0), -1 downwards
    ev[E_THETA0] = phi0 + math.pi
    if phi_dot0 >= 0.0:
        ev[E_PHIMIN] = phi0
        ev[E_TMIN] = 0.0
        ev[E_HAVEMIN] = 1.0
    return ev


@njit(cache=True, inline="always")
def crossings(t1_open, target, t0, phi0, phid0, t1, phi1, phid1, omega):  # noqa: ANN001
    """Events inside the step [t0, t1] from its end states: (which, guess), ``which`` a bit mask
    (1: a local minimum of phi, phi' crossing 0 upwards; 2: T_1, theta reaching ``target`` =
    theta0 - 2 pi for the first time, looked for while ``t1_open``) and the linear-interpolation
    guesses (s, from t0) of the minimum and of T_1."""
    which = 0
    gmin = 0.0
    gt1 = 0.0
    h = t1 - t0
    if phid0 < 0.0 and phid1 >= 0.0:
        which |= 1
        gmin = h * (-phid0) / (phid1 - phid0)
    if t1_open:
        g0 = phi0 - omega * t0 + math.pi - target
        g1 = phi1 - omega * t1 + math.pi - target
        if g0 > 0.0 and g1 <= 0.0:
            which |= 2
            gt1 = h * g0 / (g0 - g1)
    return which, gmin, gt1


@njit(cache=True, inline="always")
def section_gap(phi, t, omega, surf):  # noqa: ANN001
    """theta - surf (rad) at phi (rad) and t (s): theta = phi - omega t + pi, the section's coordinate."""
    return phi - omega * t + math.pi - surf


@njit(cache=True, inline="always")
def section_crossings(theta_s, direction, t0, phi0, t1, phi1, omega):  # noqa: ANN001
    """The Poincare section theta = theta_s (mod 2 pi) crossed in ``direction`` (1: upwards,
    theta' > 0; -1: downwards) inside the step [t0, t1], theta = phi - omega t + pi: (first, last)
    integers k of the surfaces theta = theta_s + 2 pi k crossed (last < first: none). The end
    states decide; a step is short enough (hmax, an eighth of a period) for theta not to turn back
    across a surface within it but where it turns at the surface itself."""
    g0 = section_gap(phi0, t0, omega, theta_s) / (2.0 * math.pi)
    g1 = section_gap(phi1, t1, omega, theta_s) / (2.0 * math.pi)
    # surfaces k with g0 < k <= g1 (upwards) or g1 <= k < g0 (downwards): a start on a surface is
    # not a crossing, an end on one is
    if direction > 0.0:
        return math.floor(g0) + 1, math.floor(g1)
    return math.ceil(g1), math.ceil(g0) - 1


@njit(cache=True, inline="always")
def record_minimum(ev, minima, tm, phim):  # noqa: ANN001
    """Record a located local minimum (tm s, phim rad): into ``minima`` (rows t, phi; as many as
    fit) and, if lowest so far, as the flip candidate."""
    k = int(ev[E_NMIN])
    if k < minima.shape[0]:
        minima[k, 0] = tm
        minima[k, 1] = phim
    ev[E_NMIN] += 1
    if ev[E_HAVEMIN] == 0.0 or phim < ev[E_PHIMIN]:
        ev[E_PHIMIN] = phim
        ev[E_TMIN] = tm
        ev[E_HAVEMIN] = 1.0


@njit(cache=True, inline="always")
def stop_reached(stop, havemin, phimin, tmin, t1_found, t, phi, omega, settle_turns, settle_periods):  # noqa: ANN001
    """The stop rules at an accepted state (t s, phi rad), after the step's events were recorded
    (``havemin``, ``phimin``, ``tmin``: the lowest minimum so far; ``t1_found``: T_1 located).

    ``STOP_FLIP``: the lowest minimum (phi_min at t_min) is followed by a rise of phi to
    phi_min + 2 pi settle_turns and settle_periods driving periods since t_min (a later, lower
    minimum would need the body to fall back that many turns against the drive; tests/test_flip.py
    checks the rule against ten times the margin). ``STOP_RR``: T_1 found, or omega t > 2 pi."""
    if stop == STOP_FLIP and havemin:
        if phi >= phimin + 2.0 * math.pi * settle_turns and t - tmin >= settle_periods * (2.0 * math.pi / omega):
            return FLIP_SETTLED
    if stop == STOP_RR:
        if t1_found or omega * t > 2.0 * math.pi:
            return RR_DECIDED
    return GO_ON


@njit(cache=True)
def hermite(s, h, y0, d0, y1, d1):  # noqa: ANN001
    """Cubic Hermite interpolant on [0, h] through (y0, slope d0) and (y1, slope d1): value and slope at s."""
    u = s / h
    h00 = (1.0 + 2.0 * u) * (1.0 - u) ** 2
    h10 = u * (1.0 - u) ** 2
    h01 = u * u * (3.0 - 2.0 * u)
    h11 = u * u * (u - 1.0)
    val = h00 * y0 + h10 * h * d0 + h01 * y1 + h11 * h * d1
    dh00 = 6.0 * u * (u - 1.0) / h
    dh10 = (1.0 - u) * (1.0 - 3.0 * u)
    dh01 = -dh00
    dh11 = u * (3.0 * u - 2.0)
    return val, dh00 * y0 + dh10 * d0 + dh01 * y1 + dh11 * d1


@njit(cache=True)
def _bisect(which, h, t0, phi0, phid0, phi1, phid1, omega, target):  # noqa: ANN001
    """Root in [0, h] of the Hermite interpolant's slope (which 1: phi' = 0 upwards) or of
    theta - target (which 2: theta falling), by bisection to rounding."""
    a = 0.0
    b = h
    for _ in range(200):
        m = 0.5 * (a + b)
        if m <= a or m >= b:
            break
        val, slope = hermite(m, h, phi0, phid0, phi1, phid1)
        g = -slope if which == 1 else val - omega * (t0 + m) + math.pi - target
        if g > 0.0:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


@njit(cache=True)
def on_step(ev, minima, t0, phi0, phid0, t1, phi1, phid1, omega, stop, settle_turns,  # noqa: ANN001
            settle_periods):
    """Per-step entry point for paths that cannot re-step (the pymunk engine): call it once after
    every step with the states at its two ends, in order, from the first step on.

    Events inside [t0, t1] are located on the cubic Hermite interpolant through (phi, phi') at both
    ends (bisection to rounding on its slope, resp. on theta), so their accuracy is that of the
    path's own states (O(dt^2) for the engine's second-order scheme, whose phi' is the mean of the two
    half-step spins; the interpolant itself is exact to O(h^4)); the ODE loop instead locates them by
    re-stepping, :mod:`rrbody.integrate.refine`. Returns GO_ON, FLIP_SETTLED or RR_DECIDED for
    ``stop`` (STOP_T_END, STOP_FLIP, STOP_RR); the run's report is then :func:`classify_flip` of
    ev[E_PHIMIN], ev[E_TMIN], ev[E_HAVEMIN] != 0 and ev[E_T1].
    """
    h = t1 - t0
    which, gmin, gt1 = crossings(math.isnan(ev[E_T1]), ev[E_THETA0] - 2.0 * math.pi, t0, phi0, phid0, t1, phi1,
                                 phid1, omega)
    if which & 1:
        s = _bisect(1, h, t0, phi0, phid0, phi1, phid1, omega, 0.0)
        record_minimum(ev, minima, t0 + s, hermite(s, h, phi0, phid0, phi1, phid1)[0])
    if which & 2:
        ev[E_T1] = t0 + _bisect(2, h, t0, phi0, phid0, phi1, phid1, omega, ev[E_THETA0] - 2.0 * math.pi)
    return stop_reached(stop, ev[E_HAVEMIN] != 0.0, ev[E_PHIMIN], ev[E_TMIN], not math.isnan(ev[E_T1]), t1, phi1,
                        omega, settle_turns, settle_periods)


# ---- rest of a free body under dry friction -----------------------------------------------------
#: steps are capped at this fraction of the estimated time to rest 2K/P
STEP_FRACTION: float = 0.5
#: the last stretch (speed below this fraction of the initial one) is completed analytically
STOP_SPEED_FRACTION: float = 1e-11

__all__ += ["energy_power", "rest_step_limit", "rest_admissible", "rest_reached", "STEP_FRACTION",
            "STOP_SPEED_FRACTION"]


@njit(cache=True)
def energy_power(y, f, icm):  # noqa: ANN001
    """Free body y = (x, y, alpha, vx, vy, spin), f = y': kinetic energy per unit mass K (m^2/s^2)
    and dissipated power per unit mass P = -dK/dt (m^2/s^3); icm = I_cm/m (m^2)."""
    k = 0.5 * (y[3] * y[3] + y[4] * y[4] + icm * y[5] * y[5])
    pw = -(f[3] * y[3] + f[4] * y[4] + icm * f[5] * y[5])
    return k, pw


@njit(cache=True)
def rest_step_limit(y, f, icm):  # noqa: ANN001
    """Largest step (s) toward rest: STEP_FRACTION of tau_left = 2K/P, the time left if the
    decelerations stayed as they are (exact for a point mass, asymptotically for any body, whose
    approach to rest is self-similar). The run thus approaches the stop geometrically, never across."""
    kin, pw = energy_power(y, f, icm)
    if pw > 0.0:
        return STEP_FRACTION * 2.0 * kin / pw
    return math.inf


@njit(cache=True)
def rest_admissible(y, ynew, icm, gx=0.0, gy=0.0):  # noqa: ANN001
    """Whether a step is physical under dry friction: it does not raise the mechanical energy (the
    kinetic energy, less gravity's work (gx, gy) . r along a tilted plane: m/s^2). A step may turn
    the sliding velocity or the spin through zero: friction does that while the body slides on when
    the load is centred off the centre of gravity (an off-centre ring, feet) or on a tilt. Crossing
    the stop itself is what the step cap prevents (:func:`rest_step_limit`: steps of a fraction of
    the time left to rest), not this test."""
    kin = 0.5 * (y[3] * y[3] + y[4] * y[4] + icm * y[5] * y[5])
    kin_new = 0.5 * (ynew[3] * ynew[3] + ynew[4] * ynew[4] + icm * ynew[5] * ynew[5])
    work = gx * (ynew[0] - y[0]) + gy * (ynew[1] - y[1])
    return kin_new - work <= kin * (1.0 + 1e-14)


@njit(cache=True)
def rest_reached(y, f, icm, u_stop):  # noqa: ANN001
    """Whether the body is slow enough (speed sqrt(2K) <= u_stop, m/s) for the last stretch to be
    completed analytically; returns (reached, tau_left = 2K/P in s)."""
    kin, pw = energy_power(y, f, icm)
    if math.sqrt(2.0 * kin) <= u_stop:
        return True, (2.0 * kin / pw if pw > 0.0 else 0.0)
    return False, 0.0
