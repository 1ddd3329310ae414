"""The plugin's active bodies: :meth:`PlaneFriction.activate`'s store and the arrays its step passes on.

``PlaneFriction.activate(body, Active(...))`` makes a plugin body self-propelled
(:mod:`rrbody.model.active`: the propulsion fixed in the body frame at a body point, a medium's drag,
Langevin noise). The parameters live in an array of their own, ``active`` (one row per plugin row,
columns :mod:`rrbody.physics.effects.active`), rebuilt from the stored :class:`Active` values
whenever the plugin's membership changed (O(n), once per change), so the plugin's own rows stay as
they are. The noise comes from one ``numpy.random.Generator(PCG64(seed))`` per plugin: one vectorised
draw per step of the standard normal numbers the noisy bodies use (two for a translational noise, one
for a rotational one, in the plugin's row order), so the same seed and the same program give
bit-identical runs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.contact import columns
from rrbody.contact.columns import NO_ACTIVE
from rrbody.model.active import MAX_SEED, Active
from rrbody.model.checks import check_int
from rrbody.model.laws import law_coded
from rrbody.physics.effects import active as A

__all__ = ["ActiveSet"]


class ActiveSet:
    """The active bodies of one PlaneFriction ``pf`` (which owns the rows: ``pf.row_index(body)``)."""

    def __init__(self, seed: int = 0) -> None:
        self.params: dict[Any, Active] = {}
        self.pending: set[Any] = set()  # activated since the last step: their half kick is due
        self.seed(seed)
        self._members = -1  # pf.members when the rows were built (-1: never)
        self._rows, self._noise = NO_ACTIVE
        self._noisy = 0

    def seed(self, seed: int) -> None:
        """Restart the noise from ``seed`` (an integer in [0, 2^63 - 1])."""
        s = check_int("seed", seed, 0, MAX_SEED)
        self.rng = np.random.Generator(np.random.PCG64(s))

    def set(self, body: Any, active: Active | None) -> None:
        """Store (or, with None, drop) ``body``'s parameters; the rows are rebuilt at the next step."""
        if active is None:
            self.params.pop(body, None)
            self.pending.discard(body)
        else:
            if not isinstance(active, Active):
                raise ValueError(f"active must be an rrbody.plugin.Active, got {active!r}")
            self.params[body] = active
            self.pending.add(body)
        self._members = -1

    def _build(self, pf: Any) -> None:
        """The ``active`` rows in the plugin's row order (bodies no longer in the plugin dropped)."""
        for body in [b for b in self.params if pf.row_index(b) is None]:
            del self.params[body]
            self.pending.discard(body)
        order = pf.bodies_by_row
        n = len(order)
        rows = np.zeros((n, A.N_ACTIVE))
        first = 0
        for j, body in enumerate(order):  # in row order: the noise's numbers go to the bodies in a fixed order
            a = self.params.get(body)
            if a is not None:
                rows[j] = A.row(a.body_force, a.torque, a.drag, a.rot_drag, a.diffusion, a.rot_diffusion,
                                          float(body.mass), float(body.moment), first)
                first += A.noise_count(a.diffusion, a.rot_diffusion)
        self._rows = rows if self.params else NO_ACTIVE[0]
        self._noisy = first
        self._noise = np.zeros(first) if first else NO_ACTIVE[1]
        self._members = pf.members

    def kick(self, pf: Any, dt: float) -> None:
        """Half a kick of the deterministic active terms for bodies activated since the last step (the
        staggered scheme's start, as the plugin's own half kick of friction: docs/engine.md).

        A body exactly at rest on dry friction (a law that sticks) under the rest rule gets none: its
        propulsion is a load like a hand-applied force or a tilt's pull, which the step's rest rule and
        static friction hold exactly, or let break away, as they do those (a kick without friction moved a
        body that static friction holds, and it slid off)."""
        h = 0.5 * dt
        for body in self.pending:
            j = pf.row_index(body)
            if j is None:
                continue
            row = pf.rows[j]
            if law_coded(row[columns.LAW]).sticks and row[columns.REST_RULE] > 0.0 and body.angular_velocity == 0.0 \
                    and body.velocity == (0.0, 0.0):
                continue
            a = self.params[body]
            m, moment = float(body.mass), float(body.moment)
            fbx, fby = a.body_force
            ca, sa = math.cos(body.angle), math.sin(body.angle)
            v = body.velocity
            w = float(body.angular_velocity)
            body.velocity = (v.x + h * ((ca * fbx - sa * fby) / m - a.drag * v.x),
                             v.y + h * ((sa * fbx + ca * fby) / m - a.drag * v.y))
            body.angular_velocity = w + h * (a.torque / moment - a.rot_drag * w)
        self.pending.clear()

    def arrays(self, pf: Any) -> tuple[np.ndarray, np.ndarray]:
        """This step's ``active`` and ``noise`` arrays (fresh normal numbers if any body is noisy)."""
        if self._members != pf.members:
            self._build(pf)
        if self._noisy:
            self.rng.standard_normal(out=self._noise)
        return self._rows, self._noise
