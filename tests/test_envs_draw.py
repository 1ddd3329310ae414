"""Push-T's pictures drawn without pygame or OpenCV (rrbody.envs.pusht_draw) against gym-pusht 0.1.8's own.

The comparisons need gym-pusht (its pygame, pymunk and OpenCV): they are skipped without it, unless
RRBODY_REQUIRE_PUSHT=1 (for the oldest-versions venv, which has gym-pusht), which makes a missing one fail.

Measured on the states below (seeds 0-23, the reset and 5 steps each aimed near the block so that the
agent pushes it: 144 states, 63 of them with contact marks), on 2026-11-29 with gym-pusht 0.1.8,
pygame 2.6.1, pymunk 6.6.0, opencv-python 4.11.0.86, numpy 1.26: the 512 x 512 surface, the 96 x 96
observation and the 680 x 680 render (red cross included) are identical to gym-pusht's, pixel for
pixel, in every state; so are pictures of 84 x 64 and 300 x 200. The tolerance asserted is therefore
none. That this is not vacuous: the block moved by 1 unit puts more than 8 levels off at least
0.24 % of the pixels of every 96 x 96 picture, with a mean absolute difference of at least 0.080
levels (asserted: more than 0.1 % and 0.02 levels). Left out, the contact marks put at most 0.022 %
of the pixels more than 8 levels off (mean at most 0.011 levels).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from rrbody.envs import pusht_draw
from rrbody.envs.pusht_draw import draw
from tests.pusht_support import need

#: what a picture 1 unit off exceeds in every state (see the module's docstring)
FAR, LEVELS, MEAN = 0.001, 8, 0.02


def _tee(x: float, y: float, angle: float) -> np.ndarray:
    """gym-pusht's T (bar, then stem; scale 30) at pose (x, y, angle), world vertices (2, 4, 2), units."""
    local = np.array([[(-60, 30), (60, 30), (60, 0), (-60, 0)], [(-15, 30), (-15, 120), (15, 120), (15, 30)]], float)
    c, s = np.cos(angle), np.sin(angle)
    return local @ np.array([[c, s], [-s, c]]) + (x, y)


GOAL = _tee(256, 256, np.pi / 4)


@dataclass
class State:
    agent: tuple[float, float]
    block: np.ndarray  # the bar, then the stem
    goal: np.ndarray
    contacts: np.ndarray | None
    action: Any
    surface: np.ndarray  # gym-pusht's 512 x 512 surface
    obs: np.ndarray  # its observation (96 x 96 unless said)
    render: np.ndarray  # its render (680 x 680 unless said)


def _states(seeds: range, steps: int, **sizes: int) -> list[State]:
    """gym-pusht's pictures of the states after a reset and each of ``steps`` actions aimed near the block."""
    need("gym_pusht")
    gym, pygame = need("gymnasium"), need("pygame")
    env = gym.make("gym_pusht/PushT-v0", obs_type="pixels", render_mode="rgb_array", **sizes)
    u, out = env.unwrapped, []
    for seed in seeds:
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        for k in range(steps + 1):
            if k:
                env.step(np.asarray(u.block.position + rng.normal(0, 50, 2), dtype=float))
            # the bar, then the stem (gym-pusht's list; ``block.shapes`` is a set)
            block = np.array([[u.block.local_to_world(v) for v in s.get_vertices()] for s in u._block_shapes])
            goal_body = u.get_goal_pose_body(u.goal_pose)
            goal = np.array([[goal_body.local_to_world(v) for v in s.get_vertices()] for s in u._block_shapes])
            segments: list[Any] = []

            def contact(arbiter: Any) -> None:
                cps = arbiter.contact_point_set
                n = np.array(cps.normal)
                segments.extend([np.array(p.point_a) - 2 * n, np.array(p.point_b) + 2 * n] for p in cps.points)

            u.block.each_arbiter(contact)
            surface = np.transpose(np.array(pygame.surfarray.pixels3d(u._draw())), (1, 0, 2))
            out.append(State(tuple(u.agent.position), block, goal, np.array(segments) if segments else None,
                             u._last_action, surface, u._render(), env.render()))
    env.close()
    return out


@pytest.fixture(scope="module")
def states() -> list[State]:
    return _states(range(24), 5)


def _far_mean(mine: np.ndarray, theirs: np.ndarray) -> tuple[float, float]:
    """The fraction of pixels with a channel off by more than LEVELS, the mean absolute difference (levels)."""
    d = np.abs(mine.astype(np.int64) - theirs)
    return float((d.max(axis=2) > LEVELS).mean()), float(d.mean())


def test_the_surface_is_gym_pushts_pixel_for_pixel(states: list[State]) -> None:
    assert sum(s.contacts is not None for s in states) >= 20  # contact marks are among those compared
    for s in states:
        assert np.array_equal(draw(s.agent, s.block, s.goal, 512, 512, contacts=s.contacts), s.surface)


def test_the_pictures_are_gym_pushts_pixel_for_pixel(states: list[State]) -> None:
    for s in states:
        assert np.array_equal(draw(s.agent, s.block, s.goal, 96, 96, contacts=s.contacts), s.obs)
        assert np.array_equal(draw(s.agent, s.block, s.goal, 680, 680, s.action, s.contacts), s.render)
        # the comparison can fail: the block 1 unit off is seen in every picture
        far, mean = _far_mean(draw(s.agent, s.block + 1.0, s.goal, 96, 96, contacts=s.contacts), s.obs)
        assert far > FAR and mean > MEAN, (far, mean)


def test_other_sizes_are_gym_pushts() -> None:
    sizes = dict(observation_width=84, observation_height=64, visualization_width=300, visualization_height=200)
    for s in _states(range(3), 2, **sizes):
        assert np.array_equal(draw(s.agent, s.block, s.goal, 84, 64, contacts=s.contacts), s.obs)
        assert np.array_equal(draw(s.agent, s.block, s.goal, 300, 200, s.action, s.contacts), s.render)


def test_the_rasterisation_is_pygames_off_the_surface_too() -> None:
    """Fat segments, polygons and disks, some partly or wholly off the surface (clipped), against pygame."""
    need("gym_pusht")
    pygame = need("pygame")
    from gym_pusht.envs.pymunk_override import DrawOptions
    from pymunk.space_debug_draw_options import SpaceDebugColor

    t, white = pusht_draw._tables(512, 512), SpaceDebugColor(255, 255, 255, 255)

    def theirs(paint: Any) -> np.ndarray:
        surface = pygame.Surface((512, 512))
        paint(surface)
        return pygame.surfarray.pixels3d(surface)[..., 0].T > 0

    def mine(spans: Any) -> np.ndarray:
        grid = np.zeros((512, 512), dtype=np.uint8)
        pusht_draw._paint(grid, t, spans, [1] * (int(spans[4].max(initial=0)) + 1))
        return grid > 0

    rng, none = np.random.default_rng(1), np.zeros((0, 4, 2), np.int64)
    for i in range(120):
        a = rng.uniform(-150, 662, 2) if i % 2 else rng.uniform(20, 490, 2)
        b = a + rng.normal(0, 150 if i % 3 else 8, 2)
        got = mine(pusht_draw._fat(a[None], b[None], none, t))
        assert np.array_equal(got, theirs(lambda s: DrawOptions(s).draw_fat_segment(tuple(a), tuple(b), 2, white,
                                                                                    white)))
        p = np.rint(_tee(*rng.uniform(-40, 550, 2), rng.uniform(-np.pi, np.pi))[i % 2]).astype(np.int64)
        got = mine(pusht_draw._fat(*np.zeros((2, 0, 2)), p[None], t))
        assert np.array_equal(got, theirs(lambda s: pygame.draw.polygon(s, (255, 255, 255), [*map(tuple, p),
                                                                                             tuple(p[0])])))
        c, r = rng.integers(-10, 522, 2), int(rng.integers(1, 20))
        grid = np.zeros((512, 512), dtype=np.uint8)
        pusht_draw._disk(grid, t, c, r, 1)
        assert np.array_equal(grid > 0, theirs(lambda s: pygame.draw.circle(s, (255, 255, 255), tuple(c), r)))


def test_the_cross_is_opencvs() -> None:
    cv2 = need("cv2")
    for side in (50, 96, 150, 200, 680, 1000):
        ms, th = int(8 / 96 * side), int(1 / 96 * side)
        for x, y in ((side // 2, side // 3), (2, side - 3)):
            mine, theirs = np.zeros((side, side, 3), np.uint8), np.zeros((side, side, 3), np.uint8)
            pusht_draw._marker(mine, x, y, ms, max(th, 1))
            cv2.drawMarker(theirs, (x, y), color=(255, 0, 0), markerType=cv2.MARKER_CROSS, markerSize=ms,
                           thickness=max(th, 1))  # OpenCV refuses a thickness of 0, as gym-pusht would pass
            assert np.array_equal(mine, theirs), (side, x, y)


def test_shapes_dtypes_and_determinism() -> None:
    block = _tee(300, 200, 0.3)
    for width, height in ((96, 96), (680, 680), (64, 80), (1, 1), (513, 7)):
        img = draw((100.0, 400.0), block, GOAL, width, height, action=np.array([100.0, 400.0]))
        assert img.shape == (height, width, 3) and img.dtype == np.uint8 and img.flags.c_contiguous
    first = draw((100.0, 400.0), block, GOAL, 96, 96)
    other = draw((100.0, 400.0), block, _tee(200, 300, 1.0), 96, 96)  # another goal, then the first again
    assert not np.array_equal(first, other)
    assert np.array_equal(draw((100.0, 400.0), block, GOAL, 96, 96), first)
    assert np.array_equal(draw([100, 400], block.tolist(), GOAL, 96, 96), first)  # lists are arrays
    assert (first[75, 18] == pusht_draw.PALETTE[5]).all()  # the agent's inner disk at (98.2, 402.2)


def test_bad_input_is_a_value_error_naming_it() -> None:
    block = _tee(300, 200, 0.3)
    for width, height, name in ((0, 96, "width"), (96, -1, "height"), (96.0, 96, "width"), (96, 5000, "height"),
                                (True, 96, "width"), ("96", 96, "width")):
        with pytest.raises(ValueError, match=f"{name} must be an integer from 1 to 4096"):
            draw((1.0, 2.0), block, GOAL, width, height)
    for kwargs, name in ((dict(agent=(1.0, 2.0, 3.0)), "agent"), (dict(agent=(np.nan, 2.0)), "agent"),
                         (dict(block=block[0]), "block"), (dict(goal=GOAL * np.inf), "goal"),
                         (dict(action=(1.0,)), "action"), (dict(contacts=np.zeros((2, 3))), "contacts"),
                         (dict(agent="here"), "agent")):
        args = dict(agent=(1.0, 2.0), block=block, goal=GOAL, width=96, height=96) | kwargs
        with pytest.raises(ValueError, match=name):
            draw(**args)
