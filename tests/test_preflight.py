"""Nothing is computed before every output can be written: each command checks each output's writer
(its format, the extra it needs, its folder) before any work, through the real command.

Each case runs ``rrbody`` (its ``main``) in a subprocess whose import system refuses the extra under
test, as if it were not installed, and numba too: every computation in rrbody runs compiled kernels,
so a command that reached its work would stop with a traceback naming numba instead of the one line
naming the extra. The contract checked: exit 2, one line on stderr naming the package and the
install command of its extra, nothing on stdout, nothing written (no checkpoint either).
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


def _prelude(blocked: tuple[str, ...]) -> str:
    return textwrap.dedent(f"""
        import importlib.abc, sys
        class _Absent(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in {blocked!r}:
                    raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
                return None
        sys.meta_path.insert(0, _Absent())
        from pathlib import Path
        import rrbody.cli.scenes
        rrbody.cli.scenes.output_root = lambda: Path.cwd()  # a scene's results/ and movies/ here, not the checkout's
    """)


def _rrbody(argv: list[str], cwd: Path, blocked: tuple[str, ...],
            stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    code = _prelude(blocked) + f"from rrbody.cli.main import main\nraise SystemExit(main({argv!r}))\n"
    env = {**os.environ, "RRBODY_WORKER": "off", "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=300, input=stdin)


ROD = ["--H", "0.2", "--k", "0.05", "--omega", "0.6"]
CASES = [  # (argv, the package refused, its extra)
    (["simulate", *ROD, "--t-max", "2", "--out", "o.csv", "--movie", "m.mp4"], "matplotlib", "movie"),
    (["simulate", *ROD, "--t-max", "2", "--movie", "m.mp4"], "imageio_ffmpeg", "movie"),
    (["simulate", *ROD, "--t-max", "2", "--out", "o.csv", "--rerun", "r.rrd"], "rerun", "rerun"),
    (["simulate", *ROD, "--t-max", "2", "--rerun-spawn"], "rerun", "rerun"),
    (["simulate", *ROD, "--t-max", "2", "--method", "engine", "--out", "o.csv"], "pymunk", "engine"),
    # the newcomer's case: every point was computed, then xarray was missing and a checkpoint stayed
    (["sweep", "--quantity", "flip_time", "--k", "1.5", "--axis", "omega=0.05:1:10", "--axis", "H=0.1:0.8:10",
      "--out", "tf.nc"], "xarray", "data"),
    (["sweep", "--quantity", "chaos", "--H", "0.5", "--friction", "none", "--axis", "tilt=0:1:2", "--axis",
      "omega=0.5:4:2", "--t-max", "20", "--out", "map.csv", "--plot", "map.png"], "matplotlib", "movie"),
    (["sweep", *ROD[:4], "--axis", "omega=0.5,1", "--out", "tf.csv", "--scheduler", "tcp://127.0.0.1:8786"],
     "distributed", "dask"),
    (["lyapunov", *ROD, "--t-max", "20", "--out", "l.csv", "--plot", "l.png"], "matplotlib", "movie"),
    (["poincare", "--H", "0.2", "--omega", "0.6", "--friction", "none", "--points", "5", "--plot", "s.png"],
     "matplotlib", "movie"),
    (["active", "--n", "5", "--t-end", "1", "--out", "a.json"], "pymunk", "engine"),
    (["active", "--n", "5", "--t-end", "1", "--movie", "a.mp4"], "matplotlib", "movie"),
    (["active", "--n", "5", "--t-end", "1", "--rerun", "a.rrd"], "rerun", "rerun"),
    (["active-ensemble", "--n", "5", "--t-end", "1", "--out", "e.csv", "--plot", "e.png"], "matplotlib", "movie"),
    (["active-ensemble", "--n", "5", "--t-end", "1", "--out", "e.json", "--scheduler", "tcp://127.0.0.1:8786"],
     "distributed", "dask"),
    (["scene", "tfvshvsomega"], "xarray", "data"),
    (["scene", "topdown"], "pymunk", "engine"),
    (["scene", "movie-s2"], "imageio_ffmpeg", "movie"),
    (["scene", "pushing"], "mujoco", "mujoco"),
    (["scene", "all"], "matplotlib", "movie"),
    (["demo"], "matplotlib", "movie"),
]


def _id(argv: list[str], package: str) -> str:
    return " ".join(argv if len(argv) <= 3 else [argv[0], *argv[-2:]]) + f" without {package}"


@pytest.mark.parametrize("argv,package,extra", CASES, ids=[_id(a, p) for a, p, _ in CASES])
def test_a_missing_writer_stops_the_command_before_any_work(tmp_path: Path, argv: list[str], package: str,
                                                             extra: str) -> None:
    p = _rrbody(argv, tmp_path, (package, "numba"))
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2, (p.returncode, p.stderr[-1500:])
    assert len(lines) == 1 and "Traceback" not in p.stderr, p.stderr[-1500:]
    assert lines[0].startswith(f"rrbody {argv[0]}: error: ") and f"'{package}'" in lines[0], lines[0]
    assert f"'.[{extra}]'" in lines[0], lines[0]  # the checkout's install command for the extra
    assert p.stdout == ""
    assert sorted(x.name for x in tmp_path.iterdir()) == []  # no output, checkpoint, sidecar or folder


def test_batch_lines_check_their_outputs_before_their_work(tmp_path: Path) -> None:
    """In batch mode each line is checked as a single call: a line whose movie cannot be written is an
    error line, computes nothing (numba refused) and writes nothing; the other lines still answer."""
    lines = [{"H": 0.2, "k": 0.05, "omega": 0.6, "t-max": 2, "movie": "a.mp4"},
             {"H": 0.3, "k": 0.05, "omega": 0.6, "t-max": 2, "rerun": "b.rrd"}]
    stdin = "".join(json.dumps(x) + "\n" for x in lines)
    p = _rrbody(["simulate", "--json", "--batch", "-"], tmp_path, ("matplotlib", "rerun", "numba"), stdin=stdin)
    assert p.returncode == 2, p.stderr[-1500:]
    out = [json.loads(x) for x in p.stdout.splitlines()]
    assert [o["line"] for o in out] == [1, 2]
    assert "'matplotlib'" in out[0]["error"] and "'.[movie]'" in out[0]["error"]
    assert "'rerun'" in out[1]["error"] and "'.[rerun]'" in out[1]["error"]
    assert sorted(x.name for x in tmp_path.iterdir()) == []


def test_a_missing_folder_or_an_unknown_format_stops_before_any_work(tmp_path: Path) -> None:
    cases = [(["sweep", *ROD[:4], "--axis", "omega=0.5,1", "--out", "no/such/tf.csv"], "--out", "does not exist"),
             (["sweep", *ROD[:4], "--axis", "omega=0.5,1", "--out", "tf.parquet"], "--out", ".csv or .nc"),
             (["simulate", *ROD, "--t-max", "2", "--movie", "m.gif"], "--movie", ".mp4"),
             (["lyapunov", *ROD, "--t-max", "20", "--plot", "no/such/l.png"], "--plot", "does not exist"),
             (["active", "--n", "5", "--t-end", "1", "--out", "a.csv"], "--out", ".json")]
    for argv, option, words in cases:
        p = _rrbody(argv, tmp_path, ("numba",))
        lines = p.stderr.strip().splitlines()
        assert p.returncode == 2 and len(lines) == 1, (argv, p.stderr[-1500:])
        assert lines[0].startswith(f"rrbody {argv[0]}: error: {option}") and words in lines[0], lines[0]
        assert sorted(x.name for x in tmp_path.iterdir()) == [], argv


def test_the_same_sweep_runs_once_the_extra_is_there(tmp_path: Path) -> None:
    """The refused sweep left nothing that blocks it: with xarray importable the same command writes its
    table (before, the first run's checkpoint asked for --resume)."""
    argv = ["sweep", "--k", "1.5", "--axis", "omega=0.5,1", "--axis", "H=0.2,0.3", "--out", "tf.nc"]
    assert _rrbody(argv, tmp_path, ("xarray",)).returncode == 2
    p = _rrbody(argv, tmp_path, ())
    assert p.returncode == 0, p.stderr[-1500:]
    assert sorted(x.name for x in tmp_path.iterdir()) == ["tf.nc", "tf.nc.json"]


# ---- the registry itself, in process ------------------------------------------------------------
def test_every_writer_names_its_extra_and_a_missing_one_is_one_message(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    from rrbody.model import outputs
    from rrbody.model.extras import EXTRA_OF, MissingExtraError

    assert {s: w.modules for s, w in outputs.WRITERS.items() if w.modules} == {
        ".nc": ("xarray",), ".mp4": ("matplotlib", "imageio_ffmpeg"), ".png": ("matplotlib",),
        ".svg": ("matplotlib",), ".rrd": ("rerun",)}
    assert all(m in EXTRA_OF for w in outputs.WRITERS.values() for m in w.modules)

    def absent(module: str, *, purpose: str | None = None) -> None:
        raise MissingExtraError(f"{purpose} needs the optional package {module!r}")

    monkeypatch.setattr(outputs, "require", absent)
    with pytest.raises(MissingExtraError, match=r"^a NetCDF table \(out\) needs the optional package 'xarray'"):
        outputs.preflight({"out": (tmp_path / "t.nc", (".csv", ".nc"))})
    # a CSV written under any name needs nothing, whatever its suffix says
    csv = outputs.WRITERS[".csv"]
    assert outputs.preflight({"out": (tmp_path / "t.nc", None, csv)}) == {"out": tmp_path / "t.nc"}
    with pytest.raises(ValueError, match=r"^movie must end in \.mp4, got '.*m\.avi'"):
        outputs.preflight({"movie": (tmp_path / "m.avi", (".mp4",))})
    with pytest.raises(ValueError, match=r"^a and b name the same file"):
        outputs.preflight({"a": (tmp_path / "x.csv", None), "b": (tmp_path / "x.csv", None)})
    assert list(tmp_path.iterdir()) == []
