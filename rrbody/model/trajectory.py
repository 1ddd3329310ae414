"""The one result type: a sampled trajectory with its events and metadata.

Every integrator path (ODE, engine, free body) returns a :class:`Trajectory`; analysis,
renderers, sweeps and tests read only this. World frame, SI units: t (s), angles (rad),
positions (m), velocities (m/s), spin (rad/s).

CSV format: the first line is ``# rrbody-meta: {json}`` (scene, method, settings, events,
rrbody version), the second the column names, then one row per sample.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rrbody._version import __version__
from rrbody.model.io import atomic_path

if TYPE_CHECKING:
    from rrbody.model.scene import Scene

__all__ = ["Trajectory", "COLUMNS", "VOLATILE_META", "driven_trajectory", "jsonable"]

COLUMNS: tuple[str, ...] = ("t", "phi", "phi_dot", "x_cm", "y_cm", "vx_cm", "vy_cm", "x_p", "y_p", "body_angle",
                            "spin")
_META_PREFIX = "# rrbody-meta: "
#: metadata keys that measure the machine, not the run (wall-clock seconds): kept in memory, never
#: written to a file, so regenerating a run with unchanged numbers rewrites identical bytes
VOLATILE_META: tuple[str, ...] = ("wall_s",)


def jsonable(obj: Any) -> Any:
    """``obj`` as plain Python that :func:`json.dumps` writes as strict JSON: dict keys made strings,
    tuples and arrays made lists, numpy scalars made ``float`` and ``int``, and a non-finite float
    (NaN, inf) made ``None`` (JSON has no such number); anything else is returned as it is. Values keep
    their units: nothing is converted. Used for every JSON rrbody writes (CSV headers, summaries,
    sweep specs, the CLI's ``--json`` lines)."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    return obj


@dataclass
class Trajectory:
    """Samples of one run (arrays of equal length) plus ``events`` and ``meta`` dictionaries.

    ``phi``: angle of CM -> P; ``body_angle``: angle of the body's R_A axis; ``spin``: d(body_angle)/dt.
    ``events`` holds e.g. ``t_f``, ``phi_min``, ``T1``, ``minima`` (list of [t, phi]).
    """

    t: np.ndarray
    phi: np.ndarray
    phi_dot: np.ndarray
    x_cm: np.ndarray
    y_cm: np.ndarray
    vx_cm: np.ndarray
    vy_cm: np.ndarray
    x_p: np.ndarray
    y_p: np.ndarray
    body_angle: np.ndarray
    spin: np.ndarray
    events: dict[str, Any] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def theta(self) -> np.ndarray:
        """Rotating-frame angle theta = phi - omega t + pi (rad); needs a driven run."""
        omega = float(self.meta.get("scene", {}).get("drive", {}).get("omega", math.nan) or math.nan)
        return self.phi - omega * self.t + math.pi

    def settled_flip(self, *, settle_turns: float = 2.0, settle_periods: float = 3.0) -> tuple[float | None, bool]:
        """The flip as far as this run alone can tell: ``(t_f, settled)``.

        Applies :func:`rrbody.analysis.flip_time`'s stopping rule to the run's located minima
        (``events['minima']``, [t (s), phi (rad)] rows) and its samples: the flip is *settled* once,
        after the lowest minimum so far (phi_min at t_min), phi has risen to phi_min + 2 pi
        ``settle_turns`` and ``settle_periods`` driving periods have passed. Then ``t_f`` is that
        minimum's time, or None when phi_min is not below phi0 (no reverse rotation). A run that
        ends before the rule is met returns ``(None, False)``: its flip may lie beyond the span
        (ask ``flip_time`` for the whole run). Free or undriven runs, runs without minima
        information and frictionless runs (no flip ever) also return ``(None, False)``.
        """
        sc = self.meta.get("scene") or {}
        drive = sc.get("drive")
        minima = np.asarray(self.events.get("minima") or [], dtype=float).reshape(-1, 2)
        if not drive or len(self) == 0 or (sc.get("friction") or {}).get("law", "dry") == "none":
            return None, False
        period = 2.0 * math.pi / float(drive["omega"])
        phi0 = float(sc.get("phi0", self.phi[0]))
        if len(minima) == 0:
            return None, False
        # the lowest minimum at or before each sample: running min and the index where it was reached
        order = np.argsort(minima[:, 0], kind="stable")
        mt, mv = minima[order, 0], minima[order, 1]
        run_v = np.minimum.accumulate(mv)
        new_low = np.concatenate([[True], mv[1:] < run_v[:-1]])
        run_i = np.maximum.accumulate(np.where(new_low, np.arange(len(mv)), 0))
        j = np.searchsorted(mt, self.t, side="right") - 1  # index of the last minimum at or before t
        has = j >= 0
        jj = np.where(has, j, 0)
        low = np.where(has, run_v[jj], np.inf)
        t_low = np.where(has, mt[run_i[jj]], np.nan)
        ok = has & (self.phi >= low + 2.0 * math.pi * settle_turns) & (self.t - t_low >= settle_periods * period)
        if not ok.any():
            return None, False
        first = int(np.argmax(ok))
        if low[first] >= phi0:
            return None, True
        return float(t_low[first]), True

    def column_array(self) -> np.ndarray:
        return np.column_stack([getattr(self, c) for c in COLUMNS])

    def save(self, path: str | Path, *, force: bool = False) -> Path:
        """Write CSV (JSON metadata in the first line) atomically; refuses to overwrite unless ``force``.

        Wall-clock timings (:data:`VOLATILE_META`) are left out, so the file depends on the run only.
        """
        meta = {k: v for k, v in self.meta.items() if k not in VOLATILE_META}
        header = _META_PREFIX + json.dumps(jsonable({"meta": meta, "events": self.events}))
        with atomic_path(path, force=force, name="out") as tmp, open(tmp, "w") as fh:
            fh.write(header + "\n")
            fh.write(",".join(COLUMNS) + "\n")
            np.savetxt(fh, self.column_array(), delimiter=",", fmt="%.17g")
        return Path(path)

    @classmethod
    def load(cls, path: str | Path) -> Trajectory:
        """Read a CSV written by :meth:`save`."""
        p = Path(path)
        with open(p) as fh:
            first = fh.readline()
            names = fh.readline().strip().split(",")
            if not first.startswith(_META_PREFIX) or tuple(names[: len(COLUMNS)]) != COLUMNS:
                raise ValueError(f"{str(p)!r} is not an rrbody trajectory CSV")
            data = np.loadtxt(fh, delimiter=",", ndmin=2)
        head = json.loads(first[len(_META_PREFIX):])
        cols = {c: (data[:, i] if data.size else np.empty(0)) for i, c in enumerate(COLUMNS)}
        return cls(**cols, events=head.get("events", {}), meta=head.get("meta", {}))


def driven_trajectory(scene: Scene, t: np.ndarray, phi: np.ndarray, phi_dot: np.ndarray) -> Trajectory:
    """Assemble a Trajectory of a driven body from samples of phi(t), phi'(t) (rad, rad/s)."""
    drive = scene.drive
    if drive is None:
        raise ValueError("driven_trajectory needs a driven scene (drive is None)")
    l = scene.body.l
    P = drive.position(t)
    V = drive.velocity(t)
    e = np.column_stack([np.cos(phi), np.sin(phi)])
    eperp = np.column_stack([-np.sin(phi), np.cos(phi)])
    cm = P - l * e
    vcm = V - l * phi_dot[:, None] * eperp
    beta = scene.phi0 - scene.body.alpha0
    return Trajectory(t=t, phi=phi, phi_dot=phi_dot, x_cm=cm[:, 0], y_cm=cm[:, 1], vx_cm=vcm[:, 0],
                      vy_cm=vcm[:, 1], x_p=P[:, 0], y_p=P[:, 1], body_angle=phi - beta, spin=phi_dot.copy(),
                      meta={"scene": scene.describe(), "rrbody_version": __version__})
