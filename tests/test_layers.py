"""Import contract: rrbody's sub-packages form layers and every import runs downward.

Layers, bottom to top: model -> physics -> integrate -> contact -> {engine, mujoco_adapter} -> analysis
-> render -> envs -> cli. ``contact`` is the plane step both engine adapters call and imports no engine; the two
adapters (pymunk's ``engine`` and ``mujoco_adapter``) share a level and never import each other, and no
package imports two engines. A module may import from its own layer or a lower one, never from a higher
one (a back edge), and the module graph has no cycle. Inside ``engine`` the same holds for its sub-packages, one
owner each (``ENGINE_LEVELS``, bottom to top): memory -> plugin -> {recording, scenes}. Imports inside functions
count too: a lazy import is still a dependency. The
package root ``rrbody/__init__.py`` (with ``rrbody/plugin.py``, the plugin's entry point, ``rrbody/mujoco.py``, the
MuJoCo adapter's, and
``rrbody/pressure.py`` and ``rrbody/planar.py``, the contacts' and the batched wrench's) is the curated public
API above every layer; below it only
``rrbody._version``, ``rrbody._cache`` (where caches live) and ``rrbody._private`` (the switch for private
internals) may be imported from the root.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "rrbody"
#: the levels, bottom to top; the packages of one level may not import each other (the two engine adapters)
LEVELS: tuple[tuple[str, ...], ...] = (("model",), ("physics",), ("integrate",), ("contact",), ("engine",
                                                                                                "mujoco_adapter"),
                                       ("analysis",), ("render",), ("envs",), ("cli",))
LAYERS = tuple(name for level in LEVELS for name in level)
#: the third-party engines, and the packages that may import each (no other may, and none both); the
#: gymnasium environments (envs) are pymunk programs of their own: they build the spaces they step
ENGINES = {"pymunk": {"engine", "envs"}, "mujoco": {"mujoco_adapter"}}
#: modules at the package root and the layer they count as
ROOT_MODULES = {"rrbody._version": -1, "rrbody._cache": -1, "rrbody._private": -1, "rrbody": len(LEVELS),
                "rrbody.plugin": len(LEVELS),
                "rrbody.mujoco": len(LEVELS), "rrbody.pressure": len(LEVELS), "rrbody.planar": len(LEVELS)}


#: the sub-packages of ``engine``, bottom to top, one owner each: pymunk's memory read and written, the plugin with
#: its stores, then the recorder's tape and rrbody's own scenes, which share a level and never import each other;
#: the package's face (rrbody/engine/__init__.py) stands above them all
ENGINE_LEVELS: tuple[tuple[str, ...], ...] = (("memory",), ("plugin",), ("recording", "scenes"))
ENGINE_PACKAGES = tuple(name for level in ENGINE_LEVELS for name in level)


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
    return next(i for i, level in enumerate(LEVELS) if parts[1] in level)


def _package(module: str) -> str:
    """The sub-package of a module below the root (``engine`` for rrbody.engine.plugin), or ''."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in LAYERS else ""


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


def test_the_packages_of_one_level_do_not_import_each_other() -> None:
    """The two engine adapters share a level: neither may import the other (the plane step they share
    is below them, in rrbody.contact)."""
    crossing = sorted(f"{m} -> {t}" for m, targets in GRAPH.items() for t in targets
                      if _package(m) and _package(t) and _package(m) != _package(t) and _layer(m) == _layer(t))
    assert not crossing, crossing


def _engine_level(module: str) -> int:
    """The level of an ``engine`` module among :data:`ENGINE_LEVELS` (the package's face above them all)."""
    if module == "rrbody.engine":
        return len(ENGINE_LEVELS)
    parts = module.split(".")
    if len(parts) < 3 or parts[2] not in ENGINE_PACKAGES:
        raise AssertionError(f"{module} is in no sub-package of rrbody.engine: put it in one of "
                             f"rrbody.engine.{{{','.join(ENGINE_PACKAGES)}}}")
    return next(i for i, level in enumerate(ENGINE_LEVELS) if parts[2] in level)


def _engine_package(module: str) -> str:
    """The sub-package of an ``engine`` module (``plugin`` for rrbody.engine.plugin.plane), or '' for the face."""
    parts = module.split(".")
    return parts[2] if len(parts) > 2 else ""


ENGINE_MODULES = sorted(m for m in GRAPH if _package(m) == "engine")


def test_every_engine_module_is_in_a_sub_package() -> None:
    assert "rrbody.engine.plugin.plane" in ENGINE_MODULES  # the walk found the sub-packages
    for module in ENGINE_MODULES:
        _engine_level(module)


@pytest.mark.parametrize("module", ENGINE_MODULES)
def test_imports_inside_the_engine_run_downward(module: str) -> None:
    """Inside rrbody.engine a module imports from its own sub-package or a lower one (:data:`ENGINE_LEVELS`), never
    from a higher one, nor from the other sub-package of its level (the recorder's tape and rrbody's scenes)."""
    own = _engine_level(module)
    inside = [t for t in GRAPH[module] if _package(t) == "engine"]
    back = sorted(t for t in inside if _engine_level(t) > own)
    assert not back, f"{module} (engine level {own}) imports from higher sub-packages of rrbody.engine: {back}"
    crossing = sorted(t for t in inside if _engine_level(t) == own and _engine_package(t) != _engine_package(module))
    assert not crossing, f"{module} imports the other sub-package of its level: {crossing}"


def test_the_engine_contract_catches_a_back_edge(tmp_path: Path) -> None:
    """The engine's inner order itself: the plugin importing the scenes, or the tape importing a scene, is refused."""
    f = tmp_path / "mod.py"
    f.write_text("def g():\n    from rrbody.engine.scenes.run import simulate_engine\n")
    found = _imports(f, "rrbody.engine.plugin.mod")
    assert "rrbody.engine.scenes.run" in found
    assert max(_engine_level(t) for t in found) > _engine_level("rrbody.engine.plugin.mod")
    assert _engine_level("rrbody.engine.recording.tape") == _engine_level("rrbody.engine.scenes.run")
    assert _engine_level("rrbody.engine.memory.bodymem") < _engine_level("rrbody.engine.plugin")
    with pytest.raises(AssertionError, match="no sub-package"):
        _engine_level("rrbody.engine.loose")


#: the bottom of the physics layer and what each may import from it: the parameter layout nothing, the effects
#: (laws, drive, tilt, the area methods that apply a law alone) the layout and each other; the kernels import
#: them, and the area methods that call kernels stand above those (rrbody.physics.areas)
PHYSICS_LEAVES = {"rrbody.physics.params": (),
                  "rrbody.physics.effects": ("rrbody.physics.params", "rrbody.physics.effects")}


def test_the_effects_and_the_parameter_layout_import_no_kernel() -> None:
    """Within physics the imports run downward too: no effect imports a kernel that imports the effects."""
    def under(m: str, root: str) -> bool:
        return m == root or m.startswith(root + ".")

    up = sorted(f"{m} -> {t}" for leaf, allowed in PHYSICS_LEAVES.items() for m, targets in GRAPH.items()
                if under(m, leaf) for t in targets
                if _package(t) == "physics" and not any(under(t, a) for a in allowed))
    assert not up, up


def _third_party(path: Path) -> set[str]:
    """The top-level names of the packages outside rrbody that ``path`` imports (at any depth, or through
    rrbody.model.extras.require("NAME", ...))."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            found.add(node.module.split(".")[0])
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "require"
              and node.args and isinstance(node.args[0], ast.Constant)):
            found.add(str(node.args[0].value).split(".")[0])
    found.discard("rrbody")
    return found


def _engines(module: str) -> set[str]:
    """The engines (pymunk, MuJoCo) a module imports itself."""
    path = PKG.parent / Path(*module.split("."))
    path = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
    return _third_party(path) & set(ENGINES)


def test_the_plane_step_imports_no_engine() -> None:
    """rrbody.contact, the step both adapters call, imports neither pymunk nor MuJoCo, itself or through
    any rrbody module it imports (the whole downward closure)."""
    seen: set[str] = set()
    todo = [m for m in GRAPH if _package(m) == "contact"]
    while todo:
        m = todo.pop()
        if m not in seen:
            seen.add(m)
            todo.extend(GRAPH.get(m, ()))
    wrong = sorted(f"{m} imports {e}" for m in seen for e in _engines(m))
    assert not wrong, wrong


def test_no_package_imports_two_engines() -> None:
    """Each sub-package imports at most one engine, and each engine's adapter package is the one that
    steps it: pymunk in rrbody.engine, MuJoCo in rrbody.mujoco_adapter (others may read one engine's
    objects, as the recorder reads pymunk's shapes, never both)."""
    by_package: dict[str, set[str]] = {}
    for m in GRAPH:
        if _package(m):
            by_package.setdefault(_package(m), set()).update(_engines(m))
    both = {p: sorted(e) for p, e in by_package.items() if len(e) > 1}
    assert not both, both
    for engine, homes in ENGINES.items():
        for home in homes:
            assert by_package.get(home) == {engine}, (home, by_package.get(home))


def test_the_engine_scan_finds_an_import(tmp_path: Path) -> None:
    f = tmp_path / "m.py"
    f.write_text("def g():\n    import pymunk.batch\n    m = require('mujoco', purpose='x')\n")
    assert _third_party(f) == {"pymunk", "mujoco"}


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


def test_the_makefile_rebuilds_the_kernels_on_an_edit_of_any_of_their_sources() -> None:
    """The Makefile's ``KERNEL_SOURCES`` (what makes ``.venv/.kernels`` stale) names every folder and root
    file ``rrbody._cache.source_hash`` covers, so a kernel edit is compiled again by ``make test``."""
    import re

    from rrbody import _cache

    text = (PKG.parent / "Makefile").read_text()
    block = re.search(r"^KERNEL_SOURCES := (.*?)\n(?!\t)", text, re.S | re.M)
    assert block, "no KERNEL_SOURCES in the Makefile"
    names = set(re.findall(r"rrbody/([\w.]+)", block.group(1)))
    assert set(_cache.KERNEL_LAYERS) <= names, set(_cache.KERNEL_LAYERS) - names
    assert set(_cache.KERNEL_ROOT_FILES) <= names, set(_cache.KERNEL_ROOT_FILES) - names
