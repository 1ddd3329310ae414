"""The Runge-Kutta constants written out in rrbody.integrate.tableaus are scipy's, bit for bit.

rrbody once read them from scipy's private files at import; now they are copied into the repository
(with their source named there), and this test holds the copy to scipy's own arrays on whichever scipy
the suite runs (the newest and, in ``.venv-lowest``, the oldest pyproject allows). The comparison is
exact (``np.array_equal``): the constants are the same decimal literals and expressions, so any
difference, even in the last bit, is a copying error.
"""

from __future__ import annotations

import numpy as np


def test_dop853_constants_are_scipys() -> None:
    from scipy.integrate._ivp import dop853_coefficients as co

    from rrbody.integrate import tableaus as tb
    from rrbody.integrate.dop853 import TABLEAU

    n = co.N_STAGES
    assert tb.DOP853_STAGES == n == 12
    assert np.array_equal(tb.DOP853_A, co.A[:n, :n])
    assert np.array_equal(tb.DOP853_B, co.B)
    assert np.array_equal(tb.DOP853_C, co.C[:n])
    assert np.array_equal(tb.DOP853_E3, co.E3)
    assert np.array_equal(tb.DOP853_E5, co.E5)
    for ours, theirs in zip(TABLEAU, (co.A[:n, :n], co.B, co.C[:n], co.E3, co.E5), strict=True):
        assert ours.dtype == np.float64 and ours.flags.c_contiguous and np.array_equal(ours, theirs)
    # a classic check beside the copy: the weights sum to 1 and each row of A sums to its node
    assert abs(tb.DOP853_B.sum() - 1.0) < 1e-14
    assert np.allclose(tb.DOP853_A.sum(axis=1), tb.DOP853_C, rtol=0, atol=1e-14)


def test_radau_constants_are_scipys() -> None:
    from scipy.integrate._ivp import radau as ra

    from rrbody.integrate import tableaus as tb
    from rrbody.integrate.radau import RADAU_TABLE

    for name in ("C", "E", "T", "TI", "P"):
        assert np.array_equal(getattr(tb, f"RADAU_{name}"), getattr(ra, name)), name
    assert tb.RADAU_MU_REAL == ra.MU_REAL and tb.RADAU_MU_COMPLEX == ra.MU_COMPLEX
    C, E, T, TI, MU, P = RADAU_TABLE
    assert np.array_equal(MU, [ra.MU_REAL, ra.MU_COMPLEX.real, ra.MU_COMPLEX.imag])
    assert all(a.dtype == np.float64 and a.flags.c_contiguous for a in RADAU_TABLE)
    # T and TI are inverses to the digits scipy prints them with (17 significant): 1e-14
    assert np.allclose(T @ TI, np.eye(3), rtol=0, atol=1e-14)


def test_no_library_source_is_executed_or_loaded_by_path() -> None:
    """No module of rrbody ``exec``s text or loads a module from a file path (the constants above were
    read so before); the one load by path left, ``rrbody.cli.lean``'s of scipy's public
    ``cython_blas``, is a start-up trim with its own fallback (docs/versions.md). ``rrbody.cli.scenes``
    loads scene scripts by path: that is its job (``rrbody scene NAME``), and they are rrbody's own or the
    user's, never a library's."""
    import re
    from pathlib import Path

    import rrbody

    root = Path(rrbody.__file__).parent
    found = []
    for path in sorted(set(root.rglob("*.py")) - {root / "cli" / "scenes.py"}):
        text = path.read_text(encoding="utf-8")
        for pattern in (r"\bexec\(", r"spec_from_file_location", r"\bcompile\(.*\"exec\""):
            if re.search(pattern, text):
                found.append(f"{path.relative_to(root)}: {pattern}")
    assert found == [], found
