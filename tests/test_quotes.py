"""Every benchmark figure the README and the docs quote is the recorded one (``benchmarks/results/``).

The figures sit in ``<!--q:NAME-->...<!--/q-->`` spans that ``python -m benchmarks.quotes`` writes from
the results; these tests fail when a span differs from what the generator writes (a page edited by
hand, or ``make bench`` re-run without the generator), when a figure known to be stale comes back,
or when a marker would change how the page renders.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from benchmarks import quotes
from benchmarks.quotes import MARKER, PLACEHOLDER, QuoteError, quote, quoted_files, rewrite, stale_spans

ROOT = Path(__file__).resolve().parent.parent
PAGES = quoted_files(ROOT)

#: figures a review found quoted beside the recorded ones (another run's batch, plugin and engine-step
#: ratios and times, and a Movie S1 frame count the file does not have)
STALE = ["2.25x", "1.89x", "1.35x", "**1.35**", "5.0x", "4.79 us", "0.965 us", "1294", "1.50 s, 1.89x",
         "~0.7-1.4 s", "0.79 s for the call"]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_quoted_span_equals_what_the_generator_writes(page: Path) -> None:
    assert stale_spans(page) == []


def test_the_pages_quote_the_recorded_benchmarks() -> None:
    """The known contested figures are all quoted spans (batch, plugin, engine step), on the pages that
    state them; the README quotes none (its snippets state their own output: tests/test_readme.py)."""
    names = {p.name: {m["name"] for m in MARKER.finditer(p.read_text())} for p in PAGES}
    assert names["README.md"] == set()
    assert {"head.startup.1", "head.engine.2", "head.engine.4", "table.targets-brief"} <= names["benchmarks.md"]
    assert {"head.startup.1", "startup.single"} <= names["cli.md"]
    assert {"table.targets", "head.startup.1"} <= names["accuracy.md"]
    assert {"table.plugin", "head.engine.4"} <= names["engine.md"]
    assert sum(len(v) for v in names.values()) >= 40


@pytest.mark.parametrize("page", [p for p in PAGES if p.name != "CHANGELOG.md"],
                         ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_known_stale_figure_remains(page: Path) -> None:
    """No stale figure written by hand: the quoted spans are the generator's (checked above), and a
    recorded figure may happen to equal an old one, so they are left out of this search. (The
    CHANGELOG's older entries are history: their figures stay as measured then.)"""
    text = MARKER.sub("", page.read_text())
    assert [s for s in STALE if s in text] == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_markers_do_not_change_the_rendering(page: Path) -> None:
    """An HTML comment at the start of a line opens an HTML block (CommonMark, GFM, MyST): an inline
    quote there would turn the rest of its line into raw HTML, so inline quotes sit after a word;
    a table quote is a block of its own, its markers alone on their lines between blank lines."""
    text = page.read_text()
    shown = text.count(PLACEHOLDER)  # the syntax itself, shown on a page: no quote
    assert text.count("<!--q:") - shown == text.count("<!--/q-->") - shown == len(MARKER.findall(text))
    for m in MARKER.finditer(text):
        line_start = text.rfind("\n", 0, m.start()) + 1
        if m["name"].startswith("table."):
            assert text[line_start:m.start()] == "" and text[m.end():m.end() + 2] == "\n\n", m["name"]
            assert m["body"].startswith("\n\n") and m["body"].endswith("\n\n")
        else:
            assert text[line_start:m.start()].strip() != "", f"{m['name']} starts a line"
            assert "\n" not in m["body"] and "|" not in m["body"], m["name"]


def test_targets_table_is_summary_md_s_table() -> None:
    """The generated targets table is the one ``benchmarks.run`` assembled into SUMMARY.md."""
    summary = (quotes.DEFAULT_OUT / "SUMMARY.md").read_text()
    table = summary.split("## Targets\n\n", 1)[1].split("\n\n", 1)[0]
    assert quote("table.targets").strip() == table


def test_a_new_recorded_run_rewrites_every_page(tmp_path: Path) -> None:
    """Change one recorded ratio: every span quoting it follows, and nothing else moves."""
    results = tmp_path / "results"
    shutil.copytree(quotes.DEFAULT_OUT, results)
    jt = results / "startup_targets.json"
    data = json.loads(jt.read_text())
    recorded = data["targets"][0]["measured"]  # whatever the last `make bench` wrote
    changed = "2.71x (1.60 s vs 0.591 s); 20 of 20 checked lines equal to single calls"
    data["targets"][0]["measured"] = changed
    jt.write_text(json.dumps(data))
    for page in PAGES:
        old = page.read_text()
        new = rewrite(old, results)
        n_quotes = len(re.findall(r"<!--q:(head|target)\.startup\.1-->", old))
        assert new.count("2.71x") == old.count("2.71x") + n_quotes + (
            "<!--q:table.targets" in old)  # the targets tables hold the ratio once more
        assert new.replace(changed, recorded).replace("2.71x", quotes._head(recorded)) == old


@pytest.mark.parametrize("name,says", [
    ("head.startup.9", "study 'startup' has targets 1..1, not '9'"),
    ("head.nosuchstudy.1", "unknown quote 'head.nosuchstudy.1'"),
    ("nonsense", "unknown quote 'nonsense'"),
])
def test_a_wrong_quote_name_is_an_error_naming_it(name: str, says: str) -> None:
    with pytest.raises(QuoteError, match=re.escape(says)):
        quote(name)


#: the set-up figures a newcomer found disagreeing (the install's compilation "about a minute", a first
#: use "15-30 s", MuJoCo "1.3 to 1.8 times", pymunk said missing from the demo's venv), written by hand
SETUP_STALE = ["about a minute", "15-30 s", "20-30 s", "1.3 to\n1.8", "1.3 to 1.8", "make demo does not install"]
#: where each set-up figure must be quoted, and by which names
SETUP_QUOTES = {
    "getting-started.md": {"setup.demo.total", "setup.demo.kernels", "setup.test.total", "setup.test.kernels",
                           "coldstart.compile", "head.coldstart.1"},
    "compile.md": {"setup.demo.kernels", "setup.test.kernels", "setup.test.total", "setup.test.suite",
                   "setup.test.set-up", "coldstart.compile"},
    "benchmarks.md": {"summary.minutes", "head.coldstart.1"},
    "mujoco.md": {"mujoco.own-smooth", "mujoco.own-cylinder", "mujoco.adapter-smooth", "mujoco.adapter-cylinder"},
    "CHANGELOG.md": {"setup.test.total", "setup.demo.kernels"},
    "Makefile": {"setup.demo.venv", "setup.demo.build-reqs", "setup.demo.install", "setup.test.install",
                 "setup.demo.kernels", "setup.test.kernels", "setup.demo.demo", "setup.test.suite",
                 "setup.test.lowest-venv", "setup.test.suite-lowest"},
}


@pytest.mark.parametrize("page", [p for p in PAGES if p.name in SETUP_QUOTES], ids=lambda p: p.name)
def test_the_set_up_figures_are_quoted_from_their_records(page: Path) -> None:
    """Each set-up figure is a span of its one record (setup.json, coldstart.csv, mujoco.csv), and
    none of the contradicting hand-written figures is left outside the spans."""
    text = page.read_text()
    assert SETUP_QUOTES[page.name] <= {m["name"] for m in MARKER.finditer(text)}
    bare = MARKER.sub("", text)
    assert [s for s in SETUP_STALE if s in bare] == []


def _setup_record(results: Path, kernels_s: float) -> None:
    """A setup.json like the recorder's, with the demo's kernel step at ``kernels_s``."""
    rec = {"date_utc": "2026-01-02 03:04 UTC", "total_s": 200.0, "tests_passed": {},
           "load_avg_before": [1.0, 1.0, 1.0], "load_avg_after": [2.0, 1.0, 1.0],
           "steps_s": {"venv": 5.0, "build-reqs": 20.0, "install": 15.0, "kernels": kernels_s, "demo": 40.0}}
    (results / "setup.json").write_text(json.dumps({"targets": {"demo": rec}}))


def test_a_changed_set_up_record_changes_every_span_and_the_makefile_s_step_line(tmp_path: Path) -> None:
    """Record another time for the kernels: the pages' spans and the line `make demo` prints before
    compiling (make -n: nothing runs) follow it; with no record of a target its spans say "?"."""
    results = tmp_path / "results"
    shutil.copytree(quotes.DEFAULT_OUT, results)
    _setup_record(results, 987.4)
    assert quote("setup.demo.kernels", results) == "987 s" and quote("setup.demo.set-up", results) == "1027 s"
    assert quote("setup.test.total", results) == "?"
    with pytest.raises(QuoteError, match="no step 'nope'"):
        quote("setup.demo.nope", results)
    clone = tmp_path / "clone"
    clone.mkdir()
    (clone / "Makefile").write_text(rewrite((ROOT / "Makefile").read_text(), results))
    for name in ("pyproject.toml", "rrbody", "scenes"):  # the kernels' sources the Makefile lists (and Movie S1's)
        (clone / name).symlink_to(ROOT / name)
    for page in PAGES:
        if "<!--q:setup.demo.kernels-->" in page.read_text():
            assert "<!--q:setup.demo.kernels-->987 s<!--/q-->" in rewrite(page.read_text(), results), page.name
    p = subprocess.run(["make", "-n", "demo"], cwd=clone, capture_output=True, text=True, timeout=60)
    said = [ln for ln in p.stdout.splitlines() if "==> kernels:" in ln]
    assert len(said) == 1 and "(about 987 s in the recorded run" in said[0], p.stdout
    assert "<!--" not in p.stdout  # the markers stay in the Makefile, out of what it prints


def test_the_mujoco_summary_is_its_table_s(tmp_path: Path) -> None:
    """docs/mujoco.md's summary sentence reads its figures from the rows the page tabulates: change
    MuJoCo's cylinder row and the sentence follows."""
    results = tmp_path / "results"
    shutil.copytree(quotes.DEFAULT_OUT, results)
    csv_path = results / "mujoco.csv"
    text = csv_path.read_text()
    row = next(ln for ln in text.splitlines() if ln.startswith('"MuJoCo condim 4, elliptic",disk (cylinder)'))
    csv_path.write_text(text.replace(row, '"MuJoCo condim 4, elliptic",disk (cylinder),0.3,4.0'))
    page = (ROOT / "docs" / "mujoco.md").read_text()
    low = quote("mujoco.own-cylinder").split(" to ")[0]
    assert f"<!--q:mujoco.own-cylinder-->{low}" in page
    assert "<!--q:mujoco.own-cylinder-->0.30 to " in rewrite(page, results)


def test_the_set_up_recorder_times_each_announced_step() -> None:
    """benchmarks.setup_times reads make's timestamped lines: a step lasts from its ``==>`` line to the
    next; the tests each suite passed and the slowest tests pytest listed are kept."""
    from benchmarks.setup_times import parse_steps

    lines = [(0.5, "python3 -m venv .venv"), (1.0, "==> venv: creating .venv"), (4.0, "==> kernels: compiling"),
             (9.0, "rrbody: compiling [1/6] the stepping loop under dry friction done (5 s)"),
             (30.0, "==> suite: running the test suite"), (31.0, "35.12s call     tests/test_readme.py::test_x"),
             (32.0, "1.50s setup    tests/test_install.py::test_y"),
             (90.0, "===== 1012 passed, 3 skipped in 59.0s ====="), (91.0, "==> suite-lowest: running part"),
             (120.0, "40 passed in 28.2s")]
    steps, passed, slowest = parse_steps(lines, 121.0)
    assert steps == {"start": 1.0, "venv": 3.0, "kernels": 26.0, "suite": 61.0, "suite-lowest": 30.0}
    assert passed == {"suite": 1012, "suite-lowest": 40}
    assert slowest == {"call tests/test_readme.py::test_x": 35.12, "setup tests/test_install.py::test_y": 1.5}
