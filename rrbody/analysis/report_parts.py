"""Small pieces the results report is written with (:mod:`rrbody.analysis.report` and
:mod:`rrbody.analysis.report_contacts`): a scene's summary, a section heading, a figure link, a number."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

__all__ = ["read_summary", "heading", "img", "fmt"]


def read_summary(results: Path, scene: str) -> dict[str, Any] | None:
    """A scene's ``summary.json`` or None if the scene has not been run."""
    p = Path(results) / scene / "summary.json"
    if not p.exists():
        return None
    return json.loads(p.read_text())


def heading(L: list[str], title: str, summary: dict[str, Any] | None) -> bool:
    """Append a section heading; if the scene has not been run, say so and return False."""
    L.append(title)
    L.append("")
    if not summary:
        L.append("*(not run)*\n")
        return False
    return True


def img(scene: str, name: str, results: Path) -> str:
    """A Markdown link to a scene's figure ``name``.png, or a note that it was not generated."""
    p = results / scene / f"{name}.png"
    return f"![{scene}]({scene}/{name}.png)" if p.exists() else f"*(figure {scene}/{name}.png not generated)*"


def fmt(x: Any, spec: str = ".4g") -> str:
    """A number for the report; None or a non-finite float as n/a (a run that found no value)."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    return format(x, spec)
