"""The MuJoCo adapter: rrbody's plane step (:mod:`rrbody.contact`) under the free bodies of a MuJoCo model.

- :mod:`~rrbody.mujoco_adapter.plane`: ``PlaneFriction`` for a MuJoCo model and its data (imports MuJoCo);
- :mod:`~rrbody.mujoco_adapter.geoms`: a body's geoms as footprint parts (imports MuJoCo);
- :mod:`~rrbody.mujoco_adapter.seat`: the bodies resting on the plane moved with the switch of its contacts
  (imports MuJoCo);
- :mod:`~rrbody.mujoco_adapter.kernel`: the compiled reads and writes of MuJoCo's arrays (no MuJoCo
  import: they take its arrays, so they compile at install without the extra).

Users import :mod:`rrbody.mujoco` (``from rrbody.mujoco import PlaneFriction``). This package imports
neither pymunk nor :mod:`rrbody.engine` (``tests/test_layers.py``).
"""
