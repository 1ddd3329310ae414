"""Bind a scene to the compiled kernels: its parameter vector ``p`` and area samples ``S``.

The layout of ``p`` is :mod:`rrbody.physics.params`; this module is the only writer.
"""

from __future__ import annotations

import math

import numpy as np

from rrbody.model.bodies import Polygon
from rrbody.model.laws import AREA_METHODS, N_LAW_PARAMS, bound_params, check_area, law_named, zero_speed_mu
from rrbody.model.scene import Scene
from rrbody.physics import params as P
from rrbody.physics.area import area_samples, icr_nodes, icr_supported
from rrbody.physics.footprint import packed
from rrbody.physics.icr_table import build_table

__all__ = ["area_model", "kernel_params", "ode_params", "pinned_params", "friction_per_mass", "DRIVEN_DEAD_BAND",
           "FREE_DEAD_BAND"]

#: Zero-speed dead band of dry friction, relative to the scene's velocity scale, for driven bodies.
#: At the impulsive start from phi0 = pi the CM starts at rest and its speed grows like
#: |v| = d w W t, W = w (1 + 1/H); the friction that the dead band switches off there is the
#: self-consistent one, whose contribution to phi'' is at most w W^2 t / H whatever k is (the
#: series solution near t = 0: the CM is dragged along the rod, docs/accuracy.md). Over the band,
#: t < eps / W, it changes phi' by at most eps^2 w / (2 H): 5e-19 relative at eps = 1e-9, far below
#: rounding. A wider band than the old 1e-12 lets a step of ~eps / W start the run at any k instead
#: of step sizes that underflow (k = 1e3: "step size underflow at t = 6.3e-13 s").
DRIVEN_DEAD_BAND: float = 1e-9
#: Free bodies keep the narrow band: their stop is completed analytically from a speed above it.
FREE_DEAD_BAND: float = 1e-12


def area_model(scene: Scene) -> int:
    """Which friction integration the kernels use for ``scene``: P.BODY_POINT, P.BODY_SAMPLED,
    P.BODY_ICR, P.BODY_TABLE or P.BODY_CONTACT (any pressure but uniform). ValueError naming the law and
    the method if the scene's law has no form for the method it needs (the law table,
    :func:`rrbody.model.laws.check_area`): the composition is checked here, before any kernel runs."""
    model = _area_model(scene)
    check_area(scene.friction.law, AREA_METHODS[model], where=f"body {scene.body.kind!r}, friction_method "
                                                            f"{scene.friction_method!r}")
    return model


def _area_model(scene: Scene) -> int:
    """:func:`area_model` before its check of the law."""
    method = scene.friction_method
    if scene.body.is_point and method in ("icr", "table", "contact"):
        raise ValueError(f"friction_method {method!r} needs an extended body (disk or ellipse), got body "
                         f"{scene.body.kind!r}; a point mass feels friction at its CM ('auto')")
    if scene.body.is_point and scene.tilt != 0.0:
        # one element at the CM: exactly a point mass's friction, through the extended bodies' call,
        # which carries the tilt's terms (the inline point mass, every level run's, stays without them)
        return P.BODY_SAMPLED
    if scene.body.is_point or not scene.friction.active:
        return P.BODY_POINT
    if isinstance(scene.body, Polygon):
        if method not in ("auto", "contact"):
            raise ValueError("friction_method must be 'auto' or 'contact' for a polygon (its exact wrench), got "
                             f"{method!r}")
        return P.BODY_CONTACT
    if method == "contact" or not scene.pressure.is_uniform:
        return P.BODY_CONTACT
    if method == "sampled":
        return P.BODY_SAMPLED
    supported = icr_supported(scene.body, scene.friction.law)
    if method in ("icr", "table") and not supported:
        raise ValueError(f"friction_method {method!r} does not apply to body {scene.body.kind!r} with friction "
                         f"{scene.friction.law!r}; use 'sampled' or 'auto'")
    if method == "table":
        return P.BODY_TABLE
    if method == "icr":
        return P.BODY_ICR
    if not supported:
        return P.BODY_SAMPLED
    # "auto": a dry disk uses the table (1-D, quick to build, within 3e-14 of the quadrature and
    # cheaper to evaluate); an ellipse keeps the quadrature, since its 2-D table per aspect ratio
    # takes longer to build than a typical run saves (docs/extended.md gives the times); the
    # table is dry friction's own (a viscous disk's quadrature is already a closed form)
    ra, rb = scene.body.semi_axes
    return P.BODY_TABLE if (ra == rb and scene.friction.law == "dry") else P.BODY_ICR


def friction_per_mass(scene: Scene) -> tuple[float, float]:
    """(kinetic, static) friction per unit mass of the scene's body, m/s^2 (dry: mu g and mu_static g,
    both times cos(tilt), the normal load of a tilted plane; viscous: gamma in 1/s and no static
    friction; none: 0, 0). What both paths bind: the ODE path's ``p``, the engine path's plane. The law's
    declaration says which (:mod:`rrbody.model.laws`: a load-scaled coefficient, a law that sticks); an
    unknown law raises ValueError."""
    fr = scene.friction
    law = law_named(fr.law)
    if not fr.active:
        return 0.0, 0.0
    if not law.load_scaled:
        return fr.coeff, 0.0
    c = math.cos(scene.tilt)
    if not law.sticks:
        return fr.coeff * c, 0.0
    # static friction's default: the law's coefficient at zero speed (dry: mu; Stribeck: mu_s)
    mu_s = zero_speed_mu(fr.law, fr.coeff / scene.g, fr.params) if scene.mu_static is None else scene.mu_static
    return fr.coeff * c, mu_s * scene.g * c


def kernel_params(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """The parameter vector ``p`` and area-sample array ``S`` for the compiled kernels: ``S`` holds the
    area samples (rows x_b, y_b, w) for the sampled method, the wrench table
    (:mod:`rrbody.physics.icr_table`, cached per aspect ratio) for the table method, the packed
    footprint (:func:`rrbody.physics.footprint.packed`) for the contact method, else nothing."""
    p = np.zeros(P.SIZE)
    p[P.OMEGA] = scene.omega
    p[P.D] = scene.d
    p[P.L] = scene.body.l
    p[P.IP] = scene.inertia_about_pivot
    p[P.INV_IP] = 1.0 / p[P.IP] if p[P.IP] > 0.0 else 0.0
    p[P.ICM] = scene.body.inertia_per_mass
    beta = scene.phi0 - scene.body.alpha0
    p[P.CBETA] = math.cos(beta)
    p[P.SBETA] = math.sin(beta)
    p[P.LAW] = float(scene.friction.code if scene.friction.active else 0)
    p[P.COEFF], p[P.MUS] = friction_per_mass(scene)
    p[P.LAWP:P.LAWP + N_LAW_PARAMS] = bound_params(scene.friction.law, scene.friction.params,
                                                   scene.g * math.cos(scene.tilt))
    if scene.tilt != 0.0:  # gravity pulls along a tilted plane
        pull = scene.g * math.sin(scene.tilt)
        p[P.TILTED] = 1.0
        p[P.GTX] = pull * math.cos(scene.downhill)
        p[P.GTY] = pull * math.sin(scene.downhill)
    if scene.active is not None:  # a free body's self-propulsion, its medium's drag and Langevin noise
        a = scene.active
        m = scene.body.mass
        p[P.ACTIVE] = 1.0
        p[P.AFX], p[P.AFY] = (f / m for f in a.body_force)
        icm = scene.body.inertia_per_mass
        p[P.AALPHA] = a.torque / (m * icm) if icm > 0.0 else 0.0
        p[P.ADRAG] = a.drag
        p[P.ARDRAG] = a.rot_drag if icm > 0.0 else 0.0
        # the noise per unit mass (moment): the force m gamma_t sqrt(2 D_t) dW over m; a point mass's spin is
        # kinematic, and a Scene refuses rot_diffusion for it
        p[P.ANOISE] = a.drag * math.sqrt(2.0 * a.diffusion)
        p[P.ARNOISE] = a.rot_drag * math.sqrt(2.0 * a.rot_diffusion) if icm > 0.0 else 0.0
    p[P.VEPS] = (DRIVEN_DEAD_BAND if scene.driven else FREE_DEAD_BAND) * scene.velocity_scale()
    ra, rb = scene.body.semi_axes
    p[P.RA] = ra
    p[P.RB] = rb
    model = area_model(scene)
    p[P.BODY] = float(model)
    S = np.zeros((0, 3))
    if model == P.BODY_SAMPLED:
        S = np.array([[0.0, 0.0, 1.0]]) if scene.body.is_point else area_samples(scene.body, scene.samples)
    elif model == P.BODY_ICR:
        p[P.NQ] = float(icr_nodes(scene.body))
    elif model == P.BODY_CONTACT:
        S = packed(scene.body, scene.pressure)
    elif model == P.BODY_TABLE:
        p[P.NQ] = float(icr_nodes(scene.body))
        if scene.friction.law == "dry":
            S = build_table(ra, rb)
    return p, S


def ode_params(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """:func:`kernel_params` for the ODE path. Every pressure runs, feet (``points``) included: a
    driven body's feet stop only at isolated instants (it has one degree of freedom, and a foot at
    rest needs two conditions), and a free body that comes to pivot on a foot is followed in the pivot
    mode (:mod:`rrbody.integrate.pivot`, with :func:`pinned_params`)."""
    return kernel_params(scene)


def pinned_params(p: np.ndarray, foot: tuple[float, float]) -> np.ndarray:
    """The parameter vector of a free body's ``p`` pinned at its point ``foot`` (m, body frame from the
    centre of gravity; a foot at rest): the driven body's equations with the pivot P at rest
    (omega = d = 0), l = |foot| (m), I_P / m = I_cm / m + l^2 (m^2) and beta the foot's direction in
    the body frame (rad; 0 for a foot at the centre of gravity). Friction, its dead band and a tilt's
    pull are the free body's, so phi'' is the spin's rate about the foot under the other feet's
    friction and the pull's torque about it (:mod:`rrbody.physics.pivot_foot`)."""
    x, y = float(foot[0]), float(foot[1])
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"foot must be a finite point (x, y) in m, got {foot!r}")
    q = p.copy()
    l = math.hypot(x, y)
    beta = math.atan2(y, x) if l > 0.0 else 0.0
    q[P.OMEGA] = 0.0
    q[P.D] = 0.0
    q[P.L] = l
    q[P.IP] = p[P.ICM] + l * l
    q[P.INV_IP] = 1.0 / q[P.IP] if q[P.IP] > 0.0 else 0.0
    q[P.CBETA] = math.cos(beta)
    q[P.SBETA] = math.sin(beta)
    return q
