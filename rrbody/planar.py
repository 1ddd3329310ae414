"""The batched dry-friction wrench of planar contacts, public entry point: ``from rrbody.planar import
Footprints``.

Like :mod:`rrbody.plugin` this module is part of the curated public API above every layer; the wrench
lives in :mod:`rrbody.physics.planar` (footprints in m in the body frame, forces in N in the world
frame, torques in N m). ``import rrbody.planar``, ``from rrbody import planar`` and the attribute
``rrbody.planar`` all give this module. Importing it loads numpy and the compiled kernels' modules;
``import rrbody`` alone does not.
"""

from rrbody.physics import planar as _source
from rrbody.physics.planar import *  # noqa: F403  (every name of its __all__, so the two never drift apart)

__all__ = list(_source.__all__)
