"""The coupled step in pymunk: the plane's friction solved together with the contacts of the plugin's bodies.

After ``space.step`` the plugin reads, through pymunk's public API, the contacts pymunk found and solved in
that step for each of its bodies (``body.each_arbiter``: the bodies, points, normal, friction, restitution
and surface velocity of each), groups its bodies into islands joined by contacts, and solves each island's
velocities again with the plane's friction inside the solve (:func:`rrbody.contact.coupled.couple`), from
the velocity each body had before any impulse of the step: its velocity at the step's start and the loads
the plugin applied (pymunk's own velocity update: ``space.gravity`` and ``space.damping``). The answer
replaces the velocity pymunk's solver gave those bodies; pymunk keeps everything else: positions (which it
moves at the start of its next step, with its own penetration correction, kept apart from the velocity),
collision detection, its contacts' impulses as its collision handlers saw them, joints and bodies off the
plane. Why after the step and not instead of pymunk's contact solve: docs/plugin.md, "The coupled step".

An island with a dynamic body that is not on the plane, or a body held by a joint, is left as pymunk
solved it (the split step: the plane's friction applied before pymunk's solve), and so is a body whose
contacts all touched nothing this step.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from rrbody.contact import coupled as CP
from rrbody.contact import kernel as K
from rrbody.model.laws import LAW_TABLE

__all__ = ["Coupling", "TOL", "MAX_ITER", "MAX_SWEEPS"]

#: relative tolerance of the coupled solve: each body's velocity change in a Newton iteration, over its
#: free velocity plus mu g dt (the Newton iteration converges quadratically, so the answer is far closer)
TOL = 1e-10
#: Newton iterations at most per island (a step that needs more warns, naming the body)
MAX_ITER = 60
#: projected Gauss-Seidel sweeps over an island's contact points at most per Newton iteration
MAX_SWEEPS = 2000


class Coupling:
    """The plugin's coupled step for ``space`` (made by :class:`rrbody.engine.plugin.PlaneFriction`):
    :meth:`after_step` runs after each ``space.step``. ``tol``, ``max_iter`` and ``max_sweeps``: see the module constants."""

    def __init__(self, space: Any, *, tol: float = TOL, max_iter: int = MAX_ITER, max_sweeps: int = MAX_SWEEPS) -> None:
        import pymunk

        self.space = space
        self.tol = tol
        self.max_iter = max_iter
        self.max_sweeps = max_sweeps
        self._static = pymunk.Body.STATIC
        self._kinematic = pymunk.Body.KINEMATIC
        self._sticky_laws = {K.LAW_CODE[law.name] for law in LAW_TABLE if law.sticks}
        self.last_report: np.ndarray = np.zeros((0, CP.N_OUT))  # the last step's report, a row per island
        self.last_bodies: list[Any] = []  # the bodies the last step solved, in the rows of the report's islands

    def after_step(self, dt: float, slots: dict[Any, int], rows: np.ndarray,
                   arrays: tuple[np.ndarray, np.ndarray, np.ndarray]) -> list[tuple[Any, bool, bool]]:
        """Solve again, coupled, the velocities of the plugin's bodies that touched something in the step
        just taken (``dt``, s): the plugin hands over its bodies and their rows (``slots``: body -> row of
        ``rows``, columns :mod:`rrbody.contact.columns`) and its footprint arrays (shapes, geo, tables).
        Returns, for every body whose velocity it set: (body, held at rest now, at rest at the step's start)."""
        found: list[tuple] = []
        read = found.append
        for body in slots:
            # (read inside the call: pymunk hands each arbiter over with this body's shape first only there)
            body.each_arbiter(lambda arb: read(_contact(arb)))
        if not found:
            return []
        return self._solve(found, dt, slots, rows, arrays)

    def _decel(self, rows: np.ndarray, j: int) -> float:
        """The deceleration the plane's friction gives body row j at any speed (m/s^2): mu g cos(tilt) for a law
        that sticks (dry, Stribeck), none for one whose force vanishes at rest (viscous)."""
        return float(rows[j, K.COEFF]) if rows[j, K.LAW] in self._sticky_laws else 0.0

    # ---- one step's islands ------------------------------------------------------------------------
    def _solve(self, arbiters: list[tuple], dt: float, slots: dict[Any, int], rows: np.ndarray,
               arrays: tuple[np.ndarray, np.ndarray, np.ndarray]) -> list[tuple[Any, bool, bool]]:
        space = self.space
        members: dict[Any, int] = {}  # plugin body -> its index among the touched bodies
        order: list[Any] = []
        parent: list[int] = []
        blocked: set[int] = set()
        joined = _jointed(space)

        def index(body: Any) -> int:
            k = members.get(body)
            if k is None:
                k = members[body] = len(order)
                order.append(body)
                parent.append(k)
                if body in joined:
                    blocked.add(k)
            return k

        def root(k: int) -> int:
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        points: list[tuple] = []
        seen: set[tuple[int, int]] = set()
        for sa, sb, n, pts, friction, restitution, sv in arbiters:
            if sa.sensor or sb.sensor or not pts:
                continue
            key = (id(sa), id(sb)) if id(sa) < id(sb) else (id(sb), id(sa))
            if key in seen:
                continue
            seen.add(key)
            ba, bb = sa.body, sb.body
            ka = index(ba)  # each_arbiter hands every arbiter over with the plugin's body as shape a
            if bb in slots:
                kb = index(bb)
                ra, rb = root(ka), root(kb)
                if ra != rb:
                    parent[rb] = ra
                    if rb in blocked or ra in blocked:
                        blocked.update((ra, rb))
            elif bb.body_type == self._static or bb.body_type == self._kinematic:
                kb = -1
            else:  # a dynamic body off the plane: its velocity before the step is not known here
                blocked.add(ka)
                continue
            for p in pts:
                points.append((ka, kb, bb, n.x, n.y, p.point_a.x, p.point_a.y, p.point_b.x, p.point_b.y,
                               friction, restitution, sv.x, sv.y))
        if not order:
            return []
        # islands, and those left to pymunk's split step
        roots = [root(k) for k in range(len(order))]
        bad_roots = {root(k) for k in blocked}
        keep = [k for k in range(len(order)) if roots[k] not in bad_roots]
        if not keep:
            return []
        label: dict[int, int] = {}
        for k in keep:
            label.setdefault(roots[k], len(label))
        keep.sort(key=lambda k: (label[roots[k]], slots[order[k]]))  # by island, then by plugin row
        where = {k: i for i, k in enumerate(keep)}
        nb = len(keep)
        isl = np.zeros((nb, CP.N_IB))
        q = np.zeros((nb, 3))
        cog = np.zeros((nb, 2))
        damp = space.damping ** dt
        gx, gy = space.gravity
        for i, k in enumerate(keep):
            body = order[k]
            j = slots[body]
            row = rows[j]
            m = row[K.MASS]
            rg = math.sqrt(row[K.IPM])
            a = body.angle
            ca, sa = math.cos(a), math.sin(a)
            c = body.center_of_gravity
            p = body.position
            cog[i] = (p.x + ca * c.x - sa * c.y, p.y + sa * c.x + ca * c.y)
            vx, vy, w = row[K.PVX], row[K.PVY], row[K.PW]  # the velocity the step started from
            isl[i, CP.IB_ROW] = j
            isl[i, CP.IB_M] = m
            isl[i, CP.IB_RG] = rg
            isl[i, CP.IB_CA] = ca
            isl[i, CP.IB_SA] = sa
            isl[i, CP.IB_SX] = vx * damp + dt * (gx + row[K.LDX] / m)
            isl[i, CP.IB_SY] = vy * damp + dt * (gy + row[K.LDY] / m)
            isl[i, CP.IB_SW] = rg * (w * damp + dt * row[K.LDT] / (m * row[K.IPM]))
            isl[i, CP.IB_VX] = vx
            isl[i, CP.IB_VY] = vy
            isl[i, CP.IB_VW] = rg * w
            isl[i, CP.IB_REST] = 1.0 if (vx == 0.0 and vy == 0.0 and w == 0.0) else 0.0
            isl[i, CP.IB_ISLAND] = label[roots[k]]
            v = body.velocity
            isl[i, CP.IB_PX:CP.IB_PW + 1] = (v.x, v.y, rg * body.angular_velocity)
            # Newton starts from the last step's answer, or from pymunk's where it was at rest
            q[i] = isl[i, CP.IB_PX:CP.IB_PW + 1] if isl[i, CP.IB_REST] > 0.0 else (vx, vy, rg * w)
        con_rows = []
        for (ka, kb, other, nx, ny, pax, pay, pbx, pby, fric, rest, svx, svy) in points:
            if ka not in where or (kb >= 0 and kb not in where):
                continue
            ia = where[ka]
            r1x, r1y = pax - cog[ia, 0], pay - cog[ia, 1]
            tx, ty = -ny, nx
            # the relative velocity b - a at the point, at the step's start (the bounce) and of the fixed
            # parts at its end (a fixed body's own velocity, the surface velocity)
            wa = isl[ia, CP.IB_VW] / isl[ia, CP.IB_RG]
            va0x = isl[ia, CP.IB_VX] - wa * r1y
            va0y = isl[ia, CP.IB_VY] + wa * r1x
            if kb >= 0:
                ib = where[kb]
                r2x, r2y = pbx - cog[ib, 0], pby - cog[ib, 1]
                wb = isl[ib, CP.IB_VW] / isl[ib, CP.IB_RG]
                vb0x = isl[ib, CP.IB_VX] - wb * r2y
                vb0y = isl[ib, CP.IB_VY] + wb * r2x
                fixx = fixy = 0.0
            else:
                ib = -1
                v, w = other.velocity, other.angular_velocity
                c = other.local_to_world(other.center_of_gravity)
                r2x, r2y = pbx - c.x, pby - c.y
                fixx = v.x - w * r2y
                fixy = v.y + w * r2x
                vb0x, vb0y = fixx, fixy
            bounce = rest * ((vb0x - va0x) * nx + (vb0y - va0y) * ny)
            # a bounce the two bodies' plane friction takes away within the step is none: the end-of-step
            # velocity a step can give (it cannot hold a separation friction stops before the step ends)
            stop = dt * (self._decel(rows, slots[order[ka]]) + (self._decel(rows, slots[order[kb]]) if kb >= 0 else 0.0))
            if -bounce <= stop:
                bounce = 0.0
            con_rows.append((ia, ib, nx, ny, r1x, r1y, r2x, r2y, fric, bounce, (fixx + svx) * nx + (fixy + svy) * ny,
                             (fixx + svx) * tx + (fixy + svy) * ty))
        con = np.array(con_rows, dtype=np.float64).reshape(-1, CP.N_CN)
        con = con[np.argsort(con[:, CP.CN_A], kind="stable")]  # grouped by island (their body a is in it)
        lam = np.zeros((con.shape[0], 2))
        pinned = np.zeros(nb, dtype=np.int64)
        fric = np.zeros((nb, 3))
        report = np.zeros((len(label), CP.N_OUT))
        n_bad = CP.couple(isl, con, rows, *arrays, dt, q, lam, pinned, fric, self.tol, self.max_iter,
                          self.max_sweeps, report)
        bodies = [order[k] for k in keep]
        self.last_report = report
        self.last_bodies = bodies
        if n_bad:
            for r in report:
                if r[CP.OUT_RESIDUAL] > self.tol:
                    worst = bodies[int(r[CP.OUT_WORST])] if r[CP.OUT_WORST] >= 0 else None
                    k = list(slots).index(worst) if worst is not None else -1
                    warnings.warn(f"the coupled step did not converge for body pf.bodies[{k}] ({worst!r}): its velocity "
                                  f"still moved by {r[CP.OUT_RESIDUAL]:.3g} of its scale after {int(r[CP.OUT_ITER])} "
                                  f"Newton iterations (tolerance {self.tol:g}); its velocity is the last iterate",
                                  RuntimeWarning, stacklevel=4)
        out = []
        for i, body in enumerate(bodies):
            j = slots[body]
            m = rows[j, K.MASS]
            rg = isl[i, CP.IB_RG]
            body.velocity = (q[i, 0], q[i, 1])
            body.angular_velocity = q[i, 2] / rg
            rows[j, K.FFX] = m * fric[i, 0]
            rows[j, K.FFY] = m * fric[i, 1]
            rows[j, K.FFT] = m * rg * fric[i, 2]
            out.append((body, bool(pinned[i]), isl[i, CP.IB_REST] > 0.0))
        return out


def _contact(arb: Any) -> tuple:
    """What the coupled step needs of a pymunk arbiter, read while ``each_arbiter`` hands it over: its
    shapes (the body's own first), normal (from the first to the second), points, friction, restitution
    and surface velocity."""
    cps = arb.contact_point_set
    return (*arb.shapes, cps.normal, cps.points, arb.friction, arb.restitution, arb.surface_velocity)


def _jointed(space: Any) -> set[Any]:
    """The bodies of ``space`` that a joint (any pymunk constraint) holds."""
    held: set[Any] = set()
    for c in space.constraints:
        held.add(c.a)
        held.add(c.b)
    return held
