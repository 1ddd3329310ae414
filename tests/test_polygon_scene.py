"""The polygon scene: its convention, and a tiny version of its H_c construction (fast: no scene run)."""

from __future__ import annotations

import ast
import importlib.util
import math

import numpy as np

from rrbody.analysis.flip import critical_h_of, frictionless_critical_h
from rrbody.analysis.simulate import simulate
from rrbody.cli.scenes import list_scenes, scenes_dir
from rrbody.model.scene import rod_mass_scene

PATH = scenes_dir() / "polygon.py"


def _scene_module():
    spec = importlib.util.spec_from_file_location("rrbody_scene_polygon_test", PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_polygon_scene_follows_the_convention() -> None:
    assert "polygon" in [n for n, _ in list_scenes()]
    tree = ast.parse(PATH.read_text())
    first = (ast.get_docstring(tree) or "").splitlines()[0]
    assert first.startswith("Polygons: t_f(omega) and H_c(k)") and "no paper figure" in first
    mains = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "main"]
    assert len(mains) == 1
    args = mains[0].args
    assert [a.arg for a in args.args] == ["out_dir"] and [a.arg for a in args.kwonlyargs] == ["force"]
    assert any(isinstance(n, ast.If) and "__main__" in ast.unparse(n.test) for n in tree.body)


def test_scene_bodies_have_equal_areas_and_the_pivot_inside() -> None:
    mod = _scene_module()
    for name, b in mod.BODIES.items():
        body = mod.hc_family(b, 0.0)(0.5).body
        assert math.isclose(body.area, math.pi * 0.01, rel_tol=1e-12), name
        assert body.pivot_inside and body.l == 0.05, name


def test_frictionless_square_obeys_the_rod_mass_pendulum_and_has_its_Hc() -> None:
    """Without friction the driven body's phi obeys the rod-mass equation with H = I_P / (m d l): phi(t)
    of the scene's square equals the rod mass's at the same H, and the scene's H_c construction (d set
    by H at fixed l) gives the exact H_c(0) = 0.79272623 to the bisection tolerance."""
    mod = _scene_module()
    square_at = mod.hc_family(mod.BODIES["square"], 0.0)
    T = 2 * math.pi / mod.OMEGA_HC
    for H in (0.5, 1.2):
        sq = square_at(H)
        assert math.isclose(sq.H, H, rel_tol=1e-12) and not sq.friction.active
        a = simulate(sq, t_max=T, dt_out=T / 50)
        b = simulate(rod_mass_scene(H, 0.0, mod.OMEGA_HC, friction="none"), t_max=T, dt_out=T / 50)
        assert np.max(np.abs(a.phi - b.phi)) < 1e-10
    tol = 1e-6
    hc = critical_h_of(square_at, tol=tol, H_lo=0.5, H_hi=1.0, n_scan=6)
    assert abs(hc - frictionless_critical_h()) <= tol
    assert abs(frictionless_critical_h() - 0.79272623) < 1e-8
