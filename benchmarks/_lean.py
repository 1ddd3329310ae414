"""A lean compiled DOP853 for the rod-mass equation: the per-step floor rrbody's loop is measured against.

Everything is specialised by hand: two states, the point-mass dry right-hand side written inline
(the paper's Eq. 2 in the frame of the rod, d = 1 m), scipy's tableau, scipy's error norm and step-size
controller, the same error scales as rrbody (phi absolute rtol*pi, phi' rtol times its running
maximum). No events, no output, no dispatch: only the arithmetic of a DOP853 step, and the same
arithmetic shortcuts as rrbody's kernel (a stage's sin and cos of the drive phase by angle addition
from the step's start with rrbody's short series, and 1/H multiplied rather than divided), so that
the ratio measures the loop's overhead, not a difference in how the equation is evaluated.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rrbody.physics.effects.drive_circular import sincos_shifted


@njit(cache=True, inline="always")
def _f(t, phi, pd, H, k, w, d, s0, c0):  # noqa: ANN001
    """(phi', phi'') at a stage whose drive phase is psi0 + d, (sin, cos)(psi0) = (s0, c0)."""
    s, c = sincos_shifted(phi - w * t, d, s0, c0)
    ve = w * s
    vp = w * c - H * pd
    sp2 = ve * ve + vp * vp
    fr = k * vp / math.sqrt(sp2) if sp2 > 1e-18 * w * w else 0.0
    return pd, (w * w * s + fr) * (1.0 / H)


@njit(cache=True)
def lean_dop853(H, k, w, t_end, rtol, A, B, C, E3, E5):  # noqa: ANN001
    """Integrate from phi0 = pi to t_end; returns (phi(t_end), accepted steps)."""
    K0 = np.empty(13)
    K1 = np.empty(13)
    phi = math.pi
    pd = -w / H
    f0, f1 = _f(0.0, phi, pd, H, k, w, math.nan, 0.0, 0.0)
    t = 0.0
    h = 1e-3 / w
    pscale = max(w, abs(pd))
    steps = 0
    rejected = False
    while t < t_end:
        hh = min(h, t_end - t)
        s0 = math.sin(phi - w * t)
        c0 = math.cos(phi - w * t)
        K0[0] = f0
        K1[0] = f1
        for s in range(1, 12):
            a0 = 0.0
            a1 = 0.0
            for r in range(s):
                a0 += A[s, r] * K0[r]
                a1 += A[s, r] * K1[r]
            K0[s], K1[s] = _f(t + C[s] * hh, phi + hh * a0, pd + hh * a1, H, k, w, hh * a0 - w * (C[s] * hh), s0, c0)
        b0 = 0.0
        b1 = 0.0
        for r in range(12):
            b0 += B[r] * K0[r]
            b1 += B[r] * K1[r]
        n0 = phi + hh * b0
        n1 = pd + hh * b1
        K0[12], K1[12] = _f(t + hh, n0, n1, H, k, w, hh * b0 - w * hh, s0, c0)
        sc0 = rtol * math.pi
        sc1 = rtol * max(pscale, abs(pd))
        e50 = 0.0
        e51 = 0.0
        e30 = 0.0
        e31 = 0.0
        for r in range(13):
            e50 += E5[r] * K0[r]
            e51 += E5[r] * K1[r]
            e30 += E3[r] * K0[r]
            e31 += E3[r] * K1[r]
        e5 = (e50 / sc0) ** 2 + (e51 / sc1) ** 2
        e3 = (e30 / sc0) ** 2 + (e31 / sc1) ** 2
        err = 0.0 if e5 == 0.0 and e3 == 0.0 else hh * e5 / math.sqrt((e5 + 0.01 * e3) * 2.0)
        if err < 1.0:
            fac = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** -0.125)
            if rejected:
                fac = min(1.0, fac)
            t += hh
            phi = n0
            pd = n1
            f0 = K0[12]
            f1 = K1[12]
            pscale = max(pscale, abs(pd))
            steps += 1
            rejected = False
            h = hh * fac
        else:
            h = hh * max(0.2, 0.9 * err ** -0.125)
            rejected = True
    return phi, steps
