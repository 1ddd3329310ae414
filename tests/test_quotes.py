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
from pathlib import Path

import pytest

from benchmarks import quotes
from benchmarks.quotes import MARKER, QuoteError, quote, quoted_files, rewrite, stale_spans

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
    """The known contested figures are all quoted spans (batch, plugin, engine step), on both pages."""
    names = {p.name: {m["name"] for m in MARKER.finditer(p.read_text())} for p in PAGES}
    assert {"head.startup.1", "head.engine.2", "head.engine.4", "table.targets-brief"} <= names["README.md"]
    assert {"table.targets", "head.startup.1"} <= names["accuracy.md"]
    assert {"table.plugin", "head.engine.4"} <= names["engine.md"]
    assert sum(len(v) for v in names.values()) >= 40


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_known_stale_figure_remains(page: Path) -> None:
    """No stale figure written by hand: the quoted spans are the generator's (checked above), and a
    recorded figure may happen to equal an old one, so they are left out of this search."""
    text = MARKER.sub("", page.read_text())
    assert [s for s in STALE if s in text] == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_markers_do_not_change_the_rendering(page: Path) -> None:
    """An HTML comment at the start of a line opens an HTML block (CommonMark, GFM, MyST): an inline
    quote there would turn the rest of its line into raw HTML, so inline quotes sit after a word;
    a table quote is a block of its own, its markers alone on their lines between blank lines."""
    text = page.read_text()
    assert text.count("<!--q:") == text.count("<!--/q-->") == len(MARKER.findall(text))
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
