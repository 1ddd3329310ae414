"""What the long set-up steps print: a movie's frame progress on a terminal and in a log, and the
kernel prebuild's line per job (``make demo`` and ``make test`` show them; docs/compile.md).

A movie written in a subprocess whose stderr is a pipe (as in a CI log) prints one plain line per
tenth of its frames, no carriage return; a terminal gets tqdm's bar. The prebuild prints a line as
each of its jobs ends, naming the job, how many are done and the time so far. Each test runs tiny
jobs (a 20-frame 32 x 32 movie, jobs that exit at once): together about 2 s.
"""

from __future__ import annotations

import io
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from rrbody.render.movie_progress import LOG_STEPS, FrameProgress

ROOT = Path(__file__).resolve().parents[1]

#: write a 20-frame 32 x 32 movie with progress through the renderers' own writer
MOVIE = """
import sys
from pathlib import Path
import numpy as np
from rrbody.render.mp4 import write_frames
frames = (np.full((32, 32, 4), 12 * k, dtype=np.uint8) for k in range(20))
write_frames(Path(sys.argv[1]), frames, 20, size=(32, 32), fps=10, force=False, progress=True)
print("done")
"""


def test_a_movie_in_a_log_prints_a_line_per_tenth_of_its_frames(tmp_path: Path) -> None:
    """stderr a pipe (not a terminal): ten lines, 10 % ... 100 %, each with its frame count, and no
    carriage return (a CI log shows each line once); stdout holds only the program's own output."""
    pytest.importorskip("imageio_ffmpeg")
    out = tmp_path / "m.mp4"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-c", MOVIE, str(out)], capture_output=True, text=True, env=env,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout == "done\n" and out.stat().st_size > 0
    assert "\r" not in p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.startswith("movie m.mp4: ")]
    assert [re.match(r"movie m\.mp4: (\d+)% \((\d+)/20 frames, \d+\.\d s\)$", ln).groups() for ln in lines] == \
        [(str(10 * k), str(2 * k)) for k in range(1, 11)]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_terminal_gets_a_bar_and_a_log_gets_lines() -> None:
    """The same counts, two looks: on a terminal tqdm's bar (redrawn in place: carriage returns, the
    total shown); elsewhere LOG_STEPS lines whatever the number of frames, even fewer frames than that."""
    tty = _Terminal()
    with FrameProgress(1290, "movie s1.mp4", stream=tty) as bar:
        for _ in range(1290):
            bar.update()
    assert "\r" in tty.getvalue() and "1290/1290" in tty.getvalue()
    for total in (3, 1290):
        log = io.StringIO()
        with FrameProgress(total, "movie x.mp4", stream=log) as bar:
            for _ in range(total):
                bar.update()
        text = log.getvalue()
        assert "\r" not in text and len(text.splitlines()) == LOG_STEPS
        assert text.splitlines()[-1].startswith(f"movie x.mp4: 100% ({total}/{total} frames")


def test_the_prebuild_prints_a_line_as_each_job_ends(tmp_path: Path) -> None:
    """The prebuild's job runner names each job as it ends, with the count done and the time so far,
    on stderr, terminal or not (through uv or pip the build's output is hidden: the Makefile runs the
    prebuild as a step of its own, whose lines show)."""
    code = ("import sys; from rrbody.cli.prebuild import _run_jobs; "
            "_run_jobs([[sys.executable, '-c', 'pass']] * 3, None, '.', 2, names=['a', 'b', 'c'], what='compiling')")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=60)
    assert p.returncode == 0, p.stderr
    lines = p.stderr.splitlines()
    assert len(lines) == 3 and "\r" not in p.stderr
    for k, ln in enumerate(lines, 1):
        assert re.match(rf"rrbody: compiling \[{k}/3\] [abc] done \(\d+ s\)$", ln), ln
    assert sorted(ln.split("] ")[1][0] for ln in lines) == ["a", "b", "c"]
