"""The README's snippets, then those of docs/cli.md (the command line's tour, which holds the commands the
README held before it became three quick starts), run in document order in one empty folder, as a new
user would: all succeed, and each that states its output prints it.

Every ```sh line and every ```python block runs in the same temporary folder, so a snippet that
writes a file a later one writes too (the CLI's ``traj.csv`` and the Python API's) fails here as it
would for a reader. ``.venv/bin/`` becomes the folder of this interpreter, which also comes first on
the PATH for docs/cli.md's bare ``rrbody`` (the test's environment holds every extra). A ```text block
right after a snippet is the output it states: the snippet's stdout, line for line, where ``...``
stands for any text and a run of spaces for any run. Skipped, each for the reason in
:func:`_skip_reason`: the ``make`` set-up lines (they create ``.venv`` in the clone and run the whole
suite, including this test) and ``pip install`` lines (they would change the environment the suite
runs in).
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
#: the pages whose snippets run, in this order, in one folder
PAGES = (README, ROOT / "docs" / "cli.md")
BIN = Path(sys.executable).parent

FENCE = re.compile(r"^```(?P<lang>[a-z]*)\n(?P<code>.*?)^```$", re.M | re.S)


def blocks(text: str) -> list[tuple[str, str, str | None]]:
    """(language, code, the output it states or None) of every ```sh and ```python block of
    ``text``, in document order; the output is a ```text block that follows it with nothing between
    but blank lines."""
    out: list[tuple[str, str, str | None]] = []
    found = list(FENCE.finditer(text))
    for m, after in zip(found, [*found[1:], None]):
        if m["lang"] not in ("sh", "python"):
            continue
        stated = None
        if after is not None and after["lang"] == "text" and not text[m.end():after.start()].strip():
            stated = after["code"]
        out.append((m["lang"], m["code"], stated))
    return out


def commands(lang: str, code: str) -> list[str]:
    """A python block whole; a shell block split into its commands (a line ending in a backslash
    continues on the next; comment lines dropped)."""
    if lang == "python":
        return [code]
    return [cmd for cmd in re.sub(r"\\\n", " ", code).splitlines() if cmd.strip() and not cmd.lstrip().startswith("#")]


def snippets(text: str) -> list[tuple[str, str]]:
    """(language, code) of every ```python block and every command of a ```sh block, in order."""
    return [(lang, cmd) for lang, code, _ in blocks(text) for cmd in commands(lang, code)]


def matches(stated: str, printed: str) -> bool:
    """Whether ``printed`` is the output ``stated``: line for line, ``...`` any text, spaces any run."""
    want = [ln.strip() for ln in stated.strip().splitlines()]
    got = [ln.strip() for ln in printed.strip().splitlines()]
    if len(want) != len(got):
        return False
    for w, g in zip(want, got):
        pattern = r"\s+".join(re.escape(part).replace(r"\.\.\.", ".*?") for part in w.split())
        if re.fullmatch(pattern, g) is None:
            return False
    return True


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


def test_the_readme_is_three_quick_starts() -> None:
    """What a reader finds: the two set-up commands, exactly; three snippets with their stated output
    (a pymunk program, Push-T, the paper's flip time and movie), each with a picture that is in the
    repository; no quoted benchmark figure (those live on the docs pages, benchmarks/quotes.py)."""
    text = README.read_text()
    found = blocks(text)
    setup = [cmd for lang, code, _ in found for cmd in commands(lang, code) if cmd.split()[0] == "make"]
    assert [cmd.split()[:2] for cmd in setup] == [["make", "demo"], ["make", "test"]]
    stated = [(lang, code) for lang, code, out in found if out is not None]
    assert len(stated) == 3
    assert "PlaneFriction" in stated[0][1] and "rrbody/PushT-v0" in stated[1][1] and "flip-time" in stated[2][1]
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(pictures) == 3 and all((ROOT / p).is_file() for p in pictures), pictures
    assert "<!--q:" not in text
    assert len(text.splitlines()) <= 200
    links = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text)
    assert [x for x in links if not x.startswith("http") and not (ROOT / x).exists()] == []


def test_the_readme_the_docs_index_and_pyproject_say_the_same() -> None:
    """The README's first paragraph (what rrbody is) is the docs index's, word for word, and pyproject's
    description names the same four things."""
    import tomllib

    def first_paragraph(path: Path) -> str:
        return " ".join(path.read_text().split("\n\n")[1].split())

    said = first_paragraph(README)
    assert said == first_paragraph(ROOT / "docs" / "index.md")
    assert said.count(". ") == 1 and said.endswith(".")  # two sentences
    description = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["description"]
    for part in ("pymunk", "MuJoCo", "Push-T", "paper"):
        assert part in said and part in description, part


def test_stated_outputs_are_compared_line_for_line() -> None:
    assert matches("t_f = 42.13... s\n[1.5 2. ]", "t_f = 42.137088 s\n[1.5   2. ]")
    assert not matches("t_f = 42.13... s", "t_f = 41.137088 s")
    assert not matches("a\nb", "a")


def test_snippets_are_found_in_order() -> None:
    found = [x for page in PAGES for x in snippets(page.read_text())]
    langs = [lang for lang, _ in found]
    assert langs.count("python") >= 3 and langs.count("sh") >= 20
    text = "\n".join(code for _, code in found)
    # the batch inputs are made before they are used
    assert text.index("> ks.jsonl") < text.index("--batch ks.jsonl")
    assert text.index("> runs.jsonl") < text.index("--batch runs.jsonl")


@pytest.mark.slow
def test_readme_snippets_run_in_one_empty_folder(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"  # no display: matplotlib must not look for one
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    ran = skipped = compared = 0
    for page in PAGES:
        for lang, code, stated in blocks(page.read_text()):
            printed = ""
            for cmd in commands(lang, code):
                if lang == "python":
                    p = subprocess.run([sys.executable, "-c", cmd], cwd=tmp_path, env=env, capture_output=True,
                                       text=True, timeout=900)
                else:
                    if _skip_reason(cmd) is not None:
                        skipped += 1
                        continue
                    p = subprocess.run(["bash", "-o", "pipefail", "-c", cmd.replace(".venv/bin/", f"{BIN}/")],
                                       cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)
                assert p.returncode == 0, f"{page.name}: {cmd}\nexit {p.returncode}\n{p.stderr[-2000:]}"
                assert "Traceback" not in p.stderr, cmd
                printed += p.stdout
                ran += 1
            if stated is not None:
                assert matches(stated, printed), f"{page.name}: {code}\nstated:\n{stated}\nprinted:\n{printed}"
                compared += 1
    assert ran >= 25 and skipped == 3 and compared == 3
    # what the snippets say they write is there, under distinct names
    for name in ("topdown.png", "topdown.mp4", "s1.mp4", "traj.csv", "traj_py.csv", "e.csv", "a.csv", "b.csv",
                 "tf.csv", "tf.nc", "delta.csv", "f.csv", "run.mp4", "run.rrd", "sec.csv", "sec.png", "map.nc",
                 "map.png"):
        assert (tmp_path / name).stat().st_size > 0, name
