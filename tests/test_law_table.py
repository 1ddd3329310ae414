"""The one law table (rrbody.model.laws): every table derived from it agrees with it, and the composition checks
itself. The five places where an unknown law, or a law on an area method without a form for it, once became dry
friction or no friction in silence (the builder, bind, the contact method, the quadrature, the plugin's kernel)
now raise a ValueError naming the law (and the method) where the scene is bound or the body added, before any
kernel runs.

A law without some form is made here by restricting a real law's declaration in the table (``_restricted``):
every law of the shipped table has a form for every method, which is exactly why the checks need this test.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import math

import numpy as np
import pymunk
import pytest

from rrbody.model import laws as L
from rrbody.model.bodies import Disk
from rrbody.model.checks import Limit, MissingParameters
from rrbody.model.friction import Friction
from rrbody.model.scene import FRICTION_METHODS, NUMERIC_SCENE_PARAMS, SCENE_PARAMS, scene_from_params


def _restricted(monkeypatch: pytest.MonkeyPatch, name: str, areas: tuple[str, ...]) -> None:
    """Law ``name`` declared with only ``areas`` (in the table's look-ups by name and by code)."""
    law = dataclasses.replace(L._BY_NAME[name], areas=areas)
    monkeypatch.setitem(L._BY_NAME, name, law)
    monkeypatch.setitem(L._BY_CODE, law.code, law)


def _unknown(scene: object, law: str = "bogus") -> object:
    """``scene`` with its Friction's law replaced by one the table does not have (as a stale object, or a
    table edited under it, would carry): what the old fallbacks turned into dry or no friction."""
    object.__setattr__(scene.friction, "law", law)  # type: ignore[attr-defined]
    return scene


def _disk(law: str = "viscous", **kw: object) -> object:
    return scene_from_params(body="disk", R0=0.1, k=0.5, friction=law, **kw)  # type: ignore[arg-type]


def _free_disk(law: str = "viscous", **kw: object) -> object:
    return _disk(law, no_drive=True, v0=(0.3, 0.0), **kw)


# ---- one table, everything derived ------------------------------------------------------------
def test_the_derived_tables_agree_with_the_law_table() -> None:
    from rrbody.contact import columns
    from rrbody.model import friction
    from rrbody.physics import effects
    from rrbody.physics import params as P
    from rrbody.physics.effects import laws as EL

    codes = {law.name: law.code for law in L.LAW_TABLE}
    assert friction.LAWS == L.LAWS == tuple(codes)
    assert friction.LAW_CODES == effects.LAWS == codes
    assert (EL.NONE, EL.DRY, EL.VISCOUS) == (codes["none"], codes["dry"], codes["viscous"])
    assert columns.LAW_CODE == {n: float(c) for n, c in codes.items()}
    assert (columns.LAW_NONE, columns.LAW_DRY, columns.LAW_VISCOUS) == (0.0, 1.0, 2.0)
    assert list(effects.AREAS) == list(L.AREA_METHODS) and list(effects.AREAS.values()) == list(range(5))
    assert (P.BODY_POINT, P.BODY_SAMPLED, P.BODY_ICR, P.BODY_TABLE, P.BODY_CONTACT) == (0, 1, 2, 3, 4)
    assert FRICTION_METHODS == ("auto", *L.AREA_METHODS[1:])
    # the law parameters' slots, on both paths, and the scene's flat parameters
    assert P.SIZE == P.LAWP + L.N_LAW_PARAMS and columns.N_BODY >= columns.LAW_PARAMS + L.N_LAW_PARAMS
    assert set(L.LAW_PARAMS) <= set(SCENE_PARAMS) and set(L.LAW_PARAMS) <= set(NUMERIC_SCENE_PARAMS)


def test_each_law_module_declares_its_name_and_entry_points() -> None:
    from rrbody.physics.effects import laws as EL

    for law in L.LAW_TABLE:
        if not law.module:
            assert law.name == "none"
            continue
        mod = importlib.import_module(f"rrbody.physics.effects.{law.module}")
        assert mod.NAME == law.name and EL.MODULES[law.name] is mod
        assert callable(mod.force) and callable(mod.perp)
        # the contact method of both paths: dry's footprint kernel, any other law's own footprint form, or the
        # quadrature of its element force (rrbody.physics.footprint_quad), which needs nothing of the module
        assert callable(getattr(mod, "footprint", None)) == (law.name == "viscous"), law.name


def _friction_actions(parser: argparse.ArgumentParser) -> list[tuple[str, argparse.Action]]:
    """Every --friction option of every subcommand, with the subcommand's name."""
    found = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found += [(f"{name} {n}".strip(), a) for n, a in _friction_actions(sub)]
        elif "--friction" in action.option_strings:
            found.append(("", action))
    return found


def test_the_command_line_offers_the_tables_laws() -> None:
    from rrbody.cli.main import build_parser

    actions = _friction_actions(build_parser())
    assert len(actions) >= 5, [n for n, _ in actions]  # simulate, flip-time, critical-h, sweep, ...
    for name, action in actions:
        assert tuple(action.choices) == L.LAWS, name


def test_the_table_checks_itself() -> None:
    assert [law.code for law in L.LAW_TABLE] == [1, 2, 3, 0]
    with pytest.raises(ValueError, match=r"friction must be one of 'dry', 'viscous', 'stribeck', 'none', got 'bogus'"):
        L.law_named("bogus")
    with pytest.raises(ValueError, match=r"law must be one of the law codes .*got 7\.0"):
        L.law_coded(7.0)
    with pytest.raises(ValueError, match=r"law must be one of the law codes .*got 1\.5"):
        L.law_coded(1.5)
    assert L.law_coded(2.0).name == "viscous"
    with pytest.raises(ValueError, match="area method must be one of"):
        L.check_area("dry", "quadrature")


def test_law_parameters_are_validated_and_bound_from_their_declaration(monkeypatch: pytest.MonkeyPatch) -> None:
    """No shipped law has parameters yet: one is declared here (a friction coefficient, scaled by the normal
    load, and a speed) to check the path a law's parameters take: validation, order, binding."""
    with pytest.raises(ValueError, match=r"friction 'dry' has no parameter 'v_s' \(its parameters: none\)"):
        Friction("dry", 1.0, {"v_s": 0.1})
    with pytest.raises(ValueError, match="friction 'dry' has no parameter 'v_s'"):
        scene_from_params(H=0.2, k=0.05, omega=0.6, v_s=0.1)
    qs = (L.LawParam("mu_s", Limit(0.0, 10.0, "(dimensionless)"), "static coefficient", 0.5, load=True),
          L.LawParam("v_s", Limit(0.0, 1e3, "m/s", lo_open=True), "Stribeck speed", 0.1))
    monkeypatch.setitem(L._BY_NAME, "dry", dataclasses.replace(L._BY_NAME["dry"], params=qs))
    assert L.check_law_params("dry", {"v_s": 0.1, "mu_s": 0.6}) == (("mu_s", 0.6), ("v_s", 0.1))
    with pytest.raises(MissingParameters) as e:
        L.check_law_params("dry", {"mu_s": 0.6})
    assert e.value.names == ["v_s"]
    with pytest.raises(ValueError, match=r"v_s must be in \(0, 1000\] m/s, got -1\.0"):
        L.check_law_params("dry", {"mu_s": 0.6, "v_s": -1.0})
    assert L.bound_params("dry", (("mu_s", 0.5), ("v_s", 0.1)), 2.0)[:2] == (1.0, 0.1)
    fr = Friction("dry", 1.0, {"v_s": 0.1, "mu_s": 0.6})
    assert fr.describe() == {"law": "dry", "coeff": 1.0, "params": {"mu_s": 0.6, "v_s": 0.1}}
    assert Friction(**fr.describe()) == fr
    assert Friction("viscous", 2.0).describe() == {"law": "viscous", "coeff": 2.0}  # as before: no params key


# ---- the five former fallbacks --------------------------------------------------------------------
def test_builder_refuses_a_law_the_plugin_has_no_form_for(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody.engine.scenes.builder mapped every law but viscous to dry friction."""
    from rrbody.engine import attach

    space = pymunk.Space()
    with pytest.raises(ValueError, match="friction must be one of 'dry', 'viscous', 'stribeck', 'none', got 'bogus'"):
        attach(space, _unknown(_free_disk()))
    _restricted(monkeypatch, "viscous", ("point", "sampled"))
    with pytest.raises(ValueError, match=r"friction 'viscous' has no form for the area method 'contact' \(the "
                                         r"engine path integrates"):
        attach(space, _free_disk())
    assert not space.bodies  # refused before anything was added


def test_bind_refuses_an_unknown_law() -> None:
    """rrbody.physics.bind bound every law but dry as viscous friction."""
    from rrbody.physics.bind import friction_per_mass, kernel_params

    for fn in (friction_per_mass, kernel_params):
        with pytest.raises(ValueError, match="friction must be one of .*got 'bogus'"):
            fn(_unknown(_disk(omega=0.6)))


def test_the_contact_method_refuses_a_law_without_its_form(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody.physics.areas.area_contact gave no force for a law other than dry and viscous."""
    from rrbody.physics.bind import kernel_params

    _restricted(monkeypatch, "viscous", ("point", "sampled", "icr", "table"))
    for kw in ({"pressure": "ring:0.05"}, {"friction_method": "contact"}):
        with pytest.raises(ValueError, match=r"friction 'viscous' has no form for the area method 'contact' "
                                             r"\(body 'disk'"):
            kernel_params(_disk(omega=0.6, **kw))
    with pytest.raises(ValueError, match="friction 'viscous' has no form for the area method 'contact'"):
        kernel_params(scene_from_params(body="box", R0=0.1, k=0.5, omega=0.6, friction="viscous"))


def test_the_quadrature_refuses_a_law_without_its_form(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody.physics.icr gave no force for a law other than dry and viscous."""
    from rrbody.physics.area import icr_wrench, sampled_wrench
    from rrbody.physics.bind import kernel_params

    with pytest.raises(ValueError, match="law must be one of .*got 'bogus'"):
        icr_wrench(Disk(R=0.1), 0.0, 1.0, 0.0, 0.0, law="bogus")
    with pytest.raises(ValueError, match="law must be one of .*got 'bogus'"):
        sampled_wrench(Disk(R=0.1), 0.0, 1.0, 0.0, 0.0, law="bogus")
    _restricted(monkeypatch, "viscous", ("point", "sampled", "contact"))
    with pytest.raises(ValueError, match="friction 'viscous' has no form for the area method 'icr'"):
        icr_wrench(Disk(R=0.1), 0.0, 1.0, 0.0, 0.0, law="viscous")
    for method in ("icr", "table"):
        with pytest.raises(ValueError, match=f"friction_method {method!r} does not apply to body 'disk' with "
                                             f"friction 'viscous'"):
            kernel_params(_disk(omega=0.6, friction_method=method))
    p, _ = kernel_params(_disk(omega=0.6))  # "auto" takes a method the law has a form for
    assert int(p[5]) == 2 and int(p[7]) == L.AREA_METHODS.index("sampled")


def test_the_plugin_refuses_a_law_without_its_form(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody.contact.accel evaluated every law but viscous as dry friction."""
    from rrbody.contact import columns
    from rrbody.engine import PlaneFriction
    from rrbody.engine.plugin.shapes import body_footprint
    from rrbody.model.pressure import uniform

    space = pymunk.Space()
    pf = PlaneFriction(space)
    body = pymunk.Body()
    shape = pymunk.Circle(body, 0.1)
    shape.density = 1.0
    space.add(body, shape)
    fp = body_footprint(body, uniform())
    kw = {"coeff": 1.0, "footprint": fp, "snap": True, "history": None}
    with pytest.raises(ValueError,
                       match=r"law must be one of the law codes 1 \(dry\), 2 \(viscous\), 3 \(stribeck\), 0 \(none\), "
                                         r"got 7\.0"):
        pf.add_footprint(body, law=7.0, **kw)
    with pytest.raises(ValueError, match=r"coeff must be 0 for friction 'none'"):
        pf.add_footprint(body, law=columns.LAW_NONE, **kw)
    with pytest.raises(ValueError, match=r"params must be 0 numbers for friction 'dry'"):
        pf.add_footprint(body, law=columns.LAW_DRY, params=(0.1,), **kw)
    # pf.add: the law by name, checked before the body is added
    with pytest.raises(ValueError, match="law must be one of 'dry', 'viscous', 'stribeck', 'none', got 'bogus'"):
        pf.add(body, mu=0.4, law="bogus")
    with pytest.raises(ValueError,
                       match=r"law must be one with a friction coefficient mu \('dry', 'stribeck'\) for add, got "
                                         r"'viscous'"):
        pf.add(body, mu=0.4, law="viscous")
    with pytest.raises(ValueError, match="friction 'dry' has no parameter 'v_s'"):
        pf.add(body, mu=0.4, params={"v_s": 0.1})
    _restricted(monkeypatch, "viscous", ("point", "sampled"))
    with pytest.raises(ValueError, match=r"friction 'viscous' has no form for the area method 'contact' \(the "
                                         r"plugin integrates"):
        pf.add_footprint(body, law=columns.LAW_VISCOUS, **kw)
    _restricted(monkeypatch, "dry", ("point", "sampled", "icr", "table"))
    with pytest.raises(ValueError, match=r"friction 'dry' has no form for the area method 'contact' \(add "
                                         r"integrates"):
        pf.add(body, mu=0.4)
    assert pf.members == 0  # nothing was added
    monkeypatch.undo()
    pf.add(body, mu=0.4, law="dry", params={})  # dry friction: the plugin's own
    assert pf.rows[0][columns.LAW] == columns.LAW_DRY


def test_every_declared_form_exists_in_the_kernels() -> None:
    """The table's other half: each law has a nonzero wrench by each area method it declares (and "none", whose
    scene binds no friction, a zero one), so no declared combination falls through a kernel's final branch."""
    from rrbody.physics.bind import kernel_params
    from rrbody.physics.wrench import body_wrench

    for law in L.LAW_TABLE:
        for method in (m for m in FRICTION_METHODS[1:] if m in law.areas):
            ex = {q.name: q.example for q in law.params}
            sc = _disk(law.name, omega=0.6, friction_method=method, samples=64, **ex) if law.name != "none" else \
                scene_from_params(body="disk", R0=0.1, omega=0.6, friction="none", friction_method=method)
            p, S = kernel_params(sc)
            f = body_wrench(p, S, 0.3, 0.2, -0.1, 1.5)
            assert all(map(math.isfinite, f)), (law.name, method)
            assert (np.hypot(f[0], f[1]) > 0.0) == (law.name != "none"), (law.name, method, f)
