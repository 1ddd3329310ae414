"""What takes over where rrbody's uses of pymunk's and numba's private names are missing
(docs/versions.md lists every such use): each takeover is forced here and must give the same bits
as the route it replaces (or, for numba's cache, refuse what it cannot trust).

References: the default route of the same program (bit-for-bit equality: the takeovers move the
same numbers by other means, they compute nothing of their own), and numba's own cache index.
"""

from __future__ import annotations

import math
import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pymunk
import pytest

from rrbody.engine import EngineSettings, attach
from rrbody.engine.memory.batchio import ROUTES, BatchIO
from rrbody.engine.memory.bodymem import layout
from rrbody.engine.memory.compat import on_begin
from rrbody.model.bodies import Ellipse
from rrbody.model.drive import CircularDrive
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene
from rrbody.plugin import PlaneFriction, Recorder


def _sliding() -> tuple[pymunk.Space, PlaneFriction, list[pymunk.Body]]:
    """Three bodies sliding into each other (two in the plugin, one not) and a spinning kinematic one."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    bodies = []
    for i, make in enumerate((lambda b: pymunk.Circle(b, 0.2), lambda b: pymunk.Poly.create_box(b, (0.4, 0.3)),
                              lambda b: pymunk.Circle(b, 0.15, (0.05, 0.0)))):
        b = pymunk.Body()
        s = make(b)
        s.density = 1.0
        b.position, b.angle = (0.5 * i, 0.1 * i), 0.3 * i
        b.velocity, b.angular_velocity = (1.0 - i, 0.3 * i), 4.0 - 3.0 * i
        space.add(b, s)
        if i != 2:
            pf.add(b, mu=0.3)
        bodies.append(b)
    kin = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    kin.position, kin.velocity, kin.angular_velocity = (0.2, 0.8), (0.1, 0.0), 1.5
    space.add(kin, pymunk.Circle(kin, 0.05))
    return space, pf, bodies


@pytest.mark.private
def test_every_recorder_route_captures_the_same_frames(monkeypatch: pytest.MonkeyPatch) -> None:
    """The recorder reads its bodies' structs where the layout is proven (bodymem.layout), else the
    space's bulk read on BatchIO's routes (pymunk.batch's C iterator, its public function, each body's
    properties): every route stores the same frames, bit for bit, through collisions, a kinematic
    body and a body outside the plugin."""
    assert layout() is not None  # on every pymunk the suite runs on: else the struct route goes untested
    space, pf, bodies = _sliding()
    recs = [Recorder(space, pf)]
    monkeypatch.setattr("rrbody.engine.recording.tape.layout", lambda: None)
    for route in ROUTES:
        rec = Recorder(space, pf)
        rec.tape._io = BatchIO(space, poses=True, route=route)  # forced (the default is the fastest this pymunk has)
        assert rec.tape._io.route == route
        recs.append(rec)
    assert recs[0].tape._io is None
    for _ in range(60):
        pf.step(1e-2)
        assert all(r.capture() for r in recs)
    for r in recs[1:]:
        assert np.array_equal(r.frames, recs[0].frames) and np.array_equal(r.times, recs[0].times)
    assert recs[0].frames[-1, 0, 0] != recs[0].frames[0, 0, 0]  # they moved


@pytest.mark.private
def test_the_drive_without_chipmunks_setters_runs_the_same_bits(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody's builder moves a driven body's driver through Chipmunk's setters (pymunk.batch.lib,
    not a documented name); without them, through the driver's public properties: the same run."""
    import pymunk.batch as pb

    def run() -> tuple[Any, ...]:
        sc = Scene(body=Ellipse(R0=0.1, delta=0.5, l=0.2), drive=CircularDrive(0.6),
                   friction=Friction.from_k("dry", 0.05, 1.0), phi0=math.pi)
        space = pymunk.Space()
        h = attach(space, sc, settings=EngineSettings(dt=2e-3))
        for _ in range(300):
            h.plane.step(2e-3)
        return (*h.body.position, h.body.angle, *h.body.velocity, h.body.angular_velocity, h.phi, h._drv_ptr is None)

    fast = run()
    assert fast[-1] is False  # Chipmunk's setters: the fast route
    real = pb.lib

    class NoSetters:
        """pymunk's cffi lib without Chipmunk's body setters (as a pymunk that stopped exposing them)."""

        def __getattr__(self, name: str) -> Any:
            if name in ("cpBodySetVelocity", "cpBodySetPosition"):
                raise AttributeError(name)
            return getattr(real, name)

    monkeypatch.setattr(pb, "lib", NoSetters())
    slow = run()
    assert slow[-1] is True and slow[:-1] == fast[:-1]


def test_on_begin_observes_contacts_and_lets_them_act() -> None:
    """rrbody.engine.memory.compat.on_begin (pymunk 6's collision handlers, pymunk 7's on_collision): the
    callback sees each contact begin, and the contact still acts. Two equal disks head on: the
    collision reverses their approach (elasticity 0: they leave together, each at their mean
    velocity, 0 m/s)."""
    for types_ in ((None, None), (1, 2), (1, None)):
        space = pymunk.Space()
        disks = []
        for x, v, ct in ((-0.5, 1.0, 1), (0.5, -1.0, 2)):
            b = pymunk.Body()
            s = pymunk.Circle(b, 0.1)
            s.density, s.collision_type = 1.0, ct
            b.position, b.velocity = (x, 0.0), (v, 0.0)
            space.add(b, s)
            disks.append(b)
        hits: list[float] = []
        on_begin(space, *types_, lambda arb, sp, data: hits.append(1.0))
        for _ in range(100):
            space.step(1e-2)
        assert hits == [1.0], types_
        assert abs(disks[0].velocity.x) < 1e-9 and abs(disks[1].velocity.x) < 1e-9  # the contact acted
    with pytest.raises(ValueError, match="b must be None when a is None"):
        on_begin(pymunk.Space(), None, 2, lambda *a: None)


@pytest.mark.private
def test_kernels_compile_without_numbas_private_option(monkeypatch: pytest.MonkeyPatch) -> None:
    """rrbody.lean's kernels are compiled with numba's undocumented ``_nrt=False``; a numba without it
    gets no option (rrbody._private.no_refcount), and a kernel compiled so computes the same numbers."""
    import numba
    import numba.core.cpu as cpu

    from rrbody._private import no_refcount, private_allowed
    from rrbody.engine.memory.structio import gather

    assert no_refcount() == ({"_nrt": False} if private_allowed() else {})  # the numbas the suite runs on have it
    monkeypatch.setattr(cpu, "CPUTargetOptions", type("Options", (), {}))
    assert no_refcount.__wrapped__() == {}
    monkeypatch.undo()
    space, pf, bodies = _sliding()
    pf.step(1e-3)
    sio = pf._sio
    got = [np.zeros((2, 7)), np.zeros((2, 7))]
    args = (sio._addr, sio._offs, sio._space)
    assert gather(*args, got[0]) == -1
    assert numba.njit(gather.py_func)(*args, got[1]) == -1  # with reference counting
    assert np.array_equal(got[0], got[1]) and got[0][0, 1] == bodies[0].velocity.x


def test_sleeping_turned_on_sends_the_step_to_the_bulk_route() -> None:
    """The one-call struct step runs only while sleeping is off (pymunk's space.sleep_time_threshold is inf):
    turned on mid-run, the step goes through pymunk.batch, and the run goes on."""
    space, pf, bodies = _sliding()
    for n in range(200):
        if n == 100:
            space.sleep_time_threshold = 0.5
        pf.step(1e-3)
        if n == 100:
            assert pf._route()[0] is pf._io
    assert all(math.isfinite(b.position.x) for b in bodies)


@pytest.mark.private
def test_the_space_probe_reads_what_pymunk_says() -> None:
    """bodymem.sleep_offset: found on the suite's pymunk, and a compiled read at that place of a space's
    struct gives what pymunk's property gives, through values set by its setter (its other settings moved
    too); the plugin's one call reads it there."""
    from numba import njit

    from rrbody.engine.memory.bodymem import address, f64_at, sleep_offset

    @njit
    def read(a: int) -> float:
        return f64_at(a)

    off = sleep_offset()
    assert off is not None
    space, pf, _ = _sliding()
    pf.step(1e-3)
    assert pf._sio._sleep_at == address(space._space) + off
    for v in (0.5, math.inf, 2.0, 1e-9, math.inf):
        space.sleep_time_threshold = v
        space.idle_speed_threshold, space.damping = 0.25 * v if v < math.inf else 0.0, 0.5
        assert read(address(space._space) + off) == v == space.sleep_time_threshold


def test_without_the_space_probe_the_property_decides_the_route(monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the probe of cpSpace finds nothing (bodymem.sleep_offset None) the plugin reads pymunk's
    property each step and keeps no plan: sleeping turned on mid-run still sends the step to the bulk
    route, and the run is the one with the probe, bit for bit."""
    import rrbody.engine.memory.structio as sio_module

    runs = []
    for probe in (True, False):
        if not probe:
            monkeypatch.setattr(sio_module, "sleep_offset", lambda: None)
        space, pf, bodies = _sliding()
        if pf._sio is None:  # RRBODY_NO_PRIVATE: no struct route at all, nothing to compare
            pytest.skip("the struct route is off (RRBODY_NO_PRIVATE)")
        assert (pf._sio._sleep_at == 0) is not probe
        for n in range(200):
            if n == 100:
                space.sleep_time_threshold = 0.5
                assert pf._route()[0] is pf._io
            if n == 150:
                space.sleep_time_threshold = math.inf
            pf.step(1e-3)
            if not probe:
                assert pf._plan is None
        runs.append([(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies])
    assert runs[0] == runs[1]


def test_numba_refuses_kernels_another_numba_cached(tmp_path: Path) -> None:
    """rrbody's kernel folders are keyed by its version and sources, not by numba's: two environments
    with different numbas share a folder. numba's own index names the numba that wrote it and
    numba loads none written by another (numba.core.caching.IndexDataCacheFile): such an index reads
    as empty, so the kernel is compiled again, never loaded."""
    from numba.core import caching

    idx = caching.IndexDataCacheFile(str(tmp_path), "kernel-probe", "stamp")
    idx.save("key", "data")
    assert idx.load("key") == "data"
    index = next(tmp_path.glob("*.nbi"))
    with open(index, "rb") as f:
        version = pickle.load(f)
        rest = f.read()
    with open(index, "wb") as f:
        pickle.dump(version + ".other", f, protocol=-1)
        f.write(rest)
    assert caching.IndexDataCacheFile(str(tmp_path), "kernel-probe", "stamp").load("key") is None


@pytest.mark.private
def test_cython_blas_preload_falls_back() -> None:
    """rrbody.cli.lean.preload_cython_blas loads scipy's ``cython_blas`` without ``scipy.linalg``; where
    it is not where expected it does nothing, and numba's own import (the whole of scipy.linalg) gives
    the same module a flip time needs. Each in a fresh process: the module can be loaded once."""
    import subprocess
    import sys

    probe = ("import sys, os, scipy{patch}; from rrbody.cli.lean import preload_cython_blas; preload_cython_blas(); "
             "print('scipy.linalg.cython_blas' in sys.modules, 'scipy.linalg' in sys.modules); "
             "from rrbody import flip_time, rod_mass_scene; "
             "print(repr(flip_time(rod_mass_scene(H=0.2, k=0.05, omega=0.6)).t_f))")
    runs = {}
    for name, patch in (("preload", ""), ("fallback", "; scipy.__path__[:] = [os.devnull]")):
        out = subprocess.run([sys.executable, "-c", probe.format(patch=patch)], capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        runs[name] = out.stdout.split("\n")
    assert runs["preload"][0] == "True False"  # loaded alone, scipy.linalg not imported
    assert runs["fallback"][0] == "False False"  # nothing loaded: numba imports it when it needs it
    assert runs["preload"][1] == runs["fallback"][1]  # the same flip time, to the bit
