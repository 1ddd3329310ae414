"""The pymunk engine path: rrbody's plane step (:mod:`rrbody.contact`) for pymunk bodies, and rrbody's
scenes run in pymunk (``--method engine``; the ``engine`` extra).

- :class:`PlaneFriction` (``rrbody.engine.plugin``): the plugin for any pymunk program (users import it
  from :mod:`rrbody.plugin`); its table of bodies and the read-only accessors to their rows
  (``plane_rows``), what ``add`` checks and writes (``admit``), its bodies' shapes as footprints
  (``shapes``) and its reads and writes of pymunk's memory (``bodymem``, ``structio``, ``batchio``;
  ``compat`` for pymunk 6 and 7);
- the recorder's capture tape (``tape``, with its copy kernels in ``capture``): the frames of filmed
  bodies, which :class:`rrbody.render.recorder.Recorder` draws;
- :func:`attach` (``rrbody.engine.builder``): rrbody's own scenes built on it;
- :func:`simulate_engine`, :func:`engine_flip_time` (``rrbody.engine.run``, ``track``): the run loop;
- :class:`EngineSettings` and the dt rules (``rrbody.engine.settings``). Needs pymunk.

This package imports no MuJoCo and nothing of :mod:`rrbody.mujoco_adapter` (``tests/test_layers.py``).
"""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined: numba caches them in rrbody's cache folder

from rrbody.engine.builder import EngineHandle, attach, plane_for
from rrbody.engine.plugin import PRESSURES, PlaneFriction
from rrbody.engine.run import engine_flip_time, simulate_engine
from rrbody.engine.settings import COARSE_FRACTION, MAX_FRACTION, EngineSettings, default_dt, valid_dt_range

__all__ = ["PlaneFriction", "PRESSURES", "EngineSettings", "EngineHandle", "attach", "plane_for", "simulate_engine",
           "engine_flip_time", "valid_dt_range", "default_dt", "COARSE_FRACTION", "MAX_FRACTION"]
