"""Progress over a movie's frames, readable on a terminal and in a log alike.

On a terminal, a tqdm bar (redrawn in place with carriage returns, at most twice a second). Anywhere
else (a CI log, a pipe, a file) a redrawn bar would be one long line of carriage returns, or a line
per redraw: there, one plain line per tenth of the frames, with the time so far, e.g.
``movie movie_s1.mp4: 30% (387/1290 frames, 10.2 s)``. Both go to stderr, so a command's stdout
(its answer, or a JSON line) is untouched.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO

__all__ = ["FrameProgress", "LOG_STEPS"]

#: lines a non-terminal stream gets over a whole movie (one per tenth)
LOG_STEPS = 10


class FrameProgress:
    """Count frames as they are written; show it on ``stream`` (default: stderr at the time of the call).

    Parameters
    ----------
    total : int
        Frames the movie will have (> 0).
    desc : str
        What is being made, e.g. ``"movie movie_s1.mp4"``.
    stream : text stream or None
        Where to write; a terminal (``isatty()`` true) gets a tqdm bar, anything else a line per tenth.
    """

    def __init__(self, total: int, desc: str, *, stream: TextIO | None = None) -> None:
        self.total, self.desc = max(int(total), 1), desc
        self.stream = sys.stderr if stream is None else stream
        self.done = 0
        self._t0 = time.perf_counter()
        self._next = 1  # the next tenth to report (non-terminal)
        isatty = getattr(self.stream, "isatty", None)
        self._bar: Any = None
        if callable(isatty) and isatty():
            from tqdm import tqdm

            # mininterval: redrawing more often than twice a second costs frames and shows nothing more
            self._bar = tqdm(total=self.total, desc=desc, unit="frame", file=self.stream, mininterval=0.5,
                             dynamic_ncols=True)

    def update(self, n: int = 1) -> None:
        """``n`` more frames written."""
        self.done += n
        if self._bar is not None:
            self._bar.update(n)
            return
        while self._next <= LOG_STEPS and self.done * LOG_STEPS >= self._next * self.total:
            shown = min(self.done, self.total)
            print(f"{self.desc}: {100 * self._next // LOG_STEPS}% ({shown}/{self.total} frames, "
                  f"{time.perf_counter() - self._t0:.1f} s)", file=self.stream, flush=True)
            self._next += 1

    def close(self) -> None:
        """End the bar (a terminal keeps its last state on screen)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> FrameProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
