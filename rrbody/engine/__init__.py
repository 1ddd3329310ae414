"""Engine layer: area friction from a horizontal plane for pymunk bodies, and rrbody's scenes in pymunk.

- :class:`PlaneFriction` (``rrbody.engine.plugin``): the plugin for any pymunk program;
- :func:`attach` and the run loop (``simulate_engine``, ``engine_flip_time``): rrbody's own scenes built
  on it (needs pymunk).
"""

from rrbody.engine.core import (COARSE_FRACTION, MAX_FRACTION, EngineHandle, EngineSettings, attach,
                                engine_flip_time, simulate_engine, valid_dt_range)
from rrbody.engine.plugin import PRESSURES, PlaneFriction

__all__ = ["PlaneFriction", "PRESSURES", "EngineSettings", "EngineHandle", "attach", "simulate_engine",
           "engine_flip_time", "valid_dt_range", "COARSE_FRACTION", "MAX_FRACTION"]
