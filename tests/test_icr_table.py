"""The precomputed wrench table (friction_method "table") against the instantaneous-centre quadrature.

Tolerance: the method's stated accuracy, 1e-10 relative to mu g (force) and mu g max(a, b)
(torque), against ``icr_wrench`` at 256 nodes per panel (self-converged to ~1e-14,
docs/extended.md), at random instantaneous centres that include kappa' = sqrt(1 - kappa^2) in
[1e-12, 1e-2] on both sides of the boundary, the far field and near-translation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

from rrbody.analysis.flip import flip_time
from rrbody.model.bodies import Disk, Ellipse
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene, rod_mass_scene
from rrbody.physics import params as P
from rrbody.physics.areas import TABLE, body_wrench
from rrbody.physics.bind import kernel_params
from rrbody.physics.effects.laws import DRY, NO_PARAMS
from rrbody.physics.icr import icr_wrench
from rrbody.physics.icr_fit import NM, NT, OCTAVES
from rrbody.physics.icr_table import _HEADER, build_table
from rrbody.physics.icr_table import _horner2 as _full_inline
from rrbody.physics.icr_table import _horner_tri as _tri_inline

# `make test` (pytest-xdist, --dist loadgroup) runs this file's tests in one worker: each ellipse table
# (seconds to build; build_table caches it per process) is then built once, not in both workers
pytestmark = pytest.mark.xdist_group("icr_tables")

TOL = 1e-10


def _axes(delta: float) -> tuple[float, float]:
    """Semi-axes (m) of the ellipse R0 = 0.1 m, ``delta``, spelled so that delta 0.5 gives the aspect ratio
    of (0.15, 0.05) and of Ellipse(R0=0.3, delta=0.5) to the bit: the tests below then share one build of
    that table (each build costs seconds; build_table caches per ratio, the float's every bit)."""
    return (1.0 + delta) / 10.0, (1.0 - delta) / 10.0


@njit(cache=True)
def _tri(S, base, zt, zm):  # noqa: ANN001
    return _tri_inline(S, base, zt, zm)


@njit(cache=True)
def _full(S, base, nt, nm, zt, zm):  # noqa: ANN001
    return _full_inline(S, base, nt, nm, zt, zm)


@njit(cache=True)
def _errors(S, ra, rb, V, coeff):  # noqa: ANN001
    out = np.empty((V.shape[0], 3))
    L = max(ra, rb)
    for i in range(V.shape[0]):
        al, vx, vy, w = V[i, 0], V[i, 1], V[i, 2], V[i, 3]
        f = body_wrench(TABLE, DRY, S, ra, rb, 0, 0.0, al, vx, vy, w, coeff, 0.0, NO_PARAMS)
        g = icr_wrench(ra, rb, 256, al, vx, vy, w, 1, coeff, 0.0, 0.0)
        out[i, 0] = abs(f[0] - g[0]) / coeff
        out[i, 1] = abs(f[1] - g[1]) / coeff
        out[i, 2] = abs(f[2] - g[2]) / (coeff * L)
    return out


def _motions(ra: float, rb: float, n: int, seed: int) -> np.ndarray:
    """Rows (alpha, vx, vy, spin) whose scaled ICR radius r covers the body, its boundary from
    both sides (kappa' in [1e-12, 1e-2]), the far field and near-translation."""
    rng = np.random.default_rng(seed)
    kp = 10.0 ** rng.uniform(-12.0, -2.0, n)
    r = np.where(rng.random(n) < 0.5, np.sqrt(1.0 - kp * kp), 1.0 / np.sqrt(1.0 - kp * kp))
    q = n // 3
    r[:q] = 10.0 ** rng.uniform(-3.0, 3.0, q)
    r[q:q + n // 20] = 10.0 ** rng.uniform(5.0, 9.0, n // 20)
    th = rng.uniform(0.0, 2.0 * math.pi, n)
    al = rng.uniform(-4.0, 4.0, n)
    w = rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-1.0, 1.0, n)
    qx = r * np.cos(th) * ra
    qy = r * np.sin(th) * rb
    vbx, vby = w * qy, -w * qx  # v_b = spin (q_y, -q_x) puts the ICR at q (body frame)
    return np.column_stack([al, np.cos(al) * vbx - np.sin(al) * vby, np.sin(al) * vbx + np.cos(al) * vby, w])


@pytest.mark.parametrize("delta", [0.0, 0.3, 0.5, -0.5, 0.8])
def test_table_matches_icr_to_1e_10(delta: float) -> None:
    ra, rb = _axes(delta)
    S = build_table(ra, rb)
    err = _errors(S, ra, rb, _motions(ra, rb, 2400, 7), 0.37)
    assert err[:, :2].max() <= TOL
    assert err[:, 2].max() <= TOL


def _panel_rows(S: np.ndarray) -> tuple[int, np.ndarray]:
    """Index of an ellipse table's first radial-panel row, and those rows (base row, then the m-panel
    count of each octant, negative for triangles)."""
    first = _HEADER + 2 * OCTAVES
    return first, S[first:int(S[first, 0])]


@pytest.mark.parametrize("delta", [0.5, 0.8])
def test_triangular_blocks_cover_most_panels_and_evaluate_as_the_full_block(delta: float) -> None:
    # The build keeps only the total-degree-NTRI triangle of a block when the dropped Chebyshev
    # coefficients sum to <= TAIL_TOL (checked above against the quadrature), an octant of a radial
    # panel at a time. Measured coverage: 95.2 % of the m-panels at delta 0.5 (b/a = 1/3), 73.9 % at
    # 0.8 (b/a = 1/9), as docs/extended.md states; the floors 90 % and 70 % guard it. The triangle's
    # kernel must equal the full tensor Horner on the same (zero-padded) block to round-off:
    # ~45 terms of size <= ~1, so 1e-13.
    S = build_table(*_axes(delta))
    first, heads = _panel_rows(S)
    counts = heads[:, 1:3].ravel()
    tri = -counts[counts < 0].sum()
    assert tri >= (0.9 if delta == 0.5 else 0.7) * np.abs(counts).sum()
    if delta == 0.8:
        assert (counts > 0).any()  # a thin ellipse keeps some full blocks: both kernels are in use
    rows = np.flatnonzero(heads[:, 1] < 0)[:20] + first
    rng = np.random.default_rng(3)
    for r in rows:
        base = int(S[r, 0])
        for zt, zm in rng.uniform(-1.0, 1.0, (5, 2)):
            a = _tri(S, base, zt, zm)
            b = _full(S, base, NT, NM, zt, zm)
            assert np.allclose(a, b, rtol=0.0, atol=1e-13)


def test_table_is_cached_per_aspect_ratio() -> None:
    assert build_table(0.15, 0.05) is build_table(0.3, 0.1)
    assert build_table(0.3, 0.3) is build_table(0.01, 0.01)


def test_spin_sign_and_reflection_symmetry() -> None:
    ra, rb = 0.15, 0.05
    S = build_table(ra, rb)
    for vx, vy, w in [(0.3, 0.1, 2.0), (-0.02, 0.07, 0.5), (0.0, 0.4, -3.0)]:
        f = np.array(body_wrench(TABLE, DRY, S, ra, rb, 0, 0.0, 0.0, vx, vy, w, 1.0, 0.0, NO_PARAMS))
        g = np.array(body_wrench(TABLE, DRY, S, ra, rb, 0, 0.0, 0.0, -vx, -vy, -w, 1.0, 0.0, NO_PARAMS))
        assert np.allclose(f, -g, rtol=0.0, atol=1e-15)
        # mirror y -> -y of the motion: v -> (vx, -vy), spin -> -spin; F mirrors, tau flips
        m = np.array(body_wrench(TABLE, DRY, S, ra, rb, 0, 0.0, 0.0, vx, -vy, -w, 1.0, 0.0, NO_PARAMS))
        assert np.allclose(m, [f[0], -f[1], -f[2]], rtol=0.0, atol=2e-11)


def test_translation_and_dead_band_are_those_of_icr() -> None:
    for ra, rb in [(0.1, 0.1), (0.15, 0.05)]:
        S = build_table(ra, rb)
        for args in [(0.3, 0.2, 0.0), (0.3, 0.2, 1e-11), (0.0, 0.0, 0.0), (1e-13, 0.0, 1e-13)]:
            f = body_wrench(TABLE, DRY, S, ra, rb, 0, 0.0, 0.4, *args, 2.0, 1e-12, NO_PARAMS)
            g = icr_wrench(ra, rb, 64, 0.4, *args, 1, 2.0, 1e-12, 0.0)
            assert f == pytest.approx(g, abs=1e-15)


def test_bad_semi_axes_name_the_parameter() -> None:
    with pytest.raises(ValueError, match="rb must be"):
        build_table(0.1, -1.0)
    with pytest.raises(ValueError, match="ra must be"):
        build_table(float("nan"), 0.1)


def test_friction_method_table_binds_and_rejects_a_point_mass() -> None:
    sc = Scene(body=Ellipse(R0=0.3, delta=0.5, l=0.2), drive=CircularDrive(omega=0.6, d=1.0),
               friction=Friction("dry", 0.05), friction_method="table")
    p, S = kernel_params(sc)
    assert int(p[P.BODY]) == P.BODY_TABLE and S.shape[0] > 100
    with pytest.raises(ValueError, match="friction_method 'table' needs an extended body"):
        kernel_params(rod_mass_scene(0.2, 0.05, 0.6).__class__(**{**rod_mass_scene(0.2, 0.05, 0.6).__dict__,
                                                                  "friction_method": "table"}))


def test_auto_picks_the_table_for_a_dry_disk_only() -> None:
    drive = CircularDrive(omega=0.6, d=1.0)
    for body, method, law, want in [(Disk(R=0.1, l=0.2), "auto", "dry", P.BODY_TABLE),
                                    (Disk(R=0.1, l=0.2), "icr", "dry", P.BODY_ICR),
                                    (Disk(R=0.1, l=0.2), "auto", "viscous", P.BODY_ICR),
                                    (Ellipse(R0=0.1, delta=0.5, l=0.2), "auto", "dry", P.BODY_ICR)]:
        p, _ = kernel_params(Scene(body=body, drive=drive, friction=Friction(law, 0.05), friction_method=method))
        assert int(p[P.BODY]) == want, (body, method, law)


def test_flip_time_table_equals_icr() -> None:
    # an eccentric ellipse (delta 0.5, l 0.2, k 0.033; t_f ~ 8.13 s): the wrench differs by < 1e-10
    # relative (test above), and t_f by about that times its sensitivity to the friction; measured
    # 2.1e-12 relative at rtol 1e-12 (the table's triangular blocks are within ~7e-12 of the
    # quadrature). (A slow flip such as k 0.0033, t_f ~ 73 s, amplifies any wrench difference:
    # there the default-node "icr" itself moves t_f by ~5e-8.)
    def tf(method: str) -> float:
        sc = Scene(body=Ellipse(R0=0.3, delta=0.5, l=0.2), drive=CircularDrive(omega=0.6, d=1.0),
                   friction=Friction.from_k("dry", 0.033, 1.0), friction_method=method)
        r = flip_time(sc, rtol=1e-12)
        assert r.t_f is not None
        return r.t_f

    assert tf("table") == pytest.approx(tf("icr"), rel=1e-9)


@pytest.mark.parametrize("delta", [0.0, 0.5])  # a disk and the ellipse b/a = 1/3 (the table the tests above build)
def test_tiny_and_huge_twists_read_the_same_table(delta: float) -> None:
    """The dry wrench depends on the twist's direction only (v_eps = 0): scaled by 1e-166 or 1e-300
    (whose squares underflow), 1e-320 (subnormal) or 1e300 (overflow), the table gives what the
    quadrature gives at scale 1, within the table's 1e-10 (a disk left with a velocity of 1e-166 m/s
    once made the plugin divide by zero); never inf or NaN; the twist 0 and a tiny twist inside a
    dead band give zero."""
    from rrbody.physics.icr_table import table_wrench_body

    a, b = _axes(delta)
    S = build_table(a, b)
    for twist in ((-7.5, -4.0, -1.3), (0.3, -0.1, 20.0), (1.0, 0.5, 0.0), (0.0, 0.0, 3.0)):
        for k in (1e-166, 1e-300, 1e300, 1e-320):
            tw = tuple(k * x for x in twist)  # a subnormal twist has few bits: the reference scales it up exactly
            ref = icr_wrench(a, b, 64, 0.0, *((2.0**1000 * x for x in tw) if k < 1e-310 else twist), DRY, 1.0, 0.0,
                             0.0)
            got = table_wrench_body(S, a, b, *tw, 1.0, 0.0)
            assert all(math.isfinite(g) for g in got)
            assert max(abs(got[0] - ref[0]), abs(got[1] - ref[1]), abs(got[2] - ref[2]) / a) <= 1e-10
    assert table_wrench_body(S, a, b, 0.0, 0.0, 0.0, 1.0, 0.0) == (0.0, 0.0, 0.0)
    assert table_wrench_body(S, a, b, 1e-200, 0.0, 1e-200, 1.0, 1e-9) == (0.0, 0.0, 0.0)
