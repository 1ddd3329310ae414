"""Active chiral bodies (the paper's second outlook): reverse rotations begun by collisions, a binary mixture, 1,000 bodies.

Bodies and rules: :mod:`rrbody.analysis.active_study` (L-shapes that collisions can turn against their
orbit, frictionless disks that they cannot; propulsion off the centre of gravity, drag, rotational
noise, dry plane friction; episodes by :func:`rrbody.analysis.episodes.reverse_episodes`).
1. A headline run: 1,000 bodies at packing 0.3, activity 3, 30 s, filmed by the public Recorder; the
   movie and the rerun recording colour a body red only inside an episode the analysis established
   (blue: turning with its orbit; grey: neither).
2. An ensemble: 200 bodies, 60 s, packing 0.1-0.4 x activity 1.5 and 3 x 3 seeds, on local processes
   (resumable: finished points are kept in results/active/_cache/ until the ensemble is complete).
Outputs: results/active/ (summary.json, active.png, active.rrd: regenerated here, too large for git),
movies/active.mp4 (the first 20 s at 2x).
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

PACKINGS, ACTIVITIES, SEEDS = (0.1, 0.2, 0.3, 0.4), (1.5, 3.0), (0, 1, 2)
HEADLINE = {"n": 1000, "packing": 0.3, "activity": 3.0, "seed": 0, "t_end": 30.0, "every": 4}
RRD_EVERY, MOVIE_T = 6, 20.0  # the rerun recording keeps every 6th sample (5 per s); the movie the first 20 s


class _Films:
    """Two recorders of one run (the movie's and the rerun recording's), captured together."""

    def __init__(self, *recs: object) -> None:
        self.recs = recs

    def capture(self) -> None:
        for r in self.recs:
            r.capture()  # type: ignore[attr-defined]


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.analysis.active_study import SPECIES, Box, ensemble, run_box
    from rrbody.analysis.episodes import episode_marks
    from rrbody.analysis.report import write_summary
    from rrbody.plugin import Recorder
    from rrbody.render.figures import save_figure

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. the headline run, filmed (poses only: the marks come from the analysis, not from the pictures)
    box = Box(**HEADLINE)
    head = run_box(box, watch=lambda space, pf, bodies: _Films(Recorder(space, pf, bodies=bodies, every=box.every,
                                                                         motion=False, max_mb=4000.0),
                                                                Recorder(space, pf, bodies=bodies, every=RRD_EVERY * box.every,
                                                                         motion=False, max_mb=4000.0)))
    rec, rrd = head["watcher"].recs
    marks = np.column_stack([episode_marks(head["t"], head["spin"][:, j], b["episodes"], sense=b["sense"])
                             for j, b in enumerate(head["bodies"])])
    if not np.allclose(rec.times, head["t"]):  # the same samples (every box.every steps, from t = 0)
        raise RuntimeError("the recorder and the analysis sampled different times")
    # 2. the ensemble over packing fraction, activity and seeds
    points = [Box(n=200, packing=p, activity=a, seed=s, t_end=60.0)
              for p, a, s in itertools.product(PACKINGS, ACTIVITIES, SEEDS)]
    ck = out_dir / "_cache" / "ensemble.jsonl"  # an interrupted scene resumes its ensemble from here
    ck.parent.mkdir(exist_ok=True)
    rows = ensemble(points, checkpoint=ck)
    ck.unlink()
    if not any(ck.parent.iterdir()):
        ck.parent.rmdir()
    table = {}
    for (p, a), grp in itertools.groupby(rows, key=lambda r: (r["packing"], r["activity"])):
        grp = list(grp)
        for sp in SPECIES:
            st = [r["stats"][sp] for r in grp]
            vals = {k: [s[k] for s in st if s.get(k) is not None] for k in
                    ("episodes_per_body_per_min", "fraction_at_collision", "chance_at_collision", "fraction_at_wall_only",
                     "duration_mean_s",
                     "time_fraction", "reversed_fraction", "collisions_per_body_per_min")}
            table[f"{p}|{a}|{sp}"] = {"packing": p, "activity": a, "species": sp,
                                      "episodes": sum(s.get("episodes", 0) for s in st),
                                      **{k: (float(np.mean(v)) if v else None) for k, v in vals.items()},
                                      **{f"{k}_sd": (float(np.std(v, ddof=1)) if len(v) > 1 else None)
                                         for k, v in vals.items()}}
    summary = {"headline": {**HEADLINE, "stats": head["stats"], "side_m": head["side"]},
               "ensemble": {"n": 200, "t_end_s": 60.0, "packings": PACKINGS, "activities": ACTIVITIES,
                            "seeds": SEEDS, "rows": list(table.values())}}
    write_summary(out_dir, summary, force=force)
    # figure: the ensemble's statistics against packing (mean +- sd over seeds); the headline's episodes
    fig, ax = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    for (k, label), a in zip((("episodes_per_body_per_min", "RR episodes per body per minute"),
                              ("fraction_at_collision", "fraction begun at a body-body collision"),
                              ("duration_mean_s", "mean episode duration (s)")), ax.flat):
        for sp, act in itertools.product(SPECIES, ACTIVITIES):
            r = [table[f"{p}|{act}|{sp}"] for p in PACKINGS]
            y = [x[k] if x[k] is not None else np.nan for x in r]
            e = [x[f"{k}_sd"] if x[f"{k}_sd"] is not None else 0.0 for x in r]
            a.errorbar(PACKINGS, y, yerr=e, marker="o" if sp == "L" else "s", ls="-" if act == 3.0 else "--",
                       color="tab:red" if sp == "L" else "tab:blue", capsize=3, label=f"{sp}, activity {act:g}")
        if k == "fraction_at_collision":  # the fraction expected if episodes began at random times (dotted)
            for act in ACTIVITIES:
                r = [table[f"{p}|{act}|L"] for p in PACKINGS]
                a.plot(PACKINGS, [x["chance_at_collision"] if x["chance_at_collision"] is not None else np.nan for x in r],
                       ":" if act == 3.0 else "-.", marker="x", color="0.4", label=f"L, activity {act:g}: by chance")
            a.legend(fontsize=7)
            a.set_ylim(0.0, 1.1)
        a.set(xlabel="packing fraction", ylabel=label)
    ax[0, 0].legend(fontsize=8)
    a = ax[1, 1]  # the headline: episodes of the first 80 L-shapes (dark: begun at a collision)
    ls = [j for j, b in enumerate(head["bodies"]) if b["species"] == "L"][:80]
    for row, j in enumerate(ls):
        for e in head["bodies"][j]["episodes"]:
            a.plot([e["t_start"], e["t_end"]], [row, row], lw=3,
                   color="tab:red" if e["starts_at_collision"] else "salmon", solid_capstyle="butt")
    a.set(xlabel="t (s)", ylabel="L-shape", xlim=(0, HEADLINE["t_end"]),
          title=f"{HEADLINE['n']} bodies, packing {HEADLINE['packing']}: 80 L's episodes (dark: at a collision)")
    a.title.set_fontsize(9)
    save_figure(fig, out_dir, "active", force=force)
    plt.close(fig)
    # movie and rerun recording of the headline, episodes in red
    movies = out_dir.parent.parent / "movies"  # movies/ is the sibling of results/ (the runner's layout)
    movies.mkdir(parents=True, exist_ok=True)
    s = head["side"]
    rec.movie(movies / "active.mp4", fps=20, speed=2.0, size=(480, 480), color=marks, box=(-0.2, s + 0.2, -0.2, s + 0.2),
              t_end=MOVIE_T, title="red: in an RR episode; blue: with its orbit; grey: neither", force=force)
    rrd.rerun(out_dir / "active.rrd", color=marks[::RRD_EVERY], force=force)  # 5 samples per s (~14 MB: not in git)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "active")
