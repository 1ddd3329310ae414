"""Exact references for a body on the plane pushed by a kinematic disk: the dt -> 0 limit and the quasi-static push.

A body at rest on the plane (dry friction mu over its footprint, normal load m g) is pushed by a disk of
radius ``radius`` whose centre moves at constant velocity ``velocity`` from ``start``; the contact between
them is frictionless. Two references that use no time-stepping engine, only the footprint's friction
wrench (:func:`rrbody.physics.contact.footprint_wrench`) and scipy's integrators:

- :func:`push_limit`, the exact motion (the limit dt -> 0 of any consistent time-stepping): until the
  disk touches the body nothing moves; the touch is an inelastic impact, which the bounded friction
  does not resist (the body's velocity jumps to the least-energy one that lets the disk's point of
  contact move with the disk); from then on the body moves under its friction and the contact force,
  the contact kept closed (an index-reduced differential-algebraic system: the contact's gap has zero
  second derivative, which fixes the force; the force must stay >= 0, else the result is refused);
- :func:`quasi_static_push`, the limit of slow pushing: at each pose the twist whose friction wrench
  balances the contact force (no inertia), moved along by the disk.

Both report the rotation of the body per unit travel of its centre of gravity, dtheta/ds (rad per unit
length), when that travel first reaches each of ``travels``. The contact is with the body's convex
polygons (``pymunk.Poly`` shapes): its nearest edge or vertex. Lengths and times in the body's own
units (m and s, or gym-pusht's workspace units); the plane's friction coefficient per unit mass is
mu g (the plugin's ``g`` times ``mu``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["PushGeometry", "push_limit", "quasi_static_push"]


class PushGeometry:
    """A pymunk body (dynamic, at rest, its shapes' footprint uniformly loaded as the plugin takes it) and a
    disk pusher: the body's footprint (body frame from its centre of gravity), mass, moment, its convex
    polygons from the centre of gravity, its pose, and the disk."""

    def __init__(self, body: Any, radius: float, start: Sequence[float], velocity: Sequence[float]) -> None:
        import pymunk

        from rrbody.engine.plugin.shapes import body_footprint

        self.shapes, self.geo = body_footprint(body)[:2]
        self.m = float(body.mass)
        self.inertia = float(body.moment)
        cg = body.center_of_gravity
        self.cg = np.array([cg.x, cg.y])
        self.polys = [np.array([(v.x, v.y) for v in s.get_vertices()]) - self.cg for s in body.shapes
                      if isinstance(s, pymunk.Poly)]
        self.angle0 = float(body.angle)
        c, s = math.cos(self.angle0), math.sin(self.angle0)
        self.x0 = np.array(body.position) + np.array([c * self.cg[0] - s * self.cg[1], s * self.cg[0] + c * self.cg[1]])
        self.radius = float(radius)
        self.p0 = np.array(start, dtype=float)
        self.v = np.array(velocity, dtype=float)

    def wrench(self, vbx: float, vby: float, w: float) -> tuple[float, float, float]:
        """Friction per unit load and mu g at the body-frame twist: force (body frame), torque about the
        centre of gravity (length)."""
        from rrbody.physics.contact import footprint_wrench

        return footprint_wrench(self.shapes, self.geo, 0, self.shapes.shape[0], vbx, vby, w, 0.0)

    def feature(self, p: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, float]:
        """The polygons' point nearest to ``p`` (body frame from the centre of gravity): (distance, the point,
        the outward unit normal there, the curvature term's radius: 0 on an edge, the distance at a vertex)."""
        best = (math.inf, p, p, 0.0)
        for poly in self.polys:
            n = len(poly)
            for k in range(n):
                a, b = poly[k], poly[(k + 1) % n]
                e = b - a
                t = float(np.clip(np.dot(p - a, e) / np.dot(e, e), 0.0, 1.0))
                q = a + t * e
                d = p - q
                dist = float(np.hypot(*d))
                if dist < best[0]:
                    if 0.0 < t < 1.0:  # the edge's interior: its outward normal (counter-clockwise polygons)
                        normal = np.array([e[1], -e[0]]) / math.hypot(*e)
                        best = (dist, q, normal, 0.0)
                    else:
                        best = (dist, q, d / dist, dist)
        return best


def _rot(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _travel_events(x0: np.ndarray, travels: Sequence[float]) -> list[Any]:
    events = []
    for s in travels:
        def ev(t: float, y: np.ndarray, s: float = s) -> float:
            return math.hypot(y[0] - x0[0], y[1] - x0[1]) - s
        ev.terminal = False  # type: ignore[attr-defined]
        ev.direction = 1.0  # type: ignore[attr-defined]
        events.append(ev)
    return events


def push_limit(geom: PushGeometry, mu_g: float, travels: Sequence[float], *, rtol: float = 1e-10,
               atol: float = 1e-12) -> dict[float, float]:
    """The exact push (dt -> 0): dtheta/ds when the centre of gravity's travel first reaches each of
    ``travels``. ``mu_g``: mu times the plugin's g (acceleration units). The motion alternates between
    contact (the disk pushing, the force >= 0; it ends where the force would turn to a pull) and free
    sliding (until the disk catches up: an impact). Raises ValueError if the body would stop while free
    (outside this reference: static friction's rest), or the disk never reaches it."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    m, inertia = geom.m, geom.inertia
    J = np.array([[0.0, -1.0], [1.0, 0.0]])

    def contact(t: float, y: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
        """(gap, the disk's centre p and its rate (body frame), the normal n, the point r, the vertex radius)."""
        R = _rot(y[2])
        p = R.T @ (geom.p0 + geom.v * t - y[:2])
        dist, r, n, curv = geom.feature(p)
        pdot = R.T @ (geom.v - y[3:5]) - y[5] * (J @ p)
        return dist - geom.radius, p, pdot, n, r, curv

    def friction(y: np.ndarray) -> tuple[np.ndarray, float]:
        R = _rot(y[2])
        vb = R.T @ y[3:5]
        fx, fy, tq = geom.wrench(vb[0], vb[1], y[5])
        return mu_g * m * (R @ np.array([fx, fy])), mu_g * m * tq

    def free(t: float, y: np.ndarray) -> np.ndarray:
        ff, tf = friction(y)
        return np.array([y[3], y[4], y[5], ff[0] / m, ff[1] / m, tf / inertia])

    def pushed(t: float, y: np.ndarray) -> tuple[np.ndarray, float]:
        """The motion with the contact closed, and the contact force (>= 0 while it pushes)."""
        ff, tf = friction(y)
        R = _rot(y[2])
        _, p, pdot, n, r, curv = contact(t, y)
        w = y[5]
        # the gap's second derivative is zero: n . p'' + kappa = 0, p'' = -R^T X'' - a'' J p + b0
        b0 = -w * (J @ (R.T @ (geom.v - y[3:5]))) - w * (J @ pdot)
        kappa = (float(pdot @ pdot) - float(n @ pdot) ** 2) / curv if curv > 0.0 else 0.0
        jp = float(n @ (J @ p))
        lam = (float(n @ (R.T @ ff)) / m + jp * tf / inertia - float(n @ b0) - kappa) / (1.0 / m + jp * _cross(r, n)
                                                                                          / inertia)
        force = ff + lam * (R @ (-n))
        torque = tf + lam * _cross(r, -n)
        return np.array([y[3], y[4], w, force[0] / m, force[1] / m, torque / inertia]), lam

    def impact(t: float, y: np.ndarray) -> np.ndarray:
        """The inelastic impact: the least-energy velocity jump that stops the gap's closing."""
        _, _, pdot, n, r, _ = contact(t, y)
        lam = -float(n @ pdot) / (1.0 / m + _cross(r, n) ** 2 / inertia)
        out = y.copy()
        out[3:5] += _rot(y[2]) @ (-n) * lam / m
        out[5] += _cross(r, -n) * lam / inertia
        return out

    def touch(t: float, y: np.ndarray) -> float:
        return contact(t, y)[0]
    touch.terminal, touch.direction = True, -1.0  # type: ignore[attr-defined]

    def release(t: float, y: np.ndarray) -> float:
        return pushed(t, y)[1]
    release.terminal, release.direction = True, -1.0  # type: ignore[attr-defined]

    speed = float(np.hypot(*geom.v))
    t_end = 50.0 * max(travels) / speed + 1.0
    y = np.array([*geom.x0, geom.angle0, 0.0, 0.0, 0.0])
    # the first touch, the body at rest
    gap0 = touch(0.0, y)
    closing = -float(contact(0.0, y)[3] @ (_rot(geom.angle0).T @ geom.v))
    if gap0 < 0.0 or closing <= 0.0:
        raise ValueError("the disk does not move toward the body from outside it")
    t = brentq(lambda s: touch(s, y), 0.0, 2.0 * gap0 / closing + 1e-9, xtol=1e-15, rtol=1e-15)
    found: dict[float, float] = {}
    events = _travel_events(geom.x0, travels)
    in_contact = True
    y = impact(t, y)
    while len(found) < len(travels) and t < t_end:
        if in_contact:
            sol = solve_ivp(lambda s, z: pushed(s, z)[0], (t, t_end), y, method="Radau", rtol=rtol, atol=atol,
                            events=[*events, release])
        else:
            sol = solve_ivp(free, (t, t_end), y, method="Radau", rtol=rtol, atol=atol, events=[*events, touch])
            if np.min(np.hypot(sol.y[3], sol.y[4])) <= 1e-9 * speed:
                raise ValueError("the body came to rest between contacts: outside this reference")
        for s, te, ye in zip(travels, sol.t_events, sol.y_events):
            if len(te) and s not in found:
                found[s] = float((ye[0][2] - geom.angle0) / s)
        if sol.status != 1 or len(sol.t_events[-1]) == 0:
            break
        t, y = float(sol.t_events[-1][0]), sol.y_events[-1][0].copy()
        if in_contact:
            in_contact = False
        else:
            y = impact(t, y)
            in_contact = True
    missing = [s for s in travels if s not in found]
    if missing:
        raise ValueError(f"the centre of gravity never travelled {missing[0]} before t = {t_end:.3g}")
    return {s: found[s] for s in travels}


def quasi_static_push(geom: PushGeometry, travels: Sequence[float], *, rtol: float = 1e-9) -> dict[float, float]:
    """The slow-push limit: dtheta/ds when the centre of gravity's travel first reaches each of ``travels``,
    the body moving at each instant with the twist whose friction wrench (direction only: the limit surface)
    balances the disk's frictionless push and whose contact point keeps pace with the disk. Independent of mu
    and of the speed. The body starts touching the disk (the quasi-static motion has no impact)."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq, root

    # start where the disk first touches the body at rest (its approach has no effect at this limit)
    R0 = _rot(geom.angle0)

    def gap(t: float) -> float:
        return geom.feature(R0.T @ (geom.p0 + geom.v * t - geom.x0))[0] - geom.radius

    closing = -float(geom.feature(R0.T @ (geom.p0 - geom.x0))[2] @ (R0.T @ geom.v))
    if gap(0.0) < 0.0 or closing <= 0.0:
        raise ValueError("the disk does not move toward the body from outside it")
    t0 = brentq(gap, 0.0, 2.0 * gap(0.0) / closing + 1e-9, xtol=1e-15, rtol=1e-15)
    guess = [0.0, 0.0]

    def twist(t: float, y: np.ndarray) -> np.ndarray:
        x, a = y[:2], y[2]
        R = _rot(a)
        p = R.T @ (geom.p0 + geom.v * t - x)
        _, r, n, _ = geom.feature(p)
        tdir = np.array([-n[1], n[0]])

        def unit(z: np.ndarray) -> tuple[float, float, float]:
            # the twist (body frame): a motion into the disk's push (-n) plus z[0] along t, and spin z[1]
            v = -n + z[0] * tdir
            return v[0], v[1], z[1]

        def balance(z: np.ndarray) -> list[float]:
            fx, fy, tq = geom.wrench(*unit(z))
            f = np.array([fx, fy])
            return [float(np.dot(f, tdir)), tq - float(np.dot(f, n)) * _cross(r, n)]

        sol = root(balance, guess, method="hybr", tol=1e-14)
        z = sol.x
        if not np.all(np.abs(balance(z)) <= 1e-10):
            raise ValueError(f"no twist balances the push at t = {t:.6g} (residual {balance(z)})")
        guess[:] = list(z)
        vx, vy, w = unit(z)
        # scale: the body's point at the contact moves along -n as fast as the disk does
        vpoint_n = -1.0 + w * _cross(r, n)
        disk_n = float(np.dot(n, R.T @ geom.v))
        s = disk_n / vpoint_n
        vw = R @ np.array([vx, vy]) * s
        return np.array([vw[0], vw[1], w * s])

    events = _travel_events(geom.x0, travels)
    speed = float(np.hypot(*geom.v))
    sol = solve_ivp(twist, (t0, t0 + 50.0 * max(travels) / speed + 1.0), np.array([*geom.x0, geom.angle0]),
                    method="RK45", rtol=rtol, atol=1e-12, events=events)
    out = {}
    for s, te, ye in zip(travels, sol.t_events, sol.y_events):
        if len(te) == 0:
            raise ValueError(f"the centre of gravity never travelled {s}")
        out[s] = float((ye[0][2] - geom.angle0) / s)
    return out
