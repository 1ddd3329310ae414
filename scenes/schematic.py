"""Schematic (definitions, not a paper figure): O, P, CM, d, l, phi and omega t drawn to scale.

The picture that defines the symbols every other figure and movie uses: P is driven counter-clockwise
on a circle of radius d about O; the body turns freely about P; the CM is at distance l from P; phi is
the angle of the vector CM -> P with the x axis; theta = phi - omega t + pi is the rotating-frame angle.
Reverse rotation means phi decreasing while P goes round counter-clockwise.

Outputs in ``out_dir``: schematic.png and schematic.svg.
"""

from __future__ import annotations

from pathlib import Path


def main(out_dir: Path, *, force: bool = True) -> None:
    from rrbody.render.figures import save_figure
    from rrbody.render.schematic import schematic_figure

    # 1. the figure, with the defaults (d = 1 m, l = 0.5 m, omega t = 40 deg, phi = 100 deg)
    fig = schematic_figure()
    # 2. PNG and SVG, byte-reproducible
    save_figure(fig, out_dir, "schematic", force=force)


if __name__ == "__main__":
    main(Path(__file__).resolve().parent.parent / "results" / "schematic")
