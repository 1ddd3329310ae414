"""rrbody's own scenes in pymunk (``--method engine``), built on the plugin.

- :mod:`~rrbody.engine.scenes.builder`: :func:`~rrbody.engine.scenes.builder.attach`, a scene's body, drive and
  table in a pymunk space;
- :mod:`~rrbody.engine.scenes.run`: the run loop, :func:`~rrbody.engine.scenes.run.simulate_engine` and
  :func:`~rrbody.engine.scenes.run.engine_flip_time`, with its per-step compiled call in
  :mod:`~rrbody.engine.scenes.track`;
- :mod:`~rrbody.engine.scenes.settings`: :class:`~rrbody.engine.scenes.settings.EngineSettings` and the dt rules.
"""
