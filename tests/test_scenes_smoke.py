"""The paper-figure scenes follow the scene convention and the report builds from their summaries (fast: no runs)."""

from __future__ import annotations

import ast
import inspect
import json
from pathlib import Path

import pytest

from rrbody.analysis.report import write_report
from rrbody.cli.scenes import list_scenes, scenes_dir

FIGURE_SCENES = ("phixtpm", "sss", "seco1", "normal-and-phase-portrait", "tfxwpm2", "hc", "tfvshvsomega",
                 "extended-phi", "movie-s1", "movie-s2")


@pytest.mark.parametrize("name", FIGURE_SCENES)
def test_scene_convention(name: str) -> None:
    assert name in [n for n, _ in list_scenes()]
    path = scenes_dir() / f"{name.replace('-', '_')}.py"
    tree = ast.parse(path.read_text())
    doc = ast.get_docstring(tree) or ""
    assert "paper Fig." in doc.splitlines()[0]  # the listing line names the figure it reproduces
    mains = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "main"]
    assert len(mains) == 1
    args = mains[0].args
    assert [a.arg for a in args.args] == ["out_dir"] and [a.arg for a in args.kwonlyargs] == ["force"]


def test_report_from_summaries(tmp_path: Path) -> None:
    # A minimal hc summary: the report must put the paper's values beside ours and the k range.
    (tmp_path / "hc").mkdir()
    fit = {"q": 1.93, "q_err": 0.003, "lam": 41.8, "lam_err": 0.2, "k_range": [0.0, 1.0], "n": 101, "rms": 1e-3}
    paper = {"dry": {"q": 1.936, "q_err": 0.004, "lam": 41.32, "lam_err": 0.09},
             "viscous": {"q": 1.724, "q_err": 0.003, "lam": 11.64, "lam_err": 0.01}}
    (tmp_path / "hc" / "summary.json").write_text(json.dumps({
        "omega": 0.3, "tol": 1e-8, "Hc0_exact": 0.79272623, "Hc0_numeric": 0.79272624, "paper": paper,
        "fits": {"dry": fit, "viscous": {**fit, "q": 1.72, "lam": 11.7}},
        "range_study": [{"k_max": 1.0, "dry": {"q": 1.93, "lam": 41.8}, "viscous": {"q": 1.72, "lam": 11.7}}]}))
    text = write_report(tmp_path).read_text()
    assert "| q, dry | 1.936 ± 0.004 | 1.93 ± 0.003 (-0.3%)" in text
    assert "k in [0, 1] s^-2" in text
    assert write_report(tmp_path).read_text() == text  # no timing or date: a rewrite gives the same bytes
    assert "*(not run)*" in text  # the other figures are reported as missing, not invented
    assert not (tmp_path / "run_time.json").exists()


def test_write_report_rejects_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="results"):
        write_report(tmp_path / "nope")
    assert inspect.signature(write_report).parameters["force"].default is True


@pytest.mark.parametrize("name", [n for n, _ in list_scenes()])
def test_scene_imports_resolve(name: str) -> None:
    """Every rrbody name a scene script imports (at any depth, lazy imports too) exists: a scene
    must not fail on an import after hours of computing (a moved helper is caught here, not there)."""
    import importlib
    import importlib.util

    path = scenes_dir() / f"{name.replace('-', '_')}.py"
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "rrbody":
            if node.module in ("rrbody.engine", "rrbody.plugin") or node.module.startswith("rrbody.engine."):
                pytest.importorskip("pymunk")
            module = importlib.import_module(node.module)
            for alias in node.names:
                assert hasattr(module, alias.name) or importlib.util.find_spec(f"{node.module}.{alias.name}"), \
                    f"{path.name}: {node.module} has no {alias.name}"
