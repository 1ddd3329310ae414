"""The table under a pymunk environment: its parameters, their defaults and their checks.

Shared by the Push-T environment (:mod:`rrbody.envs.pusht`) and the wrapper that puts gym-pusht's own
environment on a table (:mod:`rrbody.envs.wrapper`), so that both take the same keywords with the same
defaults and refuse the same values with the same messages.

Units. A pymunk environment has its own length unit (Push-T: a 512 x 512 workspace); ``scale`` is the
length of one such unit in metres, so the gravitational acceleration the plugin is given, in the
space's units, is ``g / scale`` (units/s^2). Masses keep the environment's own unit: dry friction's
deceleration mu g does not depend on it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from rrbody.model.checks import LIMITS, check, check_positive, range_text
from rrbody.model.friction import check_mu_static
from rrbody.model.pressure import Pressure, as_pressure

#: One Push-T workspace unit in metres. The real-robot T of Diffusion Policy (its 3D-printed tee, of
#: which ManiSkill's PushT-easy-v1 is a replica) has a top bar 0.2 m long and 0.05 m wide; gym-pusht's
#: top bar is 120 x 30 units, so one unit is 0.2 / 120 = 0.05 / 30 m (both sides agree).
SCALE = 1.0 / 600.0
#: Gravitational acceleration, m/s^2.
G = 9.81
#: Kinetic friction coefficient of the table: a plastic (PLA) part on a wooden or laminate table top.
MU = 0.3


@dataclass(frozen=True)
class Table:
    """A table's checked parameters.

    ``mu``, ``mu_static`` (None: equal to ``mu``) and ``pressure`` as
    :meth:`rrbody.engine.plugin.plane.PlaneFriction.add` takes them; ``g`` in m/s^2; ``scale`` in m per unit
    of the environment's space.
    """

    mu: float
    mu_static: float | None
    pressure: Pressure | str
    g: float
    scale: float

    @property
    def g_space(self) -> float:
        """The gravitational acceleration in the space's units, units/s^2."""
        return self.g / self.scale


def make_table(mu: Any = MU, mu_static: Any = None, pressure: Any = "uniform", g: Any = G,
               scale: Any = SCALE) -> Table:
    """Check a table's parameters (ValueError naming the parameter, its value and the valid range)."""
    mu_f = float(check("mu", mu))
    mu_s = None if mu_static is None else check_mu_static(mu_static, mu_f)
    as_pressure(pressure)  # refuses an unknown pressure now, before any environment is built
    t = Table(mu=mu_f, mu_static=mu_s, pressure=pressure, g=float(check("g", g)),
              scale=check_positive("scale", scale, unit="m per unit"))
    lim = LIMITS["g"]
    if not lim.lo <= t.g_space <= lim.hi:  # PlaneFriction would refuse g / scale later: say it now, naming scale
        raise ValueError(f"scale must be {range_text(t.g / lim.hi, t.g / lim.lo, unit='m per unit')} for "
                         f"g = {t.g:g} m/s^2 (the plane presses with g / scale units/s^2, which PlaneFriction "
                         f"takes {range_text(lim.lo, lim.hi)}), got {scale!r}")
    return t
