"""Engine layer: area friction from a horizontal plane for pymunk bodies, and rrbody's scenes in pymunk.

- :class:`PlaneFriction` (``rrbody.engine.plugin``): the plugin for any pymunk program;
- :func:`attach` (``rrbody.engine.builder``): rrbody's own scenes built on it;
- :func:`simulate_engine`, :func:`engine_flip_time` (``rrbody.engine.run``): the run loop;
- :class:`EngineSettings` and the dt rules (``rrbody.engine.settings``). Needs pymunk.
"""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined: numba caches them in rrbody's cache folder

from rrbody.engine.builder import EngineHandle, attach, plane_for
from rrbody.engine.plugin import PRESSURES, PlaneFriction
from rrbody.engine.run import engine_flip_time, simulate_engine
from rrbody.engine.settings import COARSE_FRACTION, MAX_FRACTION, EngineSettings, default_dt, valid_dt_range

__all__ = ["PlaneFriction", "PRESSURES", "EngineSettings", "EngineHandle", "attach", "plane_for", "simulate_engine",
           "engine_flip_time", "valid_dt_range", "default_dt", "COARSE_FRACTION", "MAX_FRACTION"]
