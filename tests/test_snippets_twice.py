"""Examples a user copies run again unchanged: every snippet of the README and the docs that writes a
file says ``--force`` (command line) or ``force=True`` (Python) where it means to replace what a first
run wrote, and the Python snippets write files of their own names, so that reading the pages top to
bottom in one folder, twice, fails nowhere. The README's plugin snippet, the command line page's Python
snippet and getting-started's run twice here for real.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```(?P<lang>[a-z]*)\n(?P<code>.*?)^```$", re.M | re.S)
#: options of rrbody commands that name a file the command writes
WRITING = ("--out", "--movie", "--rerun", "--plot")
#: Python calls that write a file (their first argument)
WRITER_CALL = re.compile(r"(?:\.(?:save|movie|poster|rerun)|\brender_movie|\brun_sweep|\bplot_chaos_map)\(")


def _blocks(lang: tuple[str, ...]) -> list[tuple[Path, str]]:
    return [(page, m["code"]) for page in PAGES for m in FENCE.finditer(page.read_text()) if m["lang"] in lang]


def _commands(code: str) -> list[str]:
    return [c for c in re.sub(r"\\\n", " ", code).splitlines() if c.strip() and not c.lstrip().startswith("#")]


def _call_text(code: str, start: int) -> str:
    """The argument text of the call whose '(' ends at ``start``."""
    depth, i = 1, start
    while depth and i < len(code):
        depth += {"(": 1, ")": -1}.get(code[i], 0)
        i += 1
    return code[start:i - 1]


def test_every_writing_command_says_force() -> None:
    seen = 0
    for page, code in _blocks(("sh", "bash")):
        for cmd in _commands(code):
            words = cmd.split("#")[0].split()
            if "rrbody" not in " ".join(words) or "..." in words:
                continue  # not an rrbody command, or a sketch of one ("rrbody sweep ... --resume")
            if any(w.split("=")[0] in WRITING for w in words):
                seen += 1
                assert "--force" in words or "--resume" in words, f"{page.name}: {cmd}"
    assert seen >= 20


def test_every_python_writer_says_force_and_names_its_own_file() -> None:
    names: dict[str, str] = {}
    seen = 0
    for page, code in _blocks(("python",)):
        for m in WRITER_CALL.finditer(code):
            args = _call_text(code, m.end())
            seen += 1
            assert "force=True" in args, f"{page.name}: {m.group(0)}{args})"
            first = re.match(r"\s*(?:[a-z_]+\s*,\s*)?(?:[a-z_(]+\()?\s*\"([^\"]+)\"", args)
            if first is None:
                continue
            name = first.group(1)
            assert names.setdefault(name, page.name) == page.name, f"{name} is written by {names[name]} and {page.name}"
    assert seen >= 5  # (the README's poster and movie, getting-started's two writers, the command line page's)
    assert "topdown.mp4" in names and names["topdown.mp4"] == "README.md"
    assert "traj_py.csv" in names and names["traj_py.csv"] == "cli.md"


def _python_block(page: Path, marker: str) -> str:
    for m in FENCE.finditer(page.read_text()):
        if m["lang"] == "python" and marker in m["code"]:
            return m["code"]
    raise AssertionError(f"no python block with {marker!r} in {page.name}")


@pytest.mark.slow
def test_the_first_snippets_run_twice_in_one_folder(tmp_path: Path) -> None:
    """README's plugin snippet, the command line page's "From Python" and getting-started's, in document
    order, twice."""
    blocks = [_python_block(ROOT / "README.md", "Recorder(space, pf)"),
              _python_block(ROOT / "docs" / "cli.md", "traj.save("),
              _python_block(ROOT / "docs" / "getting-started.md", "render_movie(")]
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    for round_ in (1, 2):
        for code in blocks:
            p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                               timeout=1200)
            assert p.returncode == 0, f"run {round_}:\n{code}\n{p.stderr[-2000:]}"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["run_started.mp4", "topdown.mp4", "topdown.png",
                                                          "traj_py.csv", "traj_started.csv"]
