"""Import contract: rrbody's sub-packages form layers and every import runs downward.

Layers, bottom to top: model -> physics -> integrate -> engine -> analysis -> render -> cli. A module
may import from its own layer or a lower one, never from a higher one (a back edge), and the module
graph has no cycle. Imports inside functions count too: a lazy import is still a dependency. The
package root ``rrbody/__init__.py`` (with ``rrbody/plugin.py``, the plugin's entry point, ``rrbody/mujoco.py``, the MuJoCo adapter's, and
``rrbody/pressure.py`` and ``rrbody/planar.py``, the contacts' and the batched wrench's) is the curated public
API above every layer; below it only
``rrbody._version`` and ``rrbody._cache`` (where caches live) may be imported from the root.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "rrbody"
LAYERS = ("model", "physics", "integrate", "engine", "analysis", "render", "cli")
#: modules at the package root and the layer they count as
ROOT_MODULES = {"rrbody._version": -1, "rrbody._cache": -1, "rrbody": len(LAYERS), "rrbody.plugin": len(LAYERS),
                "rrbody.mujoco": len(LAYERS), "rrbody.pressure": len(LAYERS), "rrbody.planar": len(LAYERS)}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _layer(module: str) -> int:
    if module in ROOT_MODULES:
        return ROOT_MODULES[module]
    parts = module.split(".")
    if len(parts) < 2 or parts[1] not in LAYERS:
        raise AssertionError(f"{module} is in no layer: put it in one of rrbody.{{{','.join(LAYERS)}}}")
    return LAYERS.index(parts[1])


def _imports(path: Path, module: str) -> set[str]:
    """Every rrbody module that ``path`` imports (absolute or relative, at any depth)."""
    is_pkg = path.name == "__init__.py"
    package = module if is_pkg else module.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.split(".")[0] == "rrbody")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "rrbody":
                continue
            # `from pkg import name`: name may be a sub-module of pkg
            for a in node.names:
                sub = f"{target}.{a.name}"
                found.add(sub if _exists(sub) else target)
    found.discard(module)
    return found


def _exists(module: str) -> bool:
    rel = Path(*module.split("."))
    return (PKG.parent / rel).with_suffix(".py").exists() or (PKG.parent / rel / "__init__.py").exists()


def _graph() -> dict[str, set[str]]:
    return {(m := _module_name(p)): _imports(p, m) for p in sorted(PKG.rglob("*.py"))}


GRAPH = _graph()


def test_every_module_is_in_a_layer() -> None:
    for module in GRAPH:
        _layer(module)


@pytest.mark.parametrize("module", sorted(GRAPH))
def test_imports_run_downward(module: str) -> None:
    own = _layer(module)
    back = sorted(t for t in GRAPH[module] if _layer(t) > own)
    assert not back, f"{module} (layer {own}) imports from higher layers: {back}"


def test_no_import_cycle() -> None:
    state: dict[str, int] = {}  # 1 on the DFS stack, 2 done
    stack: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for t in sorted(GRAPH.get(m, ())):
            if state.get(t) == 1:
                cycle = stack[stack.index(t):] + [t]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(GRAPH):
        if m not in state:
            visit(m)


def test_the_contract_catches_a_back_edge(tmp_path: Path) -> None:
    """The walker itself: a lazy import of a higher layer inside a function is found."""
    f = tmp_path / "mod.py"
    f.write_text("def g():\n    from rrbody.cli.main import main\n    from ..render import mp4\n")
    found = _imports(f, "rrbody.physics.mod")
    assert "rrbody.cli.main" in found and "rrbody.render.mp4" in found
    assert max(_layer(t) for t in found) > _layer("rrbody.physics.mod")


# ---- the kernels' sources: what rrbody._cache.source_hash covers --------------------------------
_NUMBA_MAKERS = {"njit", "jit", "cfunc", "vectorize", "guvectorize", "generated_jit", "overload", "intrinsic",
                 "jitclass", "literal_unroll"}


def _makes_kernels(path: Path) -> list[str]:
    """Names of numba's kernel makers used in ``path`` (as decorators or calls)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        target = node.func if isinstance(node, ast.Call) else node
        name = target.attr if isinstance(target, ast.Attribute) else target.id if isinstance(target, ast.Name) else ""
        if name in _NUMBA_MAKERS and isinstance(node, (ast.Call, ast.Name, ast.Attribute)):
            found.append(name)
    return sorted(set(found))


def test_the_kernel_hash_covers_every_kernel_and_what_it_can_inline() -> None:
    """source_hash reads only KERNEL_LAYERS (and two root files): sound only if those are the bottom
    layers (imports run downward, so a kernel inlines nothing from above) and no file above them
    makes a kernel."""
    from rrbody import _cache

    assert tuple(_cache.KERNEL_LAYERS) == LAYERS[:len(_cache.KERNEL_LAYERS)]
    covered = set(_cache.kernel_sources())
    outside = {p.relative_to(PKG).as_posix(): names for p in sorted(PKG.rglob("*.py"))
               if p.resolve() not in {c.resolve() for c in covered} and (names := _makes_kernels(p))}
    assert not outside, f"files outside rrbody._cache.KERNEL_LAYERS make numba kernels: {outside}"
    assert any(_makes_kernels(p) for p in covered)  # the scan itself finds the kernels there


def test_the_kernel_scan_finds_a_decorator(tmp_path: Path) -> None:
    f = tmp_path / "k.py"
    f.write_text("import numba\n@numba.njit(cache=True)\ndef f(x):\n    return x\n")
    assert _makes_kernels(f) == ["njit"]
