"""Lyapunov exponents of a driven body (the paper's first outlook: the tilted, circularly forced
double pendulum), on the one stepping loop.

Two estimates, both by Benettin's method (renormalise every ``renorm`` seconds, one driving period by
default, and average the logarithms of the growth):

- ``"tangent"``: the variational equations ride along in the state (the effect
  :mod:`rrbody.physics.effects.tangent`: y = (phi, phi', two tangent vectors)); every ``renorm``
  seconds the two vectors are re-orthonormalised by a QR decomposition and the logarithms of R's
  diagonal summed: the full spectrum (lambda_1 >= lambda_2, 1/s). Their sum is the mean of the
  flow's divergence d phi''/d phi' exactly (Liouville: log |det| of the tangent matrix), whatever
  the renormalisation. For a smooth right-hand side (no friction, viscous friction, or dry friction
  while the contact never stops sliding). Integrated by DOP853 (the loop's stiff methods serve the
  bare 2-state system).
- ``"two"``: the maximal exponent from two trajectories ``d0`` apart in (phi, phi'), the second
  pulled back to distance d0 along their separation every ``renorm`` seconds. It needs no
  derivative, so it also serves dry friction, whose right-hand side has a kink where the contact's
  slip speed is zero: a separation of d0 (1e-8 by default) straddles the kink only for the short
  time the slip speed spends within d0's reach of zero, and what it adds there is the finite jump of
  the flow, not an infinite rate, so the average converges to the exponent of the piecewise smooth
  flow. Where both estimates apply they agree (``tests/test_chaos.py``).

Norm: the plain Euclidean norm of (dphi, dphi') (rad, rad/s); an exponent does not depend on it.
Units: exponents in 1/s, times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rrbody.integrate.events import E_SECDIR, E_SECTION, new_event_state
from rrbody.integrate.loop import L_NOUT, L_T, STEP_METHODS, advance_for, new_loop_state
from rrbody.integrate.ode import driven_steps
from rrbody.model.checks import MAX_TIME, check, check_int, check_range
from rrbody.model.scene import Scene
from rrbody.physics import params as P
from rrbody.physics.bind import ode_params
from rrbody.physics.dynamics import SYSTEM_DRIVEN, system_from_params, tangent_rhs_for

__all__ = ["LyapunovResult", "lyapunov", "auto_method", "METHODS", "Section", "poincare", "SECTIONS", "rotating_energy"]

METHODS = ("tangent", "two")


def auto_method(scene: Scene) -> str:
    """The estimate for ``scene``: ``"tangent"`` where the right-hand side is smooth (no or viscous
    friction), ``"two"`` under dry friction (its kink at zero slip speed)."""
    return "two" if scene.friction.active and not scene.friction.spec.smooth else "tangent"  # (the law table's)


@dataclass
class LyapunovResult:
    """Exponents (1/s, largest first) and their running estimates at each renormalisation time."""

    exponents: np.ndarray
    times: np.ndarray
    running: np.ndarray
    method: str
    renorm: float
    rtol: float
    divergence: float | None = None
    meta: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (no per-interval arrays)."""
        return {"exponents": [float(x) for x in self.exponents], "method": self.method, "t_max": float(self.times[-1]),
                "renorm": self.renorm, "rtol": self.rtol, "n_renorm": int(len(self.times)),
                "divergence": self.divergence, **self.meta}




def lyapunov(scene: Scene, *, t_max: float, renorm: float | None = None, rtol: float = 1e-10, method: str = "tangent",
             d0: float = 1e-8, progress: bool = False, transient: float = 0.0, rr_samples: int = 0) -> LyapunovResult:
    """Lyapunov exponents of the driven ``scene`` averaged over [``transient``, ``transient + t_max``]
    (s): the spectrum (``"tangent"``) or the maximal exponent (``"two"``); see the module docstring.
    ``renorm``: seconds between renormalisations (default one driving period). ``transient`` (s,
    default 0): run first and discarded (the perturbations start afresh at its end); ``times`` count
    from t = 0.

    ``rr_samples`` (default 0: none): also the fraction of the averaging span in reverse rotation,
    the spin phi' against the orbit (phi' omega < 0), from phi' at ``rr_samples`` equally spaced
    times per ``renorm`` interval, each a step of the integrator from the last accepted step
    (the loop's dense output: the trajectory itself is unchanged). Stored in ``meta``:
    ``rr_fraction`` (the share of samples with phi' omega < 0), ``rr_changes`` (sign changes between
    samples) and ``rr_bound`` = rr_changes x spacing / span, which bounds the fraction's error when no
    two sign changes fall within one spacing."""
    if scene.drive is None:
        raise ValueError("scene must be driven (a drive): Lyapunov exponents here are those of the driven body")
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(repr(m) for m in METHODS)}, got {method!r}")
    t_max = float(check("t_max", t_max))
    omega = scene.omega
    renorm = 2.0 * math.pi / abs(omega) if renorm is None else float(check("renorm", renorm))
    rtol = float(check("rtol", rtol))
    d0 = float(check("d0", d0))
    transient = check_range("transient", transient, 0.0, MAX_TIME, unit="s")
    rr_samples = check_int("rr_samples", rr_samples, 0, 100_000)
    if method == "tangent" and scene.friction.active and not scene.friction.spec.smooth:
        raise ValueError(f"method 'tangent' needs a smooth right-hand side; friction {scene.friction.law!r} has a kink "
                         f"where the contact stops sliding: use method 'two' (two nearby trajectories)")
    n_int = int(math.ceil(t_max / renorm - 1e-9))
    times = transient + np.minimum(renorm * np.arange(1, n_int + 1), t_max)
    y0 = (scene.phi0, scene.initial_phi_dot)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n_int, desc=f"lyapunov ({method})", unit="period", leave=False)
    try:
        dt_rr = renorm / rr_samples if rr_samples else 0.0
        if method == "tangent":
            res = _tangent(scene, y0, times, renorm, rtol, bar, transient, dt_rr)
        else:
            res = _two(scene, y0, times, renorm, rtol, d0, bar, transient, dt_rr)
        if transient:
            res.meta["transient"] = transient
        return res
    finally:
        if bar is not None:
            bar.close()


class _Run:
    """One trajectory on the stepping loop (state y, f = f(t, y), loop and event state)."""

    def __init__(self, scene: Scene, y: np.ndarray, rtol: float, mode: int, *, dt_out: float = 0.0,
                 t_end: float = 0.0) -> None:
        self.p, self.S = ode_params(scene)
        system = system_from_params(self.p, SYSTEM_DRIVEN)
        self.run, self.rhs = advance_for(system), tangent_rhs_for(system)
        self.y = np.array(y, dtype=float)
        self.f = np.empty_like(self.y)
        self.rhs(0.0, self.y, self.p, self.S, self.f)
        yscale, self.hmax, h0 = driven_steps(scene.omega, float(self.y[1]))  # as integrate_driven's
        self.scale = rtol * np.concatenate([[math.pi, yscale], np.ones(len(y) - 2)])  # tangent vectors: O(1)
        self.st = new_loop_state(h0, mode, yscale=yscale)
        self.ev = new_event_state(float(y[0]), float(y[1]))
        self.minima = np.empty((16, 2))
        # dense output (rows t, y...) every dt_out s from t = 0 up to t_end; 0: none
        n_out = int(t_end / dt_out * (1.0 + 1e-12)) + 2 if dt_out > 0.0 else 0
        self.out = np.empty((n_out, len(y) + 1))
        self.rtol, self.mode, self.dt_out = rtol, mode, dt_out

    def advance(self, t_end: float) -> None:
        while True:
            code = self.run(self.y, self.f, self.st, self.ev, self.p, self.S, t_end, 0, 2.0, 3.0, self.rtol, self.scale,
                            1, self.hmax, 1_000_000, self.minima, self.out, self.dt_out, self.mode, 0.0)
            if code == 0:
                return
            if code != 5:
                raise RuntimeError(f"integration failed at t={self.st[L_T]:.6g} s (loop status {code})")

    def rr_stats(self, t0: float, t1: float, omega: float) -> dict[str, Any]:
        """Reverse rotation (phi' omega < 0) over [t0, t1) (s) from the dense output's samples: the
        share of samples, the sign changes between them and the bound changes x spacing / span."""
        rows = self.out[:int(self.st[L_NOUT])]
        keep = (rows[:, 0] >= t0 - 1e-9 * self.dt_out) & (rows[:, 0] < t1 - 1e-9 * self.dt_out)
        against = rows[keep, 2] * omega < 0.0
        if not len(against):
            return {"rr_fraction": None, "rr_changes": 0, "rr_bound": None}
        changes = int(np.count_nonzero(against[1:] != against[:-1]))
        return {"rr_fraction": float(np.mean(against)), "rr_changes": changes,
                "rr_bound": changes * self.dt_out / (t1 - t0)}

    def changed(self) -> None:
        """After editing y: f = f(t, y) again (the loop carries f from step to step)."""
        self.rhs(float(self.st[L_T]), self.y, self.p, self.S, self.f)


def _tangent(scene: Scene, y0: tuple[float, float], times: np.ndarray, renorm: float, rtol: float,
             bar: Any, transient: float = 0.0, dt_rr: float = 0.0) -> LyapunovResult:
    r = _Run(scene, np.array([y0[0], y0[1], 1.0, 0.0, 0.0, 1.0]), rtol, STEP_METHODS["dop853"], dt_out=dt_rr,
             t_end=float(times[-1]))
    # the tangent vectors are re-orthonormalised at least once a driving period, whatever renorm: the
    # loop's error scale for them is absolute, O(1), so vectors left to grow by e^(lambda renorm) would
    # force ever smaller steps. The logarithms of R's diagonal add up over the sub-intervals, so this
    # changes no exponent (renorm sets where the running estimate is recorded)
    sub = min(renorm, 2.0 * math.pi / abs(scene.omega))

    def reorthonormalise() -> np.ndarray:
        D = np.array([[r.y[2], r.y[4]], [r.y[3], r.y[5]]])  # columns: the tangent vectors
        Q, R = np.linalg.qr(D)
        sign = np.sign(np.diag(R))
        sign[sign == 0.0] = 1.0
        Q = Q * sign
        r.y[2:] = (Q[0, 0], Q[1, 0], Q[0, 1], Q[1, 1])
        r.changed()
        return np.log(np.abs(np.diag(R)))

    # the transient: the perturbations' growth is never measured; they start afresh (unit vectors)
    # after every sub-interval of it and at its end
    for t in [*np.arange(sub, transient - 1e-9 * sub, sub), transient] if transient else []:
        r.advance(float(t))
        r.y[2:] = (1.0, 0.0, 0.0, 1.0)
        r.changed()
    sums = np.zeros(2)
    running = np.empty((len(times), 2))
    t_prev = transient
    for i, t in enumerate(times):
        for ts in [*np.arange(t_prev + sub, t - 1e-9 * sub, sub), t]:
            r.advance(float(ts))
            sums += reorthonormalise()
        t_prev = float(t)
        running[i] = sums / (t - transient)
        if bar is not None:
            bar.update(1)
    # the flow's divergence d phi''/d phi': -gamma under viscous friction (its torque about P is
    # -gamma phi' I_P / m plus terms free of phi', for any body), 0 without friction
    div = None
    if not scene.friction.active:
        div = 0.0
    elif scene.friction.law == "viscous":
        div = -float(r.p[P.COEFF])
    return LyapunovResult(exponents=running[-1].copy(), times=times, running=running, method="tangent", renorm=renorm,
                          rtol=rtol, divergence=div,
                          meta=r.rr_stats(transient, float(times[-1]), scene.omega) if dt_rr else {})


def _two(scene: Scene, y0: tuple[float, float], times: np.ndarray, renorm: float, rtol: float, d0: float,
         bar: Any, transient: float = 0.0, dt_rr: float = 0.0) -> LyapunovResult:
    base = _Run(scene, np.array(y0, dtype=float), rtol, STEP_METHODS["auto"], dt_out=dt_rr, t_end=float(times[-1]))
    if transient:
        base.advance(transient)  # the twin starts d0 away at the transient's end
    twin = _Run(scene, base.y + d0 * np.array([1.0, 0.0]), rtol, STEP_METHODS["auto"])
    if transient:
        twin.st[L_T] = transient
        twin.changed()
    total = 0.0
    running = np.empty((len(times), 1))
    for i, t in enumerate(times):
        base.advance(float(t))
        twin.advance(float(t))
        sep = twin.y - base.y
        dist = float(np.hypot(sep[0], sep[1]))
        if not dist > 0.0:
            raise RuntimeError(f"the two trajectories met at t={t:.6g} s: choose another d0")
        total += math.log(dist / d0)
        twin.y[:] = base.y + sep * (d0 / dist)
        twin.changed()
        running[i, 0] = total / (t - transient)
        if bar is not None:
            bar.update(1)
    return LyapunovResult(exponents=running[-1].copy(), times=times, running=running, method="two", renorm=renorm,
                          rtol=rtol, meta={"d0": d0, **(base.rr_stats(transient, float(times[-1]), scene.omega)
                                                        if dt_rr else {})})


# ---- Poincare sections -----------------------------------------------------------------------------
SECTIONS = ("theta", "strobe")


@dataclass
class Section:
    """Points of a Poincare section: times (s), phi (rad), phi' (rad/s) and theta = phi - omega t + pi
    reduced to [0, 2 pi) (rad)."""

    t: np.ndarray
    phi: np.ndarray
    phi_dot: np.ndarray
    kind: str
    theta_s: float
    rtol: float

    @property
    def theta(self) -> np.ndarray:
        """theta = phi - omega t + pi at the points, in [0, 2 pi) (rad; needs the drive's omega: see
        :func:`poincare`, which stores it in ``omega``)."""
        return np.mod(self.phi - self.omega * self.t + math.pi, 2.0 * math.pi)

    omega: float = 0.0

    @property
    def drive_phase(self) -> np.ndarray:
        """The drive's phase omega t at the points, in [0, 2 pi) (rad): with phi' the coordinates of a
        theta section, on which theta itself is fixed."""
        return np.mod(self.omega * self.t, 2.0 * math.pi)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "n": int(len(self.t)), "theta_s": self.theta_s, "rtol": self.rtol,
                "t_last": float(self.t[-1]) if len(self.t) else None}


def poincare(scene: Scene, *, points: int, kind: str = "theta", theta_s: float = 0.0, direction: int = 1,
             t_max: float | None = None, rtol: float = 1e-10) -> Section:
    """``points`` points of a Poincare section of the driven ``scene``:

    - ``"theta"``: the crossings of theta = ``theta_s`` (mod 2 pi) with theta' = phi' - omega of the
      sign ``direction`` (1: upwards, the default; -1: downwards, for an orbit that only turns back
      against the drive), theta = phi - omega t + pi the angle in the frame turning with the drive, each located by the
      stepping loop's event detector (Newton on the step size, every iterate a fresh step: the
      point has the integrator's accuracy, not an interpolant's);
    - ``"strobe"``: the state at every driving period T = 2 pi / omega, t = T, 2 T, ... (the loop
      steps onto each exactly).

    ``t_max`` (s) caps the run (default 100 driving periods per point asked: a section that is not
    crossed returns the points found, perhaps none)."""
    if scene.drive is None:
        raise ValueError("scene must be driven (a drive): the sections are those of the driven body")
    if kind not in SECTIONS:
        raise ValueError(f"kind must be one of {', '.join(repr(k) for k in SECTIONS)}, got {kind!r}")
    n = int(check("points", points))
    rtol = float(check("rtol", rtol))
    omega = scene.omega
    period = 2.0 * math.pi / abs(omega)
    theta_s = float(check("theta_s", theta_s))
    if direction not in (1, -1):
        raise ValueError(f"direction must be 1 (theta' > 0) or -1 (theta' < 0), got {direction!r}")
    t_max = float(check("t_max", t_max)) if t_max is not None else 100.0 * period * n
    run = _Run(scene, np.array((scene.phi0, scene.initial_phi_dot)), rtol, STEP_METHODS["auto"])
    if kind == "strobe":
        rows = []
        for k in range(1, n + 1):
            if k * period > t_max:
                break
            run.advance(k * period)
            rows.append((k * period, run.y[0], run.y[1]))
        pts = np.array(rows, dtype=float).reshape(-1, 3)
    else:
        run.ev[E_SECTION] = float(theta_s)
        run.ev[E_SECDIR] = float(direction)
        run.out = np.empty((n, 3))
        t = 0.0
        while int(run.st[L_NOUT]) < n and t < t_max:
            t = min(t + 64.0 * period, t_max)
            run.advance(t)
        pts = run.out[:int(run.st[L_NOUT])]
    return Section(t=pts[:, 0].copy(), phi=pts[:, 1].copy(), phi_dot=pts[:, 2].copy(), kind=kind,
                   theta_s=float(theta_s), rtol=rtol, omega=omega)


def rotating_energy(scene: Scene, t: np.ndarray, phi: np.ndarray, phi_dot: np.ndarray) -> np.ndarray:
    """The frictionless driven body's first integral (rad^2/s^2): with psi = phi - omega t,
    psi'' = (omega^2 l d m / I_P) sin psi is a pendulum, so E = psi'^2 / 2 + (omega^2 l d m / I_P) cos psi
    is conserved (a level plane, no friction)."""
    w = scene.omega
    a = w * w * scene.body.l * scene.d / scene.inertia_about_pivot
    return 0.5 * (np.asarray(phi_dot) - w) ** 2 + a * np.cos(np.asarray(phi) - w * np.asarray(t))
