"""What a parameter sweep computes: :class:`Sweep`, its base scene, axes, quantity and options, all
validated when it is built, and the scene of each of its points (:func:`make_scene`).

Its execution (running the points on workers, the checkpoint, resuming, the faults) is in the sibling
:mod:`rrbody.analysis.sweep`, and its files in :mod:`rrbody.analysis.sweep_store`. A sweep's
:meth:`Sweep.spec` is what a worker receives and a checkpoint or table records; :func:`sweep_from_spec`
builds the sweep back from it.

Parameters of the base scene
----------------------------
Any scene: the flat parameters of :func:`rrbody.model.scene.scene_from_params` (``body`` = rod,
disk or ellipse; ``H`` or ``l``, ``R0``, ``delta``, ``orientation``, ``omega``, ``d``, ``k`` or
``mu``/``g``, ``friction``, ``phi0``, ``phi_dot0``, ``t_max``, ``friction_method``, ``samples``,
``no_drive``, ``v0``, ``spin0``), whose numeric ones axes vary by name; or a full
``Scene.describe()`` dictionary under the key ``"scene"``, whose entries axes vary by dotted path
(``"drive.omega"``, ``"friction.coeff"``, ``"l"``, ``"R_A"``, ``"phi0"``, ...). Free bodies
(``no_drive``) have the quantity ``rest`` (stop time, distance, turn; needs the option ``t_max``).

Validation
----------
A :class:`Sweep` checks its options and every value of every axis when it is built (each value
with the base and the other axes' first values), and refuses an axis that changes nothing its quantity
reads from a point's scene (:data:`READS`: H for critical_h, whose H is the answer; downhill on a level
plane; the drive of a free body's rest); :func:`rrbody.analysis.sweep.run_sweep` checks the outputs, the options
and the scheduler (its address, then that it answers) before any work or file.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rrbody._version import __version__
from rrbody.analysis.chaos_map import CHAOS_COLUMNS, CHAOS_OPTIONS, check_chaos_options, check_chaos_scene
from rrbody.model.checks import MissingParameters, check, check_choice
from rrbody.model.scene import NUMERIC_SCENE_PARAMS, SCENE_PARAMS

__all__ = ["Sweep", "QUANTITIES", "AXIS_PARAMS", "READS", "critical_h_args", "make_scene", "sweep_from_spec"]

#: quantity -> result columns it produces (in order)
QUANTITIES: dict[str, tuple[str, ...]] = {
    "flip_time": ("t_f", "phi_min", "t_phi_min", "reverse_rotation", "T1", "settled", "n_steps", "regime"),
    "critical_h": ("H_c",),
    "rr": ("reverse_rotation",),
    "rest": ("t_stop", "distance", "turn", "status"),
    "chaos": CHAOS_COLUMNS,
}
_OPTION_KEYS = {"flip_time": ("accuracy", "rtol", "t_max"),
                "critical_h": ("accuracy", "rtol", "tol", "H_lo", "H_hi", "n_scan"),
                "rr": ("accuracy", "rtol"),
                "rest": ("accuracy", "rtol", "t_max"),
                "chaos": CHAOS_OPTIONS}
_OPTION_LIMITS = {"rtol": "rtol", "t_max": "t_max", "tol": "tol", "H_lo": "H", "H_hi": "H"}


#: parameters a flat sweep may put on an axis: every numeric scene parameter
AXIS_PARAMS: tuple[str, ...] = NUMERIC_SCENE_PARAMS


def critical_h_args(scene: Any) -> dict[str, Any]:
    """What :func:`rrbody.analysis.flip.critical_h` takes from a point's scene (its H is the unknown):
    the rod-mass ``k``, ``omega``, ``phi0`` and the friction law."""
    return {"k": scene.k, "omega": scene.omega, "phi0": scene.phi0, "friction": scene.friction.law}


#: what a quantity reads from a point's scene, where it is not the whole scene (``Scene.describe``):
#: critical_h reads its arguments (the point evaluator calls it with exactly these). An axis that changes
#: none of what its quantity reads is refused (:meth:`Sweep._check_axes_matter`)
READS: dict[str, Callable[[Any], dict[str, Any]]] = {"critical_h": critical_h_args}



@dataclass(frozen=True)
class Sweep:
    """What to compute.

    Parameters
    ----------
    base : dict
        Fixed scene parameters: the flat parameters of ``scene_from_params`` (any body), or
        ``{"scene": Scene.describe()}``.
    axes : dict name -> sequence of float
        The varied parameters, in order. ``mode="grid"``: the Cartesian product (the first axis
        varies slowest); ``mode="list"``: the axes are zipped (equal lengths), one point per index.
    quantity : {"flip_time", "critical_h", "rr", "rest", "chaos"}
        ``critical_h`` varies the rod-mass ``k``, ``omega``, ``phi0``, ``friction`` (H is the answer);
        ``rest`` is for free bodies (``no_drive``); ``chaos``: the maximal Lyapunov exponent and the
        fraction of time in reverse rotation (:mod:`rrbody.analysis.chaos_map`).
    options : dict
        Passed to the analysis: ``accuracy``, ``rtol``; ``t_max`` (flip_time, rest); ``tol``,
        ``H_lo``, ``H_hi``, ``n_scan`` (critical_h); ``periods`` or ``t_max``, ``transient``,
        ``rtol``, ``d0``, ``rr_samples``, ``estimate`` (chaos).
    """

    base: dict[str, Any]
    axes: dict[str, tuple[float, ...]]
    quantity: str = "flip_time"
    mode: str = "grid"
    options: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_choice("quantity", self.quantity, tuple(QUANTITIES))
        check_choice("mode", self.mode, ("grid", "list"))
        if not isinstance(self.axes, dict) or not self.axes:
            raise ValueError(f"axes must be a non-empty dict name -> values, got {self.axes!r}")
        axes: dict[str, tuple[float, ...]] = {}
        for name, vals in self.axes.items():
            try:
                tv = tuple(float(v) for v in np.atleast_1d(np.asarray(vals, dtype=float)))
            except (TypeError, ValueError):
                raise ValueError(f"axes[{name!r}] must be numbers, got {vals!r}") from None
            if not tv:
                raise ValueError(f"axes[{name!r}] must hold at least one value, got {vals!r}")
            if not all(math.isfinite(v) for v in tv):
                raise ValueError(f"axes[{name!r}] must be finite numbers, got {vals!r}")
            axes[str(name)] = tv
        object.__setattr__(self, "axes", axes)
        if self.mode == "list" and len({len(v) for v in axes.values()}) != 1:
            raise ValueError(f"mode='list' needs axes of equal length, got lengths "
                             f"{ {n: len(v) for n, v in axes.items()} }")
        self._check_options()
        if "scene" in self.base:
            if self.quantity == "critical_h":
                raise ValueError("quantity 'critical_h' needs rod-mass base parameters (k, omega, ...), not a scene")
        else:
            bad = [k for k in self.base if k not in SCENE_PARAMS]
            if bad:
                raise ValueError(f"sweep parameters must be among {', '.join(SCENE_PARAMS)}, got {bad!r}")
            bad = [k for k in axes if k not in AXIS_PARAMS]
            if bad:
                raise ValueError(f"axes must be among {', '.join(AXIS_PARAMS)}, got {bad!r}")
            both = [k for k in axes if k in self.base]
            if both:
                raise ValueError(f"base and axes both give {', '.join(both)} (base {both[0]}={self.base[both[0]]!r}); "
                                 "an axis sets its parameter at every point: give each parameter in one place")
        self._check_points()
        self._check_axes_matter()

    def _check_options(self) -> None:
        bad = [k for k in self.options if k not in _OPTION_KEYS[self.quantity]]
        if bad:
            raise ValueError(f"options for {self.quantity} must be among {', '.join(_OPTION_KEYS[self.quantity])}, "
                             f"got {bad!r}")
        if self.quantity == "chaos":  # its own options (periods, transient, ...): rrbody.analysis.chaos_map
            check_chaos_options(self.options)
            return
        for k, v in self.options.items():
            if k == "accuracy":
                check_choice("accuracy", v, ("draft", "default", "paper"))
            elif k == "n_scan":
                check("samples", v, label="n_scan")
            elif v is not None:
                check(_OPTION_LIMITS[k], v, label=k)
        if self.quantity == "rest" and self.options.get("t_max") is None:
            raise ValueError("t_max must be given for quantity 'rest' (the horizon of a free body, s)")

    def _check_points(self) -> None:
        """Build the scene of every axis value (the other axes at their first values), before any work:
        a bad value fails now, naming its axis, not as an error row after hours."""
        first = self.point(0)
        for name, vals in self.axes.items():
            for v in dict.fromkeys(vals):
                try:
                    scene = make_scene(self, {**first, name: v})
                except MissingParameters as e:
                    raise MissingParameters(e.names, prefix="base must give every parameter of the scene that is "
                                                           "not on an axis") from None
                except ValueError as e:
                    raise ValueError(f"axis {name}: {e}" if name in str(e).split(" ")[0] else str(e)) from None
                if self.quantity == "rest" and scene.driven:
                    raise ValueError("quantity 'rest' needs a free body (no_drive=True)")
                if self.quantity != "rest" and not scene.driven:
                    raise ValueError(f"quantity {self.quantity!r} needs a driven scene; for a free body use 'rest'")
                if self.quantity == "chaos":
                    check_chaos_scene(scene, self.options)

    def _check_axes_matter(self) -> None:
        """Refuse an axis that changes nothing the quantity reads (:data:`READS`): its column would pair
        each value with an answer it had no part in (H for critical_h, whose H is the answer). Two of its
        values are compared (an axis of one value: with the first of twice, half, one more, one less
        that makes a valid scene) with the other axes at their first values, and at each of their values
        in turn (a tilt axis makes a downhill axis matter)."""
        reads = READS.get(self.quantity, lambda scene: scene.describe())
        first = self.point(0)
        for name, vals in self.axes.items():
            values = list(dict.fromkeys(vals))
            if len(values) == 1:
                v = values[0]
                values += [w for w in (2.0 * v, 0.5 * v, v + 1.0, v - 1.0) if w != v]
            contexts = [first, *({**first, other: w} for other, ws in self.axes.items() if other != name
                                 for w in dict.fromkeys(ws[1:]))]
            seen: list[Any] = []
            for context in contexts:
                seen = []
                for v in values:
                    try:
                        seen.append(reads(make_scene(self, {**context, name: v})))
                    except ValueError:  # a probe value, or a point's value with another axis' (checked later)
                        continue
                    if len(seen) == 2:
                        break
                if len(seen) < 2 or seen[0] != seen[1]:
                    break  # it matters, or it cannot be told here
            else:
                *most, last = list(seen[0])
                what = (f"it reads only {', '.join(most)} and {last} from each point's scene, and {name} changes "
                        "none of them" if self.quantity in READS else f"the scene is the same at every value of {name}")
                raise ValueError(f"axis {name}: the quantity {self.quantity} does not depend on {name} ({what}); "
                                 "drop this axis")

    @property
    def columns(self) -> tuple[str, ...]:
        """The result columns of the quantity."""
        return QUANTITIES[self.quantity]

    @property
    def shape(self) -> tuple[int, ...]:
        if self.mode == "list":
            return (len(next(iter(self.axes.values()))),)
        return tuple(len(v) for v in self.axes.values())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def point(self, i: int) -> dict[str, float]:
        """Axis values of point ``i`` (row-major index over the grid)."""
        names = list(self.axes)
        if self.mode == "list":
            return {n: self.axes[n][i] for n in names}
        idx = np.unravel_index(i, self.shape)
        return {n: self.axes[n][int(j)] for n, j in zip(names, idx)}

    def spec(self) -> dict[str, Any]:
        """JSON-ready description; two sweeps with equal specs compute identical results."""
        from rrbody.model.trajectory import jsonable

        return jsonable({"base": self.base, "axes": self.axes, "quantity": self.quantity, "mode": self.mode,
                          "options": self.options, "rrbody_version": __version__})


# ---- the scene of one point ------------------------------------------------------------------
def _set_path(d: dict[str, Any], path: str, value: float) -> None:
    keys = path.split(".")
    cur = d
    for k in keys[:-1]:
        if not isinstance(cur.get(k), dict):
            raise ValueError(f"axis {path!r}: {k!r} is not a group in the scene description")
        cur = cur[k]
    if keys[-1] not in cur:
        raise ValueError(f"axis {path!r}: {keys[-1]!r} is not a scene parameter (have {sorted(cur)})")
    cur[keys[-1]] = value


def make_scene(sweep: Sweep, values: dict[str, float]) -> Any:
    """The Scene of one sweep point (base parameters overridden by the axis ``values``)."""
    from rrbody.model.scene import Scene, scene_from_params

    if "scene" in sweep.base:
        desc = copy.deepcopy(sweep.base["scene"])
        for name, v in values.items():
            _set_path(desc, name, v)
        if "phi_dot0" in desc and "phi_dot0" not in values and sweep.base.get("impulsive", True):
            desc["phi_dot0"] = None  # keep the impulsive start consistent with the varied parameters
        return Scene.from_description(desc)
    kw = {**sweep.base, **values}
    if "samples" in kw:
        kw["samples"] = int(kw["samples"]) if float(kw["samples"]).is_integer() else kw["samples"]
    if sweep.quantity == "critical_h":
        kw.setdefault("H", 0.5)  # placeholder for validation only: H is the unknown
    return scene_from_params(**kw)


def sweep_from_spec(spec: dict[str, Any]) -> Sweep:
    """The sweep whose :meth:`Sweep.spec` is ``spec`` (a worker's task, a checkpoint's header)."""
    return Sweep(base=spec["base"], axes={k: tuple(v) for k, v in spec["axes"].items()}, quantity=spec["quantity"],
                 mode=spec["mode"], options=spec["options"])
