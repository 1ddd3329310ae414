"""The recorder's tape: the frames of the filmed bodies of a pymunk space, which
:class:`rrbody.render.recorder.Recorder` draws.

- :mod:`~rrbody.engine.recording.tape`: :class:`~rrbody.engine.recording.tape.Tape`, what is filmed and the frames
  (with the friction the plugin's rows hold);
- :mod:`~rrbody.engine.recording.capture`: its copy kernels, reading the bodies' structs
  (:mod:`rrbody.engine.memory.bodymem`).
"""
