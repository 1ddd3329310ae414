"""Engine layer: rrbody's bodies in a pymunk ``Space`` (needs pymunk)."""

from rrbody.engine.core import (COARSE_FRACTION, MAX_FRACTION, EngineHandle, EngineSettings, attach,
                                engine_flip_time, simulate_engine, valid_dt_range)

__all__ = ["EngineSettings", "EngineHandle", "attach", "simulate_engine", "engine_flip_time", "valid_dt_range",
           "COARSE_FRACTION", "MAX_FRACTION"]
