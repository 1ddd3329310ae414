"""Compiled timing loops for the area study (imported only once rrbody._icr exists).

Each loop calls one rrbody kernel ``m`` times with a slowly varying argument (so nothing is
hoisted out of the loop) and returns a checksum (so nothing is optimised away).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.physics.icr import icr_wrench
from rrbody.physics.wrench import sampled_wrench


@njit(cache=True)
def loop_sampled(S, m, vx, vy, spin):  # noqa: ANN001
    """m calls of the sampled-element wrench (dry, mu g = 1)."""
    acc = 0.0
    for i in range(m):
        fx, fy, tau = sampled_wrench(S, 1e-9 * i, vx, vy, spin, 1, 1.0, 0.0)
        acc += fx + fy + tau
    return acc


@njit(cache=True)
def loop_icr(a, b, n, m, vx, vy, spin, icm):  # noqa: ANN001
    """m calls of the ICR-quadrature wrench (dry, mu g = 1) with n nodes per panel."""
    acc = 0.0
    for i in range(m):
        fx, fy, tau = icr_wrench(a, b, n, 1e-9 * i, vx, vy, spin, 1, 1.0, 0.0, icm)
        acc += fx + fy + tau
    return acc


def loop_rhs(p, S, m):  # noqa: ANN001, ANN201
    """m calls of the driven right-hand side of ``p``, ``S`` (its system code compiled in)."""
    from rrbody.physics.dynamics import SYSTEM_DRIVEN, system_from_params

    return loop_rhs_for(system_from_params(p, SYSTEM_DRIVEN))(p, S, m)


_RHS_LOOPS: dict[int, object] = {}


def loop_rhs_for(system: int):  # noqa: ANN201
    """m calls of the composed right-hand side with the compiled code in (as the ODE loop does)."""
    from rrbody.physics.effects import compiled_code

    code = compiled_code(system)
    if code not in _RHS_LOOPS:
        from rrbody.physics.dynamics import rhs


        @njit(cache=True)
        def run(p, S, m):  # noqa: ANN001
            y = np.array([3.0, -2.0])
            out = np.empty((1, 2))
            acc = 0.0
            for i in range(m):
                y[0] = 3.0 + 1e-7 * i
                rhs(code, 1e-6 * i, y, p, S, out, 0)
                acc += out[0, 1]
            return acc

        _RHS_LOOPS[code] = run
    return _RHS_LOOPS[code]
