"""Effect ``contact``: friction of a footprint under any pressure distribution, exactly as the
plugin computes it (:func:`rrbody.physics.contact.footprint_wrench`: rings, annuli, Hertz patches,
feet, sampled p(x, y), convex polygons, ellipses).

``S`` is the packed footprint (:func:`rrbody.physics.contact.pack`): a header row (parts, the
load-weighted mean position and mean squared distance from the CM), the parts' rows, then their
geo rows. Every element feels the law at its own velocity, weighted by its load: dry friction
through the footprint kernel, viscous friction in closed form from the header's load moments
(:func:`rrbody.physics.effects.law_viscous.moments`, which the plugin's kernel calls too).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rrbody.physics.contact import H_GX, H_GY, H_J, H_PARTS, HEADER, footprint_wrench
from rrbody.physics.effects import law_viscous
from rrbody.physics.effects.laws import DRY, VISCOUS

__all__ = ["wrench"]

NAME = "contact"


@njit(cache=True)
def wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp):  # noqa: ANN001 (numba)
    """(Fbx, Fby, tau_cm) per unit mass (m/s^2 body frame, m^2/s^2) at CM velocity (vbx, vby) (m/s, body frame)."""
    if law == DRY:
        # np.int64(HEADER): the plugin's call passes a variable; a literal would compile the kernel twice
        fx, fy, tq = footprint_wrench(S, S, np.int64(HEADER), HEADER + int(S[0, H_PARTS]), vbx, vby, spin, v_eps)
        return coeff * fx, coeff * fy, coeff * tq
    if law == VISCOUS:
        # -gamma v(s) weighted by the load: linear, so its mean position and spread suffice
        return law_viscous.moments(vbx, vby, spin, coeff, S[0, H_GX], S[0, H_GY], S[0, H_J])
    # no law but these two has a form here (the law table): a scene with another law is refused when it is
    # bound (rrbody.physics.bind.area_model), so this is the law "none" only, which never calls friction
    return 0.0, 0.0, 0.0
