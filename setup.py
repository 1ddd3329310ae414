"""Build hook: compile rrbody's kernels once, at install (docs/compile.md, "Kernels compiled at install").

Everything else about the package is declared in pyproject.toml. After setuptools has laid out the
package (a wheel's build folder, or the checkout itself for an editable install), this runs
``python -m rrbody.cli.prebuild --into <package>/_kernels`` from the source tree, so the first command a
user runs loads compiled kernels instead of compiling them for tens of seconds (docs/compile.md, "What
it costs": the recorded times). ``RRBODY_BUILD_KERNELS=0`` skips it (the kernels are then compiled on
first use, into the user's cache folder, as numba does). The Makefile installs with it and then runs
the same prebuild as a step of its own: through uv or pip a build's output is hidden, and the
prebuild's line per job is the only sign of progress for a minute or more.
A failed kernel build fails a wheel build (`pip install .`); in an editable install setuptools turns
it into a warning, and the Makefile's ``.venv/.kernels`` step, which runs the same build, then fails.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


class BuildWithKernels(build_py):
    """setuptools' build_py, then the kernels into the package's ``_kernels`` folder."""

    def run(self) -> None:
        if not getattr(self, "editable_mode", False):
            # setuptools leaves files of earlier builds in build/lib: a module moved since would be built into
            # the wheel beside its new home, and the installed kernels' source hash (rrbody._cache) would
            # then differ from the one they were compiled for, so none would load
            shutil.rmtree(Path(self.build_lib) / "rrbody", ignore_errors=True)
        super().run()
        if os.environ.get("RRBODY_BUILD_KERNELS", "1") == "0":
            return
        package = ROOT / "rrbody" if getattr(self, "editable_mode", False) else Path(self.build_lib) / "rrbody"
        # `python -m` from the source tree imports rrbody from it (the current folder comes first on
        # sys.path); the environment, pip's isolated build environment included, stays as it is
        subprocess.run([sys.executable, "-m", "rrbody.cli.prebuild", "--into", str(package / "_kernels")],
                       check=True, cwd=str(ROOT))


setup(cmdclass={"build_py": BuildWithKernels})
