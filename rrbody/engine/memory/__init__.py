"""How rrbody reaches pymunk: its memory read and written (the bodies' structs, ``pymunk.batch``, the contacts) and
the calls in which pymunk 6 and 7 differ. The bottom of :mod:`rrbody.engine`: the plugin and the recorder's tape
import it, it imports neither.

- :mod:`~rrbody.engine.memory.bodymem`: raw access to Chipmunk's C structs in compiled code (an object's address,
  the layout of a ``cpBody`` found by a probe);
- :mod:`~rrbody.engine.memory.structio`: the plugin's per-step read and write straight from the bodies' structs
  (and its one compiled call, ``struct_step``); :mod:`~rrbody.engine.memory.batchio`: the same through
  ``pymunk.batch``, or body by body;
- :mod:`~rrbody.engine.memory.arbiters`: the contacts pymunk solved in a step, for the coupled step (Chipmunk's C
  functions called from compiled code, or pymunk's public API);
- :mod:`~rrbody.engine.memory.compat`: pymunk 6 and 7's collision callbacks behind one call.

The private fast paths here, and their takeovers, are listed in docs/versions.md.
"""
