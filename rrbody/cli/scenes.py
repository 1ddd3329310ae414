"""Find and run the scene scripts by name (``scenes/`` of a checkout, or the copies an installed wheel carries).

A scene script ``scenes/<name>.py`` (dashes in the name become underscores) has a module
docstring (its first line is the listing) and ``main(out_dir: Path, *, force: bool) -> None``
writing to ``results/<name>/`` (movies to ``movies/``, the sibling of ``results/``), both under
:func:`rrbody.model.paths.output_root` (the checkout, or the current folder for an installed rrbody).
"""

from __future__ import annotations

import ast
import importlib.util
import time

from rrbody.model.paths import output_root, scenes_dir

__all__ = ["scenes_dir", "output_root", "list_scenes", "run_scene"]


def list_scenes() -> list[tuple[str, str]]:
    """(name, first docstring line) of every scene script, sorted."""
    out = []
    for f in sorted(scenes_dir().glob("*.py")):
        if f.name.startswith("_"):  # __init__.py (the wheel's copy is a package) and private helpers
            continue
        doc = ast.get_docstring(ast.parse(f.read_text())) or ""
        out.append((f.stem.replace("_", "-"), doc.strip().splitlines()[0] if doc.strip() else ""))
    return out


def run_scene(name: str, *, force: bool = True, report: bool = False) -> None:
    """Run scene ``name``: its outputs go to ``results/<name>/``."""
    names = [n for n, _ in list_scenes()]
    if name not in names:
        raise ValueError(f"scene must be one of {', '.join(names) or '(none yet)'} or 'all', got {name!r}")
    path = scenes_dir() / f"{name.replace('-', '_')}.py"
    spec = importlib.util.spec_from_file_location(f"rrbody_scene_{name.replace('-', '_')}", path)
    if spec is None or spec.loader is None:
        raise ValueError(f"scene {name!r}: cannot load {path}")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out_dir = output_root() / "results" / name
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    mod.main(out_dir, force=force)
    print(f"scene {name}: done in {time.perf_counter() - t0:.1f} s -> {out_dir}")
