"""What a picture says about the flip: the flip time of the whole run, never a minimum of the span.

A movie, recording or figure shows a span [t0, t1] of a run. The lowest phi inside that span is not
the flip time t_f: a span that ends during reverse rotation has its lowest phi at its end (or at a
local minimum that a later, lower one will beat). So every renderer takes the flip from
:func:`rrbody.analysis.flip_time` over the whole run (or from the run itself when its own samples
already settle the flip, :meth:`rrbody.trajectory.Trajectory.settled_flip`) and says plainly
"no flip within this span" when t_f lies beyond it.

Colours follow the paper's Fig. SSs: red before t_f, blue after; a run without a flip (normal
rotation from the start) is blue throughout; a run whose flip is unknown is drawn in grey.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

from rrbody.model.trajectory import Trajectory

__all__ = ["FlipMark", "flip_mark", "RED", "BLUE", "GREY"]

#: colours of the two regimes (before / after t_f), matplotlib's tab:red and tab:blue, and "unknown"
RED = "#d62728"
BLUE = "#1f77b4"
GREY = "#7f7f7f"

Status = Literal["flip", "none", "unknown"]


@dataclass(frozen=True)
class FlipMark:
    """The flip of a whole run, as a picture of the span [t0, t1] (s) must state it.

    ``status``: ``"flip"`` (t_f known, s), ``"none"`` (settled: no flip, e.g. normal rotation from
    the start or no friction) or ``"unknown"`` (the flip is not settled; nothing is claimed).
    ``reason`` is a short phrase for ``"none"``/``"unknown"``.
    """

    status: Status
    t_f: float | None = None
    reason: str = ""

    def in_span(self, t0: float, t1: float) -> bool:
        """True when the flip happens inside the drawn span (t0, t1]."""
        return self.status == "flip" and self.t_f is not None and t0 < self.t_f <= t1

    def before(self, t: float) -> bool:
        """True while the body is still before its flip (reverse rotation) at time ``t`` (s)."""
        return self.status == "flip" and self.t_f is not None and t < self.t_f

    def colour(self, t: float) -> str:
        """Red before the flip, blue after it (or with no flip at all), grey when unknown."""
        if self.status == "unknown":
            return GREY
        return RED if self.before(t) else BLUE

    def caption(self, t0: float, t1: float) -> str:
        """One line for the picture: where the flip is relative to the span [t0, t1] (s)."""
        if self.status == "none":
            return f"no flip: {self.reason}" if self.reason else "no flip"
        if self.status == "unknown":
            return "no flip within this span" + (f" ({self.reason})" if self.reason else "")
        assert self.t_f is not None  # status "flip" always carries t_f (set by flip_mark only)
        if self.t_f > t1:
            return f"no flip within this span: t_f = {self.t_f:.2f} s comes later"
        if self.t_f <= t0:
            return f"after the flip (t_f = {self.t_f:.2f} s)"
        return f"flip at t_f = {self.t_f:.2f} s"


def _from_result(res: Any) -> FlipMark:
    t_f = getattr(res, "t_f", None)
    if t_f is not None:
        return FlipMark("flip", float(t_f))
    regime = str(getattr(res, "regime", ""))
    if regime.startswith("no friction"):
        return FlipMark("none", reason="no friction, reverse rotation never ends" if getattr(
            res, "reverse_rotation", False) else "no friction")
    if getattr(res, "settled", False):
        return FlipMark("none", reason="normal rotation from the start")
    return FlipMark("unknown", reason="flip not settled")


def flip_mark(traj: Trajectory, flip: Any = None) -> FlipMark:
    """The flip to show for ``traj``.

    ``flip`` may be a :class:`FlipMark`, a :class:`rrbody.analysis.FlipResult` (from ``flip_time``
    over the whole run: the usual case), a number (t_f in s, trusted as the whole run's flip time)
    or None: then the run's own samples are used when they settle the flip, else ``flip_time`` is
    computed for the run's scene (``traj.meta['scene']``) without a horizon, exactly as
    ``rrbody flip-time`` would. Undriven runs have no flip; a run without a scene description is
    "unknown".
    """
    if isinstance(flip, FlipMark):
        return flip
    if flip is not None and not isinstance(flip, (int, float)):
        return _from_result(flip)
    if flip is not None:
        v = float(flip)
        if not math.isfinite(v):
            raise ValueError(f"flip must be a finite time in s, a FlipResult or None, got {flip!r}")
        return FlipMark("flip", v)
    sc = traj.meta.get("scene") or {}
    if "body" not in sc:
        return FlipMark("unknown", reason="no scene description to compute it from")
    if not sc.get("drive"):
        return FlipMark("none", reason="a free body (no drive)")
    if (sc.get("friction") or {}).get("law", "dry") == "none" or not (sc.get("friction") or {}).get("coeff"):
        return FlipMark("none", reason="no friction")
    t_f, settled = traj.settled_flip()
    if settled:
        return FlipMark("flip", t_f) if t_f is not None else FlipMark("none", reason="normal rotation from the start")
    from rrbody.analysis.flip import flip_time
    from rrbody.model.scene import Scene

    # the scene's own horizon (the span's t_max) must not cap the search: the flip may come later
    return _from_result(flip_time(Scene.from_description(sc).with_(t_max=None)))
