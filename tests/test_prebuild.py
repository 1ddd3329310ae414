"""Kernels compiled once, ahead of use (docs/compile.md): after the install's compilation
(``python -m rrbody.cli.prebuild``), the commands a user runs compile nothing, whatever combination
of effects and numbers they ask for; the compiled code depends only on the kind of system and the
friction law. The first use copies the install's kernels into the cache folder, once, atomically.

"Compiles nothing" is read from numba itself: with ``NUMBA_DEBUG_CACHE=1`` numba prints a line
``[cache] data saved to ...`` for every function it compiles and saves; none may appear."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from rrbody import _cache

ROOT = Path(__file__).resolve().parents[1]

#: user commands, with other numbers and other combinations of effects than the prebuild's workload
#: (rrbody.cli.prebuild.COMMANDS): each must find every kernel it needs
FRESH_COMMANDS: tuple[list[str], ...] = (
    ["simulate", "--body", "ellipse", "--R0", "0.2", "--delta", "0.3", "--no-drive", "--v0", "0.5,0.2", "--mu", "0.4",
     "--pressure", "hertz:0.1", "--tilt", "20deg", "--downhill", "1", "--t-max", "0.3", "--json"],
    ["flip-time", "--H", "0.35", "--k", "0.02", "--omega", "1.3", "--json"],
    ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--friction", "viscous", "--json"],
    ["flip-time", "--H", "0.2", "--k", "1e4", "--omega", "0.6", "--json"],
    ["simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.9", "--l", "0.2", "--k", "0.0033", "--omega",
     "0.6", "--t-max", "3", "--json"],
    ["simulate", "--body", "disk", "--R0", "0.2", "--l", "0.1", "--omega", "0.8", "--k", "0.3", "--friction",
     "viscous", "--friction-method", "icr", "--t-max", "1", "--json"],
    ["simulate", "--body", "ellipse", "--R0", "0.2", "--delta", "0.5", "--no-drive", "--v0", "0.5,0.2", "--spin0",
     "-4", "--k", "2", "--friction-method", "sampled", "--samples", "128", "--t-max", "2", "--json"],
    ["simulate", "--H", "0.3", "--k", "0.1", "--omega", "0.5", "--method", "engine", "--t-max", "1", "--json"],
)


def _kernels(tmp_path: Path) -> Path:
    """The install's kernels for these sources; compiled here (a minute or two) if the checkout has
    none for them (sources edited since the install)."""
    shipped = _cache.shipped_kernels_dir()
    if shipped.is_dir():
        return shipped
    out = tmp_path / "built"
    subprocess.run([sys.executable, "-m", "rrbody.cli.prebuild", "--into", str(out)], check=True, cwd=ROOT,
                   capture_output=True, timeout=1800)
    return out / _cache.kernels_dir().name


#: one process runs every command of FRESH_COMMANDS (rrbody.cli.main.main, what `rrbody` runs), then a
#: program: a marker line before each names what runs, so that numba's lines can be told apart
_ALL_IN_ONE = """
import json, sys
from rrbody.cli.main import main
for argv in json.loads(sys.argv[1]):
    print("### rrbody " + " ".join(argv), flush=True)
    print("### exit", main(argv), flush=True)
print("### program", flush=True)
exec(sys.argv[2])
"""


def _saved(commands: tuple[list[str], ...], program: str, cache: Path, cwd: Path) -> tuple[dict[str, list[str]],
                                                                                          list[str]]:
    """The lines in which numba reports compiling and saving a function, under the marker of what ran
    (each command, its exit status, the program), and the commands' exit statuses."""
    env = {**os.environ, _cache.ENV: str(cache), "NUMBA_DEBUG_CACHE": "1", "MPLBACKEND": "Agg"}
    p = subprocess.run([sys.executable, "-c", _ALL_IN_ONE, json.dumps(list(commands)), program], env=env, cwd=cwd,
                       capture_output=True, text=True, timeout=1800)
    assert p.returncode == 0, p.stderr[-2000:]
    saved: dict[str, list[str]] = {"start-up": []}
    exits = []
    now = "start-up"
    for line in p.stdout.splitlines():
        if line.startswith("### exit "):
            exits.append(line[len("### exit "):])
        if line.startswith("### "):
            now = line[4:]
            saved.setdefault(now, [])
        elif "data saved" in line:
            saved[now].append(line)
    return saved, exits


@pytest.mark.slow
def test_user_commands_compile_nothing_after_the_prebuild(tmp_path: Path) -> None:
    """Every command of FRESH_COMMANDS, and a plugin program, from a cache seeded with the install's
    kernels: not one function compiled (the area method, the numbers and the stepper are run-time
    choices; the laws and kinds were all compiled at install). One process runs them all, one after
    another: a function any of them compiled would be saved, and reported, the first time it is needed,
    as in a process of its own; a process start each (~1 s) would test nothing more."""
    from benchmarks.coldstart import PLUGIN_PROGRAM

    cache = tmp_path / "cache"
    shutil.copytree(_kernels(tmp_path), cache / "kernels" / _cache.kernels_dir().name)
    # the plugin program, then a Recorder's capture (the plugin program alone runs as its first part)
    filmed = PLUGIN_PROGRAM + "\nfrom rrbody.plugin import Recorder\nRecorder(space, pf).capture()\n"
    saved, exits = _saved(FRESH_COMMANDS, filmed, cache, tmp_path)
    assert exits == ["0"] * len(FRESH_COMMANDS)
    assert [k for k in saved if k.startswith("rrbody ")] == [f"rrbody {' '.join(a)}" for a in FRESH_COMMANDS]
    assert "program" in saved
    assert {k: v for k, v in saved.items() if v} == {}


def test_first_use_seeds_the_cache_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """seed_kernels copies the install's folder into an absent cache folder, byte for byte, if the
    numba that compiled it is this one, and never over one that exists (numba's own, or another
    process's seed)."""
    pkg = tmp_path / "pkg"
    monkeypatch.setattr(_cache, "_PKG", pkg)
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))
    shipped = _cache.shipped_kernels_dir()
    assert shipped == pkg / "_kernels" / f"{_cache.__version__}-abc"
    assert _cache.seed_kernels() is False  # nothing shipped: nothing to do
    (shipped / "physics").mkdir(parents=True)
    (shipped / "physics" / "dynamics.rhs-90.py311.nbi").write_bytes(b"index")
    import json

    import numba

    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": "0.0.1"}))
    with pytest.warns(RuntimeWarning, match="compiled at install by numba 0.0.1, this is numba"):
        assert _cache.seed_kernels() is False  # another numba's kernels: never copied, and said so
    assert not _cache.kernels_dir().exists()
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    assert _cache.seed_kernels() is True
    target = _cache.kernels_dir()
    assert (target / "physics" / "dynamics.rhs-90.py311.nbi").read_bytes() == b"index"
    (target / "physics" / "dynamics.rhs-90.py311.nbi").write_bytes(b"numba's own")
    assert _cache.seed_kernels() is False  # the folder exists: left alone
    assert (target / "physics" / "dynamics.rhs-90.py311.nbi").read_bytes() == b"numba's own"
    assert not list(target.parent.glob(".seed-*"))  # no temporary copy left behind


def test_a_folder_numba_began_is_completed_from_the_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A source tree used before its prebuild finished leaves a kernel folder numba began: seeding
    then adds every function it lacks (index and data), keeps the ones numba compiled there, and marks
    the folder complete so later processes do nothing."""
    import json

    import numba

    monkeypatch.setattr(_cache, "_PKG", tmp_path / "pkg")
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))
    shipped = _cache.shipped_kernels_dir()
    (shipped / "physics").mkdir(parents=True)
    for name, data in (("f-1.py311.nbi", b"shipped f"), ("f-1.py311.0.nbc", b"shipped f0"),
                       ("g-9.py311.nbi", b"shipped g"), ("g-9.py311.0.nbc", b"shipped g0"),
                       ("g-9.py311.1.nbc", b"shipped g1")):
        (shipped / "physics" / name).write_bytes(data)
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    target = _cache.kernels_dir()
    (target / "physics").mkdir(parents=True)
    (target / "physics" / "f-1.py311.nbi").write_bytes(b"local f")
    (target / "physics" / "f-1.py311.0.nbc").write_bytes(b"local f0")
    assert _cache.seed_kernels() is True
    got = {f.name: f.read_bytes() for f in (target / "physics").iterdir()}
    assert got == {"f-1.py311.nbi": b"local f", "f-1.py311.0.nbc": b"local f0", "g-9.py311.nbi": b"shipped g",
                   "g-9.py311.0.nbc": b"shipped g0", "g-9.py311.1.nbc": b"shipped g1"}
    assert (target / _cache.BUILD_FILE).exists()
    assert _cache.seed_kernels() is False  # complete: nothing more to do


def test_no_seed_under_a_forced_build(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``prebuild --force`` must compile: its jobs run with RRBODY_NO_SEED, and seeding then copies nothing."""
    import json

    import numba

    monkeypatch.setattr(_cache, "_PKG", tmp_path / "pkg")
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))
    shipped = _cache.shipped_kernels_dir()
    shipped.mkdir(parents=True)
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    monkeypatch.setenv(_cache.NO_SEED, "1")
    assert _cache.seed_kernels() is False and not _cache.kernels_dir().exists()
    monkeypatch.delenv(_cache.NO_SEED)
    assert _cache.seed_kernels() is True


def test_a_wheel_build_copies_the_source_trees_kernels(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Building into another folder (a wheel's) when the source tree already holds these sources'
    kernels, compiled by this numba, copies them (no job runs) and replaces other sources' folders
    there; kernels of another numba are not copied (the build would compile: not run here)."""
    import json

    import numba

    from rrbody.cli import prebuild

    monkeypatch.setattr(_cache, "_PKG", tmp_path / "tree")
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    mine = _cache.shipped_kernels_dir()
    (mine / "physics").mkdir(parents=True)
    (mine / "physics" / "f.nbi").write_bytes(b"index")
    (mine / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    into = tmp_path / "wheel" / "_kernels"
    (into / "0.0.0-old").mkdir(parents=True)

    def no_jobs(*args: object, **kwargs: object) -> None:
        raise AssertionError("a job ran: the kernels were compiled, not copied")

    monkeypatch.setattr(prebuild, "_run_jobs", no_jobs)
    got = prebuild.build(into, quiet=True)
    assert got == into / mine.name and (got / "physics" / "f.nbi").read_bytes() == b"index"
    assert sorted(p.name for p in into.iterdir()) == [mine.name]
    assert (mine / "physics" / "f.nbi").exists()  # a copy: the tree keeps its own
    (mine / _cache.BUILD_FILE).write_text(json.dumps({"numba": "0.0.1"}))
    shutil.rmtree(into)
    with pytest.raises(AssertionError, match="a job ran"):
        prebuild.build(into, quiet=True)


def test_a_failing_job_stops_the_build_and_names_itself(tmp_path: Path) -> None:
    """The first failure is raised with its command and last line of error; the jobs not yet started
    never run (one at a time here, so the third is never started)."""
    from rrbody.cli.prebuild import _run_jobs

    mark = tmp_path / "ran"
    jobs = [[sys.executable, "-c", "pass"],
            [sys.executable, "-c", "import sys; print('no kernel here', file=sys.stderr); sys.exit(3)"],
            [sys.executable, "-c", f"open({str(mark)!r}, 'w')"]]
    with pytest.raises(RuntimeError, match="exited 3: no kernel here"):
        _run_jobs(jobs, dict(os.environ), str(tmp_path), 1)
    assert not mark.exists()


def test_jobs_is_validated_where_it_enters(tmp_path: Path) -> None:
    """--jobs below 1 or not an integer: exit 2 naming it, nothing built; the function: a ValueError."""
    from rrbody.cli.prebuild import build

    for bad in ("0", "-1", "two"):
        p = subprocess.run([sys.executable, "-m", "rrbody.cli.prebuild", "--jobs", bad, "--into", str(tmp_path / "k")],
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and f"--jobs must be an integer >= 1, got '{bad}'" in p.stderr
    assert not (tmp_path / "k").exists()
    with pytest.raises(ValueError, match=r"jobs must be an integer >= 1 \(processes at a time\), got 0"):
        build(tmp_path / "k", jobs=0)


def test_a_new_combination_of_effects_reuses_the_loop() -> None:
    """The loop, the right-hand side and the start probe are keyed by the compiled code only (a
    driven body's law, or a free body): an area method, a free body's law or a number never makes
    another compiled function."""
    from rrbody.integrate import loop
    from rrbody.physics import dynamics

    assert loop.advance_for(110) is loop.advance_for(10) is loop.advance_for(310)  # area 1, 0, 3; driven, dry
    assert loop.advance_for(11) is not loop.advance_for(10)  # a free body: another kind
    assert loop.advance_for(20) is not loop.advance_for(10)  # viscous: another law
    assert loop.advance_for(11) is loop.advance_for(21) is loop.advance_for(101)  # free: any law, any area
    assert dynamics.rhs_for(210) is dynamics.rhs_for(10)


#: Movie S1's own scene script, run with a few frames (the drawing compiles nothing; its computation is the
#: script's: its body, law, horizon and output grid)
_MOVIE_S1 = """
import sys
from pathlib import Path
from rrbody.cli.scenes import load_scene
s1 = load_scene("movie-s1")
s1.SPEED, s1.HOLD = 400.0, 0.0
s1.main(Path(sys.argv[1]) / "results" / "movie-s1", force=True)
"""


def _numba_log(cmd: list[str], cache: Path, cwd: Path) -> tuple[set[str], list[str]]:
    """(the compiled functions a process loads, each ``FOLDER/FILE.N.nbc``: one overload; the lines in
    which it compiles and saves one), read from numba's own log."""
    env = {**os.environ, _cache.ENV: str(cache), "NUMBA_DEBUG_CACHE": "1", "MPLBACKEND": "Agg"}
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    name = _cache.kernels_dir().name
    loaded = {ln.split(name + "/", 1)[1].rstrip("'") for ln in p.stdout.splitlines() if "data loaded from" in ln}
    return loaded, [ln for ln in p.stdout.splitlines() if "data saved" in ln]


@pytest.mark.slow
def test_the_demo_part_is_what_movie_s1_needs(tmp_path: Path) -> None:
    """``make demo`` compiles only the part demo (rrbody.cli.prebuild.PARTS) before ``rrbody demo``: every
    compiled function Movie S1's own script calls, overload for overload, is one the part calls too (so
    the part compiles it), read from numba's log on the install's kernels; neither compiles anything
    there (the whole build covers the demo's part)."""
    cache = tmp_path / "cache"
    shutil.copytree(_kernels(tmp_path), cache / "kernels" / _cache.kernels_dir().name)
    part, part_saved = _numba_log([sys.executable, "-m", "rrbody.cli.workload", "--movie-s1"], cache, ROOT)
    movie, movie_saved = _numba_log([sys.executable, "-c", _MOVIE_S1, str(tmp_path)], cache, tmp_path)
    assert (tmp_path / "movies" / "movie_s1.mp4").stat().st_size > 0
    assert any("advance" in f or "run" in f for f in movie)  # the stepping loop: the script computed its run
    assert movie <= part, sorted(movie - part)
    assert part_saved == movie_saved == []


def test_the_demo_part_fills_the_cache_folder_only_and_only_where_needed(tmp_path: Path,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """The part demo runs its one job (no second pass) into the user's cache folder and leaves it
    incomplete (no build file: the install's kernels fill it in later); it is refused for a package
    folder, and skipped where every kernel is compiled already (the cache folder complete, or the
    install's kernels of this numba, which a first use copies in)."""
    import json

    import numba

    from rrbody.cli import prebuild
    from rrbody.cli.prebuild import PARTS

    monkeypatch.setattr(_cache, "_PKG", tmp_path / "pkg")
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))
    ran: list[list[str]] = []

    def fake_jobs(jobs: list[list[str]], env: dict[str, str], *args: object, **kwargs: object) -> None:
        ran.extend(jobs)
        (Path(env[_cache.ENV]) / "kernels" / _cache.kernels_dir().name / "integrate").mkdir(parents=True, exist_ok=True)

    monkeypatch.setattr(prebuild, "_run_jobs", fake_jobs)
    with pytest.raises(ValueError, match="part 'demo' compiles into the cache folder only"):
        prebuild.build(tmp_path / "into", part="demo")
    with pytest.raises(ValueError, match="part must be one of all, demo, got 'nope'"):
        prebuild.build(None, part="nope")
    got = prebuild.build(None, quiet=True, part="demo")
    assert got == _cache.kernels_dir() and not (got / _cache.BUILD_FILE).exists()
    assert [cmd[-1] for cmd in ran] == [args[-1] for _, args in PARTS["demo"]] == ["--movie-s1"]
    ran.clear()
    shipped = _cache.shipped_kernels_dir()
    shipped.mkdir(parents=True)
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    assert prebuild.build(None, quiet=True, part="demo") == shipped and ran == []
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": "0.0.1"}))  # another numba's: no help
    prebuild.build(None, quiet=True, part="demo")
    assert len(ran) == 1
    ran.clear()
    (_cache.kernels_dir() / _cache.BUILD_FILE).write_text("{}")
    assert prebuild.build(None, quiet=True, part="demo") == _cache.kernels_dir() and ran == []


def test_a_folder_begun_before_the_install_is_completed_at_the_next_start(tmp_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """A kernel folder that exists but is not complete (``make demo``'s part, or a first use, before the
    install's kernels existed) is completed from them when a process starts, not only on these sources'
    first run; then a start costs one look. Kernels of another numba are said to be useless once, on the
    first run, not at every start."""
    import json
    import warnings

    import numba

    monkeypatch.setattr(_cache, "_PKG", tmp_path / "pkg")
    monkeypatch.setattr(_cache, "source_hash", lambda: "abc")
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "c"))
    target, shipped = _cache.kernels_dir(), _cache.shipped_kernels_dir()
    (target / "integrate").mkdir(parents=True)
    (target / "integrate" / "loop.run-1.py311.nbi").write_bytes(b"the demo's")
    _cache._ready_kernels()  # nothing shipped yet: left as it is
    assert sorted(p.name for p in target.rglob("*")) == ["integrate", "loop.run-1.py311.nbi"]
    (shipped / "integrate").mkdir(parents=True)
    for name in ("loop.run-1.py311.nbi", "plugin.step-2.py311.nbi", "plugin.step-2.py311.1.nbc"):
        (shipped / "integrate" / name).write_bytes(b"shipped")
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": "0.0.1"}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # another numba's kernels: no warning at a later start
        _cache._ready_kernels()
    assert not (target / "integrate" / "plugin.step-2.py311.nbi").exists()
    (shipped / _cache.BUILD_FILE).write_text(json.dumps({"numba": numba.__version__}))
    _cache._ready_kernels()
    got = {p.name: p.read_bytes() for p in (target / "integrate").iterdir()}
    assert got == {"loop.run-1.py311.nbi": b"the demo's", "plugin.step-2.py311.nbi": b"shipped",
                   "plugin.step-2.py311.1.nbc": b"shipped"}
    assert (target / _cache.BUILD_FILE).exists()
    monkeypatch.setattr(_cache, "seed_kernels", lambda: pytest.fail("a complete folder was seeded again"))
    _cache._ready_kernels()


def test_make_demo_compiles_the_demo_part_and_make_test_every_kernel_first(tmp_path: Path) -> None:
    """What the two set-up commands run (make -n: nothing runs): make demo compiles the part demo into
    the cache folder before `rrbody demo` and never the whole; make test compiles every kernel into
    rrbody/_kernels before the suite, which runs on the venv's own cache folder (filled from them)."""
    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    for name in ("Makefile", "pyproject.toml", "rrbody", "scenes"):
        (tmp_path / name).symlink_to(ROOT / name)

    def commands(target: str) -> list[str]:
        p = subprocess.run(["make", "-n", target], cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert p.returncode == 0, p.stderr
        return p.stdout.splitlines()

    demo = commands("demo")
    part = [i for i, c in enumerate(demo) if "rrbody.cli.prebuild --part demo" in c]
    run = [i for i, c in enumerate(demo) if c.endswith("/rrbody demo")]
    assert len(part) == len(run) == 1 and part[0] < run[0]
    assert not any("rrbody.cli.prebuild --into" in c for c in demo)
    test = commands("test")
    whole = [i for i, c in enumerate(test) if c.endswith("rrbody.cli.prebuild --into rrbody/_kernels")]
    suite = [i for i, c in enumerate(test) if "-m pytest" in c and "--dist loadgroup" in c]
    assert len(whole) == len(suite) == 1 and whole[0] < suite[0]
    assert f"RRBODY_CACHE_DIR={tmp_path}/.venv/rrbody-cache " in test[suite[0]]
    assert not any("--part" in c for c in test)
