"""Nobody but the plugin touches the plugin's private state.

:class:`rrbody.engine.plugin.PlaneFriction` keeps its bodies' rows, the id lookup and the kernel's
caches in private fields; every other module of rrbody, and the benchmarks, read them through its
accessors (``rows``, ``row_index``, ``row_of``, ``rows_of_ids``, ``drive_target``, ``step_arrays``) and write through its
methods (``add_footprint``, ``drive``): :mod:`rrbody.engine.plane_rows`. This test walks the sources
with ``ast`` and fails on an attribute of one of those names read or written on anything but
``self``, outside the plugin's own modules (plugin.py and the modules it is split into). Tests may
still reach in where they test internals.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the plugin's private fields (and methods) that no other module may touch
PRIVATE = frozenset({"_bodies", "_slots", "_add", "_relink", "_k_lookup", "_dirty", "_cache", "_k_shapes", "_k_geo"})
#: the plugin's own modules: plugin.py and the modules it is split into
OWNERS = frozenset({"rrbody/engine/plugin.py", "rrbody/engine/plane_rows.py", "rrbody/engine/admit.py"})


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
    assert not wrong, f"use PlaneFriction's accessors (rrbody/engine/plane_rows.py), not its private fields: {wrong}"


def test_the_walk_catches_a_reach_in() -> None:
    """The walker itself: reads, writes and calls on another object are found; ``self``'s own are not."""
    src = ("def f(pf, self):\n    j = pf._slots[b]\n    pf._bodies[j, 0] = 1.0\n    pf._relink()\n"
           "    self._bodies = 0\n    x = pf.rows\n")
    assert [h.split(":")[0] for h in reach_ins(src)] == ["2", "3", "4"]
