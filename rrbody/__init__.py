"""rrbody: rigid bodies driven around a circle, spinning freely about the driven point P and
sliding on a rough plane; reverse rotation under dry (Coulomb) friction.

Heavy parts (numba kernels, pymunk, renderers) load lazily, so ``import rrbody`` is cheap.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

from rrbody._version import __version__

_LAZY = {
    "RodMass": "rrbody.model.bodies", "Disk": "rrbody.model.bodies", "Ellipse": "rrbody.model.bodies",
    "CircularDrive": "rrbody.model.drive", "Friction": "rrbody.model.friction",
    "Scene": "rrbody.model.scene", "rod_mass_scene": "rrbody.model.scene",
    "Trajectory": "rrbody.model.trajectory",
    "simulate": "rrbody.analysis.simulate", "ACCURACY": "rrbody.analysis.simulate",
    "flip_time": "rrbody.analysis.flip", "FlipResult": "rrbody.integrate.events",
    "reverse_rotation_exists": "rrbody.analysis.flip", "critical_h": "rrbody.analysis.flip",
    "parse_angle": "rrbody.model.angles",
    "PlaneFriction": "rrbody.engine.plugin",
}

#: sub-modules reachable as attributes (``rrbody.pressure.ring(0.05)``, ``rrbody.planar.circle(0.1)``)
_MODULES = {"pressure": "rrbody.model.pressure", "planar": "rrbody.physics.planar"}

__all__ = ["__version__", *_LAZY, *_MODULES]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    if name in _MODULES:
        return import_module(_MODULES[name])
    raise AttributeError(f"module 'rrbody' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
