"""Active chiral bodies (the paper's second outlook): reverse rotations begun by collisions, 1,000 bodies of two kinds.

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

PACKINGS, ACTIVITIES, SEEDS = (0.1, 0.2, 0.3, 0.4), (1.5, 3.0), (0, 1, 2)
HEADLINE = {"n": 1000, "packing": 0.3, "activity": 3.0, "seed": 0, "t_end": 30.0, "every": 4}
RRD_EVERY, MOVIE_T = 6, 20.0  # the rerun recording keeps every 6th sample (5 per s); the movie the first 20 s


def main(out_dir: Path, *, force: bool = True) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rrbody.analysis.active_study import Box, ensemble, seed_table
    from rrbody.analysis.report import write_summary
    from rrbody.render.active_film import plot_ensemble, run_filmed, write_movie, write_rerun
    from rrbody.render.figures import save_figure

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # 1. the headline run, filmed (poses only: the marks come from the analysis, not from the pictures)
    box = Box(**HEADLINE)
    head, rec, rrd = run_filmed(box, movie=True, rerun_every=RRD_EVERY)
    # 2. the ensemble over packing fraction, activity and seeds
    points = [Box(n=200, packing=p, activity=a, seed=s, t_end=60.0)
              for p, a, s in itertools.product(PACKINGS, ACTIVITIES, SEEDS)]
    ck = out_dir / "_cache" / "ensemble.jsonl"  # an interrupted scene resumes its ensemble from here
    ck.parent.mkdir(exist_ok=True)
    rows = ensemble(points, checkpoint=ck)
    ck.unlink()
    if not any(ck.parent.iterdir()):
        ck.parent.rmdir()
    table = seed_table(rows)
    summary = {"headline": {**HEADLINE, "stats": head["stats"], "side_m": head["side"]},
               "ensemble": {"n": 200, "t_end_s": 60.0, "packings": PACKINGS, "activities": ACTIVITIES,
                            "seeds": SEEDS, "rows": table}}
    write_summary(out_dir, summary, force=force)
    # figure: the ensemble's statistics against packing (mean +- sd over seeds); the headline's episodes
    fig, ax = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    plot_ensemble(ax.flat, table)
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
    write_movie(head, rec, movies / "active.mp4", fps=20, speed=2.0, size=(480, 480), t_end=MOVIE_T, force=force)
    write_rerun(head, rrd, out_dir / "active.rrd", rerun_every=RRD_EVERY, force=force)  # 5 samples per s (~14 MB)

if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "active")
