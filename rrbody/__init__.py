"""rrbody: rigid bodies driven around a circle, spinning freely about the driven point P and
sliding on a rough plane; reverse rotation under dry (Coulomb) friction.

Heavy parts (numba kernels, pymunk, renderers) load lazily, so ``import rrbody`` is cheap: it imports
no numpy, numba, scipy or optional extra until a name below is used.

The public surface, every name reachable both as an attribute of ``rrbody`` and by an import:

- names (``rrbody.simulate``, ``from rrbody import simulate``): :data:`__all__`, the scene and analysis
  API, and the pymunk plugin's ``PlaneFriction``, ``Recorder`` and ``Active``;
- sub-modules (``rrbody.pressure``, ``import rrbody.pressure``, ``from rrbody import pressure``,
  ``from rrbody.pressure import ring``): ``pressure``, ``planar``, ``plugin`` and ``mujoco``. ``plugin``
  needs the ``engine`` extra and ``mujoco`` the ``mujoco`` extra: without it, using them raises an
  ImportError that names the extra to install.
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
    "PlaneFriction": "rrbody.engine.plugin", "Recorder": "rrbody.render.recorder", "Active": "rrbody.model.active",
}

#: public sub-modules: each a real module (``import rrbody.pressure`` works) that the attribute returns too
_MODULES = {"pressure": "rrbody.pressure", "planar": "rrbody.planar", "plugin": "rrbody.plugin",
            "mujoco": "rrbody.mujoco"}

__all__ = ["__version__", *_LAZY, *_MODULES]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name]), name)
        globals()[name] = value  # the next access is a plain attribute
        return value
    if name in _MODULES:
        return import_module(_MODULES[name])  # (importing a sub-module sets it as an attribute)
    raise AttributeError(f"module 'rrbody' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
