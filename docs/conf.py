"""Sphinx configuration for the rrbody documentation site (``make docs``).

Why Sphinx (with furo and MyST) rather than MkDocs: the guides were already Markdown, which MyST
reads unchanged; the API reference comes from the numpy-style docstrings through autodoc and
napoleon, the reference tool of the scientific Python stack; ``-W`` turns every warning (a broken
cross-reference, a bad docstring, a missing image) into a failed build. The site is built from the
committed ``results/`` and ``movies/`` (nothing is recomputed), so a build takes seconds.
"""

from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # autodoc imports the working tree's rrbody

project = "rrbody"
author = "the rrbody contributors"
copyright = "2026, the rrbody contributors"  # noqa: A001 (Sphinx's name)
from rrbody import __version__ as release  # noqa: E402

version = release

# no MathJax: it loads from a CDN, which an offline reader (and CI) cannot reach; equations are plain text
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
myst_enable_extensions = ["colon_fence"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "README.md"]
html_theme = "furo"
html_title = f"rrbody {release}"
html_static_path = ["_static"]
html_favicon = "_static/favicon.svg"
# no "last updated" date, no build timestamp: the site depends on the sources only
html_last_updated_fmt = None
autodoc_member_order = "bysource"
# the MuJoCo adapter's page documents without the [mujoco] extra (the docs build does not install it)
autodoc_mock_imports = ["mujoco"]
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
nitpicky = False


def _copy_movies(app, exception) -> None:  # noqa: ANN001 (Sphinx event signature)
    """Put the committed movies beside the pages that play them (``_movies/``)."""
    if exception is not None or app.builder.format != "html":
        return
    out = Path(app.outdir) / "_movies"
    out.mkdir(exist_ok=True)
    for mp4 in sorted((ROOT / "movies").glob("*.mp4")):
        shutil.copyfile(mp4, out / mp4.name)


_LITERAL = re.compile(r"(``[^`]+``)")


def _plain_bars(app, what, name, obj, options, lines) -> None:  # noqa: ANN001 (Sphinx event signature)
    """Docstrings write absolute values as plain text (``|v|``); reST would read ``|v|`` as a
    substitution reference, so every bar is escaped (no docstring uses reST substitutions or tables)."""
    # inline literals (``...``) keep their bars: reST shows their text verbatim
    lines[:] = ["".join(part if i % 2 else part.replace("|", "\\|") for i, part in enumerate(_LITERAL.split(line)))
                for line in lines]


def setup(app):  # noqa: ANN001, ANN201
    app.connect("build-finished", _copy_movies)
    app.connect("autodoc-process-docstring", _plain_bars)
