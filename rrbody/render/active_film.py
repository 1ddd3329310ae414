"""Pictures of the active-bodies box study (:mod:`rrbody.analysis.active_study`): a run filmed by the public
Recorder with only the established reverse-rotation episodes in red, and the ensemble's statistics
against the packing fraction. Shared by ``scenes/active.py`` and ``rrbody active`` / ``rrbody
active-ensemble``.

Colours (movie and rerun recording): red inside an episode the analysis established
(:func:`rrbody.analysis.episodes.episode_marks`), blue turning with the body's orbit, grey neither.
The marks come from the analysis's samples, never from the pictures: a recorder captures exactly the
analysis's sample times (checked).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["run_filmed", "episode_colours", "write_movie", "write_rerun", "plot_ensemble", "ensemble_figure",
           "TITLE", "FIGURE_PANELS"]

TITLE = "red: in an RR episode; blue: with its orbit; grey: neither"
#: the ensemble figure's panels: (statistic of seed_table, axis label)
FIGURE_PANELS = (("episodes_per_body_per_min", "RR episodes per body per minute"),
                 ("fraction_at_collision", "fraction begun at a body-body collision"),
                 ("duration_mean_s", "mean episode duration (s)"))
MARGIN = 0.2  # m around the box's walls in a movie


class _Films:
    """Recorders of one run (a movie's and a rerun recording's), captured together."""

    def __init__(self, *recs: Any) -> None:
        self.recs = recs

    def capture(self) -> None:
        for r in self.recs:
            r.capture()


class _Steps:
    """A progress bar over a run's steps, as a watcher (``capture`` is called once before the first step
    and after every step)."""

    def __init__(self, total: int) -> None:
        from tqdm import tqdm

        self.bar = tqdm(total=total, desc="active run", unit="step", dynamic_ncols=True)
        self.started = False

    def capture(self) -> None:
        if self.started:
            self.bar.update(1)
        self.started = True


def run_filmed(box: Any, *, movie: bool = True, rerun_every: int | None = None,
               max_mb: float = 4000.0, progress: bool = False) -> tuple[dict[str, Any], Any, Any]:
    """:func:`rrbody.analysis.active_study.run_box` of ``box`` watched by a Recorder (poses only) that
    keeps every sample the analysis keeps (``movie``) and one that keeps every ``rerun_every``-th of them
    (None: no such recorder); ``progress``: a progress bar over the steps on stderr. Returns (the run's
    result, the movie's recorder or None, the rerun recording's or None)."""
    from rrbody.analysis.active_study import run_box
    from rrbody.render.recorder import Recorder

    every = [box.every] if movie else []
    if rerun_every is not None:
        every.append(int(rerun_every) * box.every)
    if not every and not progress:
        return run_box(box), None, None
    bar = _Steps(int(round(box.t_end / box.dt))) if progress else None

    def watch(space: Any, pf: Any, bodies: list[Any]) -> _Films:
        recs = [Recorder(space, pf, bodies=bodies, every=e, motion=False, max_mb=max_mb) for e in every]
        return _Films(*recs, *([bar] if bar is not None else []))

    try:
        res = run_box(box, watch=watch)
    finally:
        if bar is not None:
            bar.bar.close()
    recs = [r for r in res.pop("watcher").recs if r is not bar]
    rec = recs.pop(0) if movie else None
    rrd = recs.pop(0) if rerun_every is not None else None
    return res, rec, rrd


def episode_colours(res: dict[str, Any]) -> np.ndarray:
    """The marks (samples, bodies) of a run: -1 inside an established episode, +1 turning with the orbit,
    0 neither (:func:`rrbody.analysis.episodes.episode_marks`)."""
    from rrbody.analysis.episodes import episode_marks

    return np.column_stack([episode_marks(res["t"], res["spin"][:, j], b["episodes"], sense=b["sense"])
                            for j, b in enumerate(res["bodies"])])


def _same_times(rec: Any, t: np.ndarray) -> None:
    if not np.allclose(rec.times, t):  # every `every` steps from t = 0, as the analysis samples
        raise RuntimeError("the recorder and the analysis sampled different times")


def write_movie(res: dict[str, Any], rec: Any, path: str | os.PathLike[str], *, fps: float = 20.0,
                speed: float = 2.0, size: tuple[int, int] = (480, 480), t_end: float | None = None,
                force: bool = False, progress: bool | None = None) -> Path:
    """The movie of a run filmed by :func:`run_filmed` (its movie recorder ``rec``), coloured by the
    episodes, the box and its walls in view; ``t_end`` (s) ends it early. Returns the path."""
    marks = episode_colours(res)
    _same_times(rec, res["t"])
    s = res["side"]
    box = (-MARGIN, s + MARGIN, -MARGIN, s + MARGIN)
    end = None if t_end is None else min(float(t_end), float(res["t"][-1]))
    return rec.movie(path, fps=fps, speed=speed, size=size, color=marks, box=box, t_end=end, title=TITLE,
                     force=force, progress=progress)


def write_rerun(res: dict[str, Any], rrd: Any, path: str | os.PathLike[str], *, rerun_every: int,
                force: bool = False) -> Path | None:
    """The rerun recording of a run filmed by :func:`run_filmed` (its rerun recorder ``rrd``, keeping
    every ``rerun_every``-th sample), coloured by the episodes. Returns the path."""
    marks = episode_colours(res)[::rerun_every]
    _same_times(rrd, res["t"][::rerun_every])
    return rrd.rerun(path, color=marks, plots=[], force=force)  # poses only: no plots (they need motion)


def plot_ensemble(axes: Any, table: list[dict[str, Any]]) -> None:
    """Draw :data:`FIGURE_PANELS` of an ensemble's seed table (:func:`rrbody.analysis.active_study.seed_table`)
    against the packing fraction on three matplotlib axes: mean +- standard deviation over the seeds, one
    line per species (L red circles, disk blue squares) and activity (the largest solid); on the collision
    panel, dotted, the fraction expected by chance for the L-shapes."""
    from rrbody.analysis.active_study import SPECIES

    packings = sorted({r["packing"] for r in table})
    activities = sorted({r["activity"] for r in table})
    # the largest activity solid (its chance line dotted), the next dashed (dash-dotted), ...
    styles = {a: ("-", "--", "-.", ":")[(len(activities) - 1 - i) % 4] for i, a in enumerate(activities)}
    chance = {a: (":", "-.", "--", "-")[(len(activities) - 1 - i) % 4] for i, a in enumerate(activities)}
    at = {(r["packing"], r["activity"], r["species"]): r for r in table}

    def val(r: dict[str, Any] | None, k: str, empty: float) -> float:
        return empty if r is None or r.get(k) is None else float(r[k])

    for (k, label), a in zip(FIGURE_PANELS, axes):
        for sp in SPECIES:
            for act in activities:
                r = [at.get((p, act, sp)) for p in packings]
                a.errorbar(packings, [val(x, k, np.nan) for x in r], yerr=[val(x, f"{k}_sd", 0.0) for x in r],
                           marker="o" if sp == "L" else "s", ls=styles[act],
                           color="tab:red" if sp == "L" else "tab:blue", capsize=3, label=f"{sp}, activity {act:g}")
        if k == "fraction_at_collision":
            for act in activities:
                r = [at.get((p, act, "L")) for p in packings]
                a.plot(packings, [val(x, "chance_at_collision", np.nan) for x in r], chance[act], marker="x",
                       color="0.4", label=f"L, activity {act:g}: by chance")
            a.legend(fontsize=7)
            a.set_ylim(0.0, 1.1)
        a.set(xlabel="packing fraction", ylabel=label)


def ensemble_figure(table: list[dict[str, Any]], path: str | os.PathLike[str], *, title: str = "",
                    force: bool = False) -> Path:
    """The three panels of :func:`plot_ensemble` side by side as a byte-reproducible PNG, written to a
    temporary sibling and renamed. Returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.model.io import atomic_path
    from rrbody.render.figures import savefig_reproducible

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5), constrained_layout=True)
    try:
        plot_ensemble(ax, table)
        ax[0].legend(fontsize=8)
        if title:
            fig.suptitle(title, fontsize=10)
        with atomic_path(path, force=force, name="--plot") as tmp:
            savefig_reproducible(fig, tmp, fmt="png", dpi=150)
    finally:
        plt.close(fig)
    return Path(path)
