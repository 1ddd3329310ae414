"""The README's snippets, run in document order in one empty folder, as a new user would: all succeed.

Every ```sh line and every ```python block runs in the same temporary folder, so a snippet that
writes a file a later one writes too (the CLI's ``traj.csv`` and the Python API's) fails here as it
would for a reader. ``.venv/bin/`` becomes the folder of this interpreter (the test's environment
holds every extra). Skipped, each for the reason in :func:`_skip_reason`: the ``make`` set-up lines
(they create ``.venv`` in the clone and run the whole suite, including this test) and ``pip
install`` lines (they would change the environment the suite runs in).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
BIN = Path(sys.executable).parent

FENCE = re.compile(r"^```(?P<lang>[a-z]*)\n(?P<code>.*?)^```$", re.M | re.S)


def snippets(text: str) -> list[tuple[str, str]]:
    """(language, code) of every ```sh and ```python block of ``text``, in document order; a shell
    block is split into its commands (a line ending in a backslash continues on the next)."""
    out: list[tuple[str, str]] = []
    for m in FENCE.finditer(text):
        if m["lang"] == "python":
            out.append(("python", m["code"]))
        elif m["lang"] == "sh":
            for cmd in re.sub(r"\\\n", " ", m["code"]).splitlines():
                if cmd.strip() and not cmd.lstrip().startswith("#"):
                    out.append(("sh", cmd))
    return out


def _skip_reason(cmd: str) -> str | None:
    """Why a shell line is not run here, or None to run it."""
    words = cmd.split()
    if words[0] == "make":
        return "set-up: creates .venv and runs make test (this suite); the test's environment stands in for it"
    if words[0].endswith("pip") and words[1:2] == ["install"]:
        return "installs into the environment the suite runs in; that environment already has every extra"
    if "--rerun-spawn" in words:
        return "opens the rerun viewer, which needs a display"
    return None


def test_snippets_are_found_in_order() -> None:
    found = snippets(README.read_text())
    langs = [lang for lang, _ in found]
    assert langs.count("python") >= 2 and langs.count("sh") >= 15
    text = "\n".join(code for _, code in found)
    # the batch inputs are made before they are used
    assert text.index("> ks.jsonl") < text.index("--batch ks.jsonl")
    assert text.index("> runs.jsonl") < text.index("--batch runs.jsonl")


@pytest.mark.slow
def test_readme_snippets_run_in_one_empty_folder(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"  # no display: matplotlib must not look for one
    ran = skipped = 0
    for lang, code in snippets(README.read_text()):
        if lang == "python":
            p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True,
                               text=True, timeout=900)
        else:
            if _skip_reason(code) is not None:
                skipped += 1
                continue
            cmd = code.replace(".venv/bin/", f"{BIN}/")
            p = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], cwd=tmp_path, env=env, capture_output=True,
                               text=True, timeout=900)
        assert p.returncode == 0, f"{code}\nexit {p.returncode}\n{p.stderr[-2000:]}"
        assert "Traceback" not in p.stderr, code
        ran += 1
    assert ran >= 18 and skipped == 3
    # what the snippets say they write is there, under distinct names
    for name in ("traj.csv", "traj_py.csv", "e.csv", "a.csv", "b.csv", "tf.csv", "tf.nc", "delta.csv", "f.csv", "run.mp4", "run.rrd"):
        assert (tmp_path / name).stat().st_size > 0, name
