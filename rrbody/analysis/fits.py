"""Least-squares fits with standard errors: the q-exponential of H_c(k) (docs/reproduce.md) and power laws.

Every fit returns a :class:`Fit` holding the parameters, their standard errors (square roots of
the diagonal of ``scipy.optimize.curve_fit``'s covariance, scaled by the residual variance:
``absolute_sigma=False``), the x range actually fitted, the number of points and the residuals.
The fitted values of a q-exponential depend on the range (the curve is only approximately a
q-exponential), so the range is part of the result and must be quoted with it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Fit", "q_exponential", "fit_q_exponential", "power_law", "fit_power_law", "select_range"]


@dataclass
class Fit:
    """Result of a fit.

    ``params`` / ``stderr``: name -> value; ``x_range``: (min, max) of the x values used;
    ``residuals``: y - model(x) at the fitted points (same units as y; for power laws fitted in
    log space, ``residuals`` are in ln y); ``rms``: root-mean-square of ``residuals``.
    """

    model: str
    params: dict[str, float]
    stderr: dict[str, float]
    x_range: tuple[float, float]
    n: int
    residuals: np.ndarray = field(repr=False)
    rms: float
    fixed: dict[str, float] = field(default_factory=dict)
    note: str = ""

    def __call__(self, x: Any) -> np.ndarray:
        """Evaluate the fitted model at ``x``."""
        x = np.asarray(x, dtype=float)
        if self.model == "q-exponential":
            return q_exponential(x, self.value("H0"), self.value("lam"), self.value("q"))
        return power_law(x, self.value("A"), self.value("b"))

    def value(self, name: str) -> float:
        """A fitted or fixed parameter by name."""
        if name in self.params:
            return self.params[name]
        if name in self.fixed:
            return self.fixed[name]
        raise ValueError(f"name must be one of {sorted({*self.params, *self.fixed})}, got {name!r}")

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary (residuals included as a list)."""
        return {"model": self.model, "params": self.params, "stderr": self.stderr, "fixed": self.fixed,
                "x_range": list(self.x_range), "n": self.n, "rms": self.rms, "note": self.note,
                "residuals": [float(r) for r in self.residuals]}

    def text(self, name: str, digits: int = 4) -> str:
        """'value(err)' style string, e.g. '1.936 +- 0.004'."""
        return f"{self.params[name]:.{digits}g} +- {self.stderr[name]:.2g}"


def select_range(x: np.ndarray, y: np.ndarray, x_range: tuple[float, float] | None) -> tuple[np.ndarray, np.ndarray]:
    """The finite (x, y) pairs with x in the closed interval ``x_range`` (all finite pairs if None)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"x and y must be 1-D arrays of equal length, got shapes {x.shape} and {y.shape}")
    keep = np.isfinite(x) & np.isfinite(y)
    if x_range is not None:
        lo, hi = float(x_range[0]), float(x_range[1])
        if not hi > lo:
            raise ValueError(f"x_range must be (lo, hi) with hi > lo, got {x_range!r}")
        keep &= (x >= lo) & (x <= hi)
    return x[keep], y[keep]


# ---- q-exponential ---------------------------------------------------------------------------
def q_exponential(x: Any, H0: float, lam: float, q: float) -> np.ndarray:
    """H0 [1 - lam (1 - q) x]^(1/(1 - q)); the ordinary exponential H0 exp(-lam x) at q = 1.

    For q > 1 (the paper's case) the bracket is > 1 for all x >= 0 and the curve decays like a
    power law x^(-1/(q-1)). Where the bracket is <= 0 (q < 1 beyond the cut-off) the value is 0.
    """
    x = np.asarray(x, dtype=float)
    if abs(1.0 - q) < 1e-12:
        return H0 * np.exp(-lam * x)
    base = 1.0 - lam * (1.0 - q) * x
    with np.errstate(invalid="ignore", divide="ignore"):
        out = H0 * np.where(base > 0, np.abs(base) ** (1.0 / (1.0 - q)), 0.0)
    return out


def fit_q_exponential(x: Any, y: Any, *, H0: float | None = None, x_range: tuple[float, float] | None = None,
                      p0: tuple[float, float] = (10.0, 1.5), relative: bool = True) -> Fit:
    """Fit y = H0 [1 - lam (1 - q) x]^(1/(1 - q)) for ``lam`` and ``q`` (and ``H0`` unless given).

    ``H0`` fixed (e.g. the exact frictionless H_c(0)) leaves two free parameters, as in the
    paper's Eq. (qexp0). ``relative=True`` weights each point by 1/y (relative residuals), so a
    curve spanning decades is fitted evenly rather than by its largest values only; the reported
    ``residuals`` are always absolute, y - model.
    """
    from scipy.optimize import curve_fit

    xs, ys = select_range(np.asarray(x, float), np.asarray(y, float), x_range)
    n_free = 2 if H0 is not None else 3
    if xs.size < n_free + 2:
        raise ValueError(f"x_range leaves {xs.size} points; need at least {n_free + 2} for a {n_free}-parameter fit")
    if np.any(ys <= 0):
        raise ValueError("y must be > 0 for a q-exponential fit")
    sigma = ys if relative else None
    if H0 is not None:
        h0 = float(H0)

        def f2(xx: np.ndarray, lam: float, q: float) -> np.ndarray:
            return q_exponential(xx, h0, lam, q)

        popt, pcov = curve_fit(f2, xs, ys, p0=p0, sigma=sigma, absolute_sigma=False, maxfev=20000)
        names = ["lam", "q"]
        fixed = {"H0": h0}
        model_y = f2(xs, *popt)
    else:
        popt, pcov = curve_fit(q_exponential, xs, ys, p0=(float(ys[np.argmin(xs)]), *p0), sigma=sigma,
                               absolute_sigma=False, maxfev=20000)
        names = ["H0", "lam", "q"]
        fixed = {}
        model_y = q_exponential(xs, *popt)
    err = np.sqrt(np.diag(pcov))
    res = ys - model_y
    return Fit("q-exponential", {n: float(v) for n, v in zip(names, popt)}, {n: float(e) for n, e in zip(names, err)},
               (float(xs.min()), float(xs.max())), int(xs.size), res, float(np.sqrt(np.mean(res ** 2))), fixed,
               "weights 1/y (relative residuals)" if relative else "unweighted")


# ---- power law -------------------------------------------------------------------------------
def power_law(x: Any, A: float, b: float) -> np.ndarray:
    """A x^b."""
    return A * np.asarray(x, dtype=float) ** b


def fit_power_law(x: Any, y: Any, *, x_range: tuple[float, float] | None = None) -> Fit:
    """Fit y = A x^b by linear least squares in (ln x, ln y); standard errors from the covariance.

    Fitting in log space weights every decade equally, the usual choice for a log-log plot; the
    ``residuals`` are ln y - ln(A x^b).
    """
    from scipy.optimize import curve_fit

    xs, ys = select_range(np.asarray(x, float), np.asarray(y, float), x_range)
    if xs.size < 3:
        raise ValueError(f"x_range leaves {xs.size} points; need at least 3 for a power-law fit")
    if np.any(xs <= 0) or np.any(ys <= 0):
        raise ValueError("x and y must be > 0 for a power-law fit")
    lx, ly = np.log(xs), np.log(ys)

    def line(u: np.ndarray, a: float, b: float) -> np.ndarray:
        return a + b * u

    b0 = float(np.polyfit(lx, ly, 1)[0])
    popt, pcov = curve_fit(line, lx, ly, p0=(float(np.mean(ly - b0 * lx)), b0))
    a, b = (float(v) for v in popt)
    ea, eb = (float(v) for v in np.sqrt(np.diag(pcov)))
    res = ly - line(lx, a, b)
    A = math.exp(a)
    return Fit("power law", {"A": A, "b": b}, {"A": A * ea, "b": eb}, (float(xs.min()), float(xs.max())),
               int(xs.size), res, float(np.sqrt(np.mean(res ** 2))), {}, "least squares in ln y vs ln x")
