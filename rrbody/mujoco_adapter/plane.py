"""PlaneFriction for MuJoCo: rrbody's exact dry friction of a plane under the free bodies of a MuJoCo model.

::

    import mujoco
    from rrbody.mujoco import PlaneFriction

    model = mujoco.MjModel.from_xml_path("scene.xml")
    data = mujoco.MjData(model)
    friction = PlaneFriction(model, data, plane="floor", mu=0.5)
    while running:
        friction.step()                   # instead of mujoco.mj_step(model, data)

What it does to the model: the plane geom gets ``condim = 1`` and a ``priority`` above every other
geom, so every contact with that plane keeps only its normal row (MuJoCo's documented rule: the
geom of higher priority sets the contact's condim); the plane's tangential friction (sliding,
torsional and rolling) is gone, and the bodies touching it are moved by the change that makes to the
pose MuJoCo's soft contacts rest them in (:mod:`rrbody.mujoco_adapter.seat`). Each step rrbody reads the
bodies' in-plane motion and the normal force of their plane contacts from MuJoCo's last step, computes
the exact Coulomb wrench of each footprint (the kernel of the pymunk plugin,
:func:`rrbody.contact.kernel.plane_step`, with its limiter, rest rule and static friction) and adds it
to ``data.xfrc_applied`` for the step (it is taken out again after it: your own ``xfrc_applied`` stays
yours). Every body that rests on this plane should be added: one that is not slides on it without
friction.

Footprints come from each body's geoms whose lowest point lies within ``touch`` of the plane: a box
on one of its faces (a rectangle), a cylinder on one of its flat ends (a disk), a sphere (a point);
several geoms make a union, and the load is spread over them as ``pressure`` says
(:mod:`rrbody.pressure`; by default by area, made linear where that is needed to put the centre of
pressure under the body's centre of mass: a compiled model keeps a body's mass and centre of mass,
not its geoms' masses; a footprint given by hand may carry per-part masses, ``rrbody.planar.box(...,
mass=...)``). Bodies must be single rigid bodies on a free joint.
Frames: the plane's own axes (its geom frame: t1, t2 in the plane, n its normal); angles about n
are measured from each body's pose when the adapter was built. The contract is docs/mujoco.md.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.contact.columns import NO_ACTIVE
from rrbody.model.checks import check_int, check_nonnegative, check_positive
from rrbody.model.extras import require
from rrbody.model.pressure import Pressure, as_pressure
from rrbody.mujoco_adapter import kernel as MK
from rrbody.mujoco_adapter.geoms import gap, parts_of
from rrbody.mujoco_adapter.geoms import lookup as _lookup
from rrbody.mujoco_adapter.geoms import name_of as _name
from rrbody.mujoco_adapter.seat import reseat
from rrbody.physics.batch import stack
from rrbody.physics.footprint import Part, apply_pressure
from rrbody.physics.planar import is_part, masses_given

mujoco = require("mujoco", purpose="the MuJoCo adapter (rrbody.mujoco)")

__all__ = ["PlaneFriction", "TOUCH"]

#: default largest distance (m) between a geom's lowest point and the plane for it to rest on it
TOUCH = 1e-3
#: the plugin kernel's ``tables`` (kernel.TABLE_KIND): the adapter evaluates every footprint exactly
_NO_TABLES = np.zeros((0, 3))


def _resync(rows: np.ndarray, gap: np.ndarray, dt: float) -> None:
    """A step of another size than the last (``gap``, s, per body): MuJoCo's velocity after a step belongs to
    half that step before its end, so the kick from the last step's velocity to this one's spans (gap + dt) / 2,
    not dt: each body's friction (FRICTION_FX, FRICTION_FY, FRICTION_TORQUE, which
    :func:`rrbody.mujoco_adapter.kernel.scatter` applies) is scaled by (gap + dt) / (2 dt). Without it a step that
    changes size moves the staggered velocity off its time (an error of order dt per change, which steps of alternating
    sizes pile up). A body the rest rule acts on (its impulse stops it within the step) or with no history is left."""
    k = np.flatnonzero((gap > 0.0) & (gap != dt) & (rows[:, K.STOP] == 0.0))
    if k.size:
        rows[k, K.FRICTION_FX:K.FRICTION_TORQUE + 1] *= ((gap[k] + dt) / (2.0 * dt))[:, None]


def _timestep(model: Any) -> float:
    """MuJoCo's step (s), read where the adapter uses it (a user may change it between steps): ValueError
    naming it unless it is a finite number > 0 (a negative one runs time back and friction with it)."""
    dt = float(model.opt.timestep)
    if not 0.0 < dt < math.inf:  # (also refuses NaN)
        raise ValueError(f"model.opt.timestep must be a finite number in (0, inf) s, got {dt!r}; nothing was "
                         f"changed")
    return dt


def _per_body(name: str, value: Any, n: int) -> np.ndarray:
    """One number >= 0 per body (a number is broadcast), or ValueError naming the entry."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number >= 0 or one per body ({n}), got {value!r}") from None
    a = np.full(n, float(a)) if a.ndim == 0 else a
    if a.shape != (n,):
        raise ValueError(f"{name} must be a number or one per body ({n}), got shape {a.shape}")
    for i, x in enumerate(a):
        check_nonnegative(f"{name}[{i}]" if np.ndim(value) else name, float(x))
    return a


class PlaneFriction:
    """Exact dry friction of one plane geom under free bodies of a MuJoCo model.

    Parameters
    ----------
    model, data : mujoco.MjModel, mujoco.MjData
        The model (changed in place: the plane's condim and priority) and its data.
    plane : str or int
        The plane geom (name or id): a ``type="plane"`` geom fixed to the world; it may be tilted.
    mu : float or sequence
        Kinetic friction coefficient(s), >= 0, one for all or one per body.
    bodies : sequence of str or int, optional
        The bodies (names or ids) that slide on the plane; default every body on a free joint with a
        geom resting on it (within ``touch``).
    mu_static : float or sequence, optional
        Static friction coefficient(s) >= mu (default mu): a body at rest stays exactly at rest while
        the in-plane load (gravity along a tilted plane, your forces, a push) lies in its contact's
        limit surface.
    pressure : Pressure or str
        How each body's normal load is spread over its footprint (:mod:`rrbody.pressure`; the default
        is centred on the body's centre of mass, linear where it must be: docs/mujoco.md).
    touch : float
        Largest gap (m) between a geom's lowest point and the plane for the geom to be a footprint.
    footprints : dict, optional
        Body (name or id) -> its footprint given by hand (a part or a list of parts of
        :mod:`rrbody.planar`, in the plane's axes from the body's centre of gravity at the pose the
        adapter is built in), in place of the one read from its geoms: for a body that collides through
        a mesh, or whose true footprint differs from its collision geoms.
    """

    def __init__(self, model: Any, data: Any, *, plane: int | str, mu: float | Sequence[float],
                 bodies: Sequence[int | str] | None = None, mu_static: float | Sequence[float] | None = None,
                 pressure: Pressure | str = "uniform", touch: float = TOUCH,
                 footprints: dict[int | str, Part | Sequence[Part]] | None = None) -> None:
        if not isinstance(model, mujoco.MjModel):
            raise ValueError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if not isinstance(data, mujoco.MjData):
            raise ValueError(f"data must be the model's mujoco.MjData, got {type(data).__name__}")
        _timestep(model)
        if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
            raise ValueError("model.opt.integrator must be Euler, implicit or implicitfast (semi-implicit: the "
                             "staggered scheme of the plugin), got RK4")
        self.model, self.data = model, data
        self.plane = p = _lookup(model, "geom", plane, "plane")
        if model.geom_type[p] != mujoco.mjtGeom.mjGEOM_PLANE:
            raise ValueError(f"plane must be a geom of type plane, got {_name(model, 'geom', p)} of type "
                             f"{mujoco.mjtGeom(model.geom_type[p]).name}")
        if model.body_weldid[model.geom_bodyid[p]] != 0:
            raise ValueError(f"plane must be fixed to the world (a geom of the worldbody or of a body welded to "
                             f"it), got {_name(model, 'geom', p)} on a moving body")
        if model.npair and np.any((model.pair_geom1 == p) | (model.pair_geom2 == p)):
            raise ValueError(f"plane {_name(model, 'geom', p)} must have no explicit <pair> contacts (their condim "
                             f"overrides the plane's)")
        self.touch = check_positive("touch", touch, unit="m")
        pressure = as_pressure(pressure)
        mujoco.mj_forward(model, data)  # poses (derived data only: the model is changed once all is checked)
        R = data.geom_xmat[p].reshape(3, 3)
        self._frame = np.ascontiguousarray(R.T)  # rows t1, t2, n (world)
        self._height = float(data.geom_xpos[p] @ R[:, 2])
        ids = self._body_ids(bodies)
        self._ids_list = ids
        n = len(ids)
        self.n = n
        self._mu = np.ascontiguousarray(_per_body("mu", mu, n))
        self._mus = self._mu.copy() if mu_static is None else np.ascontiguousarray(_per_body("mu_static", mu_static, n))
        if np.any(self._mus < self._mu):
            i = int(np.flatnonzero(self._mus < self._mu)[0])
            raise ValueError(f"mu_static{f'[{i}]' if n > 1 else ''} must be >= mu ({self._mu[i]:g}), "
                             f"got {self._mus[i]:g}")
        self._ids = np.array(ids, dtype=np.int64)
        jnt = model.body_jntadr[self._ids]
        self._dof = np.ascontiguousarray(model.jnt_dofadr[jnt], dtype=np.int64)
        self._qadr = np.ascontiguousarray(model.jnt_qposadr[jnt], dtype=np.int64)
        self._ipos = np.ascontiguousarray(model.body_ipos[self._ids], dtype=float)
        self._ref = np.ascontiguousarray(np.einsum("nji,j->ni", data.xmat[self._ids].reshape(-1, 3, 3),
                                                   self._frame[0]))
        self._geom_row = np.full(model.ngeom, -1, dtype=np.int64)
        given = self._given(footprints or {})
        feet, rows = [], np.zeros((n, K.N_BODY))
        for i, b in enumerate(ids):
            self._geom_row[model.geom_bodyid == b] = i
            parts = given[b] if b in given else parts_of(model, data, b, self._frame, self._height, self.touch)
            try:  # the footprint is from the centre of mass: a load centred elsewhere is made linear to centre it
                masses_given(parts)  # (geoms read from the model carry none: MuJoCo keeps only the body's mass)
                shapes, geo, reach, (gx, gy), jj = apply_pressure(parts, pressure, balance=True)
            except ValueError as e:
                raise ValueError(f"{_name(model, 'body', b)}: {e}") from None
            feet.append((shapes, geo))
            m = float(model.body_mass[b])
            Ri = data.ximat[b].reshape(3, 3)
            nb = Ri.T @ self._frame[2]  # the normal in the principal frame: I about n = n^T I n
            inertia = float(nb @ (model.body_inertia[b] * nb))
            rows[i, [K.MASS, K.INERTIA_PER_MASS, K.LAW, K.REACH, K.REST_RULE, K.LOAD_MEAN_X, K.LOAD_MEAN_Y,
                     K.LOAD_SPREAD, K.STAGGERED, K.HELD]] = \
                m, inertia / m, K.LAW_DRY, reach, 1.0, gx, gy, jj, 1.0, -1.0
        # every argument checked: the plane's contacts keep their normal row only (its condim wins over every
        # other geom's); that moves the depth and tilt at which MuJoCo's soft contacts hold a body at rest, so
        # the bodies resting on the plane are moved with it (rrbody.mujoco_adapter.seat); then MuJoCo's contact
        # forces for the first step
        def switch() -> None:
            model.geom_condim[p] = 1
            model.geom_priority[p] = int(np.max(model.geom_priority)) + 1

        reseat(model, data, plane=p, ids=self._ids, dof=self._dof, qadr=self._qadr, ipos=self._ipos, frame=self._frame,
               ref=self._ref, reach=np.ascontiguousarray(rows[:, K.REACH]), switch=switch)
        mujoco.mj_forward(model, data)
        self._shapes, self._geo, ranges = stack(feet)
        rows[:, K.SHAPE_FIRST], rows[:, K.SHAPE_END] = ranges[:, 0], ranges[:, 1]
        self._bodies = rows
        self._k_ids = np.arange(1, n + 1, dtype=np.int64)  # the kernel's ids: any distinct non-zero keys
        self._lookup = np.ascontiguousarray(np.vstack([self._k_ids, np.arange(n, dtype=np.int64)]))
        self._cache = np.zeros((3, max(n, K.N_STATUS)), dtype=np.int64)
        self._got = np.zeros((n, 7))
        self._out = np.zeros((n, 3))
        self._load = np.zeros(n)
        self._user = np.zeros((n, 6))
        self._gvec = np.ascontiguousarray(model.opt.gravity, dtype=float)
        self._fresh = True
        self.n_stopped = 0
        self._t_stop = np.full(n, np.nan)
        self._moving = np.zeros(n, dtype=bool)

    # ---- set-up ------------------------------------------------------------------------------
    def _body_ids(self, bodies: Sequence[int | str] | None) -> list[int]:
        m = self.model
        if bodies is None:
            ids = [b for b in range(1, m.nbody) if self._is_free(b) and self._touching(b)]
            if not ids:
                raise ValueError(f"bodies: no body on a free joint rests on plane {_name(m, 'geom', self.plane)} "
                                 f"(within touch = {self.touch:g} m); name them with bodies=[...]")
            return ids
        ids = [_lookup(m, "body", b, f"bodies[{k}]") for k, b in enumerate(bodies)]
        if len(set(ids)) != len(ids):
            raise ValueError(f"bodies must be distinct, got {list(bodies)!r}")
        for k, b in enumerate(ids):
            if not self._is_free(b):
                raise ValueError(f"bodies[{k}] ({_name(m, 'body', b)}) must be a single body on a free joint "
                                 f"(one joint, type free, no child bodies)")
            if not self._touching(b):
                raise ValueError(f"bodies[{k}] ({_name(m, 'body', b)}) must have a geom resting on plane "
                                 f"{_name(m, 'geom', self.plane)} (lowest point within touch = {self.touch:g} m)")
        return ids

    def _given(self, footprints: dict[int | str, Part | Sequence[Part]]) -> dict[int, list[Part]]:
        """The footprints given by hand, by body id (the bodies must be among the adapter's)."""
        out: dict[int, list[Part]] = {}
        for key, parts in footprints.items():
            b = _lookup(self.model, "body", key, "footprints key")
            if b not in self._ids_list:
                raise ValueError(f"footprints key {key!r} must be one of the adapter's bodies {self._ids_list!r}")
            parts = [parts] if is_part(parts) else list(parts)  # type: ignore[list-item]
            if not parts or not all(is_part(p) for p in parts):
                raise ValueError(f"footprints[{key!r}] must be a part or a list of parts (rrbody.planar.circle, box, "
                                 f"polygon, ellipse, point), got {parts!r}")
            out[b] = parts
        return out

    def _touching(self, b: int) -> bool:
        m = self.model
        return any(m.geom_contype[g] | m.geom_conaffinity[g]
                   and gap(m, self.data, int(g), self._frame, self._height) <= self.touch
                   for g in np.flatnonzero(m.geom_bodyid == b))

    def _is_free(self, b: int) -> bool:
        m = self.model
        return bool(m.body_jntnum[b] == 1 and m.jnt_type[m.body_jntadr[b]] == mujoco.mjtJoint.mjJNT_FREE
                    and not np.any(m.body_parentid[1:] == b))

    # ---- stepping ----------------------------------------------------------------------------
    def _gather(self, dt: float) -> None:
        """Read MuJoCo's state into the kernel's rows; ``dt``: the step (s), checked by the caller."""
        d = self.data
        c = d.contact
        # MuJoCo's contact fields are strided views (contiguous when they hold one contact or none): copied
        # contiguous, every call has the types of the first (one compiled version)
        cg = np.ascontiguousarray
        args = (self._dof, self._qadr, self._ids, self._ipos, self._ref, self._frame, self._gvec, self._mu, self._mus,
                self._geom_row, self.plane, d.qpos, d.qvel, d.qfrc_constraint, d.xfrc_applied, d.efc_force,
                cg(c.geom1), cg(c.geom2), cg(c.efc_address), int(d.ncon), self._bodies, self._got, self._load, dt)
        MK.gather(*args)

    def _refuse(self) -> None:
        m = self.model
        i = int(self._cache[K.STATUS, K.FIRST_BAD])
        raise ValueError(f"{_name(m, 'body', self._ids[i])}: angle, velocity and spin must be finite, "
                         f"got {self._got[i, :4].tolist()}; the step was refused and nothing changed")

    def _kick(self, dt: float) -> None:
        """Half a kick back: each body's velocity becomes the one at t - dt/2, as MuJoCo's semi-implicit step
        (velocity first, then positions with it) reads it, and its history the one a step earlier, so the
        kernel's extrapolation finds the velocity you set at t (second order from the first step)."""
        d = self.data
        self._gather(dt)
        for i in range(self.n):
            alpha, vx, vy, w, lx, ly, lt = self._got[i]
            m, ipm = self._bodies[i, K.MASS], self._bodies[i, K.INERTIA_PER_MASS]
            ax, ay, aw = lx / m, ly / m, lt / (m * ipm)
            if (vx, vy, w) != (0.0, 0.0, 0.0):
                fx, fy, fw = K.body_accel(i, alpha + w * dt, vx, vy, w, self._bodies, self._shapes, self._geo,
                                          _NO_TABLES)
                ax, ay, aw = ax + fx, ay + fy, aw + fw
                MK.set_planar(i, vx - 0.5 * dt * ax, vy - 0.5 * dt * ay, w - 0.5 * dt * aw, self._dof, self._qadr,
                              self._ipos, self._frame, d.qpos, d.qvel)
                self._bodies[i, [K.PREV_VX, K.PREV_VY, K.PREV_SPIN]] = (vx - 1.5 * dt * ax, vy - 1.5 * dt * ay,
                                                                        w - 1.5 * dt * aw)
            else:
                self._bodies[i, [K.PREV_VX, K.PREV_VY, K.PREV_SPIN]] = 0.0
            self._bodies[i, K.PREV_GAP] = dt
        self._fresh = False

    def restart(self) -> None:
        """Forget the velocity history: call it after setting the bodies' velocities by hand (the next
        step gives them the half kick, as the first step does)."""
        self._fresh = True
        self._bodies[:, [K.PREV_VX, K.PREV_VY, K.PREV_SPIN, K.PREV_GAP, K.STOP]] = 0.0
        self._bodies[:, K.HELD] = -1.0

    def step(self, n: int = 1) -> None:
        """``n`` steps of ``mujoco.mj_step`` with the plane's friction (use it in place of mj_step).

        ``n``: the number of steps, an integer >= 0 (0 does nothing). Raises ValueError, having changed
        nothing, for any other ``n`` (naming it), for a ``model.opt.timestep`` that is not finite and > 0, or
        naming a body whose angle, velocity or spin is not finite."""
        n = check_int("n", n, 0)  # range(-1) and range(1.5) would do nothing or fail far from the call
        m, d = self.model, self.data
        dt = _timestep(m)  # read here, not once at construction: you may change it between steps
        for _ in range(n):
            if self._fresh:
                self._gather(dt)
                if not K.plane_check(self._got, self._k_ids, self._lookup, self._cache, self.n):
                    self._refuse()
                self._kick(dt)
            self._gather(dt)
            gap = self._bodies[:, K.PREV_GAP].copy()  # the last step's size, before plane_step writes this one's
            n_flag = K.plane_step(self._got, self._k_ids, self._lookup, self._cache, self._bodies, self._shapes,
                                  self._geo, _NO_TABLES, float(d.time), dt, self._out, *NO_ACTIVE)
            if n_flag < 0:
                self._refuse()
            _resync(self._bodies, gap, dt)
            self.n_stopped += MK.scatter(self._dof, self._qadr, self._ids, self._ipos, self._frame, self._bodies,
                                         d.qpos, d.qvel, d.xfrc_applied, self._user, self._got, self._moving,
                                         self._t_stop, float(d.time), dt)
            mujoco.mj_step(m, d)
            MK.unapply(self._ids, d.xfrc_applied, self._user)

    # ---- readers -----------------------------------------------------------------------------
    @property
    def bodies(self) -> tuple[str, ...]:
        """The bodies that feel the plane's friction, their names (or ``"body <id>"``), in row order."""
        return tuple(self.model.body(int(b)).name or f"body {int(b)}" for b in self._ids)

    def _row(self, body: int | str) -> int:
        b = _lookup(self.model, "body", body, "body")
        hit = np.flatnonzero(self._ids == b)
        if not hit.size:
            raise ValueError(f"body must be one of this PlaneFriction's bodies {list(self.bodies)!r}, got {body!r}")
        return int(hit[0])

    def velocity(self, body: int | str) -> tuple[float, float, float]:
        """(vx, vy, spin) of ``body``'s centre of gravity in the plane's axes at ``data.time`` (m/s,
        rad/s): MuJoCo's velocity after a step belongs to half a step before it, so this is it
        extrapolated by half a step with the one of the step before (second-order accurate, as the
        plugin's ``velocity``), 0 where that crosses zero (a stop within the half step); in the step the rest
        rule stops the body, MuJoCo's own."""
        i = self._row(body)
        self._gather(_timestep(self.model))
        v = self._got[i, 1:4]
        p = self._bodies[i]
        if p[K.PREV_GAP] <= 0.0 or self._fresh or p[K.STOP] > 0.0 or not v.any():
            return float(v[0]), float(v[1]), float(v[2])
        e = 1.5 * v - 0.5 * p[[K.PREV_VX, K.PREV_VY, K.PREV_SPIN]]
        e[e * v < 0.0] = 0.0  # a stop within the half step: the extrapolation must not overshoot it
        return float(e[0]), float(e[1]), float(e[2])

    def normal_force(self, body: int | str) -> float:
        """The normal force (N) of ``body``'s contacts with the plane in MuJoCo's last step."""
        i = self._row(body)
        self._gather(_timestep(self.model))
        return float(self._load[i])

    def friction(self, body: int | str) -> tuple[float, float, float]:
        """The friction the last step applied to ``body``: force (N, along the plane's t1, t2) at its
        centre of gravity and torque about the normal (N m), the rest rule's stop included."""
        p = self._bodies[self._row(body)]
        return float(p[K.FRICTION_FX]), float(p[K.FRICTION_FY]), float(p[K.FRICTION_TORQUE])

    def stop_time(self, body: int | str) -> float | None:
        """When ``body`` last came to rest in the plane (s, ``data.time``; within a step), if it is at rest now."""
        i = self._row(body)
        self._gather(_timestep(self.model))
        if np.any(self._got[i, 1:4] != 0.0) and self._bodies[i, K.STOP] == 0.0:
            return None
        t = self._t_stop[i]
        return None if math.isnan(t) else float(t)
