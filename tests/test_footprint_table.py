"""A footprint's wrench table (rrbody.physics.footprint_table) against the exact formula it replaces.

Tolerance TOL = 1e-10: the table's stated accuracy (docs/footprint-table.md), in the force
(dimensionless, per unit load and mu g) and in the torque divided by the footprint's reach R (m), against
:func:`rrbody.physics.contact.footprint_wrench` itself (the table's fits are accepted at 5e-11, half of it,
and where they fail the kernel calls the exact formula). Twists: the ICR inside the footprint, within
1e-9 .. 1e-2 R of its edges and vertices, far (up to 1e9 R), pure spin, pure translation, near
translation, both spin signs, and speeds around the dead band v_eps.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from numba import njit

from rrbody.physics import contact as C
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.footprint import combine, ellipse_part, point_part, polygon_part
from rrbody.physics.footprint_table import build_footprint_table, footprint_table_wrench, table_covers, table_reach
from rrbody.physics.polygon import polygon_geometry

# `make test` (pytest-xdist, --dist loadgroup) runs this file's tests in one worker: the module fixture's
# five tables (1-2 s each) and the uncached `_both` kernel are then built once, not in both workers
pytestmark = pytest.mark.xdist_group("footprint_tables")

TOL = 1e-10
V_EPS = 1e-6  # m/s: the plugin's order of magnitude of the dead band
A = 0.08  # m: the L's leg width (benchmarks/active.py)


def _about_g(polys: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Footprint rows of convex polygons (uniform pressure), shifted so that their joint centroid is the origin."""
    geom = [polygon_geometry(p) for p in polys]
    g = sum(a * np.array([gx, gy]) for _, a, gx, gy, _ in geom) / sum(a for _, a, *_ in geom)
    shapes, geo, *_ = combine([polygon_part(p - g) for p in polys])
    return shapes, geo


def _l_shape() -> tuple[np.ndarray, np.ndarray]:
    return _about_g([np.array([(-A, -A), (A, -A), (A, 0.0), (-A, 0.0)]), np.array([(-A, 0.0), (0.0, 0.0), (0.0, A),
                                                                                   (-A, A)])])


def _box_off_g() -> tuple[np.ndarray, np.ndarray]:
    shapes, geo, *_ = combine([polygon_part(np.array([(-A, -A / 2), (A, -A / 2), (A, A / 2), (-A, A / 2)]) + (0.03,
                                                                                                              0.01))])
    return shapes, geo


def _triangle() -> tuple[np.ndarray, np.ndarray]:
    return _about_g([np.array([(0.0, 0.0), (0.1, 0.0), (0.02, 0.07)])])


def _circle() -> tuple[np.ndarray, np.ndarray]:
    shapes, geo, *_ = combine([ellipse_part(0.02, -0.01, 0.05, 0.05)])
    return shapes, geo


def _points() -> tuple[np.ndarray, np.ndarray]:
    shapes, geo, *_ = combine([point_part(0.05, 0.0), point_part(-0.03, 0.04), point_part(-0.02, -0.04)])
    return shapes, geo


FOOTPRINTS = {"L": _l_shape, "box": _box_off_g, "triangle": _triangle, "circle": _circle, "points": _points}


@functools.lru_cache(maxsize=1)
def _built() -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    out = {}
    for name, make in FOOTPRINTS.items():
        shapes, geo = make()
        out[name] = (shapes, geo, build_footprint_table(shapes, geo, 0, shapes.shape[0]))
    return out


@pytest.fixture(scope="module")
def tables() -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    # built once per process: an xdist worker that does not yet know its next test tears module
    # fixtures down, and the suite's logs showed this setup (about 6 s) twice in one worker
    return _built()


@njit  # not cached: numba would key it by this file's time stamp alone and keep a stale inlined kernel
def _both(T, t0, shapes, geo, V, v_eps):  # noqa: ANN001 (numba)
    out = np.empty((V.shape[0], 6))
    for k in range(V.shape[0]):
        a, b, c = footprint_table_wrench(T, t0, shapes, geo, 0, shapes.shape[0], V[k, 0], V[k, 1], V[k, 2], v_eps)
        out[k, 0] = a
        out[k, 1] = b
        out[k, 2] = c
        a, b, c = footprint_wrench(shapes, geo, 0, shapes.shape[0], V[k, 0], V[k, 1], V[k, 2], v_eps)
        out[k, 3] = a
        out[k, 4] = b
        out[k, 5] = c
    return out


def _icr_twists(c: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Twists (vbx, vby, w) with ICR c (rows, m, body frame) and spin w: v = -w z x c."""
    return np.column_stack([c[:, 1] * w, -c[:, 0] * w, w])


def _boundary_points(shapes: np.ndarray, geo: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
    """Points on the footprint's edges and at its vertices (polygons), on its circles (ellipses), at its points."""
    pts = []
    for row in shapes:
        if row[C.KIND] == C.POLYGON:
            v = geo[int(row[C.VERTEX_FIRST]):int(row[C.VERTEX_END]), :2]
            t = rng.uniform(0.0, 1.0, (n, 1))
            i = rng.integers(0, v.shape[0], n)
            pts += [v, v[i] + t * (np.roll(v, -1, axis=0)[i] - v[i])]
        elif row[C.KIND] == C.ELLIPSE:
            a = rng.uniform(0.0, 2.0 * math.pi, n)
            pts.append(np.column_stack([row[C.CENTRE_X] + row[C.RADIUS_A] * np.cos(a),
                                        row[C.CENTRE_Y] + row[C.RADIUS_B] * np.sin(a)]))
        else:
            pts.append(np.array([[row[C.CENTRE_X], row[C.CENTRE_Y]]]))
    return np.concatenate(pts)


def _twists(shapes: np.ndarray, geo: np.ndarray, R: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n = 1500
    sgn = lambda k: rng.choice([-1.0, 1.0], k)  # noqa: E731
    w = lambda k: sgn(k) * 10.0 ** rng.uniform(-2, 3, k)  # noqa: E731 - rad/s
    blocks = []
    blocks.append(_icr_twists(rng.uniform(-2 * R, 2 * R, (n, 2)), w(n)))  # inside and around the footprint
    b = _boundary_points(shapes, geo, rng, n // 4)
    off = (10.0 ** rng.uniform(-9, -2, (b.shape[0], 1))) * R * rng.standard_normal((b.shape[0], 2))
    blocks.append(_icr_twists(b + off, w(b.shape[0])))  # 1e-9 .. 1e-2 R from edges, vertices, points
    d = rng.standard_normal((n, 2))
    far = d / np.hypot(d[:, :1], d[:, 1:]) * R * 10.0 ** rng.uniform(0, 9, (n, 1))
    blocks.append(_icr_twists(far, w(n)))  # far: mostly translating
    blocks.append(np.column_stack([np.zeros((50, 2)), w(50)]))  # pure spin
    a = rng.uniform(0, 2 * math.pi, 200)
    sp = 10.0 ** rng.uniform(-3, 1, 200)
    blocks.append(np.column_stack([sp * np.cos(a), sp * np.sin(a), np.zeros(200)]))  # pure translation
    blocks.append(np.column_stack([sp * np.cos(a), sp * np.sin(a), sgn(200) * sp / R * 10.0 ** rng.uniform(-12, -6,
                                                                                                           200)]))
    # around the dead band: max(|v|, |w| R) in [0.1, 30] v_eps, ICR anywhere within 3 R
    c = rng.uniform(-3 * R, 3 * R, (n, 2))
    s = V_EPS * 10.0 ** rng.uniform(-1, 1.5, n) / np.maximum(R, np.hypot(c[:, 0], c[:, 1]))
    blocks.append(_icr_twists(c, sgn(n) * s))
    return np.concatenate(blocks)


@pytest.mark.parametrize("name", list(FOOTPRINTS))
def test_table_matches_exact(tables: dict, name: str) -> None:
    shapes, geo, T = tables[name]
    R = table_reach(shapes, geo, 0, shapes.shape[0])
    V = _twists(shapes, geo, R, seed=len(name))
    out = _both(T, 0, shapes, geo, V, V_EPS)
    err_f = np.abs(out[:, :2] - out[:, 3:5]).max()
    err_t = np.abs(out[:, 2] - out[:, 5]).max() / R
    assert err_f <= TOL and err_t <= TOL, (name, err_f, err_t)
    covered = np.array([table_covers(T, 0, *v, V_EPS) for v in V])
    if name != "points":  # the table is used, not only the fallback (3 points: most of it is still smooth)
        assert covered.mean() > 0.3, covered.mean()
    # the dead band is the exact formula's: all zero where it gives zero
    dead = np.all(out[:, 3:] == 0.0, axis=1)
    assert np.array_equal(dead, np.all(out[:, :3] == 0.0, axis=1))


@pytest.mark.parametrize("name", ["L", "circle"])
def test_odd_symmetry(tables: dict, name: str) -> None:
    shapes, geo, T = tables[name]
    R = table_reach(shapes, geo, 0, shapes.shape[0])
    V = _twists(shapes, geo, R, seed=7)
    a = _both(T, 0, shapes, geo, V, V_EPS)[:, :3]
    b = _both(T, 0, shapes, geo, -V, V_EPS)[:, :3]
    # the kernel maps a negative spin to a positive one: the same cell, the opposite sign, to the bit;
    # pure translation (w = 0) reads the opposite outer side: two fits, each within TOL of the exact one
    assert np.abs(a + b)[:, :2].max() <= 2 * TOL and np.abs(a + b)[:, 2].max() <= 2 * TOL * R
    spin = V[:, 2] != 0.0
    assert np.array_equal(a[spin], -b[spin])


def test_moved_copy_agrees(tables: dict) -> None:
    """The L rotated by th and moved by d in the body frame: F'(v', w) = Rot F(Rot^T (v' + w z x d), w) and
    tau' = tau + d x F' (the torque about the old centre of gravity, now at d)."""
    shapes, geo, T = tables["L"]
    th, d = 0.7, np.array([0.013, -0.021])
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    polys = [geo[int(r[C.VERTEX_FIRST]):int(r[C.VERTEX_END]), :2] @ rot.T + d for r in shapes]
    s2, g2, *_ = combine([polygon_part(p) for p in polys])
    T2 = build_footprint_table(s2, g2, 0, s2.shape[0])
    R = table_reach(shapes, geo, 0, shapes.shape[0])
    V2 = _twists(s2, g2, R, seed=3)
    got = _both(T2, 0, s2, g2, V2, 0.0)[:, :3]
    vs = V2[:, :2] + V2[:, 2:3] * np.column_stack([-np.full(len(V2), d[1]), np.full(len(V2), d[0])])  # v' + w z x d
    V = np.column_stack([vs @ rot, V2[:, 2]])  # Rot^T applied to row vectors
    ref = _both(T, 0, shapes, geo, V, 0.0)[:, :3]
    F = ref[:, :2] @ rot.T
    tq = ref[:, 2] + d[0] * F[:, 1] - d[1] * F[:, 0]
    # each side within TOL of its exact value, and the exact values agree to rounding (polygon.py: ~1e-14)
    assert np.abs(got[:, :2] - F).max() <= 2 * TOL + 1e-13
    assert np.abs(got[:, 2] - tq).max() <= (2 * TOL + 1e-13) * (R + float(np.hypot(*d)))


def test_concatenated_tables(tables: dict) -> None:
    """Tables concatenated into one array: each read at its own first row t0 gives what it gives alone."""
    sb, gb, Tb = tables["box"]
    sl, gl, Tl = tables["L"]
    TT = np.concatenate([Tb, Tl])
    R = table_reach(sl, gl, 0, sl.shape[0])
    V = _twists(sl, gl, R, seed=11)
    assert np.array_equal(_both(TT, Tb.shape[0], sl, gl, V, V_EPS), _both(Tl, 0, sl, gl, V, V_EPS))
    Vb = _twists(sb, gb, R, seed=12)
    assert np.array_equal(_both(TT, 0, sb, gb, Vb, V_EPS), _both(Tb, 0, sb, gb, Vb, V_EPS))


def test_table_size_and_determinism(tables: dict) -> None:
    shapes, geo, T = tables["L"]
    assert T.nbytes <= 4e6  # the brief's memory bound for the L
    assert np.array_equal(T, build_footprint_table(shapes, geo, 0, shapes.shape[0]),
                          equal_nan=True)  # exact cells: NaN blocks


def test_stored_coefficients_and_their_rounding(monkeypatch: pytest.MonkeyPatch) -> None:
    """A block stores the terms of degree >= F32_FROM as float32 (docs/footprint-table.md): the kernel
    reads back, through the table's float32 view, exactly the coefficients the fit returned and was
    validated with (rounded), and a fit whose rounding changes it by more than ROUND_TOL fails (with
    ROUND_TOL = 0 every fit of these cells of the L fails, with the real one most pass: the test is live)."""
    from rrbody.physics import footprint_fit as FF

    shapes, geo = _l_shape()
    R = table_reach(shapes, geo, 0, shapes.shape[0])
    e = np.linspace(-1.5 * R, 1.5 * R, 25)  # the table's first cells (CELLS = 24), those beyond x = 1.1 R
    rects = np.array([(e[i], e[i + 1], e[j], e[j + 1]) for i in range(21, 24) for j in range(24)])
    mono, ok = FF.fit_cells(shapes, geo, 0, shapes.shape[0], R, -1, rects, 1.5 * R)
    assert ok.sum() >= 20  # (26 of 72 here: the others, nearer the L, split in the table)
    deg = np.array([i + j for i in range(FF.N) for j in range(FF.N - i)])
    low = deg < FF.F32_FROM
    assert np.array_equal(mono[:, ~low], mono[:, ~low].astype(np.float32))  # already rounded
    for m in mono[ok]:
        blk = FF.pack(m)
        assert blk.shape == (FF.BLOCK, 3) and blk.dtype == np.float64
        assert np.array_equal(blk[:FF.N64], m[low])
        F = blk.view(np.float32)  # rows of 6: triple k at row N64 + k // 2, columns 3 (k % 2) ..
        back = np.array([F[FF.N64 + k // 2, 3 * (k % 2):3 * (k % 2) + 3] for k in range(int((~low).sum()))])
        assert np.array_equal(back.astype(np.float64), m[~low])
    monkeypatch.setattr(FF, "ROUND_TOL", 0.0)
    assert not FF.fit_cells(shapes, geo, 0, shapes.shape[0], R, -1, rects, 1.5 * R)[1].any()


def test_bad_input() -> None:
    shapes, geo = _l_shape()
    with pytest.raises(ValueError, match="s0, s1"):
        build_footprint_table(shapes, geo, 1, 1)
    with pytest.raises(ValueError, match="shapes"):
        build_footprint_table(shapes[:, :5], geo, 0, 1)


def test_compiles_without_refcounting(tables: dict) -> None:
    """The plugin calls the kernel from kernels compiled without numba's reference counting
    (rrbody.contact.lean.NO_REFCOUNT): it must allocate nothing, so it compiles there too and gives the same."""
    from rrbody.contact.lean import NO_REFCOUNT

    shapes, geo, T = tables["L"]

    @njit(**NO_REFCOUNT)
    def lean(T, t0, shapes, geo, vbx, vby, w, v_eps):  # noqa: ANN001, ANN202 (numba)
        return footprint_table_wrench(T, t0, shapes, geo, 0, shapes.shape[0], vbx, vby, w, v_eps)

    for v in ((0.3, -0.2, 4.0), (0.0, 0.0, 2.0), (0.5, 0.1, 0.0), (1e-9, 0.0, 1e-9)):
        assert lean(T, 0, shapes, geo, *v, V_EPS) == footprint_table_wrench(T, 0, shapes, geo, 0, 2, *v, V_EPS)


def test_non_finite_twists_go_to_the_exact_formula(tables: dict) -> None:
    """NaN or infinite velocities never become a table index: the exact formula answers (NaN where it does)."""
    shapes, geo, T = tables["L"]
    for v in ((math.nan, 0.1, 1.0), (0.1, math.inf, 1.0), (0.1, 0.2, math.nan), (0.1, 0.2, -math.inf)):
        assert not table_covers(T, 0, *v, V_EPS)
        got = footprint_table_wrench(T, 0, shapes, geo, 0, 2, *v, V_EPS)
        ref = footprint_wrench(shapes, geo, 0, 2, *v, V_EPS)
        assert np.array_equal(np.array(got), np.array(ref), equal_nan=True)


def test_tiny_and_huge_twists_read_the_same_table(tables: dict) -> None:
    """The wrench depends on the twist's direction only (v_eps = 0): a twist scaled by 1e-166 or 1e300
    gives what the exact formula gives at scale 1, within the table's TOL (the table scales such a
    twist by a power of two, exactly, before it reads the table: a body left with a velocity of
    1e-166 m/s by a collision once made the plugin's kernel divide by zero). Subnormal twists (1e-320:
    a few significant bits) against the exact formula at the same twist scaled up by 2^1000 (exact),
    and never inf or NaN. The L's table of the module's fixture (a build is deterministic to the bit:
    test_table_size_and_determinism)."""
    shapes, geo, T = tables["L"]
    n = shapes.shape[0]
    for twist in ((-7.5, -4.0, -13.0), (0.3, -0.1, 2.0), (1.0, 0.5, 0.0), (0.0, 0.0, 3.0)):
        R = table_reach(shapes, geo, 0, n)
        for k in (1e-166, 1e300, 1e-320):
            tw = tuple(k * x for x in twist)
            ref = footprint_wrench(shapes, geo, 0, n, *(2.0**1000 * x for x in tw) if k < 1e-300 else twist, 0.0)
            got = footprint_table_wrench(T, 0, shapes, geo, 0, n, *tw, 0.0)
            assert all(math.isfinite(g) for g in got)
            assert max(abs(got[0] - ref[0]), abs(got[1] - ref[1]), abs(got[2] - ref[2]) / R) <= TOL
