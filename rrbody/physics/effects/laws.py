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

__all__ = ["element_force", "element_perp", "law_params", "MODULES", "NO_PARAMS", "NONE", "DRY", "VISCOUS"]

#: the codes the area methods' closed forms branch on (rrbody.physics.effects.area_contact, area_table)
NONE, DRY, VISCOUS = LAW_CODES["none"], LAW_CODES["dry"], LAW_CODES["viscous"]
#: each law's module of compiled entry points, by name (the table's ``module``; "none" has none)
MODULES: dict[str, ModuleType] = {law.name: import_module(f"rrbody.physics.effects.{law.module}")
                                  for law in LAW_TABLE if law.module}
#: the law parameters of a call that has none (a law without parameters ignores them)
NO_PARAMS: tuple[float, ...] = (0.0,) * N_LAW_PARAMS


def _ladder(entry: str, zero: Callable[..., Any]) -> Any:
    """``law -> <module>.<entry>(...)`` over the table: a chain of inlined branches, the law's own first,
    ending in ``zero`` (no friction). A law outside the table never reaches a kernel: a scene and a plugin
    body are checked against the table when they are made (rrbody.model.laws.check_area), so the chain's
    end is the law "none" only."""
    fn = njit(inline="always")(zero)
    for law in reversed(LAW_TABLE):
        if law.module:
            fn = _branch(law.code, getattr(MODULES[law.name], entry), bool(law.params), fn)
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


def _no_force(law, vx, vy, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
    return 0.0, 0.0


def _no_perp(law, ve, vp, coeff, v_eps, lp):  # noqa: ANN001, ANN202 (numba)
    return 0.0, 0.0, 0.0


#: element_force(law, vx, vy, coeff, v_eps, lp): force per unit mass (m/s^2) of law ``law`` on an element
#: moving with (vx, vy) m/s, any frame
element_force = _ladder("force", _no_force)
#: element_perp(law, ve, vp, coeff, v_eps, lp): (f_p, df_p/dv_e, df_p/dv_p) of law ``law``, the force
#: component along the second axis and its derivatives (the point-mass right-hand side and its Jacobian)
element_perp = _ladder("perp", _no_perp)


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
