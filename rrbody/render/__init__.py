"""Pictures of a run: MP4 movies (matplotlib -> imageio-ffmpeg, extra ``movie``) and rerun recordings
(extra ``rerun``). Importing this package imports neither."""

from __future__ import annotations

__all__ = ["check_extras"]


def check_extras(*, movie: bool = False, rerun: bool = False) -> None:
    """Raise :class:`rrbody.model.extras.MissingExtraError` (naming the extra) before any work is done
    when a requested renderer's packages are not installed."""
    from rrbody.model.extras import require

    if movie:
        require("matplotlib", purpose="a movie")
        require("imageio_ffmpeg", purpose="a movie")
    if rerun:
        require("rerun", purpose="a rerun recording")
