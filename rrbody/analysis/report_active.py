"""The results report's section on active chiral bodies (``scenes/active.py``)."""

from __future__ import annotations

from pathlib import Path

from rrbody.analysis.report_parts import fmt, heading, img, read_summary

__all__ = ["section_active"]


def _pm(row: dict, key: str, spec: str = ".3g") -> str:
    v, e = row.get(key), row.get(f"{key}_sd")
    if v is None:
        return "n/a"
    return fmt(v, spec) + (f" ± {fmt(e, spec)}" if e is not None else "")


def section_active(L: list[str], res: Path) -> None:
    s = read_summary(res, "active")
    if not heading(L,
                   "## Active chiral bodies: reverse rotations begun by collisions, a binary mixture (scene active)",
                   s):
        return
    assert s is not None  # (heading returned True)
    h, en = s["headline"], s["ensemble"]
    L.append("The paper's second outlook. Chiral active bodies (propulsion fixed in the body frame, off the centre "
             "of gravity: alone each swims on a circle) with drag, rotational noise and dry plane friction collide in "
             "a walled box: L-shapes, which contacts on their arms can turn against their orbit, and disks with "
             "frictionless rims, which no collision can torque. An RR episode: a run of samples with the spin against "
             "the body's orbital sense (the sign of its propulsion's torque) during which it turns back by more than "
             "pi; it began at a collision if a body-body contact began within 0.5 s before (docs/active.md). 'By "
             "chance': the fraction of all sample times of the same bodies with a contact begun within 0.5 s before "
             "(what the fraction would be if episodes began at random times). 'Time reversed': the fraction of "
             "samples with the spin against the orbit at all (episodes or not: jammed bodies turning back less than "
             "pi, brief reversals).")
    L.append("")
    for sp in ("L", "disk"):
        st = h["stats"][sp]
        L.append(f"- Headline, {h['n']} bodies, packing {h['packing']}, activity {h['activity']}, {h['t_end']:g} s, "
                 f"{sp}: {st.get('episodes', 0)} episodes ({fmt(st.get('episodes_per_body_per_min'), '.3g')} per body "
                 f"per minute), {fmt(st.get('fraction_at_collision'), '.0%')} begun at a collision (by chance: "
                 f"{fmt(st.get('chance_at_collision'), '.0%')}), mean duration "
                 f"{fmt(st.get('duration_mean_s'), '.3g')} s; spin against the orbit "
                 f"{fmt(st.get('reversed_fraction'), '.0%')} "
                 f"of the time.")
    L.append("")
    L.append(f"Ensemble: {en['n']} bodies, {en['t_end_s']:g} s, seeds {', '.join(map(str, en['seeds']))} per point "
             "(mean ± sd over seeds):")
    L.append("")
    L.append("| packing | activity | species | episodes | per body per min | begun at a collision | by chance | "
             "at a wall only | mean duration (s) | time in RR | time reversed | collisions per body per min |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in en["rows"]:
        L.append(f"| {r['packing']:g} | {r['activity']:g} | {r['species']} | {r['episodes']} | "
                 f"{_pm(r, 'episodes_per_body_per_min')} | {_pm(r, 'fraction_at_collision', '.2f')} | "
                 f"{_pm(r, 'chance_at_collision', '.2f')} | "
                 f"{_pm(r, 'fraction_at_wall_only', '.2f')} | {_pm(r, 'duration_mean_s')} | "
                 f"{_pm(r, 'time_fraction', '.2g')} | {_pm(r, 'reversed_fraction', '.2g')} | "
                 f"{_pm(r, 'collisions_per_body_per_min')} |")
    L.append("")
    L.append(img("active", "active", res))
    L.append("")
    L.append("Movie: [movies/active.mp4](../movies/active.mp4) (red only inside the episodes found above); the rerun "
             "recording `results/active/active.rrd` is written by the scene (not kept in git: ~14 MB).")
    L.append("")
