"""The pymunk plugin: :class:`~rrbody.engine.plugin.plane.PlaneFriction` and the stores it keeps.

- :mod:`~rrbody.engine.plugin.plane`: the class (users import it from :mod:`rrbody.plugin`);
- :mod:`~rrbody.engine.plugin.plane_rows`: its table of bodies and the read-only accessors to their rows;
  :mod:`~rrbody.engine.plugin.admit`: what ``add`` checks and writes; :mod:`~rrbody.engine.plugin.shapes`: a
  body's shapes as a footprint;
- its stores: :mod:`~rrbody.engine.plugin.footprints` (the bodies' footprints and wrench tables),
  :mod:`~rrbody.engine.plugin.active` (the active bodies), :mod:`~rrbody.engine.plugin.rows` (growable arrays of
  rows, which the recorder's tape uses too);
- :mod:`~rrbody.engine.plugin.coupling`: the coupled step, the plane's friction solved with pymunk's contacts.

It steps :mod:`rrbody.contact`'s kernels and reads and writes pymunk through :mod:`rrbody.engine.memory`.
"""

from rrbody.engine.plugin.plane import PRESSURES, PlaneFriction

__all__ = ["PlaneFriction", "PRESSURES"]
