"""The sweep quantity ``chaos``: the maximal Lyapunov exponent and the fraction of time in reverse
rotation at one parameter point, for maps over (tilt, omega) or any other pair of scene parameters.

One run per point (:func:`rrbody.analysis.chaos.lyapunov`): ``transient`` driving periods first
(discarded), then the span over which the exponent is averaged (renormalised once per period) and
the spin sampled ``rr_samples`` times per period: ``periods`` driving periods of the point's
drive, or ``t_max`` seconds at every point (as ``rrbody lyapunov --t-max``; the command line's
form). The estimate is chosen per point as ``rrbody lyapunov --estimate auto`` chooses it
(:func:`rrbody.analysis.chaos.auto_method`): tangent (the variational equations) where the
right-hand side is smooth, two trajectories under dry friction.

Reverse rotation (RR) here is the paper's: the body spins against its orbit, phi' omega < 0 (the
movies' dial turns red then). ``rr_fraction`` is the share of the averaging span in RR.

Columns (units):

- ``lambda_max`` (1/s): the maximal exponent over the averaging span;
- ``lambda_2`` (1/s): the second exponent (tangent only; empty for two trajectories);
- ``method``: ``tangent`` or ``two``;
- ``lambda_spread`` (1/s): max - min of the running estimate over the last half of the span, the
  convergence check of ``rrbody scene chaos`` (converged: small next to ``lambda_max``); empty
  for a span of fewer than 4 periods;
- ``lambda_floor`` (1/s): log(T)/T for the span T: a regular (quasi-periodic) orbit's estimate
  decays like this, so ``lambda_max`` of the order of it or below is not told apart from 0;
- ``rr_fraction``: share of the samples with phi' omega < 0 (dimensionless, 0..1);
- ``rr_bound``: sign changes x sample spacing / T, a bound on ``rr_fraction``'s sampling error when
  no two sign changes fall within one spacing;
- ``t_measured`` (s): the span T (``t_max``, or periods x 2 pi / |omega|).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from rrbody.model.checks import check, check_choice, check_int

__all__ = ["CHAOS_COLUMNS", "CHAOS_OPTIONS", "CHAOS_DEFAULTS", "check_chaos_options", "check_chaos_scene",
           "chaos_point"]

CHAOS_COLUMNS: tuple[str, ...] = ("lambda_max", "lambda_2", "method", "lambda_spread", "lambda_floor", "rr_fraction",
                                  "rr_bound", "t_measured")
#: options of the quantity and their defaults: 200 periods average the exponent of the chaotic
#: points of the chaos-map scene to a median 8 % (benchmarks/results/chaos_map_summary.md)
CHAOS_DEFAULTS: dict[str, Any] = {"periods": 200, "transient": 20, "rtol": 1e-10, "d0": 1e-8, "rr_samples": 32,
                                  "estimate": "auto"}
#: ``t_max`` (s): the span in seconds at every point, in place of ``periods``
CHAOS_OPTIONS: tuple[str, ...] = (*CHAOS_DEFAULTS, "t_max")
#: string columns (the store writes them as text in NetCDF)
TEXT_COLUMNS = ("method",)


def check_chaos_options(options: Mapping[str, Any]) -> dict[str, Any]:
    """The options with their defaults filled in; ValueError naming a bad one, its value and range."""
    bad = [k for k in options if k not in CHAOS_OPTIONS]
    if bad:
        raise ValueError(f"options for chaos must be among {', '.join(CHAOS_OPTIONS)}, got {bad!r}")
    given = {k: v for k, v in options.items() if v is not None}
    if "t_max" in given and "periods" in given:
        raise ValueError(f"t_max and periods both give the span (t_max={given['t_max']!r} s, periods="
                         f"{given['periods']!r}): give one of them")
    o = {**CHAOS_DEFAULTS, **given}
    if "t_max" in given:
        o["t_max"] = float(check("t_max", given["t_max"]))
        o["periods"] = None
    else:
        o["periods"] = check_int("periods", o["periods"], 2, 10_000_000, unit="driving periods")
    o["transient"] = float(check("settle_periods", o["transient"], label="transient"))  # driving periods
    o["rtol"] = float(check("rtol", o["rtol"]))
    o["d0"] = float(check("d0", o["d0"]))
    o["rr_samples"] = check_int("rr_samples", o["rr_samples"], 1, 100_000, unit="per driving period")
    check_choice("estimate", o["estimate"], ("auto", "tangent", "two"))
    return o


def check_chaos_scene(scene: Any, options: Mapping[str, Any]) -> None:
    """Refuse, before any work, an estimate the scene cannot take: tangent under dry friction."""
    from rrbody.analysis.chaos import auto_method

    if options.get("estimate") == "tangent" and auto_method(scene) == "two":
        raise ValueError("estimate 'tangent' needs a smooth right-hand side, and dry friction has a kink where the "
                         "contact stops sliding: use estimate 'two' or 'auto'")


def chaos_point(scene: Any, **options: Any) -> dict[str, Any]:
    """The ``chaos`` columns of the driven ``scene`` (options: :data:`CHAOS_DEFAULTS`)."""
    from rrbody.analysis.chaos import auto_method, lyapunov

    o = check_chaos_options(options)
    if not scene.driven:
        raise ValueError("quantity 'chaos' needs a driven scene")
    method = auto_method(scene) if o["estimate"] == "auto" else o["estimate"]
    period = 2.0 * math.pi / abs(scene.omega)
    span = o["t_max"] if o["periods"] is None else o["periods"] * period
    res = lyapunov(scene, t_max=span, transient=o["transient"] * period, rtol=o["rtol"], method=method, d0=o["d0"],
                   rr_samples=o["rr_samples"])
    half = res.running[len(res.times) // 2:, 0]
    return {"lambda_max": float(res.exponents[0]),
            "lambda_2": float(res.exponents[1]) if len(res.exponents) > 1 else None,
            "method": method, "lambda_spread": float(np.max(half) - np.min(half)) if len(res.times) >= 4 else None,
            "lambda_floor": math.log(span) / span if span > 1.0 else None,
            "rr_fraction": res.meta["rr_fraction"], "rr_bound": res.meta["rr_bound"], "t_measured": span}
