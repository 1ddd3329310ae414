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

__all__ = ["Trajectory", "COLUMNS", "driven_trajectory"]

COLUMNS: tuple[str, ...] = ("t", "phi", "phi_dot", "x_cm", "y_cm", "vx_cm", "vy_cm", "x_p", "y_p", "body_angle",
                            "spin")
_META_PREFIX = "# rrbody-meta: "


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
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

    def column_array(self) -> np.ndarray:
        return np.column_stack([getattr(self, c) for c in COLUMNS])

    def save(self, path: str | Path, *, force: bool = False) -> Path:
        """Write CSV (JSON metadata in the first line) atomically; refuses to overwrite unless ``force``."""
        header = _META_PREFIX + json.dumps(_jsonable({"meta": self.meta, "events": self.events}))
        with atomic_path(path, force=force, name="out") as tmp, open(tmp, "w") as fh:
            fh.write(header + "\n")
            fh.write(",".join(COLUMNS) + "\n")
            np.savetxt(fh, self.column_array(), delimiter=",", fmt="%.17g")
        return Path(path)

    @classmethod
    def load(cls, path: str | Path) -> "Trajectory":
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


def driven_trajectory(scene: "Scene", t: np.ndarray, phi: np.ndarray, phi_dot: np.ndarray) -> Trajectory:
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
