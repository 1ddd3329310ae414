"""Sub-steps for a table: no body on it crosses more than a wall's thickness in one step.

On a table a body keeps its momentum (gym-pusht wipes every velocity at every step), so a fast T can
cross a wall within one physics step: pymunk moves every body first and finds the contacts after, at the
new positions, and a shape that ends a step beyond a wall's centre line is pushed out on the far side
(one that went past the wall meets nothing). :func:`guarded` steps the table so that this cannot happen.
Before each physics step it bounds the distance any point of a body on the table can travel, (|v| +
|omega| r) dt, r being the body's farthest point from its centre of gravity; where that exceeds the
thinnest wall's thickness and the distance from the body's bounding box to a wall's, it runs the step as
sub-steps of dt / 2^k, each moving the body less than a wall's thickness. Any other step (every step at
rest, nearly every step of ordinary pushing, a fast slide in the open) is the one step of dt, as before,
after one read of the body's kinetic energy where pymunk computes that in C (pymunk 7) or of its
velocity and spin (pymunk 6).

Each sub-step is a whole ``plane.step(dt / 2^k)``: friction, then pymunk's step. The sub-steps are
checked again one by one (a contact may speed a body up within a step), and a sub-step is never more
than twice the one before it, the steps after a fast spell included: Chipmunk starts each step from the
previous step's contact impulses scaled by the ratio of the two steps, so a T pinched between the agent
and a wall, held by impulses of a step a hundred times shorter, would leave at a hundred times the
speed. The sizes are powers of two of dt, each aligned on its own size, so that a physics step's
sub-steps add up to dt.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import Any

import pymunk

__all__ = ["LEVELS", "MAX_SUBSTEPS", "far_point", "guarded", "thickness", "wall_thickness"]

#: a physics step of dt is cut into pymunk steps of dt / 2^k, k <= LEVELS: at most 2^13 = 8192 of them.
#: With gym-pusht's walls and step that keeps bodies up to 3.3e6 units/s inside (its agent pushes at most
#: about 2,000 units/s; a T wedged by it into a wall is shot out faster: the table study's fastest squirt
#: was 2,897 units/s). A faster body gets 8192 sub-steps, a bounded cost, and may cross a wall.
LEVELS = 13
MAX_SUBSTEPS = 1 << LEVELS

_NEW_PYMUNK = int(pymunk.version.split(".")[0]) >= 7  # Body.kinetic_energy computed in C (in 6.x: in Python)


def thickness(shape: Any) -> float:
    """The narrowest width of ``shape`` (units): a circle's or a segment's diameter 2 r, a convex
    polygon's smallest extent across any of its edges plus 2 r (its rounding radius)."""
    if isinstance(shape, pymunk.Poly):
        pts = [(p.x, p.y) for p in shape.get_vertices()]
        best = math.inf
        for i, (ax, ay) in enumerate(pts):
            bx, by = pts[(i + 1) % len(pts)]
            length = math.hypot(bx - ax, by - ay)
            if length > 0.0:
                best = min(best, max(abs((bx - ax) * (py - ay) - (by - ay) * (px - ax)) for px, py in pts) / length)
        return (0.0 if best == math.inf else best) + 2.0 * shape.radius
    return 2.0 * shape.radius


def _walls(space: pymunk.Space) -> list[Any]:
    return [s for s in space.shapes if s.body.body_type == pymunk.Body.STATIC]


def wall_thickness(space: pymunk.Space) -> float:
    """The thickness of the thinnest shape of a static body in ``space`` (its walls), units; inf if it
    has none."""
    return min((thickness(s) for s in _walls(space)), default=math.inf)


def far_point(body: pymunk.Body) -> float:
    """The distance from ``body``'s centre of gravity to the farthest point of its shapes, units."""
    c = body.center_of_gravity
    far = 0.0
    for s in body.shapes:
        if isinstance(s, pymunk.Poly):
            pts = list(s.get_vertices())
        elif isinstance(s, pymunk.Segment):
            pts = [s.a, s.b]
        else:
            pts = [s.offset]
        far = max(far, max(abs(p - c) for p in pts) + s.radius)
    return far


def _gap(box: Any, walls: list[Any]) -> float:
    """The distance between the bounding box ``box`` and the nearest of ``walls`` (bounding boxes),
    units: no point of the box's shapes comes nearer a wall than that."""
    gap = math.inf
    for w in walls:
        dx = max(w.left - box.right, box.left - w.right, 0.0)
        dy = max(w.bottom - box.top, box.bottom - w.top, 0.0)
        gap = min(gap, math.hypot(dx, dy))
    return gap


def guarded(step: Callable[[float], None], bodies: Iterable[Any], space: pymunk.Space) -> Callable[[float], None]:
    """``step(dt)`` (the table's ``plane.step`` on ``space``) cut into sub-steps where a body would
    cross more than a wall's thickness (the thinnest static shape of ``space``; for walls without
    thickness, half the thinnest shape of the bodies) in one step and could reach a wall in it.

    Returns ``step`` itself when there is nothing to guard (no walls, no bodies). The walls, and the
    bodies' shapes, mass, moment and centre of gravity, are read once, here: guard a table again after
    changing them. One physics step makes at most :data:`MAX_SUBSTEPS` calls of ``step``, each of dt / 2^k.
    A non-finite velocity is left to ``step``, which refuses it (PlaneFriction names the body).
    """
    walls = wall_thickness(space)
    bodies = list(bodies)
    if walls == math.inf or not bodies:
        return step
    if not walls > 0.0:
        # walls without thickness (segments of radius 0): a body is pushed back while less than half of it
        # has crossed one, so its thinnest shape's half-width bounds a sub-step's travel instead
        walls = min(thickness(s) for b in bodies for s in b.shapes) / 2.0
    boxes = [s.cache_bb() for s in _walls(space)]
    # per body: (body, its farthest point r, 1/m + r^2/I). Chipmunk's kinetic energy E = m v^2 + I w^2 (no
    # 1/2) bounds |v| + |w| r by sqrt(E (1/m + r^2/I)) (Cauchy-Schwarz): one read says a body is slow enough
    reach = [far_point(b) for b in bodies]
    rows = [(b, r, 1.0 / b.mass + r * r / b.moment) for b, r in zip(bodies, reach)]
    walls2 = walls * walls
    get_v, get_w = pymunk.Body.velocity.fget, pymunk.Body.angular_velocity.fget
    energy = pymunk.Body.kinetic_energy.fget

    def pieces(dt: float) -> int:
        """How many sub-steps the step of dt needs: 1 unless a body's fastest point would move more than a
        wall's thickness and as far as a wall; NaN velocities count as 1 (the plugin refuses them)."""
        n = 1
        for b, r, _ in rows:
            v = get_v(b)
            d = (math.hypot(v.x, v.y) + abs(get_w(b)) * r) * dt
            if not d > walls:
                continue
            box = None
            for s in b.shapes:  # (cache_bb: where the body is now, whoever moved it)
                bb = s.cache_bb()
                box = bb if box is None else box.merge(bb)
            if box is None or d >= _gap(box, boxes):
                n = max(n, math.floor(d / walls) + 1)  # (d / n < walls, with room for rounding)
        return n

    full = True  # the last pymunk step was a whole physics step (no ramp owed)
    last = LEVELS  # its size, dt / 2^(LEVELS - last)

    def tile(dt: float) -> None:
        """The physics step of dt as sub-steps of dt / 2^k: each aligned on its own size (they add up to
        dt), at most twice the one before, and short enough that no body crosses a wall in it."""
        nonlocal full, last
        p = 0  # where the step has got to, in units of its smallest sub-step, dt / MAX_SUBSTEPS
        while p < MAX_SUBSTEPS:
            k = LEVELS if p == 0 else (p & -p).bit_length() - 1  # the largest sub-step aligned at p
            k = min(k, last + 1)
            h = dt / (1 << (LEVELS - k))
            if not slow(h):
                n = pieces(h)
                if n > 1:
                    k = max(0, k - (n - 1).bit_length())
                    h = dt / (1 << (LEVELS - k))
            step(h)
            p += 1 << k
            last = k
        full = last == LEVELS

    if len(rows) == 1:  # (the T of Push-T: the hot path, one read and one comparison per physics step)
        (body, r, c), = rows
        if _NEW_PYMUNK:
            def slow(dt: float) -> bool:
                return energy(body) * (dt * dt) * c <= walls2

            def advance(dt: float) -> None:
                if full and energy(body) * (dt * dt) * c <= walls2:
                    step(dt)
                else:
                    tile(dt)
        else:  # two reads: pymunk 6's kinetic_energy is Python that reads the velocity twice
            hypot = math.hypot

            def slow(dt: float) -> bool:
                vx, vy = get_v(body)
                return (hypot(vx, vy) + abs(get_w(body)) * r) * dt <= walls

            def advance(dt: float) -> None:
                if full:
                    vx, vy = get_v(body)
                    if (hypot(vx, vy) + abs(get_w(body)) * r) * dt <= walls:
                        step(dt)
                        return
                tile(dt)
    else:
        def slow(dt: float) -> bool:
            dt2 = dt * dt
            return all(energy(b) * dt2 * c <= walls2 for b, _, c in rows)

        def advance(dt: float) -> None:
            if full and slow(dt):
                step(dt)
            else:
                tile(dt)

    return advance
