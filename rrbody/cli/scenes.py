"""Find and run the scene scripts by name (``scenes/`` of a checkout, or the copies an installed wheel carries).

A scene script ``scenes/<name>.py`` (dashes in the name become underscores) has a module
docstring (its first line is the listing) and ``main(out_dir: Path, *, force: bool) -> None``
writing to ``results/<name>/`` (movies to ``movies/``, the sibling of ``results/``), both under
:func:`rrbody.model.paths.output_root` (the checkout, or the current folder for an installed rrbody).
"""

from __future__ import annotations

import ast
import importlib.util
import os
import time
from pathlib import Path
from typing import Any

from rrbody.model.paths import output_root, scenes_dir

__all__ = ["scenes_dir", "output_root", "list_scenes", "load_scene", "run_scene", "scene_needs", "check_scene"]

#: rrbody modules that import an optional package where they are used: a scene importing one needs it
_RRBODY_NEEDS = {"rrbody.plugin": ("pymunk",), "rrbody.engine": ("pymunk",), "rrbody.mujoco": ("mujoco",),
                 "rrbody.envs": ("gymnasium", "pymunk"), "rrbody.analysis.active_study": ("pymunk",),
                 "rrbody.render": ("matplotlib",)}


def list_scenes() -> list[tuple[str, str]]:
    """(name, first docstring line) of every scene script, sorted."""
    out = []
    for f in sorted(scenes_dir().glob("*.py")):
        if f.name.startswith("_"):  # __init__.py (the wheel's copy is a package) and private helpers
            continue
        doc = ast.get_docstring(ast.parse(f.read_text())) or ""
        out.append((f.stem.replace("_", "-"), doc.strip().splitlines()[0] if doc.strip() else ""))
    return out


def scene_needs(path: Path) -> tuple[str, ...]:
    """The optional packages the scene script ``path`` needs, read from its source, lazy imports
    included: the extras' packages it imports, those the rrbody modules it imports use
    (:data:`_RRBODY_NEEDS`), and the writers of the files it names (``.nc``, ``.mp4``, ``.png``, ``.rrd``:
    :data:`rrbody.model.outputs.WRITERS`)."""
    from rrbody.model.extras import EXTRA_OF
    from rrbody.model.outputs import WRITERS

    found: list[str] = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        modules: list[str] = []
        if isinstance(node, ast.Import):
            modules = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            modules = [node.module, *(f"{node.module}.{a.name}" for a in node.names)]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):  # a file name, or an f-string's tail
            text = node.value
            writer = WRITERS.get(text[text.rfind("."):].lower()) if "." in text else None
            if writer is not None and not any(c.isspace() for c in text):  # a name, not a sentence
                found += writer.modules
        for m in modules:
            if m.split(".")[0] in EXTRA_OF:
                found.append(m.split(".")[0])
            for prefix, needs in _RRBODY_NEEDS.items():
                if m == prefix or m.startswith(prefix + "."):
                    found += needs
    return tuple(dict.fromkeys(found))


def _scene_path(name: str) -> Path:
    names = [n for n, _ in list_scenes()]
    if name not in names:
        raise ValueError(f"scene must be one of {', '.join(names) or '(none yet)'} or 'all', got {name!r}")
    return scenes_dir() / f"{name.replace('-', '_')}.py"


def check_scene(name: str) -> Path:
    """Scene ``name``'s pre-flight, before it computes or writes anything: it exists, the optional
    packages it needs are installed (:class:`~rrbody.model.extras.MissingExtraError` naming the extra),
    and its output folders can be made (``ValueError`` naming the folder). Returns the script's path."""
    from rrbody.model.extras import require

    path = _scene_path(name)
    for module in scene_needs(path):
        require(module, purpose=f"scene {name}")
    root = output_root()
    for folder in (root / "results" / name, root / "movies"):
        existing = folder
        while not existing.exists() and existing.parent != existing:
            existing = existing.parent  # the nearest folder that exists is where the new ones are made
        if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
            raise ValueError(f"scene {name}: cannot write {str(folder)!r}: {str(existing)!r} is not a writable "
                             "folder")
    return path


def load_scene(name: str, path: Path | None = None) -> Any:
    """Scene ``name``'s script as a module (its constants and ``main``), run nothing else: a script
    imports what it draws with inside ``main``."""
    path = _scene_path(name) if path is None else path
    spec = importlib.util.spec_from_file_location(f"rrbody_scene_{name.replace('-', '_')}", path)
    if spec is None or spec.loader is None:
        raise ValueError(f"scene {name!r}: cannot load {path}")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def run_scene(name: str, *, force: bool = True, report: bool = False) -> None:
    """Run scene ``name``: its outputs go to ``results/<name>/``."""
    mod = load_scene(name, check_scene(name))
    out_dir = output_root() / "results" / name
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    mod.main(out_dir, force=force)
    print(f"scene {name}: done in {time.perf_counter() - t0:.1f} s -> {out_dir}")
