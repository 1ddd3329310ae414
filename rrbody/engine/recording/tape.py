"""The recorder's capture tape: the numbers of the filmed bodies of a pymunk space, frame by frame.

A :class:`Tape` holds which bodies are filmed and, per stored frame and body, its pose (x, y, angle:
the pymunk body's origin in m, world frame, and its angle in rad) and, with ``motion=True``, the
velocity of its centre of gravity and its spin at the frame's time (m/s, rad/s: for bodies of the
plugin the second-order reading :meth:`rrbody.engine.plugin.plane.PlaneFriction.velocity` gives) and the
friction the plane applied in the last step (N and N m, :meth:`rrbody.engine.plugin.plane.PlaneFriction.friction`).
:meth:`Tape.capture` stores one frame in one compiled call (:mod:`rrbody.engine.recording.capture`), read
from the bodies' structs where pymunk's layout of them is known, else from the space's bulk read.

The pictures drawn from a tape are :class:`rrbody.render.recorder.Recorder`'s (the user-facing
class): this module reads pymunk and the plugin, and draws nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from rrbody.contact import kernel as K
from rrbody.engine.memory.batchio import BatchIO, body_uid, rows_of
from rrbody.engine.memory.bodymem import address, addresses
from rrbody.engine.plugin.rows import Rows
from rrbody.engine.recording.capture import capture_direct, capture_rows, layout
from rrbody.model.checks import check_int, check_positive, check_real

__all__ = ["Tape", "WIDTH_POSE", "WIDTH_MOTION", "PX", "PY", "PA", "VX", "VY", "VW", "FX", "FY", "FT"]

#: numbers per body and frame: a pose (x, y, angle), or with motion also vx, vy, spin, fx, fy, torque
WIDTH_POSE, WIDTH_MOTION = 3, 9
#: the columns of a frame (rrbody.engine.recording.capture writes them in this order): the body origin's x, y (m)
#: and angle (rad); the centre of gravity's velocity (m/s) and the spin (rad/s); the friction force (N)
#: and torque (N m) of the plane's last step
PX, PY, PA, VX, VY, VW, FX, FY, FT = range(9)
#: the plugin's rows when there is no plane (capture_rows reads none of it then); read-only as the
#: plugin's own (PlaneFriction.rows), so that both give the capture kernels one type
_NO_ROWS = np.zeros((0, K.N_BODY))
_NO_ROWS.flags.writeable = False


class Tape:
    """The captured frames of chosen bodies of a pymunk space (see the module docstring).

    The parameters are :class:`rrbody.render.recorder.Recorder`'s of the same names: ``space``, ``plane``
    (its PlaneFriction or None), ``bodies`` (default: the plane's bodies, then every other body of the
    space that can move and has shapes), ``labels`` (a name per body), ``every``, ``motion``, ``max_mb``
    (the frames' memory cap, 10^6 bytes) and ``reserve`` (room for this many frames, written now).
    """

    def __init__(self, space: Any, plane: Any = None, *, bodies: Sequence[Any] | None = None,
                 labels: Sequence[str] | None = None, every: int = 1, motion: bool = True,
                 max_mb: float = 1000.0, reserve: int | None = None) -> None:
        import pymunk

        if not isinstance(space, pymunk.Space):
            raise ValueError(f"space must be a pymunk.Space, got {space!r}")
        if plane is not None and getattr(plane, "space", None) is not space:
            raise ValueError(f"plane must be the PlaneFriction of this space (or None), got {plane!r}")
        self.space, self.plane = space, plane
        self.every = check_int("every", every, 1, 10**9)
        self.max_mb = check_positive("max_mb", max_mb, unit="MB")
        self.motion = bool(motion)
        if bodies is None:
            first = list(plane.bodies) if plane is not None else []
            seen = set(first)
            bodies = first + [b for b in space.bodies if b not in seen and b.shapes
                              and b.body_type != pymunk.Body.STATIC]
        self.bodies: tuple[Any, ...] = tuple(bodies)
        if not self.bodies:
            raise ValueError("bodies: nothing to film, got 0 bodies (the space has no dynamic or kinematic body "
                             "with shapes): add bodies to the space before creating the Recorder")
        for k, b in enumerate(self.bodies):
            if not isinstance(b, pymunk.Body) or b.space is not space or b.body_type == pymunk.Body.STATIC \
                    or not b.shapes:
                raise ValueError(f"bodies[{k}] must be a dynamic or kinematic pymunk.Body with shapes, in this "
                                 f"space, got {b!r}")
        if len(set(self.bodies)) != len(self.bodies):
            raise ValueError("bodies must not repeat a body")
        if labels is None:
            labels = [f"b{k:04d}" for k in range(len(self.bodies))]
        self.labels = tuple(str(x) for x in labels)
        if len(self.labels) != len(self.bodies) or len(set(self.labels)) != len(self.labels):
            raise ValueError(f"labels must give {len(self.bodies)} distinct names (one per body), got "
                             f"{len(self.labels)} ({len(set(self.labels))} distinct)")
        #: each body's centre of gravity in its own frame (m), read now (like the plugin's add)
        self.cog = np.array([tuple(b.center_of_gravity) for b in self.bodies], dtype=float)
        self.ids = np.array([body_uid(b) for b in self.bodies], dtype=np.int64)
        #: the driven point P (body frame, m; NaN for a body not driven) and the drive's sense (+1, -1,
        #: or 0: not driven), for bodies rrbody's builder drives (PlaneRows.drive)
        self.anchor = np.full((len(self.bodies), 2), np.nan)
        self.drive_sense = np.zeros(len(self.bodies))
        if plane is not None:
            for k, b in enumerate(self.bodies):
                if plane.row_index(b) is not None:
                    row = plane.row_of(b)
                    if row[K.DRIVEN] > 0.0:
                        self.anchor[k] = row[[K.ANCHOR_X, K.ANCHOR_Y]]
                        self.drive_sense[k] = math.copysign(1.0, row[K.DRIVE_OMEGA])
        self.width = WIDTH_MOTION if self.motion else WIDTH_POSE
        #: memory one frame takes: bodies x width numbers x 8 bytes
        self.bytes_per_frame = len(self.bodies) * self.width * 8
        self._max_frames = int(self.max_mb * 1e6 // self.bytes_per_frame)  # the most frames max_mb allows
        self._store = Rows((len(self.bodies), self.width))  # the frames, and their times (s)
        self._clock = Rows(None)
        if reserve is not None:
            if self._max_frames < 1:
                raise ValueError(f"reserve: max_mb={self.max_mb:g} MB holds no frame of {self.bytes_per_frame} "
                                 f"bytes; raise max_mb")
            reserve = check_int("reserve", reserve, 1, self._max_frames,
                                unit=f"frames (what max_mb={self.max_mb:g} MB holds)")
            self._store.ensure(reserve, touch=True)
            self._clock.ensure(reserve, touch=True)
        self._calls = 0
        self._rows = np.full(len(self.bodies), -1, dtype=np.int64)  # their rows in the space's bulk read
        self._prow: tuple[int, np.ndarray] | None = None  # (plane.members, their rows in the plane's arrays)
        self._no_plane = np.full(len(self.bodies), -1, dtype=np.int64)
        # the bodies' state is read from their structs where pymunk's layout of them is known (no call
        # into pymunk), else from the space's bulk read, which copies every body (rrbody.engine.recording.capture)
        self._offs = layout()
        self._io = BatchIO(space, poses=True) if self._offs is None else None
        if self._offs is not None:
            self._addr = addresses(self.bodies)
            self._space_addr = address(space._space)

    # ---- the frames ------------------------------------------------------------------------------
    @property
    def n_frames(self) -> int:
        """How many frames were captured."""
        return self._store.n

    @property
    def data(self) -> np.ndarray:
        """The frame store, not a copy (its first ``n_frames`` rows are the frames, (bodies, width)
        each: see :attr:`rrbody.render.recorder.Recorder.frames`); for the pictures drawn from it."""
        return self._store.buf

    @property
    def stamps(self) -> np.ndarray:
        """The frames' times (s; the first ``n_frames``), not a copy."""
        return self._clock.buf

    def centres(self) -> np.ndarray:
        """Centres of gravity (frames, bodies, 2), m, world frame."""
        d = self._store.buf[:self.n_frames]
        c, s = np.cos(d[:, :, PA]), np.sin(d[:, :, PA])
        gx, gy = self.cog[:, 0], self.cog[:, 1]
        return np.stack([d[:, :, PX] + c * gx - s * gy, d[:, :, PY] + s * gx + c * gy], axis=2)

    # ---- capture ---------------------------------------------------------------------------------
    def capture(self, t: float | None = None) -> bool:
        """Store this instant (one call in ``every``; returns whether it stored a frame). ``t``: the time
        (s); default the plane's clock. Raises ValueError, storing nothing, if a filmed body has left the
        space or the frame would pass ``max_mb``; the frames already captured stay."""
        self._calls += 1
        if (self._calls - 1) % self.every:
            return False
        if t is None:
            if self.plane is None:
                raise ValueError("t must be given (the frame's time, s) when the Recorder has no plane")
            t = float(self.plane.t)
        else:
            t = check_real("t", t)
        n = self._store.n
        if n >= self._store.buf.shape[0] or n >= self._max_frames:
            self._make_room(n)
        prow = self._plane_rows()
        bodies = _NO_ROWS if self.plane is None else self.plane.rows
        store = self._store.buf
        if self._io is None:
            kernel, args = capture_direct, (self._addr, self._offs, self._space_addr, bodies, prow, store, n)
        else:
            got, ids, _ = self._io.read()
            kernel, args = capture_rows, (got, ids, self.ids, self._rows, bodies, prow, store, n)
        result = kernel(*args)
        if self._io is None:
            if result >= 0:  # the index of a filmed body no longer in the space
                self._gone(result, n)
        elif not result:
            # the space's order changed (bodies added or removed): find the filmed bodies again
            order = np.argsort(ids)
            rows = rows_of(ids[order], order, self.ids)
            if (rows < 0).any():
                self._gone(int(np.flatnonzero(rows < 0)[0]), n)
            self._rows = rows
            capture_rows(got, ids, self.ids, self._rows, bodies, prow, store, n)
        self._clock.buf[n] = t
        self._store.n = self._clock.n = n + 1
        return True

    def _gone(self, k: int, n: int) -> None:
        """The ValueError for filmed body ``k`` having left the space at frame ``n`` (nothing is stored)."""
        raise ValueError(f"bodies[{k}] ({self.labels[k]}) is no longer in the space (frame {n}): a filmed "
                         f"body must stay in the space; the {n} frames captured are kept")

    def _make_room(self, n: int) -> None:
        """Room for frame ``n`` (the store doubles), or the ValueError of ``max_mb`` (nothing changes)."""
        if n + 1 > self._max_frames:
            raise ValueError(f"max_mb: frame {n} would take the capture past max_mb={self.max_mb:g} MB "
                             f"({len(self.bodies)} bodies x {self.width} numbers x 8 bytes a frame); "
                             f"the {n} frames captured are kept: film them, raise max_mb, or capture less "
                             f"often (every=...)")
        self._store.ensure(n + 1)
        self._clock.ensure(n + 1)  # the same capacity as the store's: both grow by the same rule

    def _plane_rows(self) -> np.ndarray:
        """Each filmed body's row in the plane's arrays, or -1 (cached until the plane's membership changes)."""
        pf = self.plane
        if pf is None:
            return self._no_plane
        if self._prow is None or self._prow[0] != pf.members:
            self._prow = (pf.members, pf.rows_of_ids(self.ids))
        return self._prow[1]
