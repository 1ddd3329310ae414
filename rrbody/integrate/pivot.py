"""Free bodies on point feet: sliding, pivoting on a foot, breaking away, with the one stepping loop.

A body on feet (pressure ``points``) has a right-hand side that is discontinuous where a foot's
velocity vanishes, and as its sliding dies away the instantaneous centre of rotation is drawn onto
one foot and stays there (a Filippov sliding mode: the foot at rest, the body turning about it, the
other feet sliding on circles). :class:`FeetRun` follows it with two systems of the one loop
(:func:`rrbody.integrate.loop.advance`), called one accepted step at a time so that the events between
them are located here:

- **sliding** (the free system, y = (x, y, alpha, vx, vy, Omega)): steps are capped at
  ``STEP_FRACTION`` of the time each slowing foot needs to stop at its present rate, |u|^2 / (-u.u'),
  so a foot approaches rest geometrically and no step crosses its stop (a step that reverses a
  foot's velocity anyway is retried at half its length). Once the foot is slower than ``u_stop``
  (the body's own stop threshold, STOP_SPEED_FRACTION of the speed scale) the last stretch is
  completed with the present accelerations and the foot is set exactly at rest. If static friction
  can hold it there (:func:`rrbody.physics.effects.pivot_foot.pinned`: the reaction lies in the
  foot's disc mu_static N_i) the body pivots; if not, the foot breaks away at once;
- **pivoting** on foot i (the driven system, y = (phi, phi'), with its pivot at rest:
  :func:`rrbody.physics.bind.pinned_params`): one degree of freedom, rotation about the foot under
  the other feet's friction and a tilt's pull. After every step the holding reaction is tested; the
  step in which it leaves the static disc is cut at the release by the Illinois method on its
  length (each iterate a fresh integration from the step's start, as the loop locates its own
  events; :mod:`rrbody.integrate.refine`), and the foot breaks away
  (:func:`rrbody.physics.effects.pivot_foot.release`: the maximum-dissipation slip direction): the run goes on
  sliding, the foot's first stretch of ``BREAK_TAU`` of the time scale taken with the break-away's accelerations
  (exact to O(tau^2)), the foot no slower than 100 v_eps there so that the friction kernel sees its direction. Spin
  running down to zero is the body's stop: steps capped at ``STEP_FRACTION`` of Omega / |Omega'|, the last stretch
  below ``u_stop`` completed analytically (exact for the constant deceleration of a level plane);
- **rest**: every foot at rest is the body's stop, as for any free body (held by static friction on a
  tilt, or a break-away from rest, :mod:`rrbody.integrate.free`). The loop's rest rule is applied
  here between steps (steps capped at a fraction of 2K/P, the last stretch analytic), with its step
  test reduced to "friction gives no energy": on feet whose load is centred off the centre of gravity,
  or on a tilt, friction can turn the spin or the velocity through zero while the body slides on,
  which the loop's test (no reversal) would reject until the step size underflows.

Known cost: a foot released exactly at the rim of its kinetic disc (mu_static = mu) starts to slip
with an acceleration that grows from zero, so its slip speed stays near the kernel's dead band for a
while, where the direction of its friction relaxes at a rate mu g / |u|: DOP853 crosses that stretch
in steps of ~1e-10 s (one of 30 random two-to-four-foot runs: 35,000 steps, 1.5 s; the others take
100-600 steps).

Events: ``pivots``, one record per pivot (foot index, start and end times in s, and what ended it:
"release", "stop" or "t_max").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from rrbody.integrate.events import E_TSTOP, STEP_FRACTION, STOP_T_END, new_event_state, rest_reached, rest_step_limit
from rrbody.integrate.loop import L_H, L_NEXTOUT, L_NOUT, L_NREJ, L_NSTEP, L_T, advance_for, new_loop_state
from rrbody.integrate.refine import illinois_on_step
from rrbody.physics import params as P
from rrbody.physics.bind import pinned_params
from rrbody.physics.dynamics import SYSTEM_DRIVEN, SYSTEM_FREE, driven_rhs, free_rhs, system_from_params
from rrbody.physics.effects import pivot_foot as PF

__all__ = ["FeetRun", "BREAK_TAU", "REARM", "MAX_HALVINGS"]

#: a foot's break-away: its first stretch, with the break-away's accelerations, lasts this fraction of
#: the run's time scale (s; the error is O(tau^2) of the accelerations' rate of change)
BREAK_TAU: float = 1e-9
#: a foot that broke away is watched for a stop again once it is REARM u_stop fast (no re-pinning in
#: the instant after its release, where the holding reaction sits on the disc's rim)
REARM: float = 1e3
#: a step that reversed a foot's velocity (or the pivot's spin) is halved at most this many times
MAX_HALVINGS: int = 40

Held = tuple[float, float, float, bool]


def _undo(save: tuple[np.ndarray, ...], arrays: tuple[np.ndarray, ...]) -> float:
    """Put the saved (y, f, st, ev) back into ``arrays`` after a step to retry; return half its length (s)."""
    h = arrays[2][L_T] - save[2][L_T]
    for a, b in zip(arrays, save):
        a[:] = b
    return 0.5 * h


class FeetRun:
    """The run of a free body on feet: sliding, pivoting, breaking away, stopping (module docstring).

    ``y``, ``f``, ``st``, ``ev``, ``out`` are the free body's state, y', loop state, event state and
    output rows (t, x, y, alpha, vx, vy, Omega), updated in place, as :func:`rrbody.integrate.free.simulate_free`
    set them up; ``feet`` rows (x, y, share) in the body frame (m). ``held(alpha)`` tells whether the
    body at rest at angle alpha is held by static friction (:func:`rrbody.physics.limit.at_rest`),
    ``break_from_rest(y, held)`` starts it from rest along its break-away acceleration and returns
    the time that took (s)."""

    def __init__(self, p: np.ndarray, S: np.ndarray, feet: np.ndarray, y: np.ndarray, f: np.ndarray,
                 st: np.ndarray, ev: np.ndarray, out: np.ndarray, *, dt_out: float, t_max: float, rtol: float,
                 scale: np.ndarray, mode: int, u_stop: float, t_scale: float, max_steps: int,
                 held: Callable[[float], Held], break_from_rest: Callable[[np.ndarray, Held], float]) -> None:
        self.p, self.S, self.feet = p, S, feet
        self.y, self.f, self.st, self.ev, self.out = y, f, st, ev, out
        self.dt_out, self.t_max, self.rtol, self.scale, self.mode = dt_out, t_max, rtol, scale, mode
        self.u_stop, self.t_scale, self.max_steps = u_stop, t_scale, max_steps
        self.held, self.break_from_rest = held, break_from_rest
        self.ck, self.cs = float(p[P.COEFF]), float(p[P.MUS])  # kinetic and static friction per unit mass
        self.gx, self.gy = float(p[P.GTX]), float(p[P.GTY])
        self.j = float(p[P.ICM])
        self.veps = float(p[P.VEPS])
        self.armed = np.ones(feet.shape[0], dtype=bool)
        self.run_free = advance_for(system_from_params(p, SYSTEM_FREE))
        self.run_pivot = advance_for(system_from_params(p, SYSTEM_DRIVEN))
        self.minima = np.empty((0, 2))
        self.minima2 = np.empty((8, 2))  # the pivot's phi' = 0 crossings: not used, but the loop records them
        self.out2 = np.empty((out.shape[0], 3))
        self.pivots: list[dict[str, Any]] = []
        self.n_breaks = 0
        self.steps = 0

    # ---- sliding ------------------------------------------------------------------------------
    def go(self) -> int:
        """Run to t_max or to rest: 0 reached t_max, 1 came to rest (held there), 3 max_steps spent,
        4 step size underflow (the codes of :data:`rrbody.integrate.loop.STATUS`)."""
        y, f, st, ev = self.y, self.f, self.st, self.ev
        halvings = 0
        hcap = math.inf
        while True:
            if st[L_T] >= self.t_max:
                return 0
            if self.steps >= self.max_steps:
                return 3
            # the body's own stop: the loop's rest rule (rrbody.integrate.events), applied here between
            # steps, because its step test (no reversal of the velocity or the spin) does not hold on
            # feet: with the load's centre off the centre of gravity (or on a tilt) friction can turn
            # a spin or a velocity through zero while the body slides on
            reached, tau = rest_reached(y, f, self.j, self.u_stop)
            if reached:
                self._rest_rows(tau)
                y[0:3] += 0.5 * tau * y[3:6]
                y[3:6] = 0.0
                ev[E_TSTOP] = st[L_T] + tau
                st[L_T] = self.t_max
                if self._rest():
                    return 1
                continue
            u, a = PF.foot_motion(y, f, PF.foot_offsets(y[2], self.feet))
            sp = np.hypot(u[:, 0], u[:, 1])
            self.armed |= sp > REARM * self.u_stop
            speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + self.j * y[5] * y[5])
            cand = np.flatnonzero(self.armed & (sp <= self.u_stop))
            # a foot at rest while the body still moves: a pivot, or a break-away (a body about to stop
            # as a whole is the rest rule's)
            if cand.size and speed > 10.0 * self.u_stop:
                i = int(cand[np.argmin(sp[cand])])
                code = self._foot_at_rest(i, u[i], a[i])
                if code >= 0:
                    return code
                continue
            dec = np.einsum("ij,ij->i", u, a)
            hmax = min(hcap, rest_step_limit(y, f, self.j))
            for k in np.flatnonzero(dec < 0.0):
                hmax = min(hmax, STEP_FRACTION * sp[k] * sp[k] / -dec[k])
            save = (y.copy(), f.copy(), st.copy(), ev.copy())
            code = self.run_free(y, f, st, ev, self.p, self.S, self.t_max, STOP_T_END, 0.0, 0.0, self.rtol, self.scale,
                                 -1, hmax, 1, self.minima, self.out, self.dt_out, self.mode, self.u_stop)
            if code == 4:
                return 4
            u2, _ = PF.foot_motion(y, f, PF.foot_offsets(y[2], self.feet))
            if (np.any(np.einsum("ij,ij->i", u, u2) < 0.0) or self._gains(save[0], y)) and halvings < MAX_HALVINGS:
                # the step crossed a foot's stop, or friction would have given energy: again, shorter
                hcap = _undo(save, (y, f, st, ev))
                halvings += 1
                continue
            halvings = 0
            hcap = math.inf
            self.steps += 1

    def _gains(self, y0: np.ndarray, y1: np.ndarray) -> bool:
        """Whether the step y0 -> y1 raised the mechanical energy per unit mass (kinetic, less a tilt's
        work): friction never does."""
        k0 = 0.5 * (y0[3] * y0[3] + y0[4] * y0[4] + self.j * y0[5] * y0[5])
        k1 = 0.5 * (y1[3] * y1[3] + y1[4] * y1[4] + self.j * y1[5] * y1[5])
        return k1 - (self.gx * (y1[0] - y0[0]) + self.gy * (y1[1] - y0[1])) > k0 * (1.0 + 1e-14)

    def _rest_rows(self, tau: float) -> None:
        """Output rows over the analytic last stretch to rest (uniform deceleration over ``tau`` s),
        then at rest up to t_max (as the loop's rest rule writes them)."""
        y, st = self.y, self.st
        t = st[L_T]
        while st[L_NEXTOUT] <= self.t_max and st[L_NOUT] < self.out.shape[0]:
            k = int(st[L_NOUT])
            s = min(max(st[L_NEXTOUT] - t, 0.0), tau)
            self.out[k, 0] = st[L_NEXTOUT]
            self.out[k, 1:4] = y[0:3] + y[3:6] * (s * (1.0 - 0.5 * s / tau) if tau > 0.0 else 0.0)
            self.out[k, 4:7] = y[3:6] * (1.0 - s / tau if tau > 0.0 else 0.0)
            st[L_NOUT] += 1
            st[L_NEXTOUT] = st[L_NOUT] * self.dt_out

    def _rest(self) -> bool:
        """The body came to rest at ev[E_TSTOP] (the rows after it written as rest): held there (True),
        or it breaks away from the stop (False: it slides on, the rows after the stop dropped)."""
        st, ev = self.st, self.ev
        t_stop = float(ev[E_TSTOP])
        if t_stop >= self.t_max:
            return True
        held = self.held(self.y[2])
        if held[3]:
            return True
        n_keep = int(np.count_nonzero(self.out[:int(st[L_NOUT]), 0] <= t_stop))
        st[L_NOUT] = n_keep
        st[L_NEXTOUT] = n_keep * self.dt_out
        st[L_T] = t_stop + self.break_from_rest(self.y, held)
        ev[E_TSTOP] = math.nan
        free_rhs(st[L_T], self.y, self.p, self.S, self.f)
        self.n_breaks += 1
        return False

    def _stretch(self, tau: float) -> None:
        """Carry the free state over ``tau`` s with its present accelerations f[3:6] (a foot's last
        stretch to rest, a break-away's first), writing the output rows that fall inside."""
        y, f, st = self.y, self.f, self.st
        t = st[L_T]
        while st[L_NEXTOUT] <= t + tau and st[L_NOUT] < self.out.shape[0]:
            s = max(st[L_NEXTOUT] - t, 0.0)
            k = int(st[L_NOUT])
            self.out[k, 0] = st[L_NEXTOUT]
            self.out[k, 1:4] = y[0:3] + s * y[3:6] + 0.5 * s * s * f[3:6]
            self.out[k, 4:7] = y[3:6] + s * f[3:6]
            st[L_NOUT] += 1
            st[L_NEXTOUT] = st[L_NOUT] * self.dt_out
        y[0:3] += tau * y[3:6] + 0.5 * tau * tau * f[3:6]
        y[3:6] += tau * f[3:6]
        st[L_T] = t + tau

    def _foot_at_rest(self, i: int, u: np.ndarray, a: np.ndarray) -> int:
        """Foot ``i`` (velocity ``u``, acceleration ``a``) is slower than u_stop: finish its approach,
        set it exactly at rest, then pivot on it or let it break away. Returns a code of :meth:`go`,
        or -1 to go on sliding."""
        y = self.y
        dec = -(u[0] * a[0] + u[1] * a[1])
        self._stretch((u[0] * u[0] + u[1] * u[1]) / dec if dec > 0.0 else 0.0)
        r = PF.foot_offsets(y[2], self.feet)
        # exactly at rest: the centre of gravity moves with Omega z x (-r_i) (a change of O(u_stop))
        y[3], y[4] = y[5] * r[i, 1], -y[5] * r[i, 0]
        _, Rx, Ry = PF.pinned(y[2], y[5], i, self.feet, self.ck, self.gx, self.gy, self.j, self.veps)
        if math.hypot(Rx, Ry) <= self.cs * self.feet[i, 2]:
            return self._pivot(i)
        self._foot_break(i, Rx, Ry)
        return -1

    def _foot_break(self, i: int, Rx: float, Ry: float) -> None:
        """Foot ``i``, at rest, needs the reaction (Rx, Ry) (m/s^2, world) that its static disc cannot
        give: it starts to slide along the maximum-dissipation direction."""
        y, f = self.y, self.f
        ax, ay, wd, ex, ey = PF.release(y[2], y[5], i, self.feet, self.ck, self.gx, self.gy, self.j, self.veps,
                                        Rx, Ry)
        f[0:3] = y[3:6]
        f[3], f[4], f[5] = ax, ay, wd
        self._stretch(BREAK_TAU * self.t_scale)
        # the foot at least 100 v_eps fast along e (when the reaction left the disc at its kinetic rim,
        # the foot's acceleration starts from zero): below v_eps the kernel would give it no friction
        r = PF.foot_offsets(y[2], self.feet)
        along = (y[3] - y[5] * r[i, 1]) * ex + (y[4] + y[5] * r[i, 0]) * ey
        kick = max(0.0, 100.0 * self.veps - along)
        y[3] += kick * ex
        y[4] += kick * ey
        self.armed[i] = False
        free_rhs(self.st[L_T], y, self.p, self.S, f)

    # ---- pivoting -----------------------------------------------------------------------------
    def _pivot(self, i: int) -> int:
        """Pivot on foot ``i`` until it breaks away (-1: go on sliding), the body stops (1 held, or -1
        after a break-away from rest), or t_max (0); 3 and 4 as :meth:`go`."""
        y, st = self.y, self.st
        foot = self.feet[i]
        qx, qy, l, beta, phi, w = PF.pivot_state(y, foot)
        pp = pinned_params(self.p, (foot[0], foot[1]))
        y2 = np.array([phi, w])
        f2 = np.empty(2)
        driven_rhs(st[L_T], y2, pp, self.S, f2)
        st2 = new_loop_state(st[L_H], self.mode)
        st2[L_T], st2[L_NOUT], st2[L_NEXTOUT] = st[L_T], st[L_NOUT], st[L_NEXTOUT]
        ev2 = new_event_state(phi, w)
        scale2 = np.array([self.scale[2], self.scale[5]])  # the free body's angle and spin scales
        n0 = int(st[L_NOUT])
        rec: dict[str, Any] = {"foot": i, "start": float(st[L_T]), "end": None, "ended_by": "t_max"}
        self.pivots.append(rec)
        lim = self.cs * foot[2]
        gyr = math.sqrt(self.j + l * l)  # the body's speed is |Omega| times its gyration radius about the foot

        def excess(yy: np.ndarray) -> float:
            """|R| - mu_s N_i (m/s^2): the holding reaction beyond the static disc (> 0: released)."""
            _, Rx, Ry = PF.pinned(yy[0] - beta, yy[1], i, self.feet, self.ck, self.gx, self.gy, self.j, self.veps)
            return math.hypot(Rx, Ry) - lim

        def step(t_end: float, hmax: float, n: int) -> int:
            return int(self.run_pivot(y2, f2, st2, ev2, pp, self.S, t_end, STOP_T_END, 0.0, 0.0, self.rtol, scale2, -1,
                                      hmax, n, self.minima2, self.out2, self.dt_out, self.mode, 0.0))

        ended = "t_max"
        halvings = 0
        hcap = math.inf
        while st2[L_T] < self.t_max:
            if self.steps >= self.max_steps:
                ended = "max_steps"
                break
            w, wd = y2[1], f2[1]
            hmax = hcap
            if w * wd < 0.0:
                tau = -w / wd
                if abs(w) * gyr <= self.u_stop:
                    # the last stretch to rest, analytically (uniform deceleration)
                    self._stop_rows(st2, y2, tau)
                    y2[0] += 0.5 * w * tau
                    y2[1] = 0.0
                    st2[L_T] += tau
                    ended = "stop"
                    break
                hmax = min(hmax, STEP_FRACTION * tau)
            save = (y2.copy(), f2.copy(), st2.copy(), ev2.copy())
            if step(self.t_max, hmax, 1) == 4:
                ended = "underflow"
                break
            if y2[1] * w < 0.0 and halvings < MAX_HALVINGS:
                hcap = _undo(save, (y2, f2, st2, ev2))
                halvings += 1
                continue
            halvings = 0
            hcap = math.inf
            self.steps += 1
            if excess(y2) > 0.0:
                self._locate(save, y2, f2, st2, ev2, excess, step)
                ended = "release"
                break
        # back to the free state: the rows written while pivoting, then y
        for k in range(n0, int(st2[L_NOUT])):
            self.out[k, 0] = self.out2[k, 0]
            PF.free_state(qx, qy, l, beta, self.out2[k, 1], self.out2[k, 2], self.out[k, 1:])
        PF.free_state(qx, qy, l, beta, y2[0], y2[1], y)
        st[L_T], st[L_NOUT], st[L_NEXTOUT] = st2[L_T], st2[L_NOUT], st2[L_NEXTOUT]
        st[L_NSTEP] += st2[L_NSTEP]
        st[L_NREJ] += st2[L_NREJ]
        rec["ended_by"] = ended
        if ended in ("stop", "release"):
            rec["end"] = float(st[L_T])
        if ended == "t_max":
            return 0
        if ended == "max_steps":
            return 3
        if ended == "underflow":
            return 4
        if ended == "stop":
            y[3:6] = 0.0
            self.ev[E_TSTOP] = st[L_T]
            return 1 if self._rest() else -1
        _, Rx, Ry = PF.pinned(y[2], y[5], i, self.feet, self.ck, self.gx, self.gy, self.j, self.veps)
        self._foot_break(i, Rx, Ry)
        return -1

    def _stop_rows(self, st2: np.ndarray, y2: np.ndarray, tau: float) -> None:
        """Pivot output rows (t, phi, phi') over the analytic last stretch (uniform deceleration over
        ``tau`` s), then at rest up to t_max."""
        t, phi, w = st2[L_T], y2[0], y2[1]
        while st2[L_NEXTOUT] <= self.t_max and st2[L_NOUT] < self.out2.shape[0]:
            k = int(st2[L_NOUT])
            s = min(max(st2[L_NEXTOUT] - t, 0.0), tau)
            self.out2[k, 0] = st2[L_NEXTOUT]
            self.out2[k, 1] = phi + w * s * (1.0 - 0.5 * s / tau)
            self.out2[k, 2] = w * (1.0 - s / tau)
            st2[L_NOUT] += 1
            st2[L_NEXTOUT] = st2[L_NOUT] * self.dt_out

    def _locate(self, save: tuple[np.ndarray, ...], y2: np.ndarray, f2: np.ndarray, st2: np.ndarray,
                ev2: np.ndarray, g: Callable[[np.ndarray], float], step: Callable[[float, float, int], int]) -> None:
        """The step from the state ``save`` took g from <= 0 to > 0: cut it at the release
        (:func:`rrbody.integrate.refine.illinois_on_step`, each iterate a fresh integration from the
        step's start), to 1e-13 of mu_s g or a bracket a few ulps of t wide."""
        t0 = save[2][L_T]

        def redo(h: float) -> float:
            y2[:], f2[:], st2[:], ev2[:] = save
            step(t0 + h, math.inf, 1000)
            return g(y2)

        illinois_on_step(st2[L_T] - t0, g(save[0]), g(y2), redo, t0, 1e-13 * max(self.cs, 1e-300))
