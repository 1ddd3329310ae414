"""Effects: one small module each, composed into a scene's right-hand side (the REBOUNDx model).

A scene lists its effects; each contributes one term through one signature:

- drive: ``drive_circular`` (the pivot on a circle; its torque about P and the kinematics);
- friction laws (force on a mass element, ``force(vx, vy, coeff, v_eps)``; and its component along
  one axis with derivatives, ``perp``, for the point-mass Jacobian): ``law_dry``, ``law_viscous``,
  each declared in the law table (:mod:`rrbody.model.laws`), dispatched by :mod:`rrbody.physics.effects.laws`;
- area integration (the wrench of the law over the body, in the BODY frame:
  ``wrench(law, S, ra, rb, nq, icm, vbx, vby, spin, coeff, v_eps, lp) -> (Fbx, Fby, tau_cm)`` with the
  CM velocity and the force in body-frame components; :func:`rrbody.physics.areas.body_wrench` is the
  world-frame wrapper): ``area_point`` and ``area_sampled`` here; the methods that call a kernel
  (``area_icr``, ``area_table``, ``area_contact``) and their registry stand above the kernels, in
  :mod:`rrbody.physics.areas`, so that this package imports only :mod:`rrbody.physics.params` and the model.

Composition: the combination a scene lists is one small integer, its *system code*
(:func:`system_code`: kind + 10 law + 100 area). The compiled kernels are specialised on part of it
only, its *compiled code* (:func:`compiled_code`: kind + 10 law), a compile-time constant
(``numba.literally``): the kind fixes the state and the loops' trip counts, and the law is where a
run-time branch was measured to cost (docs/compile.md). Every other effect, the area method
included, is chosen at run time from the codes in the float parameter vector ``p``
(:mod:`rrbody.physics.params`), which also carries the effects' parameters; an extended body's area
method is a call of its own, so a point mass never executes, nor pays registers for, its code. So the
kernels form one fixed set (compiled at install: :mod:`rrbody.cli.prebuild`), and a new combination
of effects, or a new run-time effect, compiles nothing.

One effect is chosen by the state itself: ``tangent`` (the variational equations, for Lyapunov
exponents, :mod:`rrbody.analysis.chaos`) rides along when a driven state carries tangent vectors
after (phi, phi'); DOP853 steps them out of line (:func:`rrbody.integrate.dop853.tangent_stages`),
so a plain run pays one branch per step and no loop is compiled for it.

Adding an effect: one module with the signature of its kind plus its registration. A law is declared
in the one law table, :data:`rrbody.model.laws.LAW_TABLE` (name, code, parameters, area methods, this
package's module of its entry points), from which :mod:`rrbody.physics.effects.laws` builds the compiled dispatch; an
area
method takes a name in :data:`rrbody.model.laws.AREA_METHODS` and one branch in :mod:`rrbody.physics.areas`. A new
law adds one compiled loop per kind, which the prebuild's workload (:mod:`rrbody.cli.workload`) compiles
at install: it runs each law of the table.
"""

from __future__ import annotations

from rrbody.model.laws import AREA_CODES, LAW_CODES

__all__ = ["KINDS", "LAWS", "AREAS", "system_code", "compiled_code", "describe_system", "DRIVEN", "FREE"]

DRIVEN, FREE = 0, 1
#: kinds of system: which equations (the drive is the effect that makes a body driven)
KINDS: dict[str, int] = {"driven": DRIVEN, "free": FREE}
#: friction laws -> code (modules law_<name>; "none" lists no friction effect): the law table's
LAWS: dict[str, int] = LAW_CODES
#: area-integration methods -> code (modules area_<name>), in the law table's order of the methods
AREAS: dict[str, int] = AREA_CODES


def system_code(kind: str, law: str, area: str) -> int:
    """The system code of a combination of effects (kind + 10 law + 100 area)."""
    for name, value, table in (("kind", kind, KINDS), ("law", law, LAWS), ("area", area, AREAS)):
        if value not in table:
            raise ValueError(f"{name} must be one of {', '.join(repr(k) for k in table)}, got {value!r}")
    return KINDS[kind] + 10 * LAWS[law] + 100 * AREAS[area]


def compiled_code(system: int) -> int:
    """The part of a system code the compiled kernels are specialised on: kind + 10 law for a driven
    body (its analytic Jacobian is where a run-time law costs), the kind alone for a free body (its
    Jacobian is numerical, so its law is a run-time choice as well). The area method and every
    parameter are run-time choices."""
    system = int(system)
    if system % 10 == FREE:
        return FREE
    return system % 100


def describe_system(code: int) -> dict[str, str]:
    """The effects behind a system code (inverse of :func:`system_code`)."""
    inv = [{v: k for k, v in t.items()} for t in (KINDS, LAWS, AREAS)]
    try:
        return {"kind": inv[0][code % 10], "law": inv[1][(code // 10) % 10], "area": inv[2][code // 100]}
    except KeyError:
        raise ValueError(f"system code {code!r} names no registered combination of effects") from None
