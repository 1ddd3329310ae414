"""Where rrbody finds its scene scripts and writes scene outputs: a source checkout or an installed package.

From a source checkout (the folder above the package holds rrbody's ``pyproject.toml`` and
``scenes/``: an editable install, or the repository on ``PYTHONPATH``), scenes are the repository's
``scenes/*.py`` and their outputs go to the repository's ``results/`` and ``movies/``, as committed.
From an installed package (``pip install .`` or from an index), the scene scripts are the copies the
wheel carries (``rrbody/_scenes``) and outputs go to ``results/`` and ``movies/`` under the current
folder: an installed package is never written to.
"""

from __future__ import annotations

import functools
from pathlib import Path

__all__ = ["source_checkout", "scenes_dir", "output_root"]

_PKG = Path(__file__).resolve().parents[1]


@functools.lru_cache(maxsize=1)
def source_checkout() -> Path | None:
    """The repository root when rrbody runs from its source tree, else ``None``."""
    root = _PKG.parent
    project = root / "pyproject.toml"
    try:
        named = 'name = "rrbody"' in project.read_text()
    except OSError:
        return None
    return root if named and (root / "scenes").is_dir() else None


def scenes_dir() -> Path:
    """The folder of the scene scripts: the checkout's ``scenes/``, else the installed ``rrbody/_scenes``."""
    root = source_checkout()
    return root / "scenes" if root is not None else _PKG / "_scenes"


def output_root() -> Path:
    """The folder under which scenes write ``results/<name>/`` and ``movies/``: the checkout, else the
    current folder."""
    root = source_checkout()
    return root if root is not None else Path.cwd()
