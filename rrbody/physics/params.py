"""Layout of the float64 parameter vector ``p`` that every compiled kernel receives.

Kernels take parameters as arguments (no closures) so one compiled function serves every scene.
:func:`rrbody.physics.bind.kernel_params` fills this vector from a :class:`rrbody.model.scene.Scene`; nothing else
writes it. The codes LAW and BODY form the scene's system code (:func:`rrbody.physics.dynamics.system_from_params`);
the stepping loop is compiled for its kind and LAW, and reads BODY (the area method) at run time, as the engine's
per-step hook (:func:`rrbody.physics.wrench.body_wrench`) reads both.
"""

from rrbody.model.laws import AREA_CODES, N_LAW_PARAMS

OMEGA = 0      # drive rate (rad/s); 0 for a free body
D = 1          # drive radius (m)
L = 2          # pivot offset |CM -> P| (m)
IP = 3         # I_P / m = I_cm/m + l^2 (m^2)
CBETA = 4      # cos beta, beta = phi - alpha the angle of CM->P in the body frame: the driven extended
               # body turns its rod frame into the body frame by beta
LAW = 5        # friction law code (rrbody.model.laws.LAW_CODES: 0 none, 1 dry, 2 viscous)
COEFF = 6      # the law's coefficient: mu*g (m/s^2, dry) or gamma (1/s, viscous)
BODY = 7       # area model: 0 point, 1 sampled elements, 2 instantaneous-centre quadrature, 3 its table,
               # 4 the contact (any pressure distribution, the plugin's footprint kernel)
VEPS = 8       # speed below which a dry element's direction counts as undefined (m/s)
RA = 9         # semi-axis along body x (m)
RB = 10        # semi-axis along body y (m)
NQ = 11        # quadrature nodes of the instantaneous-centre method
ICM = 12       # I_cm / m (m^2)
SBETA = 13     # sin beta
INV_IP = 14    # 1 / IP (1/m^2; 0 where IP is 0: a free body): kernels multiply, as a division is slower
TILTED = 15    # 1.0 on a tilted plane (the tilt effect's terms are evaluated), else 0.0
GTX = 16       # gravity's in-plane pull on a tilted plane (m/s^2, world frame), x
GTY = 17       # ... and y
MUS = 18       # static friction per unit mass, mu_static g cos(tilt) (m/s^2; 0: none)
ACTIVE = 19    # 1.0: a free body's active effect (rrbody.physics.effects.active) is evaluated, else 0.0
AFX = 20       # its propulsion per unit mass (m/s^2, body frame), x
AFY = 21       # ... and y
AALPHA = 22    # its torque about the CM over I_cm (rad/s^2)
ADRAG = 23     # the medium's translational drag rate gamma_t (1/s)
ARDRAG = 24    # ... and its rotational one gamma_r (1/s)
ANOISE = 25    # its Langevin noise on the velocity, gamma_t sqrt(2 D_t) (m s^-1.5, each world component;
               # 0: none); read by the fixed-step scheme of rrbody.integrate.sde, not by the right-hand side
ARNOISE = 26   # ... and on the spin, gamma_r sqrt(2 D_r) (rad s^-1.5; 0: none)
LAWP = 27      # the law's further parameters per unit mass, N_LAW_PARAMS slots from here, in the order the law
               # table declares them (rrbody.model.laws.bound_params; none while no law has parameters)
SIZE = LAWP + N_LAW_PARAMS

# area models: the law table's codes (one table; the effects' registry and the system code carry the same numbers)
BODY_POINT = AREA_CODES["point"]
BODY_SAMPLED = AREA_CODES["sampled"]
BODY_ICR = AREA_CODES["icr"]
BODY_TABLE = AREA_CODES["table"]
BODY_CONTACT = AREA_CODES["contact"]
