"""The fitting half of :mod:`rrbody.physics.icr_table`: the dry wrench of a disk or an ellipse at the
Chebyshev points of every panel of the scaled ICR plane, from the quadrature of
:func:`rrbody.physics.icr.icr_wrench_body` at high node count (or, for a disk under a radial pressure
profile, from the closed forms of :mod:`rrbody.physics.radial`), fitted panel by panel, with the
panels refined until the fits' Chebyshev tails are below ``TAIL_TOL``.

:mod:`rrbody.physics.icr_table` describes the coordinates (t, x = 1 - t, m) and packs the fits into
its table (:func:`rrbody.physics.icr_table.build_table`), which its kernel evaluates; the fit's degrees
and octaves (``NT``, ``NM``, ``NTRI``, ``OCTAVES``) are that kernel's compile-time constants. The
footprint tables' fits (:mod:`rrbody.physics.footprint_fit`) use :func:`cheb` too.

Units: per unit mu g (force, body frame) and mu g L (torque about the CM), L = max(a, b); spin > 0.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from rrbody.physics.icr import icr_wrench_body
from rrbody.physics.radial import hertz_wrench, ring_wrench

__all__ = ["fit_panels", "cheb", "triangular", "PROFILES", "TRANSLATION_M2", "HIGH", "NT", "NM", "NTRI", "OCTAVES",
           "TAIL_TOL", "BUILD_NODES", "MAX_M_PANELS"]

#: coefficients per panel along t (degree NT - 1; even: the disk's sum takes them in pairs) and along m (degree NM - 1)
NT: int = 10
NM: int = 10
#: octaves of x = 1 - t that get panels; below 2^-OCTAVES (x log x < 2e-12) x is clamped
OCTAVES: int = 44
#: acceptance threshold on the last two Chebyshev coefficients of an angle fit (units mu g, mu g L)
TAIL_TOL: float = 1e-11
#: Gauss nodes per panel of the ICR quadrature that builds the table (self-converged to ~1e-14)
BUILD_NODES: int = 64
#: most m-panels per octant before the build gives up refining (the test reports the error)
MAX_M_PANELS: int = 128
#: total degree of the triangular blocks: a block whose Chebyshev coefficients of total degree
#: i + j > NTRI sum (in absolute value, a bound on what dropping them changes) to at most TAIL_TOL
#: keeps only i + j <= NTRI: 45 terms instead of NT x NM = 100. NTRI = 8 gave the fewest terms on
#: average over aspect ratios 0.1 - 0.9 among 8, 9 and 10 (measured when it was chosen).
NTRI: int = 8


def _sub_panels(o: int) -> int:
    """Sub-panels of octave o: the log term's size there, 2^-o (1 + o ln 2), times the Chebyshev
    decay rho^-NT of the sub-panel nearest x = 0 (rho = d + sqrt(d^2 - 1), d = 2 k + 1), kept < 1e-12."""
    amp = 2.0 ** -o * (1.0 + o * math.log(2.0))
    for k in (1, 2, 4, 8):
        d = 2.0 * k + 1.0
        if amp * (d + math.sqrt(d * d - 1.0)) ** -NT < 1e-12:
            return k
    return 16


@njit(cache=True, parallel=True)
def _values(a, b, rs, ms, octant):  # noqa: ANN001
    """Wrench (body frame, mu g = 1, spin = 1) at every scaled ICR (r, m) of the grid rs x ms."""
    out = np.empty((rs.shape[0], ms.shape[0], 3))
    for i in prange(rs.shape[0]):
        for j in range(ms.shape[0]):
            c = 1.0 / math.sqrt(1.0 + ms[j] * ms[j])
            qx = rs[i] * c
            qy = rs[i] * ms[j] * c
            if octant == 1:
                qx, qy = qy, qx
            # spin 1: v_b = (qy b, -qx a) puts the ICR at q = z x v_b / spin, i.e. Q = (qx, qy) scaled
            # np.int64: literal constants would compile the quadrature once more for the build alone
            fx, fy, tq = icr_wrench_body(a, b, np.int64(BUILD_NODES), qy * b, -qx * a, 1.0, np.int64(1), 1.0, 0.0, 0.0)
            out[i, j, 0] = fx
            out[i, j, 1] = fy
            out[i, j, 2] = tq
    return out


def cheb(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Chebyshev points of the first kind on [-1, 1], the values -> coefficients matrix, and the
    Chebyshev -> monomial matrix (degree n - 1 is small: the monomial form loses < 1e-15)."""
    k = np.arange(n)
    th = np.pi * (k + 0.5) / n
    z = np.cos(th)
    V = np.cos(np.outer(k, th)) * (2.0 / n)
    V[0] *= 0.5
    M = np.zeros((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0
        c = np.polynomial.chebyshev.cheb2poly(e)
        M[: c.size, j] = c
    return z, V, M


def _octave_edges(o: int, k: int) -> list[tuple[float, float]]:
    lo = 2.0 ** -(o + 1)
    return [(lo * (1.0 + s / k), lo * (1.0 + (s + 1) / k)) for s in range(k)]


def _fit_octant(a: float, b: float, rs: np.ndarray, octant: int, n: int, cheb: tuple) -> tuple[np.ndarray, int]:
    """Chebyshev coefficients (panel, NT, NM, 3) of one octant of one radial panel, the number of
    m-panels doubled from ``n`` (half the neighbour's, so it can also fall) until the angular tail
    is below TAIL_TOL."""
    zm, Vt, Vm = cheb
    while True:
        ms = ((np.arange(n)[:, None] + 0.5 + 0.5 * zm[None, :]) / n).ravel()
        w = _values(a, b, rs, ms, octant).reshape(NT, n, NM, 3)
        c = np.einsum("it,tpmk,jm->pijk", Vt, w, Vm)
        if np.abs(c[:, :, -2:, :]).max() < TAIL_TOL or n >= MAX_M_PANELS:
            return c, n
        n *= 2


#: the Chebyshev terms a triangular block drops (total degree above NTRI)
HIGH = np.add.outer(np.arange(NT), np.arange(NM)) > NTRI


def triangular(c: np.ndarray) -> bool:
    """Whether every m-panel of an octant's Chebyshev coefficients ``c`` (panel, NT, NM, 3) can drop
    its terms of total degree > NTRI: |T_i T_j| <= 1 on the panel, so the sum of the dropped
    coefficients' magnitudes bounds the change, and it must stay below TAIL_TOL (the accuracy the
    fit itself is accepted at). The monomial form of a truncated block stays triangular (T_i has
    degree i), so the kernel reads only its 45 terms."""
    return bool(np.abs(c[:, HIGH, :]).sum(axis=1).max() <= TAIL_TOL)


#: radial profiles a disk table can hold (:func:`rrbody.physics.icr_table.build_radial_table`): uniform
#: pressure, the load on the rim (a ring), Hertz's sqrt(1 - rho^2 / a^2); and each one's
#: <|s|^2 - (s . e)^2> / a^2 for a unit e (the near-translation torque's factor: 1/4, 1/2, 1/5), kept in
#: the table's row 0
PROFILES = {"uniform": 0, "ring": 1, "hertz": 2}
TRANSLATION_M2 = (0.25, 0.5, 0.2)


@njit(cache=True)
def _radial_values(hertz: bool, rs: np.ndarray) -> np.ndarray:
    """The ring's (or Hertz patch's) exact wrench (radius 1, spin 1) with the ICR at (r, 0), r in ``rs``."""
    out = np.empty((rs.shape[0], 3))
    for i in range(rs.shape[0]):
        # spin 1 about the ICR (r, 0): the centre moves at (0, -r)
        fx, fy, tq = hertz_wrench(1.0, 0.0, -rs[i], 1.0, 0.0) if hertz else ring_wrench(1.0, 0.0, -rs[i], 1.0, 0.0)
        out[i, 0] = fx
        out[i, 1] = fy
        out[i, 2] = tq
    return out


#: the fits of a table: per side (inside, outside) and octave, per radial panel, the Chebyshev
#: coefficient blocks (panel, NT, NM, 3) of octant 0 and octant 1 (a disk: one block (1, NT, 1, 3))
Fits = list[list[list[list[np.ndarray]]]]


def fit_panels(ratio: float, profile: int = 0) -> Fits:
    """The Chebyshev fits of the dry wrench (per unit mu g, body frame, spin > 0) of the ellipse of
    aspect ratio ``ratio`` = b/a (a disk if 1, under the radial profile ``profile``, a value of
    :data:`PROFILES`) on every panel of the scaled ICR plane: each octave's radial sub-panels
    doubled until the radial tail is below TAIL_TOL, each octant's m-panels by :func:`_fit_octant`.
    :func:`rrbody.physics.icr_table.build_table` packs them."""
    a, b = (1.0, ratio) if ratio <= 1.0 else (1.0 / ratio, 1.0)
    disk = ratio == 1.0
    zt, Vt, _ = cheb(NT)
    zm, Vm, _ = cheb(NM)
    # per side and octave: the radial panels' Chebyshev coefficients (list over sub-panels of
    # [octant 0, octant 1] blocks), sub-panels doubled until the radial tail is below TAIL_TOL
    sides: Fits = []
    for side in range(2):
        octs = []
        warm = [1, 1]
        for o in range(OCTAVES):
            k = _sub_panels(o)
            while True:
                panels = []
                rtail = 0.0
                for lo, hi in _octave_edges(o, k):
                    t = 1.0 - (0.5 * (lo + hi) + 0.5 * (hi - lo) * zt)
                    rs = t if side == 0 else 1.0 / t
                    if disk:
                        w = _values(a, b, rs, np.zeros(1), 0)[:, 0, :] if profile == 0 else \
                            _radial_values(profile == 2, rs)
                        c = (Vt @ w)[None, :, None, :]
                        panels.append([c])
                    else:
                        blocks = []
                        for octant in range(2):
                            c, warm[octant] = _fit_octant(a, b, rs, octant, max(1, warm[octant] // 2), (zm, Vt, Vm))
                            blocks.append(c)
                        panels.append(blocks)
                    rtail = max(rtail, max(float(np.abs(c[:, -2:]).max()) for c in panels[-1]))
                if rtail < TAIL_TOL or k >= 64:
                    break
                k *= 2
            octs.append(panels)
        sides.append(octs)
    return sides
