"""The plugin kernel's arrays (:mod:`rrbody.contact.kernel`): their layouts and the names of their columns.

Array layouts (columns)
-----------------------
``bodies`` (float, one row per plugin body; the columns are named, their order is the kernel's own
business): MASS (kg), INERTIA_PER_MASS = I/m (m^2), LAW (the law table's code as a float, :data:`LAW_CODE`: 0 none,
1 dry, 2 viscous), FRICTION_COEFF (mu g in m/s^2, or gamma in 1/s), REACH (m: largest distance of the footprint from the
centre of gravity), REST_RULE (1.0: the rest rule applies), SHAPE_FIRST, SHAPE_END (its rows in ``shapes``), SLIP_EPS
(m/s: slower elements have no dry-friction direction), LOAD_MEAN_X, LOAD_MEAN_Y, LOAD_SPREAD (load-weighted mean
position, m, and mean squared distance, m^2, of the footprint: all the viscous law needs), STAGGERED (1.0: the
staggered, second-order reading of velocities; 0.0: plain symplectic Euler), then the state: PREV_VX, PREV_VY, PREV_SPIN
(the velocity one step back), PREV_GAP (s between it and the current one; 0 = no history yet), STOP
(STOPPING or ZEROED if the rest rule acted in the last step, else 0), EVAL_ANGLE, EVAL_SPIN (the angle and spin
friction was evaluated at); for a body held at P by rrbody's circular driver (DRIVEN = 1): DRIVE_OMEGA, DRIVE_D
(omega, rad/s, and d, m), ANCHOR_X, ANCHOR_Y (P in the body frame, m), DRIVE_T0 (the plugin's time at attach, s), and
the driver's state for this step DRIVE_PX, DRIVE_PY, DRIVE_VX, DRIVE_VY (m, m/s), computed with the friction;
STATIC_COEFF (mu_static g cos(tilt), m/s^2: the static friction per unit mass; 0: none), TILT_GX, TILT_GY (gravity's
in-plane part on a tilted plane, m/s^2, world frame), and the last load static friction held: HELD_LOAD_X,
HELD_LOAD_Y, HELD_LOAD_TORQUE (per unit mass, world frame) at the angle HELD_ANGLE, HELD = 1.0 (the next step with the
same load and angle needs no new test); FRICTION_FX, FRICTION_FY, FRICTION_TORQUE: the friction the last step applied
(N, world frame, and N m about the centre of gravity; static friction and the rest rule's stopping impulse included),
for readers such as the recorder; FEET (1.0: a body on two or more point feet, whose foot static friction
holds at rest: :mod:`rrbody.contact.feet`), PINNED_FOOT (1 + the index of the foot held since the last step, 0:
none), LOAD_FX, LOAD_FY, LOAD_TORQUE: the load the last step applied besides friction (N, world frame, and N m about the
centre of gravity: the user's force and torque, a tilt's pull, the active load; the coupled step's free
velocity, :mod:`rrbody.contact.coupled`), DEFERRED (1.0 while :func:`rrbody.contact.kernel.plane_step` has deferred the
body to its limit-set loop), TABLE_KIND, TABLE_START: how its dry friction is evaluated (TABLE_NONE:
:func:`rrbody.physics.contact.footprint_wrench`, exact; TABLE_CIRCLE: one disk, the wrench table of
:mod:`rrbody.physics.icr_table`; TABLE_FOOTPRINT: the footprint's own table, :mod:`rrbody.physics.footprint_table`)
and where its table starts in ``tables``. ``tables`` (float, rows of 3): the wrench tables the bodies use, one copy
per distinct table. ``shapes`` (float, per footprint part) and ``geo``: the footprint rows of
:mod:`rrbody.physics.contact`. ``lookup``: row 0 the plugin bodies' ids (int64 view of pymunk's uintptr ids) sorted,
row 1 their rows. ``cache`` (int64, rows ROWMAP, ROW_ID, STATUS): the plugin row of each row of the space's bulk read,
the id it was found for, and what the last check found (see :func:`rrbody.contact.kernel.plane_check`).
``active`` (float, one row per plugin body, columns :mod:`rrbody.physics.effects.active`) and ``noise`` (this
step's standard normal numbers): the active bodies' load; :data:`NO_ACTIVE` is the pair a step without active
bodies passes.
"""

from __future__ import annotations

import numpy as np

from rrbody.model.laws import LAW_CODES, N_LAW_PARAMS
from rrbody.physics.effects import active as A

__all__ = ["MASS", "INERTIA_PER_MASS", "LAW", "FRICTION_COEFF", "REACH", "REST_RULE", "SHAPE_FIRST", "SHAPE_END",
           "SLIP_EPS", "STAGGERED", "PREV_VX", "PREV_VY", "PREV_SPIN", "PREV_GAP", "STOP", "EVAL_ANGLE", "EVAL_SPIN",
           "DRIVEN", "STATIC_COEFF", "TILT_GX", "TILT_GY", "FRICTION_FX", "FRICTION_FY", "FRICTION_TORQUE", "FEET",
           "TABLE_KIND", "TABLE_START", "DEFERRED", "LOAD_MEAN_X", "LOAD_MEAN_Y", "LOAD_SPREAD", "DRIVE_OMEGA",
           "DRIVE_D", "ANCHOR_X", "ANCHOR_Y", "DRIVE_T0", "DRIVE_PX", "DRIVE_PY", "DRIVE_VX", "DRIVE_VY", "HELD_LOAD_X",
           "HELD_LOAD_Y", "HELD_LOAD_TORQUE", "HELD_ANGLE", "HELD", "PINNED_FOOT", "LOAD_FX", "LOAD_FY", "LOAD_TORQUE",
           "N_BODY", "STOPPING", "ZEROED", "LAW_CODE", "LAW_NONE", "LAW_DRY", "LAW_VISCOUS", "LAW_PARAMS", "DEFER",
           "TABLE_NONE", "TABLE_CIRCLE", "TABLE_FOOTPRINT", "N_STATUS", "ROWMAP", "ROW_ID", "STATUS", "SEEN", "BAD",
           "FIRST_BAD", "NO_ACTIVE"]

# the columns every step reads or writes come first (the row's first four cache lines), the rest after
(MASS, INERTIA_PER_MASS, LAW, FRICTION_COEFF, REACH, REST_RULE, SHAPE_FIRST, SHAPE_END, SLIP_EPS, STAGGERED, PREV_VX,
 PREV_VY, PREV_SPIN, PREV_GAP, STOP, EVAL_ANGLE, EVAL_SPIN, DRIVEN, STATIC_COEFF, TILT_GX, TILT_GY, FRICTION_FX,
 FRICTION_FY, FRICTION_TORQUE, FEET, TABLE_KIND, TABLE_START, DEFERRED, LOAD_MEAN_X, LOAD_MEAN_Y, LOAD_SPREAD,
 DRIVE_OMEGA, DRIVE_D, ANCHOR_X, ANCHOR_Y, DRIVE_T0, DRIVE_PX, DRIVE_PY, DRIVE_VX, DRIVE_VY, HELD_LOAD_X, HELD_LOAD_Y,
 HELD_LOAD_TORQUE, HELD_ANGLE, HELD, PINNED_FOOT, LOAD_FX, LOAD_FY, LOAD_TORQUE, LAW_PARAMS) = range(50)
#: The law's further parameters per unit mass sit from LAW_PARAMS on (rrbody.model.laws.bound_params: N_LAW_PARAMS of
#: them), at the row's end
N_BODY = LAW_PARAMS + N_LAW_PARAMS
#: STOP values: the rest rule cancels the velocity in this step, or (the step after) sets it exactly zero
STOPPING, ZEROED = 1.0, 2.0
#: the LAW column's values: the law table's codes (rrbody.model.laws), as floats; numba reads these module
#: constants at compile time, so they are derived here, at import, from the table
LAW_CODE: dict[str, float] = {name: float(code) for name, code in LAW_CODES.items()}
LAW_NONE, LAW_DRY, LAW_VISCOUS = LAW_CODE["none"], LAW_CODE["dry"], LAW_CODE["viscous"]
#: what the lean sweep's step of a body returns when it leaves the body to the limit-set loop
DEFER = 2
#: TABLE_KIND values: the exact footprint wrench; a disk's wrench table (icr_table's, dimensionless); the
#: footprint's own table (rrbody.physics.footprint_table)
TABLE_NONE, TABLE_CIRCLE, TABLE_FOOTPRINT = 0.0, 1.0, 2.0

#: rows of ``cache`` (int64, 3 x at least max(N_STATUS, bodies in the space)): the plugin row of each row of
#: the space's bulk read (-1: not a plugin body), the id it was found for, and the last check's status
ROWMAP, ROW_ID, STATUS = 0, 1, 2
#: STATUS entries: plugin bodies found in the space, plugin bodies with a non-finite state, and the
#: ``got`` row of the first of them (-1 if none)
SEEN, BAD, FIRST_BAD = 0, 1, 2
N_STATUS = 3

#: the arrays a plugin without active bodies passes (the kernel skips the effect: no rows)
NO_ACTIVE: tuple[np.ndarray, np.ndarray] = (np.zeros((0, A.N_ACTIVE)), np.zeros(0))
