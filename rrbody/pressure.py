"""Normal-pressure distributions of a contact, public entry point: ``from rrbody.pressure import ring``.

Like :mod:`rrbody.plugin` this module is part of the curated public API above every layer; the
distributions live in :mod:`rrbody.model.pressure` (where each one's load goes, in m in the body frame
from the centre of gravity). ``import rrbody.pressure``, ``from rrbody import pressure`` and the
attribute ``rrbody.pressure`` all give this module.
"""

from rrbody.model import pressure as _source
from rrbody.model.pressure import *  # noqa: F403  (every name of its __all__, so the two never drift apart)

__all__ = list(_source.__all__)
