"""Optional extras: the core computes without pymunk, matplotlib, rerun, xarray; a missing extra is one line
naming it, exit 2, nothing written.

The fast tests run rrbody in a subprocess whose import system refuses the optional packages (as if they
were not installed). The ``install`` test builds a real virtual environment with only the core
dependencies and ``pip install --no-deps .`` (about a minute: pip cache, then numba compiles the kernels).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
OPTIONAL = ("pymunk", "matplotlib", "rerun", "xarray", "imageio", "imageio_ffmpeg", "dask", "pyarrow")

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
    code = BLOCK + textwrap.dedent("""
        import json, sys
        import rrbody
        from rrbody import flip_time, rod_mass_scene, simulate
        r = flip_time(rod_mass_scene(0.2, 0.05, 0.6))
        traj = simulate(rod_mass_scene(0.2, 0.05, 0.6), t_max=5.0)
        traj.save("t.csv")
        from rrbody.cli.main import main
        code = main(["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"])
        print(json.dumps({"t_f": r.t_f, "code": code,
                          "loaded": sorted(m for m in sys.modules if m.split(".")[0] in %r)}))
    """ % (OPTIONAL,))
    p = _run(code, tmp_path)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["code"] == 0 and out["loaded"] == []
    assert out["t_f"] == pytest.approx(12.928094823, abs=1e-8)  # the README's number (ODE path, default rtol)
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
    assert f"pip install 'rrbody[{extra}]'" in lines[0]
    assert sorted(x.name for x in tmp_path.iterdir()) == []  # no CSV, movie or recording, no temporary file


@pytest.mark.install
@pytest.mark.slow
def test_fresh_core_install(tmp_path: Path) -> None:
    """A real `pip install .` without extras: flip time works, optional packages are absent, a movie asks for [movie]."""
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    pip = [str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["RRBODY_WORKER"] = "off"
    deps = subprocess.run([*pip, "numpy>=1.26", "scipy>=1.11", "numba>=0.59", "tqdm>=4.66"], env=env,
                          capture_output=True, text=True, timeout=900)
    if deps.returncode != 0:
        pytest.skip(f"could not install the core dependencies here: {deps.stderr.strip()[-300:]}")
    inst = subprocess.run([*pip, "--no-deps", str(ROOT)], env=env, capture_output=True, text=True, timeout=900)
    assert inst.returncode == 0, inst.stderr
    work = tmp_path / "work"
    work.mkdir()
    code = textwrap.dedent(f"""
        import importlib.util, json
        from rrbody import flip_time, rod_mass_scene
        absent = [m for m in {OPTIONAL!r} if importlib.util.find_spec(m) is None]
        print(json.dumps({{"t_f": flip_time(rod_mass_scene(0.2, 0.05, 0.6)).t_f, "absent": absent}}))
    """)
    p = subprocess.run([str(py), "-c", code], cwd=work, env=env, capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["t_f"] == pytest.approx(12.928094823, abs=1e-8)
    assert set(out["absent"]) >= {"pymunk", "matplotlib", "rerun", "xarray"}
    cli = env_dir / "bin" / "rrbody"
    m = subprocess.run([str(cli), "simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "2",
                        "--movie", "m.mp4"], cwd=work, env=env, capture_output=True, text=True, timeout=900)
    assert m.returncode == 2 and m.stderr.strip().count("\n") == 0
    assert "pip install 'rrbody[movie]'" in m.stderr and not (work / "m.mp4").exists()
