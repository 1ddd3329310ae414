"""The MuJoCo adapter's reading of a model (:mod:`rrbody.mujoco_adapter.plane`): names and ids, and the footprint
of a body from its geoms resting on the plane (a box on a face: a rectangle; a cylinder on a flat end: a
disk; a sphere: a point), as parts of :mod:`rrbody.physics.footprint`, in the plane's axes from the body's
centre of gravity (m). Read once, when the adapter is built.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rrbody.model.extras import require
from rrbody.physics.footprint import ICR_NODES, Part, ellipse_part, point_part, polygon_part

mujoco = require("mujoco", purpose="the MuJoCo adapter (rrbody.mujoco)")

__all__ = ["name_of", "lookup", "gap", "parts_of", "ALIGN"]

#: how far from 1 |cos| between a box's or cylinder's axis and the plane's normal may be (a face
#: resting flat): rounding of a pose given as an angle
ALIGN = 1e-6


def name_of(model: Any, obj: str, i: int) -> str:
    """``geom 'floor'`` (or ``geom 3`` for an unnamed one): an object of the model, for messages."""
    name = mujoco.mj_id2name(model, getattr(mujoco.mjtObj, f"mjOBJ_{obj.upper()}"), int(i))
    return f"{obj} {name!r}" if name else f"{obj} {int(i)}"


def lookup(model: Any, obj: str, key: int | str, what: str) -> int:
    """The id of ``key`` (a name or an id) among the model's objects of kind ``obj``."""
    n = {"geom": model.ngeom, "body": model.nbody}[obj]
    if isinstance(key, str):
        i = mujoco.mj_name2id(model, getattr(mujoco.mjtObj, f"mjOBJ_{obj.upper()}"), key)
        if i < 0:
            raise ValueError(f"{what} must name a {obj} of the model, got {key!r}")
        return int(i)
    if isinstance(key, (int, np.integer)) and not isinstance(key, bool) and 0 <= key < n:
        return int(key)
    raise ValueError(f"{what} must be a {obj} name or an id in [0, {n - 1}], got {key!r}")


def gap(m: Any, d: Any, g: int, frame: np.ndarray, height: float) -> float:
    """How far geom g's lowest point lies above the plane (normal ``frame[2]``, at ``height`` along it; m;
    negative: it presses into it)."""
    n = frame[2]
    R = d.geom_xmat[g].reshape(3, 3)
    size = m.geom_size[g]
    c = float(d.geom_xpos[g] @ n) - height
    kind = m.geom_type[g]
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        return c - float(np.abs(R.T @ n) @ size)
    if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
        cz = abs(float(R[:, 2] @ n))
        return c - size[1] * cz - size[0] * math.sqrt(max(0.0, 1.0 - cz * cz))
    if kind in (mujoco.mjtGeom.mjGEOM_SPHERE, mujoco.mjtGeom.mjGEOM_CAPSULE):
        half = size[1] * abs(float(R[:, 2] @ n)) if kind == mujoco.mjtGeom.mjGEOM_CAPSULE else 0.0
        return c - size[0] - half
    return c - float(m.geom_rbound[g])  # other kinds: their bounding sphere (they are refused if it touches)

def parts_of(m: Any, d: Any, b: int, frame: np.ndarray, height: float, touch: float) -> list[Part]:
    """The footprint of body b: its geoms whose lowest point lies within ``touch`` (m) of the plane, in the
    plane's axes (``frame`` rows t1, t2, n) from the body's centre of gravity (m)."""
    t = frame
    com = d.xipos[b]
    parts: list[Part] = []
    for g in np.flatnonzero(m.geom_bodyid == b):
        if not (m.geom_contype[g] | m.geom_conaffinity[g]) or gap(m, d, int(g), frame, height) > touch:
            continue
        R = d.geom_xmat[g].reshape(3, 3)
        size = m.geom_size[g]
        kind = m.geom_type[g]
        cos = np.abs(R.T @ t[2])  # each geom axis against the normal
        if kind == mujoco.mjtGeom.mjGEOM_BOX:
            k = int(np.argmax(cos))
            if cos[k] < 1.0 - ALIGN:
                raise ValueError(f"{name_of(m, 'geom', g)} (a box) must rest flat on one of its faces on the plane, "
                                 f"got its axes at |cos| {np.round(cos, 6).tolist()} to the normal")
            i, j = [a for a in range(3) if a != k]
            base = d.geom_xpos[g] - t[2] * (size[k] * cos[k])
            corners = [base + s1 * size[i] * R[:, i] + s2 * size[j] * R[:, j]
                       for s1, s2 in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
            parts.append(polygon_part(np.array([[(c - com) @ t[0], (c - com) @ t[1]] for c in corners])))
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
            if cos[2] < 1.0 - ALIGN:
                raise ValueError(f"{name_of(m, 'geom', g)} (a cylinder) must stand on a flat end on the plane, "
                                 f"got its axis at |cos| {cos[2]:.6f} to the normal")
            o = d.geom_xpos[g] - com
            parts.append(ellipse_part(float(o @ t[0]), float(o @ t[1]), float(size[0]), float(size[0]), 0.0,
                                      ICR_NODES))
        elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            o = d.geom_xpos[g] - com
            parts.append(point_part(float(o @ t[0]), float(o @ t[1])))
        else:
            raise ValueError(f"{name_of(m, 'geom', g)} rests on the plane but is a "
                             f"{mujoco.mjtGeom(kind).name}: footprints are made of boxes, cylinders and spheres")
    return parts
