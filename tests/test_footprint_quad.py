"""The footprint quadrature (rrbody.physics.footprint_quad): the contact method of a law without a closed form.

Its rules are checked on dry friction, whose exact footprint kernels (rrbody.physics.contact.footprint_wrench)
are the reference: every part kind, the instantaneous centre far from the footprint (a smooth integrand) and
inside it (where the element force turns its direction discontinuously, and the rules converge slowly).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rrbody.physics import footprint as F
from rrbody.physics.contact import footprint_wrench
from rrbody.physics.effects.laws import DRY, NO_PARAMS, VISCOUS
from rrbody.physics.footprint_quad import element_quadrature, footprint_law_wrench

BOX = np.array([[-0.1, -0.05], [0.1, -0.05], [0.1, 0.05], [-0.1, 0.05]])
_RNG = np.random.default_rng(1)
PARTS = {
    "disk": [F.ellipse_part(0.01, -0.02, 0.1, 0.1)],
    "ellipse": [F.ellipse_part(0.0, 0.02, 0.12, 0.05, 0.3)],
    "box": [F.polygon_part(BOX)],
    "T": [F.polygon_part(BOX), F.polygon_part(BOX * np.array([0.25, 2.0]) + np.array([0.0, -0.15]))],
    "ring": [F.ring_part(0.02, 0.0, 0.08)],
    "hertz": [F.hertz_part(0.0, 0.01, 0.07)],
    "point": [F.point_part(0.03, 0.04)],
    "sampled": [F.sampled_part(np.column_stack([_RNG.normal(0.0, 0.05, (50, 2)), np.full(50, 1.0 / 50.0)]))],
}
# the rules' error with the instantaneous centre within half a reach of the centre of gravity, per unit load
# and mu g (torques over the reach), measured over these 200 twists and rounded up by ~1.5: disk 1.6e-3,
# ellipse 2.1e-3, box 6.0e-3, T 3.7e-3, ring 6e-6 (its centre is off the ring: smooth), Hertz 2.5e-3. The
# discontinuity of dry friction's direction field at the centre costs this
INSIDE = {"disk": 3e-3, "ellipse": 3e-3, "box": 1e-2, "T": 6e-3, "ring": 1e-5, "hertz": 4e-3, "point": 0.0,
          "sampled": 0.0}


def _errors(name: str, far: bool) -> float:
    shapes, geo, reach, _, _ = F.combine(PARTS[name])
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(200):
        vx, vy = rng.normal(0.0, 1.0, 2)
        # the instantaneous centre |v| / |w| from the centre of gravity: 3-30 reaches away, or within half a reach
        c = reach * (rng.uniform(3.0, 30.0) if far else rng.uniform(0.0, 0.5))
        w = math.hypot(vx, vy) / c * rng.choice([-1.0, 1.0])
        a = np.array(footprint_wrench(shapes, geo, 0, shapes.shape[0], vx, vy, w, 1e-12))
        b = np.array(element_quadrature(DRY, shapes, geo, 0, shapes.shape[0], vx, vy, w, 1.0, 1e-12, NO_PARAMS, 0.0))
        worst = max(worst, abs(a[0] - b[0]), abs(a[1] - b[1]), abs(a[2] - b[2]) / reach)
    return worst


@pytest.mark.parametrize("name", list(PARTS))
def test_the_rules_agree_with_dry_frictions_exact_kernels(name: str) -> None:
    """Far from the footprint the integrand is smooth and the rules converge spectrally: within 1e-12 (measured
    below 1e-14). Inside, within the INSIDE table's bounds (the module docstring's statement); points and
    samples are exact."""
    far = _errors(name, far=True)
    assert far <= 1e-12, far
    inside = _errors(name, far=False)
    assert inside <= INSIDE[name] + 1e-15, inside


def test_the_viscous_law_keeps_its_closed_form() -> None:
    """footprint_law_wrench sends a law with a footprint form of its own (viscous: the load's moments) there,
    not to the quadrature: the two agree (a linear law, smooth everywhere) to the rules' precision."""
    shapes, geo, reach, (gx, gy), jj = F.combine(PARTS["box"])
    got = footprint_law_wrench(VISCOUS, shapes, geo, 0, 1, gx, gy, jj, 0.3, -0.1, 2.0, 1.5, 0.0, NO_PARAMS)
    quad = element_quadrature(VISCOUS, shapes, geo, 0, 1, 0.3, -0.1, 2.0, 1.5, 0.0, NO_PARAMS, 0.0)
    assert np.allclose(got, quad, rtol=1e-12, atol=1e-14)
