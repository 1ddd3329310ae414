"""The pymunk plugin's public entry point: ``from rrbody.plugin import PlaneFriction, Recorder``.

Like :mod:`rrbody` itself this module is part of the curated public API above every layer; the
plugin lives in :mod:`rrbody.engine.plugin` (it needs the ``[engine]`` extra, pymunk), the recorder
that films its bodies in :mod:`rrbody.render.recorder` (MP4 needs the ``[movie]`` extra, rerun
recordings the ``[rerun]`` one); :class:`Active` is an active body's propulsion, drag and noise
(``pf.activate(body, Active(...))``, docs/active.md).
"""

from rrbody.engine.plugin import PlaneFriction
from rrbody.model.active import Active
from rrbody.render.recorder import Recorder

__all__ = ["PlaneFriction", "Recorder", "Active"]
