"""Effect ``contact``: friction of a footprint under any pressure distribution, exactly as the
plugin computes it (:func:`rrbody.physics.contact.footprint_wrench`: rings, annuli, Hertz patches,
feet, sampled p(x, y), convex polygons, ellipses).

``S`` is the packed footprint (:func:`rrbody.physics.contact.pack`): a header row (parts, the
load-weighted mean position and mean squared distance from the CM), the parts' rows, then their
geo rows. Every element feels the law at its own velocity, weighted by its load: dry friction
through the footprint kernel, any other law through its own footprint form
(:func:`rrbody.physics.effects.laws.law_footprint`; viscous friction: the closed form of the header's load
moments) or, for a law without one, the quadrature of its element force
(:func:`rrbody.physics.footprint_quad.footprint_law_wrench`), which the plugin's kernel calls too.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.physics.contact import H_MEAN_X, H_MEAN_Y, H_PARTS, H_SPREAD, HEADER, footprint_wrench
from rrbody.physics.effects.laws import DRY
from rrbody.physics.footprint_quad import footprint_law_wrench

__all__ = ["wrench"]

NAME = "contact"


@njit(cache=True)
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm) per unit mass (m/s^2 body frame, m^2/s^2) at CM velocity (vbx, vby) (m/s, body frame)."""
    if law == DRY:
        # np.int64(HEADER): the plugin's call passes a variable; a literal would compile the kernel twice
        fx, fy, tq = footprint_wrench(S, S, np.int64(HEADER), HEADER + int(S[0, H_PARTS]), vbx, vby, spin, v_eps)
        return coeff * fx, coeff * fy, coeff * tq
    # every other law: its own footprint form, from the law table (viscous: the load's moments), or the quadrature
    # of its element force (rrbody.physics.footprint_quad); "none" never calls friction
    return footprint_law_wrench(law, S, S, np.int64(HEADER), HEADER + int(S[0, H_PARTS]), S[0, H_MEAN_X],
                         S[0, H_MEAN_Y], S[0, H_SPREAD], vbx, vby, spin, coeff, v_eps, lp)
