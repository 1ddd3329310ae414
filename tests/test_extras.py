"""Optional extras: the core computes without pymunk, matplotlib, rerun, xarray; a missing extra is one line
naming it, exit 2, nothing written.

The fast tests run rrbody in a subprocess whose import system refuses the optional packages (as if they
were not installed). The real install of the core alone, in a fresh virtual environment, is in
``tests/test_install.py``.
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
OPTIONAL = ("pymunk", "matplotlib", "rerun", "xarray", "imageio", "imageio_ffmpeg", "dask", "pyarrow", "gymnasium")

#: a subprocess prelude: importing any optional package raises ModuleNotFoundError, as when it is absent
BLOCK = textwrap.dedent(f"""
    import importlib.abc, sys
    class _Absent(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in {OPTIONAL!r}:
                raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
            return None
    sys.meta_path.insert(0, _Absent())
""")


def _run(code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "RRBODY_WORKER": "off", "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=600)


def test_core_computes_without_optional_packages(tmp_path: Path) -> None:
    code = BLOCK + f"OPTIONAL = {OPTIONAL!r}\n" + textwrap.dedent("""
        import json, sys
        import rrbody
        from rrbody import flip_time, rod_mass_scene, simulate
        r = flip_time(rod_mass_scene(0.2, 0.05, 0.6))
        traj = simulate(rod_mass_scene(0.2, 0.05, 0.6), t_max=5.0)
        traj.save("t.csv")
        from rrbody.cli.main import main
        code = main(["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"])
        print(json.dumps({"t_f": r.t_f, "code": code,
                          "loaded": sorted(m for m in sys.modules if m.split(".")[0] in OPTIONAL)}))
    """)
    p = _run(code, tmp_path)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["code"] == 0 and out["loaded"] == []
    assert out["t_f"] == pytest.approx(12.928094823, abs=1e-8)  # docs/cli.md's number (ODE path, default rtol)
    assert (tmp_path / "t.csv").exists()


def test_import_rrbody_imports_no_optional_package(tmp_path: Path) -> None:
    """Even where the extras are installed, importing rrbody (and its CLI parser) loads none of them."""
    code = ("import sys, rrbody, rrbody.cli, rrbody.render, rrbody.model.extras\n"
            "rrbody.cli.build_parser()\n"
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {OPTIONAL!r}))")
    p = _run(code, tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "[]"


@pytest.mark.parametrize("args,extra", [
    (["--movie", "m.mp4"], "movie"),
    (["--rerun", "r.rrd"], "rerun"),
    (["--method", "engine", "--out", "o.csv"], "engine"),
])
def test_missing_extra_is_one_line_exit_2_and_writes_nothing(tmp_path: Path, args: list[str], extra: str) -> None:
    out = [] if "--out" in args else ["--out", "o.csv"]  # every option given once (repeats are an error)
    argv = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "2", *out, *args]
    code = BLOCK + f"from rrbody.cli.main import main\nraise SystemExit(main({argv!r}))"
    p = _run(code, tmp_path)
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in p.stderr
    # run from this checkout (PYTHONPATH), so the hint is the checkout's editable install, naming its folder
    assert f"pip install -e '.[{extra}]' (run in {ROOT})" in lines[0]
    assert sorted(x.name for x in tmp_path.iterdir()) == []  # no CSV, movie or recording, no temporary file


def _package_in(root: Path, pyproject: str | None) -> Path:
    """A fake ``rrbody`` package folder under ``root``, beside a pyproject.toml holding ``pyproject``."""
    pkg = root / "rrbody"
    pkg.mkdir(parents=True)
    if pyproject is not None:
        (root / "pyproject.toml").write_text(pyproject)
    return pkg


def test_install_hint_from_a_checkout_names_the_editable_install_and_its_folder(tmp_path: Path) -> None:
    from rrbody.model.extras import install_hint

    pkg = _package_in(tmp_path / "clone", '[project]\nname = "rrbody"\nversion = "0.1.0"\n')
    hint = install_hint("rerun", pkg)
    assert hint == f"pip install -e '.[rerun]' (run in {tmp_path / 'clone'})"
    assert "rrbody[" not in hint


@pytest.mark.parametrize("pyproject", [
    None,                                          # site-packages: no pyproject.toml beside the package
    '[project]\nname = "someone-else"\n',          # another project's checkout that vendors rrbody
    "this is [not toml",                           # unreadable: never guess a checkout
])
def test_install_hint_of_an_installed_package_names_the_package(tmp_path: Path, pyproject: str | None) -> None:
    from rrbody.model.extras import install_hint

    pkg = _package_in(tmp_path / "site-packages", pyproject)
    assert install_hint("rerun", pkg) == "pip install 'rrbody[rerun]'"
