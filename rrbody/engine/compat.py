"""What differs between the pymunk versions rrbody supports (6.6 and later, 7.x), in one place.

pymunk 7 replaced ``Space.add_collision_handler(a, b)`` and ``Space.add_default_collision_handler()``
(pymunk 6: a handler object whose ``begin`` callback returns whether the contact is processed) by
``Space.on_collision(a, b, begin=...)`` (a callback that returns nothing; the contact is processed
unless the arbiter says otherwise). :func:`on_begin` registers a callback that only observes contacts
on either.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["on_begin"]


def on_begin(space: Any, a: int | None, b: int | None, fn: Callable[[Any, Any, Any], None]) -> None:
    """Call ``fn(arbiter, space, data)`` when two shapes of collision types ``a`` and ``b`` start touching
    (both None: any two shapes), leaving the contact to be processed as usual."""
    if hasattr(space, "on_collision"):  # pymunk >= 7
        space.on_collision(a, b, begin=fn)
        return
    handler = space.add_default_collision_handler() if a is None and b is None \
        else space.add_collision_handler(a, b)

    def begin(arbiter: Any, sp: Any, data: Any) -> bool:
        fn(arbiter, sp, data)
        return True  # pymunk 6: process the contact

    handler.begin = begin
