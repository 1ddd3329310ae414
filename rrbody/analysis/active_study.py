"""Chiral active bodies in a walled box: reverse-rotation episodes, collisions, a binary mixture.

One run (:class:`Box`): ``n`` active bodies in a square box with walls, at area fraction ``packing``,
a binary mixture of two species, both chiral (their propulsion acts off the centre of gravity, so
alone each swims on a circle, with the orbital sense of its propulsion's torque):

- ``L``: L-shapes (two boxes 2a x a and a x 2a on one body, a = 0.08 m); their rims have friction 0.5
  with everything, and contacts on their arms torque them: collisions can turn them against their
  orbit (they *can* reverse-rotate);
- ``disk``: disks of radius 0.1 m with frictionless rims (friction 0): every contact force passes
  through the centre, so no collision torques them; only their own noise could (they *cannot*, by
  collisions).

Each body: propulsion F = ``activity`` mu m g fixed in its body frame, acting 0.02 m off its centre of
gravity (a disk: sideways; an L: along its long arm), the medium's drag gamma_t = 2/s, gamma_r = 2/s,
rotational noise D_r = 0.2 rad^2/s, dry plane friction mu = 0.1 (:class:`rrbody.plugin.Active`,
:class:`rrbody.plugin.PlaneFriction`); dt = 1/120 s, sampled every ``every`` steps. Reverse-rotation
episodes per body: :func:`rrbody.analysis.episodes.reverse_episodes` on its unwrapped angle and spin,
the orbital sense the sign of its propulsion's torque, min_turn = pi, collision window 0.5 s (contacts
with another body; walls are counted apart). A run is deterministic from its seed (placement and
noise), so an ensemble (:func:`ensemble`: local processes or a Dask cluster, resumable from a
checkpoint) gives the same rows whatever the number of workers.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rrbody.analysis.episodes import reverse_episodes
from rrbody.model.active import MAX_SEED
from rrbody.model.checks import check_int, check_range

__all__ = ["Box", "build", "run_box", "species_stats", "ensemble", "seed_table", "summary", "SPECIES", "WINDOW",
           "MU", "BOX_RANGES", "STAT_KEYS", "MEAN_KEYS"]

SPECIES = ("L", "disk")
A_ARM, R_DISK, DENSITY = 0.08, 0.1, 20.0  # m, m, kg/m^2
MU, G, DRAG, ROT_DRAG, D_ROT, OFFSET = 0.1, 9.81, 2.0, 2.0, 0.2, 0.02  # -, m/s^2, 1/s, 1/s, rad^2/s, m
WINDOW = 0.5  # s: an episode began at a collision if a contact with another body began this long before
#: Box's parameters: (lo, hi, lo open, unit), checked in this order; the command line's help shows them
BOX_RANGES: dict[str, tuple[float, float, bool, str]] = {
    "n": (2, 100_000, False, "bodies"), "packing": (0.01, 0.6, False, ""), "activity": (0.0, 100.0, True, ""),
    "mix": (0.0, 1.0, False, ""), "seed": (0, MAX_SEED, False, ""), "t_end": (0.0, 1e5, True, "s"),
    "every": (1, 1000, False, "steps"), "dt": (1e-6, 0.1, False, "s")}
BOX_INTEGERS = ("n", "seed", "every")
#: the statistics of one species (species_stats), in the order tables list them
STAT_KEYS = ("bodies", "episodes", "episodes_per_body_per_min", "fraction_at_collision", "chance_at_collision",
             "fraction_at_wall_only", "duration_mean_s", "duration_median_s", "time_fraction", "reversed_fraction",
             "collisions_per_body_per_min")
#: the statistics averaged over seeds by seed_table
MEAN_KEYS = ("episodes_per_body_per_min", "fraction_at_collision", "chance_at_collision", "fraction_at_wall_only",
             "duration_mean_s", "time_fraction", "reversed_fraction", "collisions_per_body_per_min")


@dataclass(frozen=True)
class Box:
    """One run's parameters: ``n`` bodies (in [2, 100000]), area fraction ``packing`` (in [0.01, 0.6]),
    ``activity`` = F / (mu m g) (in (0, 100]), fraction ``mix`` of L-shapes (in [0, 1]), ``seed``
    (integer in [0, 2^63 - 1]), horizon ``t_end`` (s, in (0, 1e5]), ``every`` steps between samples (in [1, 1000]),
    time step ``dt`` (s, in [1e-6, 0.1]): :data:`BOX_RANGES`; ValueError naming the parameter otherwise."""

    n: int = 200
    packing: float = 0.25
    activity: float = 3.0
    mix: float = 0.5
    seed: int = 0
    t_end: float = 60.0
    every: int = 6
    dt: float = 1.0 / 120.0

    def __post_init__(self) -> None:
        for name, (lo, hi, lo_open, unit) in BOX_RANGES.items():
            v = getattr(self, name)
            object.__setattr__(self, name, check_int(name, v, int(lo), int(hi), unit=unit) if name in BOX_INTEGERS
                               else check_range(name, v, lo, hi, lo_open=lo_open, unit=unit))


def build(box: Box) -> tuple[Any, Any, list[Any], list[str], np.ndarray, float]:
    """(space, pf, bodies, species, senses, side): the bodies on a jittered grid in a walled square box
    of side ``side`` (m), random angles, at rest; ``senses`` the orbital sense of each (+1, -1)."""
    import pymunk

    from rrbody.engine.plugin import PlaneFriction
    from rrbody.model.active import Active

    rng = np.random.default_rng(box.seed)
    n_l = int(round(box.mix * box.n))
    kinds = ["L"] * n_l + ["disk"] * (box.n - n_l)
    rng.shuffle(kinds)
    area = n_l * 4 * A_ARM**2 + (box.n - n_l) * math.pi * R_DISK**2
    side = math.sqrt(area / box.packing)
    space = pymunk.Space()
    space.iterations = 10
    # the split step (friction before pymunk's contact solve), as the recorded study ran it: in a jammed
    # cluster every body is one island with all its neighbours, and the coupled step's solve there costs far
    # more than the physics it corrects (docs/active.md, "The split step in clusters")
    pf = PlaneFriction(space, g=G, scheme="split")
    pf.seed(box.seed)
    corners = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)]
    walls = [pymunk.Segment(space.static_body, a, b, 0.05) for a, b in zip(corners, corners[1:] + corners[:1])]
    for w in walls:
        w.friction = 0.5
        w.collision_type = 2
    space.add(*walls)
    k = int(math.ceil(math.sqrt(box.n)))
    cell = side / k
    bodies, senses = [], np.empty(box.n)
    for i, kind in enumerate(kinds):
        b = pymunk.Body()
        a = A_ARM
        if kind == "L":  # the long arm along body x
            shapes = [pymunk.Poly(b, [(-a, -a), (a, -a), (a, 0.0), (-a, 0.0)]),
                      pymunk.Poly(b, [(-a, 0.0), (0.0, 0.0), (0.0, a), (-a, a)])]
        else:
            shapes = [pymunk.Circle(b, R_DISK)]
        for s in shapes:
            s.density = DENSITY
            s.friction = 0.5 if kind == "L" else 0.0
            s.elasticity = 0.2
            s.collision_type = 1
        jitter = 0.25 * max(cell - 2 * R_DISK, 0.0)
        b.position = (cell * (i % k + 0.5) + jitter * rng.uniform(-1, 1),
                      cell * (i // k + 0.5) + jitter * rng.uniform(-1, 1))
        b.angle = rng.uniform(0.0, 2 * math.pi)
        space.add(b, *shapes)
        pf.add(b, mu=MU)
        act = Active(force=box.activity * MU * G * b.mass, angle=0.0 if kind == "L" else math.pi / 2,
                     point=(0.0, OFFSET) if kind == "L" else (OFFSET, 0.0), drag=DRAG, rot_drag=ROT_DRAG,
                     rot_diffusion=D_ROT)
        pf.activate(b, act)
        senses[i] = math.copysign(1.0, act.torque)
        bodies.append(b)
    return space, pf, bodies, kinds, senses, side


def run_box(box: Box, *, watch: Callable[[Any, Any, list[Any]], Any] | None = None) -> dict[str, Any]:
    """Run ``box`` and find every body's episodes. Returns the parameters, per body its species,
    orbital sense, body-body and wall contacts (counts) and episodes, per species the statistics
    (:func:`species_stats`; each episode also says ``starts_at_wall``: a wall contact began in its window), and the
    samples: times ``t`` (s), unwrapped angles ``angle`` (rad) and spins ``spin`` (rad/s; pymunk's, half a step after
    the sample's time), (samples, bodies).

    ``watch(space, pf, bodies)``, if given, is called once before the first step and must return an
    object with a ``capture()`` method (a :class:`rrbody.plugin.Recorder`), called after every step
    and once before the first; it is returned under ``"watcher"``."""
    from rrbody.engine.memory.batchio import BatchIO, body_uid
    from rrbody.engine.memory.compat import on_begin

    space, pf, bodies, kinds, senses, side = build(box)
    index = {b: j for j, b in enumerate(bodies)}
    hits: list[list[float]] = [[] for _ in bodies]
    walls: list[list[float]] = [[] for _ in bodies]

    def begin(arb: Any, sp: Any, data: Any) -> None:
        for b in arb.bodies:
            if b in index:
                hits[index[b]].append(pf.t)

    def wall(arb: Any, sp: Any, data: Any) -> None:
        for b in arb.bodies:
            if b in index:
                walls[index[b]].append(pf.t)

    on_begin(space, 1, 1, begin)  # pymunk 6 and 7 alike
    on_begin(space, 1, 2, wall)
    io = BatchIO(space, poses=True)  # x, y, angle, vx, vy, spin of every body of the space
    got, ids, _ = io.read()
    want = np.array([body_uid(b) for b in bodies], dtype=np.int64)
    order = np.argsort(ids)
    rows = order[np.searchsorted(ids[order], want)]  # each body's row in the bulk read
    n_steps = int(round(box.t_end / box.dt))
    n_samples = n_steps // box.every + 1
    ang = np.empty((n_samples, len(bodies)))
    spin = np.empty_like(ang)
    t = np.empty(n_samples)
    watcher = watch(space, pf, bodies) if watch is not None else None
    k = 0
    for step in range(n_steps + 1):
        if step:
            pf.step(box.dt)
        if watcher is not None:
            watcher.capture()
        if step % box.every == 0:
            got, ids, _ = io.read()
            if not np.array_equal(ids[rows], want):  # (the space's order changed: find the rows again)
                order = np.argsort(ids)
                rows = order[np.searchsorted(ids[order], want)]
            t[k] = pf.t
            ang[k] = got[rows, 2]
            spin[k] = got[rows, 5]
            k += 1
    ang = np.unwrap(ang[:k], axis=0)
    spin, t = spin[:k], t[:k]
    per_body = []
    for j in range(len(bodies)):
        eps = reverse_episodes(t, ang[:, j], spin[:, j], sense=senses[j], hits=hits[j], window=WINDOW)
        at_wall = reverse_episodes(t, ang[:, j], spin[:, j], sense=senses[j], hits=walls[j], window=WINDOW)
        chance = _chance(t, hits[j])
        for e, w in zip(eps, at_wall):  # the same episodes, attributed to a wall contact instead
            e["starts_at_wall"] = w["starts_at_collision"]
            e["chance"] = chance
        per_body.append({"species": kinds[j], "sense": int(senses[j]), "collisions": len(hits[j]),
                         "wall_contacts": len(walls[j]), "episodes": eps,
                         "reversed_fraction": float(np.mean(senses[j] * spin[:, j] < 0.0))})
    out: dict[str, Any] = {"params": asdict(box), "side": side, "bodies": per_body, "t": t, "angle": ang,
                           "spin": spin, "senses": senses,
                           "stats": {s: species_stats(per_body, s, float(t[-1] - t[0])) for s in SPECIES}}
    if watcher is not None:
        out["watcher"] = watcher
    return out


def _chance(t: np.ndarray, hits: list[float]) -> float:
    """The fraction of the sample times t_k with a contact begun in [t_k - WINDOW, t_k]: how often an
    episode would 'begin at a collision' if it began at a random sample (the null the measured fraction
    is compared with)."""
    h = np.sort(np.asarray(hits, dtype=float))
    if len(h) == 0:
        return 0.0
    k = np.searchsorted(h, t - WINDOW, side="left")
    ok = k < len(h)
    return float(np.mean(ok & (h[np.minimum(k, len(h) - 1)] <= t + 1e-9)))


def species_stats(per_body: list[dict[str, Any]], species: str, span: float) -> dict[str, Any]:
    """Statistics of one species over a run of ``span`` s: bodies, episodes per body per minute, the
    fraction of its samples with the spin against the orbit (``reversed_fraction``: episodes or not), the
    fraction that began at a collision and the fraction expected by chance (each episode's body's
    :func:`_chance`, averaged over the episodes), the fraction begun at a wall contact only, mean and median duration
    (s), fraction of time in an episode, collisions per body per minute."""
    rows = [b for b in per_body if b["species"] == species]
    if not rows or span <= 0.0:
        return {"bodies": len(rows)}
    eps = [e for b in rows for e in b["episodes"]]
    dur = np.array([e["duration"] for e in eps])
    return {"bodies": len(rows), "episodes": len(eps),
            "episodes_per_body_per_min": 60.0 * len(eps) / (len(rows) * span),
            "fraction_at_collision": (sum(e["starts_at_collision"] for e in eps) / len(eps)) if eps else None,
            "chance_at_collision": float(np.mean([e["chance"] for e in eps])) if eps else None,
            "fraction_at_wall_only": (sum(e["starts_at_wall"] and not e["starts_at_collision"] for e in eps) / len(eps))
            if eps else None,
            "duration_mean_s": float(dur.mean()) if eps else None,
            "duration_median_s": float(np.median(dur)) if eps else None,
            "time_fraction": float(dur.sum() / (len(rows) * span)),
            "reversed_fraction": float(np.mean([b["reversed_fraction"] for b in rows])),
            "collisions_per_body_per_min": 60.0 * sum(b["collisions"] for b in rows) / (len(rows) * span)}


def summary(res: dict[str, Any]) -> dict[str, Any]:
    """A run's result (:func:`run_box`) without its samples and watcher: the parameters, the box's side
    (m), per body its species, sense, contacts and episodes, per species the statistics (plain JSON)."""
    return {k: res[k] for k in ("params", "side", "bodies", "stats")}


def seed_table(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """An ensemble's rows (:func:`ensemble`) averaged over seeds: per (packing, activity) and species, in
    the order the rows first give them, the episodes summed over seeds, each of :data:`MEAN_KEYS` its
    mean over the seeds where it is defined (None where none) and ``<key>_sd`` its sample standard
    deviation (None with fewer than two), and ``seeds`` the number of runs."""
    groups: dict[tuple[float, float], list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["packing"], r["activity"]), []).append(r)
    table = []
    for (p, a), grp in groups.items():
        for sp in SPECIES:
            st = [r["stats"][sp] for r in grp]
            vals = {k: [s[k] for s in st if s.get(k) is not None] for k in MEAN_KEYS}
            table.append({"packing": p, "activity": a, "species": sp, "seeds": len(grp),
                          "episodes": sum(s.get("episodes", 0) for s in st),
                          **{k: (float(np.mean(v)) if v else None) for k, v in vals.items()},
                          **{f"{k}_sd": (float(np.std(v, ddof=1)) if len(v) > 1 else None) for k, v in vals.items()}})
    return table


def _run_points(spec: dict[str, Any], batch: list[int]) -> list[dict[str, Any]]:
    """A pool task: the statistics rows of the points ``batch`` of ``spec["points"]``."""
    rows = []
    for i in batch:
        res = run_box(Box(**spec["points"][i]))
        rows.append({"i": i, **spec["points"][i], "stats": res["stats"]})
    return rows


def ensemble(points: list[Box], *, workers: int | None = None, checkpoint: str | os.PathLike[str] | None = None,
             scheduler: Any = None, progress: bool = False) -> list[dict[str, Any]]:
    """Every point's statistics (``i``, its parameters, ``stats``), in the points' order, computed on
    local processes (:func:`rrbody.analysis.pool.iter_local`; ``workers=0``: in this process). Each point
    is deterministic, so the rows do not depend on ``workers``.

    ``checkpoint``: a JSON-lines file (the sweeps' format, :mod:`rrbody.analysis.sweep_store`) that
    finished points are appended to as they finish; an existing one written for the same points and
    rrbody version is resumed (only the missing points are computed), one for other points refused
    (ValueError). The caller deletes it when the ensemble is no longer needed. ``scheduler``: a Dask
    scheduler's address or a ``distributed.Client`` (:func:`rrbody.analysis.pool.iter_dask`; overrides
    ``workers``), as for the sweeps. ``progress``: a progress bar on stderr (the sweeps' bar)."""
    from rrbody._version import __version__
    from rrbody.analysis.pool import (
        check_scheduler,
        connect_scheduler,
        iter_dask,
        iter_local,
        plan_batches,
        plan_workers,
    )
    from rrbody.analysis.sweep import progress_bar
    from rrbody.analysis.sweep_store import read_checkpoint, stream_checkpoint

    spec = {"kind": "active_study", "rrbody_version": __version__, "points": [asdict(p) for p in points]}
    path = None if checkpoint is None else Path(checkpoint)
    done: dict[int, dict[str, Any]] = read_checkpoint(path, spec) if path is not None and path.exists() else {}
    todo = [i for i in range(len(points)) if i not in done]
    if scheduler is not None:
        check_scheduler(scheduler)
    client = connect_scheduler(scheduler) if isinstance(scheduler, str) and todo else scheduler
    bar = progress_bar(len(points), len(done), progress and bool(todo), "active ensemble")
    try:
        w = 0 if client is not None or not todo else plan_workers(workers, len(todo))
        batches = plan_batches(todo, 1, w)
        results = iter_dask(_run_points, spec, batches, client) if client is not None and todo \
            else iter_local(_run_points, spec, batches, w)
        if path is not None:
            for n in stream_checkpoint(path, spec, results, done):
                if bar is not None:
                    bar.update(n)
        else:
            for rows in results:
                done.update((r["i"], r) for r in rows)
                if bar is not None:
                    bar.update(len(rows))
    finally:
        if bar is not None:
            bar.close()
        if client is not None and client is not scheduler:
            client.close()
    return [done[i] for i in range(len(points))]
