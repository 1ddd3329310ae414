"""The friction laws' compiled dispatch, built from the one law table (:data:`rrbody.model.laws.LAW_TABLE`).

Each law with a module (``law_dry``, ``law_viscous``: the table's ``module``) provides the element force
``force(vx, vy, coeff, v_eps)`` and its one-axis component ``perp(ve, vp, coeff, v_eps)`` (a law with
parameters takes them last, as the tuple ``lp``: ``force(vx, vy, coeff, v_eps, lp)``). :func:`element_force`
and :func:`element_perp` are the ladders ``if law == <code>: return <module>.force(...)`` over the table, in
its order, generated at import (numba inlines the chain: the same branches as a ladder written by hand; the
code is a compile-time constant in every composed right-hand side, :mod:`rrbody.physics.effects`, so the
branches are resolved when the kernel is compiled; the plugin's kernel and :mod:`rrbody.physics.wrench` pass
it at run time). ``lp``: the law's parameters per unit mass (:func:`rrbody.model.laws.bound_params`), a tuple
of :data:`rrbody.model.laws.N_LAW_PARAMS` floats (empty while no law has parameters): :func:`law_params` reads
them from ``p``, and :data:`NO_PARAMS` stands for them where a caller evaluates a law without any.

The contact method of both paths (the ODE path's :mod:`rrbody.physics.areas.area_contact`, the plugin's
:mod:`rrbody.contact.accel`) integrates a law over a footprint: dry friction through the footprint kernel
itself (:func:`rrbody.physics.contact.footprint_wrench`, with the plugin's wrench tables), every other law
through its module's ``footprint(shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps[, lp])`` (the
parts ``shapes[s0:s1]``, the load's mean position (gx, gy) and mean squared distance jj: the viscous law's
closed form needs only these), dispatched by :func:`law_footprint` over the table; a law whose module has no
footprint form (:func:`law_has_footprint`) is integrated over the footprint by quadrature of its element force
(:mod:`rrbody.physics.footprint_quad`, which both paths call for every law but dry). ``law_params_at(a, j,
first)`` reads a law's parameters from row ``j`` of an array (the plugin's ``bodies``, from its column
``first``).

Adding a law: its module and its entry in the table; nothing here.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from types import ModuleType
from typing import Any

from numba import njit

from rrbody.model.laws import LAW_CODES, LAW_TABLE, N_LAW_PARAMS
from rrbody.physics import params as P

__all__ = ["element_force", "element_perp", "law_footprint", "law_has_footprint", "law_rest_coeff", "one_of",
           "law_params",
           "law_params_at",
           "MODULES", "NO_PARAMS",
           "NONE", "DRY", "VISCOUS"]

#: the codes the area methods' closed forms branch on (rrbody.physics.areas.area_contact, area_table)
NONE, DRY, VISCOUS = LAW_CODES["none"], LAW_CODES["dry"], LAW_CODES["viscous"]
#: each law's module of compiled entry points, by name (the table's ``module``; "none" has none)
MODULES: dict[str, ModuleType] = {law.name: import_module(f"rrbody.physics.effects.{law.module}")
                                  for law in LAW_TABLE if law.module}
#: the law parameters of a call that has none (a law without parameters ignores them)
NO_PARAMS: tuple[float, ...] = (0.0,) * N_LAW_PARAMS


def _ladder(entry: str, zero: Callable[..., Any], branch: Callable[..., Any]) -> Any:
    """``law -> <module>.<entry>(...)`` over the table: a chain of inlined branches (``branch`` makes one),
    in the table's order, for the laws whose module has ``entry``, ending in ``zero`` (no friction). A law
    outside the table never reaches a kernel: a scene and a plugin body are checked against the table when
    they are made (rrbody.model.laws.check_area), so the chain's end is the law "none" only (or dry, in
    :func:`law_footprint`, whose callers take dry's own branch first)."""
    fn = njit(inline="always")(zero)
    for law in reversed(LAW_TABLE):
        if law.module and hasattr(MODULES[law.name], entry):
            fn = branch(law.code, getattr(MODULES[law.name], entry), bool(law.params), fn)
    return fn


def _branch(code: int, impl: Any, with_params: bool, rest: Any) -> Any:
    """``if law == code: return impl(a, b, coeff, v_eps[, lp])``, else ``rest``."""
    if with_params:
        def step(law, a, b, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
            if law == code:
                return impl(a, b, coeff, v_eps, lp)
            return rest(law, a, b, coeff, v_eps, lp)
    else:
        def step(law, a, b, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
            if law == code:
                return impl(a, b, coeff, v_eps)
            return rest(law, a, b, coeff, v_eps, lp)
    return njit(inline="always")(step)


def _footprint_branch(code: int, impl: Any, with_params: bool, rest: Any) -> Any:
    """``if law == code: return impl(shapes, ..., v_eps[, lp])``, else ``rest``: :func:`_branch` for the
    footprint form's signature."""
    if with_params:
        def step(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp):  # noqa: ANN001, ANN202
            if law == code:
                return impl(shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp)
            return rest(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp)
    else:
        def step(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp):  # noqa: ANN001, ANN202
            if law == code:
                return impl(shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps)
            return rest(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp)
    return njit(inline="always")(step)


def _no_force(law, vx, vy, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
    return 0.0, 0.0


def _no_perp(law, ve, vp, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
    return 0.0, 0.0, 0.0


def _no_footprint(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp):  # noqa: ANN001, ANN202
    return 0.0, 0.0, 0.0


#: element_force(law, vx, vy, coeff, v_eps, lp): force per unit mass (m/s^2) of law ``law`` on an element
#: moving with (vx, vy) m/s, any frame
element_force = _ladder("force", _no_force, _branch)
#: element_perp(law, ve, vp, coeff, v_eps, lp): (f_p, df_p/dv_e, df_p/dv_p) of law ``law``, the force
#: component along the second axis and its derivatives (the point-mass right-hand side and its Jacobian)
element_perp = _ladder("perp", _no_perp, _branch)
#: law_footprint(law, shapes, geo, s0, s1, gx, gy, jj, vbx, vby, w, coeff, v_eps, lp): (fx, fy, tq) of law
#: ``law`` (not dry: its callers evaluate dry friction by the footprint kernel) over the parts shapes[s0:s1]
#: per unit mass, force in the body frame (m/s^2) and torque about the centre of gravity (m^2/s^2), at the
#: centre-of-gravity velocity (vbx, vby) (m/s, body frame) and spin w (rad/s)
law_footprint = _ladder("footprint", _no_footprint, _footprint_branch)


def one_of(codes: tuple[float, ...]) -> Any:
    """A compiled ``has(law)``: whether ``law`` (an int, or the plugin's float column) is one of ``codes``, as a
    chain of inlined comparisons (numba builds no set of constants; as :func:`_ladder`)."""
    def no(law):  # noqa: ANN001, ANN202 (numba)
        return False

    fn = njit(inline="always")(no)
    for code in codes:
        fn = _or(code, fn)
    return fn


def _or(code: int, rest: Any) -> Any:
    def has(law):  # noqa: ANN001, ANN202 (numba)
        return law == code or rest(law)
    return njit(inline="always")(has)


#: law_has_footprint(law): whether law ``law``'s module has a footprint form of its own (the viscous law);
#: the contact method integrates every other law but dry friction by quadrature
#: (:func:`rrbody.physics.footprint_quad.footprint_law_wrench`)
law_has_footprint = one_of(tuple(law.code for law in LAW_TABLE
                                  if law.module and hasattr(MODULES[law.name], "footprint")))


def _rest_branch(code: int, impl: Any, with_params: bool, rest: Any) -> Any:
    """``if law == code: return impl(coeff[, lp])``, else ``rest``."""
    if with_params:
        def step(law, coeff, lp):  # noqa: ANN001, ANN202 (numba)
            if law == code:
                return impl(coeff, lp)
            return rest(law, coeff, lp)
    else:
        def step(law, coeff, lp):  # noqa: ANN001, ANN202 (numba)
            if law == code:
                return impl(coeff)
            return rest(law, coeff, lp)
    return njit(inline="always")(step)


def _no_rest(law, coeff, lp):  # noqa: ANN001, ANN202 (numba)
    return 0.0


#: law_rest_coeff(law, coeff, lp): the element force's magnitude as the speed goes to zero (m/s^2 per unit
#: mass: dry mu g, Stribeck's mu_s g), from the module's ``rest_coeff(coeff[, lp])``; 0 for a law without one.
#: The footprint quadrature integrates that much of the law exactly, as dry friction
#: (:mod:`rrbody.physics.footprint_quad`)
law_rest_coeff = _ladder("rest_coeff", _no_rest, _rest_branch)


def _reader(n: int) -> Any:
    """``law_params(p)``: the tuple p[LAWP:LAWP + n] (numba builds no tuple of a run-time length)."""
    first = P.LAWP
    if n == 0:
        def read(p):  # noqa: ANN001, ANN202 (numba)
            return ()
    elif n == 1:
        def read(p):  # noqa: ANN001, ANN202 (numba)
            return (p[first],)
    elif n == 2:
        def read(p):  # noqa: ANN001, ANN202 (numba)
            return (p[first], p[first + 1])
    elif n == 3:
        def read(p):  # noqa: ANN001, ANN202 (numba)
            return (p[first], p[first + 1], p[first + 2])
    else:
        raise ValueError(f"N_LAW_PARAMS must be at most 3 (one reader per size here), got {n}")
    return njit(inline="always")(read)


#: law_params(p): the scene's law parameters per unit mass, from its parameter vector (rrbody.physics.params)
law_params = _reader(N_LAW_PARAMS)


def _row_reader(n: int) -> Any:
    """``law_params_at(a, j, first)``: the tuple a[j, first:first + n] (as :func:`_reader`)."""
    if n == 0:
        def read(a, j, first):  # noqa: ANN001, ANN202 (numba)
            return ()
    elif n == 1:
        def read(a, j, first):  # noqa: ANN001, ANN202 (numba)
            return (a[j, first],)
    elif n == 2:
        def read(a, j, first):  # noqa: ANN001, ANN202 (numba)
            return (a[j, first], a[j, first + 1])
    elif n == 3:
        def read(a, j, first):  # noqa: ANN001, ANN202 (numba)
            return (a[j, first], a[j, first + 1], a[j, first + 2])
    else:
        raise ValueError(f"N_LAW_PARAMS must be at most 3 (one reader per size here), got {n}")
    return njit(inline="always")(read)


#: law_params_at(a, j, first): a law's parameters per unit mass from row j of ``a``, columns first on (the
#: plugin's ``bodies``: rrbody.contact.columns.LAW_PARAMS)
law_params_at = _row_reader(N_LAW_PARAMS)
