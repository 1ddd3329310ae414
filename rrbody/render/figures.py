"""Byte-reproducible matplotlib output: the same figure gives the same bytes on every run.

matplotlib stamps an SVG with the date and random ids (clip paths, glyph definitions) and a PNG
with the software version. :func:`savefig_reproducible` fixes the SVG id salt
(``svg.hashsalt``), drops the date and the software field, so regenerating a figure whose numbers
did not change leaves a tracked file byte for byte as it was.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["savefig_reproducible", "save_figure", "HASHSALT"]

#: the salt for matplotlib's SVG ids (any fixed string makes them deterministic)
HASHSALT = "rrbody"


def savefig_reproducible(fig: Any, path: str | Path, *, fmt: str, **kwargs: Any) -> None:
    """``fig.savefig(path, format=fmt, **kwargs)`` with deterministic ids and no date or version."""
    import matplotlib

    meta: dict[str, Any] = {"svg": {"Date": None, "Creator": None}, "png": {"Software": None},
                            "pdf": {"CreationDate": None, "Creator": None, "Producer": None}}.get(fmt, {})
    with matplotlib.rc_context({"svg.hashsalt": HASHSALT}):
        fig.savefig(path, format=fmt, metadata=meta, **kwargs)


def save_figure(fig: Any, out_dir: Path, name: str, *, force: bool = True) -> list[Path]:
    """Save a matplotlib figure as ``<name>.png`` (150 dpi) and ``<name>.svg`` in ``out_dir``, atomically and
    byte-reproducibly; closes it. Returns the two paths."""
    import matplotlib.pyplot as plt

    from rrbody.model.io import atomic_path

    out = []
    for ext, kw in (("png", {"dpi": 150}), ("svg", {})):
        path = Path(out_dir) / f"{name}.{ext}"
        with atomic_path(path, force=force, name=name) as tmp:
            savefig_reproducible(fig, tmp, fmt=ext, **kw)
        out.append(path)
    plt.close(fig)
    return out
