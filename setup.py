"""Build hook: compile rrbody's kernels once, at install (docs/compile.md, "Kernels compiled at install").

Everything else about the package is declared in pyproject.toml. After setuptools has laid out the
package (a wheel's build folder, or the checkout itself for an editable install), this runs
``python -m rrbody.cli.prebuild --into <package>/_kernels`` from the source tree, so the first command a
user runs loads compiled kernels instead of compiling them for 20-30 s. ``RRBODY_BUILD_KERNELS=0``
skips it (the kernels are then compiled on first use, into the user's cache folder, as numba does).
A failed kernel build fails the install: it would otherwise hide a broken kernel until first use.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


class BuildWithKernels(build_py):
    """setuptools' build_py, then the kernels into the package's ``_kernels`` folder."""

    def run(self) -> None:
        super().run()
        if os.environ.get("RRBODY_BUILD_KERNELS", "1") == "0":
            return
        package = ROOT / "rrbody" if getattr(self, "editable_mode", False) else Path(self.build_lib) / "rrbody"
        # the source tree first; the rest of PYTHONPATH is how pip's isolated build environment
        # provides numba and numpy, so it stays
        path = os.environ.get("PYTHONPATH", "")
        env = dict(os.environ, PYTHONPATH=str(ROOT) + (os.pathsep + path if path else ""))
        subprocess.run([sys.executable, "-m", "rrbody.cli.prebuild", "--into", str(package / "_kernels")],
                       env=env, check=True, cwd=str(ROOT))


setup(cmdclass={"build_py": BuildWithKernels})
