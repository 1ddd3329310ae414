"""What differs between the pymunk versions rrbody supports (6.6 and later, 7.x) in the calls its own
programs make, in one place.

pymunk 7 replaced ``Space.add_collision_handler(a, b)``, ``add_wildcard_collision_handler(a)`` and
``add_default_collision_handler()`` (pymunk 6: a handler object whose ``begin`` callback returns
whether the contact is processed) by ``Space.on_collision(a, b, begin=...)`` (a callback that
returns nothing; the contact is processed unless the arbiter says otherwise). :func:`on_begin`
registers a callback that only observes contacts, on either. (The plugin and the recorder need
nothing of the kind: their routes to the bodies are in :mod:`rrbody.engine.memory.batchio`.)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["on_begin", "on_post_solve"]


def on_begin(space: Any, a: int | None, b: int | None, fn: Callable[[Any, Any, Any], Any]) -> None:
    """Call ``fn(arbiter, space, data)`` when two shapes of collision types ``a`` and ``b`` start touching
    (``b`` None: ``a`` and any type; both None: any two shapes), and let the contact be processed as
    usual whatever ``fn`` returns."""
    if a is None and b is not None:
        raise ValueError(f"b must be None when a is None (any two shapes), got a=None, b={b!r}")
    if hasattr(space, "on_collision"):  # pymunk >= 7
        def observe(arbiter: Any, sp: Any, data: Any) -> None:
            fn(arbiter, sp, data)  # pymunk 7 processes the contact unless the arbiter is told otherwise

        space.on_collision(a, b, begin=observe)
        return
    if a is None:
        handler = space.add_default_collision_handler()
    elif b is None:
        handler = space.add_wildcard_collision_handler(a)
    else:
        handler = space.add_collision_handler(a, b)

    def begin(arbiter: Any, sp: Any, data: Any) -> bool:
        fn(arbiter, sp, data)
        return True  # pymunk 6: process the contact

    handler.begin = begin


def on_post_solve(space: Any, a: int, b: int, fn: Callable[[Any, Any, Any], Any]) -> None:
    """Call ``fn(arbiter, space, data)`` after the solver has processed a contact between shapes of
    collision types ``a`` and ``b``, on every step it lasts (to count or read contacts; it changes none)."""
    if hasattr(space, "on_collision"):  # pymunk >= 7
        space.on_collision(a, b, post_solve=fn)
    else:
        space.add_collision_handler(a, b).post_solve = fn
