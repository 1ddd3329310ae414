"""The MuJoCo adapter's public entry point: ``from rrbody.mujoco import PlaneFriction``.

Like :mod:`rrbody.plugin` this module is part of the curated public API above every layer; the adapter
lives in :mod:`rrbody.mujoco_adapter.plane` and needs the ``[mujoco]`` extra (``import rrbody`` never imports
MuJoCo). Without it, importing this module raises one ImportError naming the extra to install.
"""

from rrbody.mujoco_adapter.plane import PlaneFriction

__all__ = ["PlaneFriction"]
