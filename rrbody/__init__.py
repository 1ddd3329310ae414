"""rrbody: rigid bodies driven around a circle, spinning freely about the driven point P and
sliding on a rough plane; reverse rotation under dry (Coulomb) friction.

Heavy parts (numba kernels, pymunk, renderers) load lazily, so ``import rrbody`` is cheap.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

_LAZY = {
    "RodMass": "rrbody.bodies", "Disk": "rrbody.bodies", "Ellipse": "rrbody.bodies",
    "CircularDrive": "rrbody.drive", "Friction": "rrbody.friction",
    "Scene": "rrbody.scene", "rod_mass_scene": "rrbody.scene",
    "Trajectory": "rrbody.trajectory",
    "simulate": "rrbody.simulation", "ACCURACY": "rrbody.simulation",
    "flip_time": "rrbody.analysis", "FlipResult": "rrbody.analysis",
    "reverse_rotation_exists": "rrbody.analysis", "critical_h": "rrbody.analysis",
    "parse_angle": "rrbody.angles",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'rrbody' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
