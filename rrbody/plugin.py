"""The pymunk plugin's public entry point: ``from rrbody.plugin import PlaneFriction``.

Like :mod:`rrbody` itself this module is part of the curated public API above every layer; the
plugin lives in :mod:`rrbody.engine.plugin` (it needs the ``[engine]`` extra, pymunk).
"""

from rrbody.engine.plugin import PlaneFriction

__all__ = ["PlaneFriction"]
