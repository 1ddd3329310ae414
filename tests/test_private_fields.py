"""Private names do not cross modules; nobody but the plugin touches the plugin's private state.

:class:`rrbody.engine.plugin.plane.PlaneFriction` keeps its bodies' rows, the id lookup and the
kernel's caches in private fields; every other module of rrbody, and the benchmarks, read them through its
accessors (``rows``, ``bodies_by_row``, ``row_ids``, ``row_index``, ``row_of``, ``rows_of_ids``,
``drive_target``, ``step_arrays``) and write through its methods (``add_footprint``, ``drive``):
:mod:`rrbody.engine.plugin.plane_rows`. The first test walks the sources with ``ast`` and fails on an attribute
of one of those names read or written on anything but ``self``, outside the plugin's own modules
(plane.py and the modules it is split into).

More generally, in the package (rrbody/), a private name (one leading underscore) is used only by the
module that defines it: a ``from rrbody.x import _name`` in another module, or an ``obj._name`` on
anything but ``self``, ``cls`` or ``super()`` where the module (or the group of modules one class is
split into) never sets or binds ``_name``, fails the second test, unless the name is one of another
library's internals that rrbody reads on purpose (:data:`FOREIGN`). Tests and benchmarks may still
reach in where they test or time internals.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the plugin's private fields (and methods) that no other module may touch
PRIVATE = frozenset({"_bodies", "_slots", "_list", "_idrows", "_add", "_relink", "_k_lookup", "_dirty", "_cache",
                     "_k_shapes", "_k_geo"})
#: the plugin's own modules: plane.py and the modules it is split into
OWNERS = frozenset({"rrbody/engine/plugin/plane.py", "rrbody/engine/plugin/plane_rows.py",
                    "rrbody/engine/plugin/admit.py"})
#: modules that are one class split into files: they share its private fields
GROUPS = (OWNERS, frozenset({"rrbody/render/recorder.py", "rrbody/render/recorder_picture.py",
                             "rrbody/render/recorder_rerun.py"}))
#: other libraries' private names that rrbody reads on purpose (each fast path behind rrbody._private's switch)
FOREIGN = frozenset({
    "_body", "_space",  # pymunk: the cffi handles of a Body and a Space (their C structs' addresses)
    "_float_arr", "_int_arr",  # pymunk.batch.Buffer's arrays, handed to the batch calls without a copy
    # argparse: a parser's options and its kinds of action (argparse has no public way to list them)
    "_actions", "_SubParsersAction", "_StoreConstAction", "_AppendAction", "_HelpAction",
    # numba's cache: rrbody's cache folder, its locators and the index a save reads (rrbody._cache)
    "_CacheImpl", "_SourceFileBackedLocatorMixin", "_CacheLocator", "_locator_classes", "_cache_file", "_index_path",
    "_exit",  # os._exit: a pool worker leaves without running the parent's clean-up
    "_replace",  # a namedtuple's public copy-with-changes (underscored so as not to clash with its fields)
})


def reach_ins(source: str, name: str = "<source>") -> list[str]:
    """``line: <expr>.<field>`` for each access of a private field on anything but ``self``."""
    found = []
    for node in ast.walk(ast.parse(source, name)):
        if isinstance(node, ast.Attribute) and node.attr in PRIVATE \
                and not (isinstance(node.value, ast.Name) and node.value.id == "self"):
            found.append(f"{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_module_reaches_into_the_plugin() -> None:
    files = sorted([*(ROOT / "rrbody").rglob("*.py"), *(ROOT / "benchmarks").rglob("*.py")])
    assert len(files) > 50  # the walk found the sources
    wrong = {}
    for f in files:
        rel = f.relative_to(ROOT).as_posix()
        if rel not in OWNERS:
            hits = reach_ins(f.read_text(), rel)
            if hits:
                wrong[rel] = hits
    assert not wrong, (f"use PlaneFriction's accessors (rrbody/engine/plugin/plane_rows.py), not its private fields: "
                       f"{wrong}")


def test_the_walk_catches_a_reach_in() -> None:
    """The walker itself: reads, writes and calls on another object are found; ``self``'s own are not."""
    src = ("def f(pf, self):\n    j = pf._slots[b]\n    pf._bodies[j, 0] = 1.0\n    pf._relink()\n"
           "    self._bodies = 0\n    x = pf.rows\n")
    assert [h.split(":")[0] for h in reach_ins(src)] == ["2", "3", "4"]


def _owned(tree: ast.AST) -> set[str]:
    """The names a module defines: the fields it sets (``self._name = ...``, or ``obj._name = ...`` on an
    object it makes, such as a parsed argparse namespace), the names it binds (class attributes included)
    and its functions and classes."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name):
            names.add(node.attr)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
    return names


def crossings(sources: dict[str, str]) -> dict[str, list[str]]:
    """``{module: ["line: what", ...]}``: each private name of another module that a module of ``sources``
    (path -> text) imports or reads; :data:`GROUPS` share their names, :data:`FOREIGN` ones pass."""
    trees = {rel: ast.parse(text, rel) for rel, text in sources.items()}
    owned = {rel: _owned(tree) for rel, tree in trees.items()}
    for group in GROUPS:
        shared = set().union(*(owned[r] for r in group if r in owned))
        for r in group:
            if r in owned:
                owned[r] = shared
    wrong: dict[str, list[str]] = {}
    for rel, tree in trees.items():
        me = rel.removesuffix(".py").removesuffix("/__init__").replace("/", ".")
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module \
                    and node.module.split(".")[0] == "rrbody" and node.module != me:
                hits = [a.name for a in node.names if a.name.startswith("_") and not a.name.startswith("__")]
                wrong.setdefault(rel, []).extend(f"{node.lineno}: from {node.module} import {h}" for h in hits)
            elif isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__") \
                    and node.attr not in FOREIGN and node.attr not in owned[rel] \
                    and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")) \
                    and not (isinstance(node.value, ast.Call) and isinstance(node.value.func, ast.Name)
                             and node.value.func.id == "super"):
                wrong.setdefault(rel, []).append(f"{node.lineno}: {ast.unparse(node)}")
    return {rel: hits for rel, hits in wrong.items() if hits}


def test_no_private_name_crosses_a_module() -> None:
    files = sorted((ROOT / "rrbody").rglob("*.py"))
    assert len(files) > 50  # the walk found the sources
    wrong = crossings({f.relative_to(ROOT).as_posix(): f.read_text() for f in files})
    assert not wrong, f"give the name a public accessor (or a public name) in the module that owns it: {wrong}"


def test_the_walk_catches_a_crossing() -> None:
    """The walker itself: another module's private function imported, and a private field read where no
    method of the module assigns it, are found; a module's own fields and names, ``self``'s, a group's
    shared fields and another library's listed internals are not."""
    sources = {
        "rrbody/a.py": "def _helper():\n    pass\nclass A:\n    def __init__(self):\n        self._x = 1\n"
                       "def peek(a, o, space):\n    return a._x, o._y, space._space, _helper()\n",
        "rrbody/b.py": "from rrbody.a import _helper, peek\nfrom rrbody._private import private_allowed\n"
                       "def f(a):\n    return a._x, super()._x\n",
        "rrbody/render/recorder_rerun.py": "def send(rec):\n    return rec._times, rec._cog\n",
        "rrbody/render/recorder.py": "class Recorder:\n    _cog = None\n    def __init__(self):\n        self._times "
                                     "= []\n",
    }
    assert crossings(sources) == {"rrbody/a.py": ["7: o._y"],
                                  "rrbody/b.py": ["1: from rrbody.a import _helper", "4: a._x"]}
