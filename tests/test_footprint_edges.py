"""The wrench table on and next to a polygon's edges (rrbody.physics.footprint_fit.edge_lines, cell_line,
singular_part) and the tables' store in the cache folder (rrbody.engine.plugin.footprints.stored).

A uniformly loaded polygon's wrench, as a function of the instantaneous centre c, is not smooth across
its edges: the fan triangle on an edge (rrbody.physics.polygon) carries h^2 log|h| terms, h the distance
of c from the edge's line. A cell on an edge fits the wrench less those terms, which are smooth no more
than the wrench is, and adds them back. Tolerances: TOL = 1e-10, the table's stated accuracy; VALID_TOL
= 5e-11, what a fit must reach at its validation points to be used (docs/footprint-table.md).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody.physics.contact import footprint_wrench
from rrbody.physics.footprint import combine, polygon_part
from rrbody.physics.footprint_fit import cell_line, edge_lines, fit_cells
from rrbody.physics.footprint_table import build_footprint_table, footprint_table_wrench, table_covers, table_reach
from rrbody.physics.polygon import polygon_geometry

TOL = 1e-10
A = 0.08  # m: the L's leg width (benchmarks/active.py)
_BOXES = [np.array([(-A, -A), (A, -A), (A, 0.0), (-A, 0.0)]), np.array([(-A, 0.0), (0.0, 0.0), (0.0, A), (-A, A)])]


def _g() -> np.ndarray:
    geom = [polygon_geometry(p) for p in _BOXES]
    return sum(a * np.array([gx, gy]) for _, a, gx, gy, _ in geom) / sum(a for _, a, *_ in geom)


G = _g()
#: the corners of the L's outline (body frame from its centre of gravity); (-A, 0) is a corner of both
#: boxes but not of the L: the left edge runs straight through it
CORNERS = np.array([(-A, -A), (A, -A), (A, 0.0), (0.0, 0.0), (0.0, A), (-A, A)]) - G


@pytest.fixture(scope="module")
def ell() -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    shapes, geo, *_ = combine([polygon_part(p - G) for p in _BOXES])
    return shapes, geo, table_reach(shapes, geo, 0, 2), build_footprint_table(shapes, geo, 0, 2)


def test_edge_lines_of_the_L(ell: tuple) -> None:
    """Six lines; the shared edge of the two boxes (y = 0, x < 0) carries no net load edge, and the L's
    left edge is one line through (-A, 0)."""
    shapes, geo, R, _ = ell
    lines = edge_lines(shapes, geo, 0, 2, R)
    assert len(lines) == 6
    y0 = -G[1]  # the boxes' joint at y = 0
    # a cell around the shared edge: the boxes' edges there cancel (no line), one around the L's own
    # top edge of the lower box (x > 0): a line, kappa = 1 / (the L's area)
    h = 0.004
    assert cell_line(lines, (-A / 2 - G[0] - h, -A / 2 - G[0] + h, y0 - h, y0 + h), R)[3] == 0.0
    nx, ny, d, kap = cell_line(lines, (A / 2 - G[0] - h, A / 2 - G[0] + h, y0 - h, y0 + h), R)
    assert (abs(nx), abs(ny)) == (0.0, 1.0) and abs(abs(d) - abs(y0)) <= 1e-15
    assert math.isclose(abs(kap), 1.0 / (3 * A * A), rel_tol=1e-12)
    # the left edge through (-A, 0): one line with the same kappa on both sides of the boxes' joint
    left = cell_line(lines, (-A - G[0] - h, -A - G[0] + h, y0 - h, y0 + h), R)
    assert math.isclose(abs(left[3]), 1.0 / (3 * A * A), rel_tol=1e-12)
    # a corner of the L in the (widened) cell: no single line
    cx, cy = CORNERS[1]
    assert cell_line(lines, (cx - h, cx + h, cy - h, cy + h), R)[3] == 0.0


@pytest.mark.parametrize("size", [0.005, 0.0025])
def test_cells_across_an_edge_fit_once_the_edge_terms_are_taken_out(ell: tuple, size: float) -> None:
    """A cell straddling the L's bottom edge, far from its corners: the plain fit misses the wrench by
    O(size^2) at its validation points and fails; less the edge's terms it passes (VALID_TOL)."""
    shapes, geo, R, _ = ell
    y = -A - G[1]
    rect = np.array([(-0.02, -0.02 + size, y - 0.4 * size, y + 0.6 * size)])
    line = np.array([cell_line(edge_lines(shapes, geo, 0, 2, R), tuple(rect[0]), R)])
    assert line[0, 3] != 0.0
    assert not fit_cells(shapes, geo, 0, 2, R, -1, rect, 1.5 * R)[1][0]
    assert fit_cells(shapes, geo, 0, 2, R, -1, rect, 1.5 * R, line)[1][0]


def _on_edges(n: int, rng: np.random.Generator, clear: float) -> np.ndarray:
    """Points on the L's outline at least ``clear`` (m) from every corner of it."""
    ring = np.vstack([CORNERS, CORNERS[:1]])
    out = []
    while len(out) < n:
        k = rng.integers(0, 6)
        p = ring[k] + rng.uniform() * (ring[k + 1] - ring[k])
        if np.min(np.hypot(*(CORNERS - p).T)) >= clear:
            out.append(p)
    return np.array(out)


def test_table_reaches_the_edges(ell: tuple) -> None:
    """Instantaneous centres on the L's edges and 1e-12 .. 1e-2 R off them, at least 0.2 R from its
    corners (the joint of the boxes at (-A, 0) included: it is no corner of the L): all read from the
    table (none handed to the exact formula), within TOL of the exact wrench; exactly on an edge too
    (h = 0: the h^2 log|h| term is 0 there)."""
    shapes, geo, R, T = ell
    rng = np.random.default_rng(5)
    p = _on_edges(400, rng, 0.2 * R)
    off = 10.0 ** rng.uniform(-12, -2, (400, 1)) * R * rng.standard_normal((400, 2))
    c = np.vstack([p, p + off, [(-A - G[0], -G[1])]])
    w = rng.choice([-1.0, 1.0], c.shape[0]) * 10.0 ** rng.uniform(-1, 2, c.shape[0])
    for (cx, cy), wk in zip(c, w):
        vbx, vby = cy * wk, -cx * wk
        assert table_covers(T, 0, vbx, vby, wk, 1e-9), (cx, cy)
        got = footprint_table_wrench(T, 0, shapes, geo, 0, 2, vbx, vby, wk, 1e-9)
        ref = footprint_wrench(shapes, geo, 0, 2, vbx, vby, wk, 1e-9)
        assert max(abs(got[0] - ref[0]), abs(got[1] - ref[1]), abs(got[2] - ref[2]) / R) <= TOL, (cx, cy)


def test_tables_are_stored_in_the_cache_folder(tmp_path, monkeypatch: pytest.MonkeyPatch) -> None:  # noqa: ANN001
    """A table is built once and then read from the cache folder (the same bytes); an unreadable file is
    built again; a folder that cannot be written still gives the built table."""
    from rrbody import _cache
    from rrbody.engine.plugin.footprints import stored

    monkeypatch.setenv(_cache.ENV, str(tmp_path / "cache"))
    calls = []

    def build() -> np.ndarray:
        calls.append(1)
        return np.arange(12.0).reshape(4, 3) / 7.0

    a = stored("footprint:abc", build)
    path = _cache.kernels_dir() / "tables" / "footprint-abc.npz"
    assert path.is_file() and len(calls) == 1
    b = stored("footprint:abc", build)
    assert len(calls) == 1 and np.array_equal(a, b)
    assert not list(path.parent.glob("*.tmp"))
    path.write_bytes(b"not a table")
    assert np.array_equal(stored("footprint:abc", build), a) and len(calls) == 2
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "file"))
    (tmp_path / "file").write_text("a file where the folder should be")
    assert np.array_equal(stored("footprint:abc", build), a) and len(calls) == 3


@pytest.mark.parametrize("profile", ["ring", "hertz", "uniform"])
def test_radial_tables_match_their_closed_forms(profile: str) -> None:
    """A disk's table under a radial profile (icr_table.build_radial_table) against the profile's exact
    wrench (rrbody.physics.radial; the uniform disk's ICR quadrature): the ICR at 1 +- 1e-12 .. 0.5 radii
    from the centre (the rim, where the wrench is not smooth), at the centre (pure spin), far (to 1e9
    radii) and in pure translation; both spin senses; within TOL (force; torque / radius)."""
    from rrbody.physics.icr import icr_wrench_body
    from rrbody.physics.icr_table import build_radial_table, table_wrench_body
    from rrbody.physics.radial import hertz_wrench, ring_wrench

    S = build_radial_table(profile)
    a = 0.07  # m
    rng = np.random.default_rng(9)
    d = 10.0 ** rng.uniform(-12, np.log10(0.5), 300)
    r = np.concatenate([1.0 + d, 1.0 - d, [0.0], 10.0 ** rng.uniform(0, 9, 100)]) * a
    th = rng.uniform(0, 2 * math.pi, r.size)
    w = rng.choice([-1.0, 1.0], r.size) * 10.0 ** rng.uniform(-2, 2, r.size)
    # spin w about the ICR c: the centre moves at w z x (0 - c) = w (c_y, -c_x)
    V = [(w[k] * r[k] * math.sin(th[k]), -w[k] * r[k] * math.cos(th[k]), w[k]) for k in range(r.size)]
    V += [(0.3, -0.2, 0.0), (-1e-3, 0.0, 0.0)]  # pure translation
    for vx, vy, wk in V:
        got = table_wrench_body(S, a, a, vx, vy, wk, 1.0, 0.0)
        if profile == "uniform":
            ref = icr_wrench_body(a, a, 64, vx, vy, wk, 1, 1.0, 0.0, 0.0)
        else:
            ref = (ring_wrench if profile == "ring" else hertz_wrench)(a, vx, vy, wk, 0.0)
        assert max(abs(got[0] - ref[0]), abs(got[1] - ref[1]), abs(got[2] - ref[2]) / a) <= TOL, (profile, vx, vy, wk)
