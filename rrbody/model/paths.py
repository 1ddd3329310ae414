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


@functools.lru_cache(maxsize=4)
def source_checkout(package_dir: Path = _PKG) -> Path | None:
    """The checkout folder when ``package_dir`` is the rrbody package of a source checkout, else ``None``.

    A checkout is recognised by a ``pyproject.toml`` beside the package folder whose ``[project]`` name
    is ``rrbody``; an installed package sits in ``site-packages``, which has none."""
    import tomllib  # only when asked: `import rrbody` stays lean

    root = package_dir.parent
    try:
        meta = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return None
    project = meta.get("project")
    return root if isinstance(project, dict) and project.get("name") == "rrbody" else None


def scenes_dir() -> Path:
    """The folder of the scene scripts: the checkout's ``scenes/``, else the installed ``rrbody/_scenes``."""
    root = source_checkout()
    return root / "scenes" if root is not None else _PKG / "_scenes"


def output_root() -> Path:
    """The folder under which scenes write ``results/<name>/`` and ``movies/``: the checkout, else the
    current folder."""
    root = source_checkout()
    return root if root is not None else Path.cwd()
