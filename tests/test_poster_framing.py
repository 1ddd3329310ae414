"""Posters and movies frame the whole motion: every filmed body's whole outline, at every captured
frame, lies inside the picture with a blank margin (``rrbody.render.recorder_picture.fit_view``).

The README's box (pf.step, 1 s, a poster of four panels) once touched its panels' right edge (9 px
of 480 from it, inside the frame line's antialiasing); the check here is on the pixels each panel
shows, so it fails whatever the cause of a cut: a view fitted too tightly, a panel placed wrongly.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pymunk = pytest.importorskip("pymunk")
pytest.importorskip("matplotlib")

from rrbody.plugin import PlaneFriction, Recorder  # noqa: E402
from rrbody.render.recorder_picture import MARGIN, fit_view, to_world  # noqa: E402

#: the least blank border a panel keeps round the bodies, as a fraction of its width: the fitted
#: margin is MARGIN (8 %) of the motion's larger extent, so a panel as wide as that extent keeps
#: about 7 % (MARGIN / (1 + 2 MARGIN)); 5 % leaves room for the outline's line width and antialiasing
MIN_BORDER = 0.05


def _readme_box() -> tuple[pymunk.Space, PlaneFriction, pymunk.Body]:
    """The README's plugin example: a 0.2 m x 0.1 m box launched sliding and spinning."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    box = pymunk.Body()
    shape = pymunk.Poly.create_box(box, (0.2, 0.1))
    shape.density = 800.0
    space.add(box, shape)
    box.velocity, box.angular_velocity = (1.5, -0.4), -12.0
    pf.add(box, mu=0.5)
    return space, pf, box


def _run(space: pymunk.Space, pf: PlaneFriction, t_end: float, **kw: object) -> Recorder:
    rec = Recorder(space, pf, **kw)
    while pf.t < t_end:
        pf.step(1 / 240)
        rec.capture()
    return rec


def _panel_borders(png: Path, panels: int) -> list[tuple[float, float, float, float]]:
    """Per panel: the blank border (left, right, top, bottom) between the bodies' red pixels and the
    panel's edges, as fractions of the panel's width and height."""
    import matplotlib.image as mimg

    img = (mimg.imread(str(png))[:, :, :3] * 255).round().astype(int)
    red = (img[:, :, 0] > 200) & (img[:, :, 1] < 120) & (img[:, :, 2] < 120)
    h, w = red.shape
    pw = w // panels
    out = []
    for i in range(panels):
        rows, cols = np.nonzero(red[:, i * pw:(i + 1) * pw])
        assert rows.size > 100, f"panel {i}: the body is not drawn"
        out.append((cols.min() / pw, (pw - 1 - cols.max()) / pw, rows.min() / h, (h - 1 - rows.max()) / h))
    return out


def test_the_readme_box_poster_shows_the_whole_box_in_every_panel(tmp_path: Path) -> None:
    """Every panel of the README's poster shows the whole box with at least MIN_BORDER of blank round
    it (the framing before kept 9-20 px of 480, 2-4 %, at the nearest edge)."""
    space, pf, _ = _readme_box()
    rec = _run(space, pf, 1.0)
    png = rec.poster(tmp_path / "box.png", color=(1.0, 0.0, 0.0), force=True)
    for i, border in enumerate(_panel_borders(png, 4)):
        assert min(border) >= MIN_BORDER, (i, border)


def test_the_fitted_view_holds_every_outline_at_every_frame_with_its_margin() -> None:
    """Two bodies that move apart (a rod spinning, a disk sliding away): at every captured frame
    every vertex of every outline lies inside the fitted view by at least MARGIN / (1 + 2 MARGIN) of
    its width or height, for a wide, a square and a tall picture."""
    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    rod, disk = pymunk.Body(), pymunk.Body()
    shapes = [pymunk.Segment(rod, (-0.3, 0.0), (0.3, 0.0), 0.02), pymunk.Circle(disk, 0.05)]
    disk.position = (0.5, 0.2)
    space.add(rod, disk, *shapes)
    for s in shapes:
        s.density = 500.0
    rod.velocity, rod.angular_velocity = (-0.5, 0.1), 20.0
    disk.velocity = (2.0, 1.0)
    pf.add(rod, mu=0.3)
    pf.add(disk, mu=0.3)
    rec = _run(space, pf, 0.5)
    least = MARGIN / (1.0 + 2.0 * MARGIN) - 1e-12
    for aspect in (16 / 9, 1.0, 0.5):
        x0, x1, y0, y1 = rec._view(None, aspect)
        assert math.isclose((x1 - x0) / (y1 - y0), aspect)
        for k in range(rec.n_frames):
            d = rec._data[k]
            for b, outs in enumerate(rec._outlines):
                for o in outs:
                    w = to_world(o, d[b, 0], d[b, 1], d[b, 2])
                    assert w[:, 0].min() - x0 >= least * (x1 - x0) and x1 - w[:, 0].max() >= least * (x1 - x0)
                    assert w[:, 1].min() - y0 >= least * (y1 - y0) and y1 - w[:, 1].max() >= least * (y1 - y0)


def test_a_box_given_is_kept_and_only_widened_to_the_aspect() -> None:
    """A box the caller gives is not padded: only widened about its centre to the picture's aspect."""
    assert fit_view(np.empty((0, 0, 2)), np.empty(0), 2.0, (0.0, 2.0, 0.0, 1.0)) == (0.0, 2.0, 0.0, 1.0)
    assert fit_view(np.empty((0, 0, 2)), np.empty(0), 2.0, (0.0, 1.0, 0.0, 1.0)) == (-0.5, 1.5, 0.0, 1.0)
