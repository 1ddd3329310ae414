"""Optional dependencies ("extras") and the one-line error that names the extra to install.

The core install (``pip install rrbody``: numpy, scipy, numba, tqdm) computes flip times, H_c,
trajectories and sweeps and writes CSV. Everything else is an extra, imported only where it is used:

=========  ======================================  ==========================================
extra      packages                                needed for
=========  ======================================  ==========================================
engine     pymunk                                  ``method="engine"``, the pymunk plugin
movie      matplotlib, imageio, imageio-ffmpeg     MP4 movies, posters, every scene's figure
rerun      rerun-sdk                               ``.rrd`` recordings, the rerun viewer
dask       dask[distributed]                       sweeps on a Dask cluster
data       xarray                                  NetCDF (``.nc``) sweep output
mujoco     mujoco                                  the MuJoCo adapter (``rrbody.mujoco``)
docs       sphinx, furo, myst-parser, selenium     ``make docs`` and its browser check
test       pytest, hypothesis, pytest-xdist, ruff  ``make test``
all        every extra above
=========  ======================================  ==========================================

The hint names the install command that works where rrbody runs from: ``pip install 'rrbody[movie]'``
for an installed package, ``pip install -e '.[movie]'`` run in the checkout's folder (named in the
message) when rrbody runs from a source checkout, where ``rrbody[movie]`` would fetch a second copy
from the package index instead of adding the extra to the checkout.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from types import ModuleType

from rrbody.model.paths import source_checkout

__all__ = ["EXTRA_OF", "MissingExtraError", "require", "missing_extra_message", "install_hint",
           "source_checkout"]

#: top-level module name -> the extra that installs it
EXTRA_OF: dict[str, str] = {
    "pymunk": "engine",
    "matplotlib": "movie", "imageio": "movie", "imageio_ffmpeg": "movie",
    "rerun": "rerun", "pyarrow": "rerun",
    "dask": "dask", "distributed": "dask",
    "xarray": "data", "netCDF4": "data", "h5netcdf": "data",
    "mujoco": "mujoco",
    "gymnasium": "envs",
    "sphinx": "docs", "furo": "docs", "myst_parser": "docs", "selenium": "docs",
}


class MissingExtraError(ImportError):
    """An optional dependency is not installed; the message names the extra that provides it."""


def install_hint(extra: str, package_dir: Path | None = None) -> str:
    """The command that installs ``extra`` for the rrbody at ``package_dir`` (default: this one)."""
    root = source_checkout(package_dir) if package_dir is not None else source_checkout()
    if root is None:
        return f"pip install 'rrbody[{extra}]'"
    # from a checkout, 'rrbody[extra]' would install a second rrbody from the index beside the checkout
    return f"pip install -e '.[{extra}]' (run in {root})"


def _message(module: str, purpose: str | None) -> str:
    extra = EXTRA_OF.get(module.split(".")[0], "all")
    what = f"{purpose} needs" if purpose else "this needs"
    return f"{what} the optional package {module.split('.')[0]!r}: {install_hint(extra)}"


def require(module: str, *, purpose: str | None = None) -> ModuleType:
    """Import ``module`` or raise :class:`MissingExtraError` naming the extra to install."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as e:
        if e.name is not None and module.split(".")[0] != e.name.split(".")[0] and e.name.split(".")[0] not in EXTRA_OF:
            raise  # a broken install of something else, not a missing extra: keep the real error
        raise MissingExtraError(_message(e.name or module, purpose)) from None


def missing_extra_message(exc: BaseException) -> str | None:
    """The one-line message for an ImportError caused by a missing extra, else None."""
    if isinstance(exc, MissingExtraError):
        return str(exc)
    name = getattr(exc, "name", None)
    if isinstance(exc, ModuleNotFoundError) and name and name.split(".")[0] in EXTRA_OF:
        return _message(name, None)
    return None
