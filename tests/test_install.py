"""rrbody installed like any package: the wheel carries every package and the scene scripts, and
rrbody writes nothing inside its installed folder (caches live in one user cache folder).

The ``install`` test builds a real virtual environment, installs rrbody with ``pip install .``
(not editable; through uv's ``uv pip install .`` when the suite's environment has the uv the
Makefile installs, else pip itself) and runs, from an empty folder, what a new user runs first: the scene list, a
scene, a flip time, an ellipse simulation and the plugin. The install compiles every kernel into the
package (setup.py), and the first flip time compiles nothing. Then the installed folder must be
byte-for-byte what pip put there, and the kernels must sit in the cache folder."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import textwrap
import tomllib
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_wheel_lists_every_package() -> None:
    """pyproject lists the packages by hand (to map scenes/ into the wheel): the list must be complete."""
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    on_disk = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "rrbody").rglob("__init__.py")
               if "__pycache__" not in p.parts}
    assert set(conf["packages"]) == on_disk | {"rrbody._scenes"}
    assert conf["package-dir"] == {"rrbody._scenes": "scenes"}


def test_cache_folder_follows_the_environment(tmp_path: Path) -> None:
    """RRBODY_CACHE_DIR moves every cache; `rrbody cache clear` removes what rrbody wrote there; kernels are keyed
    by the sources."""
    env = {**os.environ, "RRBODY_CACHE_DIR": str(tmp_path / "c")}
    code = ("from rrbody._cache import kernels_dir, tables_dir, source_hash; import rrbody;"
            "print(kernels_dir()); print(tables_dir()); print(source_hash())")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    kern, tables, digest = out.stdout.split()
    assert Path(kern).parent == tmp_path / "c" / "kernels" and Path(kern).name.endswith(digest)
    assert Path(tables) == tmp_path / "c" / "tables"
    (tmp_path / "c" / "tables").mkdir(parents=True)
    (tmp_path / "c" / "tables" / "x.npz").write_bytes(b"0" * 10)
    (Path(kern) / "tables").mkdir(parents=True)  # the plugin's wrench tables: beside these sources' kernels
    (Path(kern) / "tables" / "disk.npz").write_bytes(b"0" * 7)
    rep = subprocess.run([sys.executable, "-m", "rrbody.cli", "cache", "info", "--json"], env=env,
                         capture_output=True, text=True, check=True)
    assert json.loads(rep.stdout)["tables_bytes"] == 10
    assert json.loads(rep.stdout)["wrench_tables"] == {"count": 1, "bytes": 7}
    clr = subprocess.run([sys.executable, "-m", "rrbody.cli", "cache", "clear"], env=env, capture_output=True,
                         text=True, check=True)
    assert "cleared" in clr.stdout and not (tmp_path / "c" / "tables").exists()


def test_kernels_of_other_sources_are_never_loaded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The kernel folder is keyed by a hash of the kernels' source files: an edit there (a kernel inlined
    from another file included) or another version gives another folder, so a stale kernel is never
    found; an edit in a layer above the kernels (render) keeps the folder."""
    import shutil

    from rrbody import _cache

    tree = tmp_path / "rrbody"
    shutil.copytree(ROOT / "rrbody", tree, ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    monkeypatch.setattr(_cache, "_PKG", tree)
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))

    def folder() -> Path:
        _cache.source_hash.cache_clear()
        return _cache.kernels_dir()

    first = folder()
    assert folder() == first  # deterministic
    law = tree / "physics" / "effects" / "law_dry.py"
    law.write_text(law.read_text() + "\n# an edit\n")
    edited = folder()
    assert edited != first and edited.parent == first.parent
    drawing = tree / "render" / "mp4.py"
    drawing.write_text(drawing.read_text() + "\n# an edit above the kernels\n")
    assert folder() == edited
    monkeypatch.setattr(_cache, "__version__", "9.9.9")
    assert folder().name.startswith("9.9.9-") and folder() != edited
    _cache.source_hash.cache_clear()


def _installer(py: Path) -> list[str] | None:
    """The command that installs packages into the virtual environment of ``py`` with uv, the
    installer ``make test`` puts beside this interpreter (its version pinned in the Makefile,
    UV_VERSION): PyPI's packages, as pip takes them, laid out from uv's cache, their bytecode compiled
    at install as pip compiles it (a first import then writes nothing inside a package). None: no uv."""
    uv = shutil.which("uv", path=str(Path(sys.executable).parent))
    return None if uv is None else [uv, "pip", "install", "--quiet", "--compile-bytecode", "--python", str(py)]


def _snapshot(folder: Path) -> dict[str, str]:
    return {f.relative_to(folder).as_posix(): hashlib.sha256(f.read_bytes()).hexdigest()
            for f in sorted(folder.rglob("*")) if f.is_file()}


@pytest.mark.install
@pytest.mark.slow
def test_non_editable_install_lists_scenes_and_writes_nothing_inside(tmp_path: Path) -> None:
    """`pip install .` (not editable) into a fresh venv, in two stages. The core alone: a flip time
    works, the optional packages are absent, a movie asks for the [movie] extra. Then with the
    engine and movie extras, from an empty folder: the scene list, a scene, a flip time, an ellipse
    simulation and the plugin; the installed folder stays byte-for-byte what pip put there."""
    from benchmarks.coldstart import PLUGIN_PROGRAM
    from tests.test_extras import OPTIONAL

    env_dir = tmp_path / "venv"
    py = env_dir / "bin" / "python"
    uv = _installer(py)
    venv.EnvBuilder(with_pip=uv is None).create(env_dir)  # a plain venv; pip in it only if it installs
    pip = uv or [str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env.update(RRBODY_WORKER="off", RRBODY_CACHE_DIR=str(tmp_path / "cache"), MPLBACKEND="Agg")
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    got = subprocess.run([*pip, *conf["dependencies"]], env=env, capture_output=True, text=True, timeout=900)
    if got.returncode != 0:
        pytest.skip(f"could not install the core dependencies here: {got.stderr.strip()[-300:]}")
    # built from these sources every time: uv would otherwise reuse a wheel it built from this
    # folder before (its cache keys a folder by pyproject.toml and setup.py, not by the sources)
    fresh = ["--refresh-package", "rrbody"] if uv else []
    inst = subprocess.run([*pip, *fresh, "--no-deps", str(ROOT)], env=env, capture_output=True, text=True,
                          timeout=900)
    assert inst.returncode == 0, inst.stderr
    site = Path(subprocess.run([str(py), "-c", "import rrbody, pathlib; print(pathlib.Path(rrbody.__file__).parent)"],
                               env=env, capture_output=True, text=True, check=True, cwd=tmp_path).stdout.strip())
    assert site.is_relative_to(env_dir)  # the installed copy, not the checkout
    # the build compiled every kernel into the package (setup.py, rrbody.cli.prebuild)
    assert any((site / "_kernels").glob("*/integrate/*.nbi")), "no kernels compiled at install"
    before = _snapshot(site)  # as pip put it
    work = tmp_path / "work"
    work.mkdir()
    bin_ = env_dir / "bin"

    def run(*argv: str, code: int = 0) -> subprocess.CompletedProcess[str]:
        p = subprocess.run([str(bin_ / "rrbody"), *argv], cwd=work, env=env, capture_output=True, text=True,
                           timeout=900)
        assert p.returncode == code, (argv, p.stderr)
        return p

    # 1. the core alone
    core = textwrap.dedent(f"""
        import importlib.util, json
        from rrbody import flip_time, rod_mass_scene
        absent = [m for m in {OPTIONAL!r} if importlib.util.find_spec(m) is None]
        print(json.dumps({{"t_f": flip_time(rod_mass_scene(0.2, 0.05, 0.6)).t_f, "absent": absent}}))
    """)
    p = subprocess.run([str(py), "-c", core], cwd=work, env={**env, "NUMBA_DEBUG_CACHE": "1"}, capture_output=True,
                       text=True, timeout=900)
    assert p.returncode == 0, p.stderr
    # the first flip time of a fresh install loads the install's kernels: numba compiles (and saves) nothing
    assert [line for line in p.stdout.splitlines() if "data saved" in line] == []
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["t_f"] == pytest.approx(12.928094823, abs=1e-8)  # docs/cli.md's pinned value
    assert set(out["absent"]) >= {"pymunk", "matplotlib", "rerun", "xarray"}
    m = run("simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "2", "--movie", "m.mp4", code=2)
    assert m.stderr.strip().count("\n") == 0 and not (work / "m.mp4").exists()
    assert "pip install 'rrbody[movie]'" in m.stderr  # an installed package: the index's name, not a checkout's

    # 2. with the engine and movie extras
    extras = [*conf["optional-dependencies"]["engine"], *conf["optional-dependencies"]["movie"]]
    got = subprocess.run([*pip, *extras], env=env, capture_output=True, text=True, timeout=900)
    if got.returncode != 0:
        pytest.skip(f"could not install the extras here: {got.stderr.strip()[-300:]}")
    listed = [line.split()[0] for line in run("scene", "--list").stdout.splitlines() if line.strip()]
    expected = sorted(f.stem.replace("_", "-") for f in (ROOT / "scenes").glob("*.py") if not f.name.startswith("_"))
    assert listed == expected
    run("scene", "schematic")  # a scene writes under the current folder, never the package
    assert (work / "results" / "schematic" / "schematic.png").is_file()
    t_f = json.loads(run("flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json").stdout)["t_f"]
    assert t_f == pytest.approx(12.928094823, abs=1e-8)
    run("simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.9", "--l", "0.2", "--k", "0.0033",
        "--omega", "0.6", "--t-max", "2", "--out", "e.csv")
    p = subprocess.run([str(py), "-c", PLUGIN_PROGRAM], cwd=work, env=env, capture_output=True, text=True,
                       timeout=900)
    assert p.returncode == 0, p.stderr
    assert _snapshot(site) == before  # nothing written inside the installed package
    assert any((tmp_path / "cache" / "kernels").rglob("*.nbi"))  # the kernels went to the cache folder
    assert any((tmp_path / "cache" / "tables").glob("*.npz"))


def readme_plugin_program(movie: bool) -> str:
    """The README's ``rrbody.plugin`` example, as the README has it now; without its poster and movie
    lines when the environment has no movie extra."""
    from tests.test_readme import snippets

    code = next(c for lang, c in snippets((ROOT / "README.md").read_text())
                if lang == "python" and "from rrbody.plugin import" in c)
    return code if movie else "\n".join(line for line in code.splitlines()
                                         if not line.startswith(("rec.movie(", "rec.poster(")))


@pytest.mark.install
@pytest.mark.slow
def test_the_engine_extra_installs_beside_gym_pusht(tmp_path: Path) -> None:
    """`pip install '.[engine]' gym-pusht` in a fresh venv resolves (gym-pusht pins pymunk < 7: a
    pymunk 6) and there the README's plugin example runs and the plugin's exact references hold
    (tests/test_plugin_io.py, run against the installed package: every route to the bodies, bit for
    bit). Installed as pip installs it: where this checkout holds its kernels compiled by the numba the
    build runs (``make test`` compiles them first), the wheel gets a copy (rrbody.cli.prebuild) and the
    first use loads them; elsewhere the build compiles every kernel (as the test above checks)."""
    env_dir = tmp_path / "venv"
    py = env_dir / "bin" / "python"
    uv = _installer(py)
    venv.EnvBuilder(with_pip=uv is None).create(env_dir)
    pip = uv or [str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env.update(RRBODY_WORKER="off", RRBODY_CACHE_DIR=str(tmp_path / "cache"), MPLBACKEND="Agg")
    env.pop("RRBODY_BUILD_KERNELS", None)
    test_reqs = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]["test"]
    fresh = ["--refresh-package", "rrbody"] if uv else []
    got = subprocess.run([*pip, *fresh, f"{ROOT}[engine]", "gym-pusht", *test_reqs], env=env, capture_output=True,
                         text=True, timeout=900)
    if got.returncode != 0 and "resolv" not in got.stderr.lower() and "conflict" not in got.stderr.lower():
        pytest.skip(f"could not install the packages here: {got.stderr.strip()[-300:]}")
    assert got.returncode == 0, got.stderr  # a resolution failure is this test's failure
    work = tmp_path / "work"
    work.mkdir()
    shutil.copy(ROOT / "tests" / "test_plugin_io.py", work)  # not the checkout's tests/: its rrbody would shadow
    probe = ("import importlib.metadata as m, importlib.util as u, pathlib, rrbody; "
             "print(m.version('pymunk'), all(u.find_spec(p) for p in ('matplotlib', 'imageio', 'imageio_ffmpeg')), "
             "pathlib.Path(rrbody.__file__).parent)")  # the movie extra's packages, all of them
    out = subprocess.run([str(py), "-c", probe], cwd=work, env=env, capture_output=True, text=True, check=True)
    version, movie, site = out.stdout.split()
    assert version.startswith("6.") and Path(site).is_relative_to(env_dir), out.stdout  # gym-pusht's pymunk 6
    p = subprocess.run([str(py), "-c", readme_plugin_program(movie == "True")], cwd=work, env=env,
                       capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stderr
    t = subprocess.run([str(py), "-m", "pytest", "-q", "-p", "no:cacheprovider", "test_plugin_io.py"], cwd=work,
                       env=env, capture_output=True, text=True, timeout=1800)
    assert t.returncode == 0 and " passed" in t.stdout and "failed" not in t.stdout, t.stdout[-2000:]
