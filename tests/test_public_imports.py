"""The public surface: every name and sub-module ``import rrbody`` offers is reachable both as an attribute
and by an import statement, the two give the same object, and ``import rrbody`` alone stays cheap.

Each check runs in a fresh interpreter, so that what one import loaded cannot help another.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: what ``import rrbody`` must not load: the compiled core's heavy packages and every optional extra
HEAVY = ("numpy", "numba", "scipy", "pymunk", "matplotlib", "rerun", "xarray", "mujoco", "dask", "distributed",
         "imageio", "imageio_ffmpeg", "pyarrow")


def _python(code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "RRBODY_WORKER": "off"}
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_import_rrbody_loads_nothing_heavy(tmp_path: Path) -> None:
    p = _python(f"""
        import sys, rrbody
        dir(rrbody)
        print(sorted(m for m in sys.modules if m.split(".")[0] in {HEAVY!r}))
        print(sorted(m for m in sys.modules if m.split(".")[0] == "rrbody"))
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    loaded, own = p.stdout.strip().splitlines()
    assert loaded == "[]"
    assert own == "['rrbody', 'rrbody._version']"


@pytest.mark.parametrize("statement,check", [
    ("import rrbody.pressure", "rrbody.pressure.ring(0.04)"),
    ("from rrbody.pressure import ring", "ring(0.04)"),
    ("from rrbody import pressure", "pressure.ring(0.04)"),
    ("import rrbody", "rrbody.pressure.ring(0.04)"),
    ("import rrbody.planar", "rrbody.planar.Footprints([rrbody.planar.circle(0.1)])"),
    ("from rrbody.planar import Footprints, circle", "Footprints([circle(0.1)])"),
    ("from rrbody import planar", "planar.Footprints([planar.box(0.2, 0.1)])"),
    ("import rrbody", "rrbody.planar.Footprints([rrbody.planar.circle(0.1)])"),
    ("import rrbody", "rrbody.plugin.PlaneFriction and rrbody.plugin.Recorder and rrbody.plugin.Active"),
    ("import rrbody.plugin", "rrbody.plugin.Active(force=1.0)"),
    ("from rrbody import Active, Recorder, PlaneFriction", "Active(force=1.0) and Recorder and PlaneFriction"),
    ("from rrbody import plugin", "plugin.PlaneFriction"),
    ("import rrbody", "rrbody.mujoco.PlaneFriction"),
    ("from rrbody import mujoco", "mujoco.PlaneFriction"),
    ("from rrbody.mujoco import PlaneFriction", "PlaneFriction"),
])
def test_every_documented_import_form_works(tmp_path: Path, statement: str, check: str) -> None:
    p = _python(f"{statement}\nassert {check}\n", tmp_path)
    assert p.returncode == 0, f"{statement}; {check}\n{p.stderr[-1500:]}"


def test_attribute_and_import_give_the_same_objects(tmp_path: Path) -> None:
    p = _python("""
        import json, sys, importlib
        import rrbody
        same = {}
        for name in ("pressure", "planar", "plugin", "mujoco"):
            attr = getattr(rrbody, name)
            same[name] = attr is importlib.import_module("rrbody." + name) is sys.modules["rrbody." + name]
        from rrbody import plugin
        for name in plugin.__all__:  # the plugin's three names are rrbody's too
            same[name] = getattr(rrbody, name) is getattr(plugin, name)
        missing = [n for n in dir(rrbody) if n != "__version__" and getattr(rrbody, n, None) is None]
        print(json.dumps({"same": same, "missing": missing, "dir": dir(rrbody)}))
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["same"] == {n: True for n in ("pressure", "planar", "plugin", "mujoco", "PlaneFriction", "Recorder",
                                             "Active")}
    assert out["missing"] == []
    assert {"pressure", "planar", "plugin", "mujoco", "Active", "Recorder", "simulate"} <= set(out["dir"])


def test_an_unknown_name_is_an_attribute_error() -> None:
    import rrbody

    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        rrbody.nonesuch  # noqa: B018
    assert not hasattr(rrbody, "Nonesuch")


def test_the_public_modules_export_what_their_sources_do() -> None:
    import rrbody.planar
    import rrbody.pressure
    from rrbody.model import pressure as model_pressure
    from rrbody.physics import planar as physics_planar

    for public, source in ((rrbody.pressure, model_pressure), (rrbody.planar, physics_planar)):
        assert sorted(public.__all__) == sorted(source.__all__)
        for name in public.__all__:
            assert getattr(public, name) is getattr(source, name), name


def test_without_the_extras_attributes_and_imports_still_agree(tmp_path: Path) -> None:
    """Where pymunk and MuJoCo are absent: ``rrbody.plugin`` and its names are reachable (pymunk is needed
    only to make a space), and ``rrbody.mujoco`` raises the ImportError naming its extra, as ``import
    rrbody.mujoco`` does, never an AttributeError."""
    p = _python("""
        import importlib.abc, sys
        class _Absent(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in ("pymunk", "mujoco"):
                    raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        sys.meta_path.insert(0, _Absent())
        import rrbody
        from rrbody import Active, PlaneFriction
        print(rrbody.plugin.Active is Active, rrbody.plugin.PlaneFriction is PlaneFriction)
        for use in (lambda: rrbody.mujoco, lambda: __import__("rrbody.mujoco")):
            try:
                use()
            except AttributeError as e:
                print("AttributeError", e)
            except ImportError as e:
                print("ImportError", e)
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    assert lines[0] == "True True"
    assert len(lines) == 3
    for line in lines[1:]:
        assert line.startswith("ImportError") and "'mujoco'" in line and "[mujoco]" in line, line
