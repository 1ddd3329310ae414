"""rrbody.physics.overlap: the area common to two unions of convex pieces, against exact areas and,
where shapely is installed (beside gym-pusht), against its polygon overlay."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody.physics.overlap import overlap_area, pieces_area

SQUARE = np.array([[[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]])
TEE = np.array([[[-60.0, 30.0], [60.0, 30.0], [60.0, 0.0], [-60.0, 0.0]],
                [[-15.0, 30.0], [-15.0, 120.0], [15.0, 120.0], [15.0, 30.0]]])


def _turn(p: np.ndarray, angle: float, dx: float = 0.0, dy: float = 0.0) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return p @ np.array([[c, s], [-s, c]]) + [dx, dy]


def test_exact_areas() -> None:
    """Closed forms, to rounding (1e-14 of areas of order 1)."""
    assert pieces_area(TEE) == 120 * 30 + 30 * 90
    assert overlap_area(SQUARE, SQUARE) == pytest.approx(1.0, abs=1e-14)
    assert overlap_area(SQUARE, SQUARE + [0.25, 0.5]) == pytest.approx(0.75 * 0.5, abs=1e-14)
    assert overlap_area(SQUARE, SQUARE + [1.5, 0.0]) == 0.0
    assert overlap_area(SQUARE, SQUARE + [1.0, 0.0]) == 0.0  # touching along an edge
    # a unit square and itself turned by 45 degrees about its centre: a regular octagon, 2 (sqrt 2 - 1)
    assert overlap_area(SQUARE, _turn(SQUARE, math.pi / 4)) == pytest.approx(2 * (math.sqrt(2) - 1), abs=1e-14)
    # either orientation of either polygon
    assert overlap_area(SQUARE[:, ::-1], _turn(SQUARE, 0.3)[:, ::-1]) == pytest.approx(
        overlap_area(SQUARE, _turn(SQUARE, 0.3)), abs=1e-15)


def test_a_tee_against_itself_shifted_along_its_bar() -> None:
    """30 along the top bar: the bar keeps 90 x 30, the stem (30 wide) leaves its place: 2700 exactly."""
    assert overlap_area(TEE, TEE + [30.0, 0.0]) == pytest.approx(2700.0, abs=1e-10)


def test_against_shapely() -> None:
    """Random poses of a T against the goal T: the same area as shapely's overlay to 1e-12 relative
    (both exact up to rounding; measured 5e-15)."""
    sg = pytest.importorskip("shapely.geometry")
    goal = _turn(TEE, math.pi / 4, 256, 256)
    g = sg.MultiPolygon([sg.Polygon(p) for p in goal])
    rng = np.random.default_rng(5)
    hits = 0
    for _ in range(300):
        t = _turn(TEE, rng.uniform(-math.pi, math.pi), *rng.uniform(150, 350, 2))
        ref = sg.MultiPolygon([sg.Polygon(p) for p in t]).intersection(g).area
        assert overlap_area(t, goal) == pytest.approx(ref, abs=1e-12 * 6300)
        hits += ref > 0
    assert hits > 50
