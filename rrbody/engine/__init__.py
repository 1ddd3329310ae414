"""The pymunk engine path: rrbody's plane step (:mod:`rrbody.contact`) for pymunk bodies, and rrbody's
scenes run in pymunk (``--method engine``; the ``engine`` extra). One owner per sub-package, bottom to top
(imports run downward only: ``tests/test_layers.py``):

- :mod:`rrbody.engine.memory`: pymunk's memory read and written (``bodymem``, ``structio``, ``batchio``), the
  contacts pymunk solved (``arbiters``), and ``compat`` for pymunk 6 and 7;
- :mod:`rrbody.engine.plugin`: :class:`PlaneFriction` (``plane``), the plugin for any pymunk program (users import
  it from :mod:`rrbody.plugin`), its table of bodies and the read-only accessors to their rows (``plane_rows``),
  what ``add`` checks and writes (``admit``), its bodies' shapes as footprints (``shapes``), its stores
  (``footprints``, ``active``, ``rows``) and the coupled step (``coupling``);
- :mod:`rrbody.engine.recording`: the recorder's capture tape (``tape``, with its copy kernels in ``capture``): the
  frames of filmed bodies, which :class:`rrbody.render.recorder.Recorder` draws;
- :mod:`rrbody.engine.scenes`: rrbody's own scenes built on the plugin: :func:`attach` (``builder``), the run loop
  :func:`simulate_engine`, :func:`engine_flip_time` (``run``, ``track``), :class:`EngineSettings` and the dt rules
  (``settings``). Needs pymunk.

The recording and the scenes share a level and do not import each other. This package imports no MuJoCo and
nothing of :mod:`rrbody.mujoco_adapter` (``tests/test_layers.py``).
"""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined (the sub-packages' too): numba caches them in rrbody's cache folder

from rrbody.engine.plugin import PRESSURES, PlaneFriction
from rrbody.engine.scenes.builder import EngineHandle, attach, plane_for
from rrbody.engine.scenes.run import engine_flip_time, simulate_engine
from rrbody.engine.scenes.settings import COARSE_FRACTION, MAX_FRACTION, EngineSettings, default_dt, valid_dt_range

__all__ = ["PlaneFriction", "PRESSURES", "EngineSettings", "EngineHandle", "attach", "plane_for", "simulate_engine",
           "engine_flip_time", "valid_dt_range", "default_dt", "COARSE_FRACTION", "MAX_FRACTION"]
