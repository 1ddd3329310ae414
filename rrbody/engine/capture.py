"""The recorder's copy kernel (:class:`rrbody.render.recorder.Recorder`): one frame of the filmed
bodies from the space's bulk read and the plugin's rows, in one compiled call."""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.engine.kernel import FFT, FFX, FFY, GAP, PVX, PVY, PW, STAG

__all__ = ["capture_rows"]


@njit(cache=True)
def capture_rows(got: np.ndarray, ids: np.ndarray, want: np.ndarray, rows: np.ndarray, bodies: np.ndarray,
                 prow: np.ndarray, out: np.ndarray) -> bool:
    """One frame of the recorder: the filmed bodies' state from the space's bulk read ``got`` (rows x,
    y, angle, vx, vy, spin; ``ids`` their ids) into ``out`` (one row per filmed body: x, y, angle and,
    if ``out`` has 9 columns, vx, vy, spin at the plugin's time and the friction of its last step).
    ``rows``: each filmed body's row in ``got`` (found by the caller; ``want`` their ids, to check it);
    ``prow``: its row in ``bodies`` (the plugin's), or -1. Returns False if ``rows`` no longer points at
    the filmed bodies (the space changed: the caller finds them again and calls again; what was
    written meanwhile is overwritten then)."""
    n = want.shape[0]
    m = got.shape[0]
    motion = out.shape[1] >= 9
    for k in range(n):
        r = rows[k]
        if r < 0 or r >= m or ids[r] != want[k]:
            return False
        out[k, 0] = got[r, 0]
        out[k, 1] = got[r, 1]
        out[k, 2] = got[r, 2]
        if not motion:
            continue
        vx = got[r, 3]
        vy = got[r, 4]
        w = got[r, 5]
        j = prow[k]
        if j >= 0:
            if bodies[j, GAP] > 0.0 and bodies[j, STAG] > 0.0:
                # the staggered scheme's velocity after a step belongs to half a step later: the mean
                # with the one before is the velocity at the plugin's time (PlaneFriction.velocity)
                vx = 0.5 * (bodies[j, PVX] + vx)
                vy = 0.5 * (bodies[j, PVY] + vy)
                w = 0.5 * (bodies[j, PW] + w)
            out[k, 6] = bodies[j, FFX]
            out[k, 7] = bodies[j, FFY]
            out[k, 8] = bodies[j, FFT]
        else:
            out[k, 6] = 0.0
            out[k, 7] = 0.0
            out[k, 8] = 0.0
        out[k, 3] = vx
        out[k, 4] = vy
        out[k, 5] = w
    return True
