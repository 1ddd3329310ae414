"""The plane step both engine adapters call: rrbody's exact area friction for rigid bodies on a plane,
with no engine in it (this package imports neither pymunk nor MuJoCo; ``tests/test_layers.py``).

- :mod:`~rrbody.contact.columns`: the layout of the flat arrays an adapter fills (one row per body);
- :mod:`~rrbody.contact.accel`: one body's friction wrench and its limiter (the force);
- :mod:`~rrbody.contact.kernel`: the compiled step over all bodies (the force pass), and
  :mod:`~rrbody.contact.rest`: the operator applied in it (the rest rule, static friction's hold or break);
- :mod:`~rrbody.contact.feet`: bodies on point feet; self-propelled bodies are a load in the step (their
  arrays: :mod:`~rrbody.contact.columns`, with ``NO_ACTIVE``, the pair passed when there are none);
- :mod:`~rrbody.contact.lean`: the kernels' numba options (no reference counting).

The adapters: :mod:`rrbody.engine` (pymunk: the plugin ``PlaneFriction``, which keeps its bodies' footprints,
wrench tables and active bodies in :mod:`rrbody.engine.plugin`, and rrbody's own scenes) and
:mod:`rrbody.mujoco_adapter` (MuJoCo, entered through :mod:`rrbody.mujoco`). Units: SI; per unit mass, forces in m/s^2
and torques in m^2/s^2.
"""

from rrbody._cache import use_for_kernels

use_for_kernels()  # before any kernel is defined: numba caches them in rrbody's cache folder
