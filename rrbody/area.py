"""Area-integrated friction for extended bodies (owned by the extended-bodies work).

Placeholder interface until that lands: no extended-body friction yet.
"""

from __future__ import annotations

import numpy as np

from .bodies import Body


def icr_supported(body: Body, law: str) -> bool:
    """Whether the instantaneous-centre quadrature applies (not implemented yet)."""
    return False


def icr_nodes(body: Body) -> int:
    raise NotImplementedError("instantaneous-centre quadrature not implemented yet")


def area_samples(body: Body, n: int) -> np.ndarray:
    raise NotImplementedError("area samples not implemented yet")
