"""Trajectory save/load round trip and atomic, non-clobbering writes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rrbody import rod_mass_scene, simulate
from rrbody.model.io import atomic_path
from rrbody.model.trajectory import Trajectory


def test_round_trip_is_exact(tmp_path: Path) -> None:
    tr = simulate(rod_mass_scene(0.2, 0.05, 0.6), t_max=10.0, dt_out=0.1)
    path = tr.save(tmp_path / "a.csv")
    back = Trajectory.load(path)
    for name in ("t", "phi", "phi_dot", "x_cm", "y_cm", "vx_cm", "vy_cm", "x_p", "y_p", "body_angle", "spin"):
        np.testing.assert_array_equal(getattr(back, name), getattr(tr, name))  # %.17g is exact for float64
    assert back.meta["rrbody_version"] == tr.meta["rrbody_version"]
    assert back.events["phi_min"] == pytest.approx(tr.events["phi_min"], rel=0, abs=0)


def test_interrupted_write_leaves_previous_file(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_text("old")
    with pytest.raises(KeyboardInterrupt), atomic_path(target, force=True) as tmp:
        tmp.write_text("half")
        raise KeyboardInterrupt
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]  # no temp file left behind


def test_velocity_columns_are_derivatives_of_positions() -> None:
    tr = simulate(rod_mass_scene(0.3, 0.1, 0.8), t_max=5.0, dt_out=1e-3)
    vx = np.gradient(tr.x_cm, tr.t)
    # central differences at dt = 1e-3 s: error ~ dt^2 |x'''| / 6 ~ 1e-6 m/s for these O(1) motions
    assert np.max(np.abs(vx[1:-1] - tr.vx_cm[1:-1])) < 1e-4
