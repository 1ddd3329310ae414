"""Normal-pressure distributions of a contact, public entry point: ``from rrbody.pressure import ring``.

Like :mod:`rrbody.plugin` this module is part of the curated public API above every layer; the
distributions live in :mod:`rrbody.model.pressure` (where each one's load goes, in m in the body frame
from the centre of gravity). ``import rrbody.pressure``, ``from rrbody import pressure`` and the
attribute ``rrbody.pressure`` all give this module.
"""

from rrbody.model.pressure import (PRESSURE_KINDS, Pressure, annulus, as_pressure, field, hertz, parse_pressure,
                                   points, pressure_from_description, ring, uniform)

__all__ = ["Pressure", "uniform", "ring", "annulus", "hertz", "points", "field", "parse_pressure", "as_pressure",
           "pressure_from_description", "PRESSURE_KINDS"]
