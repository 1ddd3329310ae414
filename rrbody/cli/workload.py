"""The prebuild's workload (:mod:`rrbody.cli.prebuild`): rrbody's own entry points on tiny problems,
which between them reach every compiled kernel.

``python -m rrbody.cli.workload --job I`` runs command I of :data:`COMMANDS` (as ``rrbody`` would,
its output discarded), ``--extras`` the workload outside the command line (the plugin, the batched
wrench and the MuJoCo adapter, the stand-alone right-hand sides), ``--movie-s1`` what ``rrbody
demo`` computes (Movie S1: the prebuild's part ``demo``, which ``make demo`` compiles alone),
``--all`` everything, one after the other in one process. A new kernel joins the whole build with
one line: a command in :data:`COMMANDS`, or a call in one of the workloads :func:`run_extras` runs;
the demo's part runs the Movie S1 scene's own computation, so it follows that scene and nothing
else. Nothing in rrbody imports this module (it imports the command line, which imports the
prebuild).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys

from rrbody.model.laws import LAW_TABLE, Law

__all__ = ["COMMANDS", "run_command", "run_extras", "run_movie_s1", "run_all", "main"]

_ROD = ["--H", "0.2", "--omega", "0.6"]


def _driven_job(law: Law) -> list[str]:
    """A driven rod-mass run under ``law`` (its coefficient and its parameters' examples, from the law table):
    it compiles that law's stepping loop, the law being compiled in."""
    coeff = ["--k", "0.05"] if law.module else []  # (the law "none" has no coefficient)
    params = [x for q in law.params for x in ("--" + q.name.replace("_", "-"), repr(q.example))]
    return ["simulate", *_ROD, *coeff, "--friction", law.name, *params, "--t-max", "0.5", "--json"]


def _free_contact_job(law: Law) -> list[str]:
    """A free disk under ``law`` by the contact method (its footprint quadrature): that law's free loop."""
    params = [x for q in law.params for x in ("--" + q.name.replace("_", "-"), repr(q.example))]
    return ["simulate", "--body", "disk", "--R0", "0.3", "--no-drive", "--v0", "1,0", "--spin0", "3", "--k", "1",
            "--friction", law.name, *params, "--friction-method", "contact", "--t-max", "0.5", "--json"]


#: the command-line workload (each a tiny horizon), heaviest first: the first driven run of each law
#: and the first free run compile a loop, the rest mostly load them
COMMANDS: tuple[list[str], ...] = (
    # the four jobs that compile a stepping loop first (the prebuild's first pass runs them: its
    # N_LOOPS), ordered so that two workers finish them together; the free runs cover every law
    # (run-time choices in the one free loop)
    ["flip-time", *_ROD, "--k", "0.05", "--json"],
    ["simulate", "--body", "disk", "--R0", "0.3", "--no-drive", "--v0", "1,0", "--spin0", "3", "--k", "1",
     "--t-max", "0.5", "--json"],
    # every other law of the table (dry's loop is the flip-time's above): viscous, none, ...
    *(_driven_job(law) for law in LAW_TABLE if law.name != "dry"),
    # a law integrated over a footprint by quadrature (rrbody.physics.footprint_quad): a free disk's loop
    *(_free_contact_job(law) for law in LAW_TABLE if law.params),
    ["simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.3", "--no-drive", "--v0", "1,0", "--spin0", "3",
     "--k", "1", "--friction", "viscous", "--t-max", "0.5", "--json"],
    ["simulate", "--no-drive", "--H", "0.2", "--v0", "1,0", "--friction", "none", "--t-max", "0.5", "--json"],
    ["simulate", *_ROD, "--k", "10000", "--t-max", "0.5", "--stepper", "rodas", "--json"],
    ["critical-h", "--k", "0.05", "--omega", "0.6", "--tol", "0.01", "--accuracy", "draft", "--json"],
    # extended driven bodies: every area method (run time choices inside the same loop)
    ["simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.3", "--l", "0.2", "--omega", "0.6", "--k",
     "0.05", "--t-max", "0.5", "--json"],
    ["simulate", "--body", "disk", "--R0", "0.3", "--l", "0.2", "--omega", "0.6", "--k", "0.05",
     "--friction-method", "icr", "--t-max", "0.5", "--json"],
    ["simulate", "--body", "disk", "--R0", "0.3", "--l", "0.2", "--omega", "0.6", "--k", "0.05",
     "--friction-method", "sampled", "--samples", "64", "--t-max", "0.5", "--json"],
    ["simulate", "--body", "ellipse", "--R0", "0.3", "--delta", "0.3", "--omega", "0.6", "--k", "0.05",
     "--friction", "viscous", "--t-max", "0.5", "--method", "engine", "--json"],
    # real contacts: a pressure profile (the contact method), a tilt and static friction
    ["simulate", "--body", "disk", "--R0", "0.3", "--no-drive", "--v0", "1,0", "--spin0", "3", "--mu", "0.3",
     "--pressure", "ring:0.3", "--tilt", "0.3", "--mu-static", "0.5", "--t-max", "0.5", "--json"],
    ["simulate", *_ROD, "--k", "0.05", "--tilt", "0.2", "--t-max", "0.5", "--json"],
    # an active body with noise on the ODE path: the fixed-step stochastic scheme (rrbody.integrate.sde)
    ["simulate", "--body", "disk", "--R0", "0.3", "--no-drive", "--v0", "1,0", "--k", "1", "--friction", "viscous",
     "--active-force", "1", "--rot-drag", "2", "--rot-diffusion", "0.1", "--seed", "1", "--t-max", "0.5", "--json"],
)


def run_movie_s1() -> None:
    """What ``rrbody demo`` computes before it draws (the scene ``movie-s1``): the flip time, the run
    sampled for the movie, and the friction the movie's arrows show (the scene's own wrench kernel,
    :func:`rrbody.render.quantities.mechanics`), on a short horizon, with the scene script's own body,
    law and numbers (which decide the kernels); the drawing itself compiles nothing."""
    from rrbody.analysis.flip import flip_time
    from rrbody.analysis.simulate import simulate
    from rrbody.cli.scenes import load_scene
    from rrbody.model.scene import rod_mass_scene
    from rrbody.render.quantities import mechanics

    s1 = load_scene("movie-s1")
    scene = rod_mass_scene(s1.H, s1.K, s1.OMEGA, s1.PHI0)
    flip_time(scene)
    mechanics(simulate(scene, t_max=1.0, dt_out=s1.DT_OUT))


def _plugin_workload() -> None:
    """The plugin's kernels: a circle (the disk's table), a box (its footprint table) and a thick segment
    (the exact wrench), stepped a few times; static friction on a tilt; the coupled step of two boxes a
    pusher presses together (a new user's first contact would otherwise compile its solve)."""
    try:
        import pymunk
    except ImportError:  # the engine extra is absent: nothing of the plugin can run here
        return
    from rrbody.engine.plugin import PlaneFriction

    space = pymunk.Space()
    pf = PlaneFriction(space, g=9.81)
    for k, make in enumerate((lambda b: pymunk.Circle(b, 0.05), lambda b: pymunk.Poly.create_box(b, (0.1, 0.06)),
                              lambda b: pymunk.Segment(b, (-0.05, 0.0), (0.05, 0.0), 0.01))):
        body = pymunk.Body()
        shape = make(body)
        shape.density = 800.0
        body.position = (0.3 * k, 0.0)
        space.add(body, shape)
        body.velocity, body.angular_velocity = (1.0, 0.2), 5.0
        pf.add(body, mu=0.3, friction_method="table" if k == 1 else "auto")  # the box: the footprint table's build
    from rrbody.model.active import Active

    pf.activate(pf.bodies[0], Active(force=0.01, point=(0.01, 0.0), rot_drag=1.0, rot_diffusion=0.1))  # active rows
    from rrbody.model import pressure as rp

    tilted = PlaneFriction(pymunk.Space(), g=9.81, tilt=0.3)  # static friction and the tilt's pull
    for k, pr in enumerate((rp.hertz(0.04), rp.points([(0.02, 0.0, 1.0), (-0.02, 0.0, 1.0)]))):
        body = pymunk.Body()
        shape = pymunk.Circle(body, 0.05)
        shape.density = 800.0
        body.position = (0.3 * k, 0.0)
        tilted.space.add(body, shape)
        body.velocity, body.angular_velocity = (0.2, 0.0), 1.0  # (a moving body on feet: its first half kick)
        tilted.add(body, mu=0.2, mu_static=0.5, pressure=pr)
    # the coupled step (its first look, its islands and its solve): two boxes pressed together by a pusher
    pushed = PlaneFriction(pymunk.Space(), g=9.81)
    for k in range(2):
        body = pymunk.Body()
        shape = pymunk.Poly.create_box(body, (0.1, 0.1))
        shape.density = 10.0
        body.position = (0.0995 * k, 0.0)
        pushed.space.add(body, shape)
        pushed.add(body, mu=0.4)
    pusher = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    pusher.position = (-0.0605, 0.01)
    pusher.velocity = (0.02, 0.0)
    pushed.space.add(pusher, pymunk.Circle(pusher, 0.01))
    for _ in range(3):
        pf.step(1 / 240)
        tilted.step(1 / 240)
        pushed.step(0.01)
    pf.wrench(pf.bodies[0])
    from rrbody.render.recorder import Recorder

    Recorder(space, pf).capture()  # the recorder's copy kernel (every capture has the same types)
    pf.remove(pf.bodies[-1])


def _rhs_workload() -> None:
    """The stand-alone right-hand sides (``rhs_for``: the engine path's set-up, tests, benchmarks)
    for every compiled code: the command line reaches only some of them."""
    import numpy as np

    from rrbody.model.scene import scene_from_params
    from rrbody.physics.bind import kernel_params
    from rrbody.physics.dynamics import driven_rhs, free_rhs

    for law in LAW_TABLE:
        k = 0.05 if law.module else None  # (the law "none" has no coefficient)
        kw = {"k": k, "friction": law.name, **{q.name: q.example for q in law.params}}
        p, S = kernel_params(scene_from_params(H=0.2, omega=0.6, **kw))  # type: ignore[arg-type]
        driven_rhs(0.0, np.array([3.0, 0.0]), p, S, np.empty(2))
        p, S = kernel_params(scene_from_params(body="disk", R0=0.3, no_drive=True, v0=(1.0, 0.0), **kw))  # type: ignore[arg-type]
        free_rhs(0.0, np.array([0.0, 0.0, 0.0, 1.0, 0.0, 2.0]), p, S, np.empty(6))


def _planar_workload() -> None:
    """The batched wrench (``rrbody.planar``) and the MuJoCo adapter's kernels, called with arrays of the
    types the adapter passes (MuJoCo's own: float64 and int32), so they compile without MuJoCo installed."""
    import numpy as np

    from rrbody.contact import kernel as K
    from rrbody.contact.columns import NO_ACTIVE
    from rrbody.model.pressure import uniform
    from rrbody.mujoco_adapter import kernel as MK
    from rrbody.physics import planar
    from rrbody.physics.batch import stack
    from rrbody.physics.footprint import apply_pressure

    planar.Footprints([planar.circle(0.1), planar.box(0.2, 0.1)]).wrench(0.0, [[1.0, 0.0], [0.0, 1.0]], 2.0)
    shapes, geo, ranges = stack([apply_pressure([planar.box(0.2, 0.2)], uniform())[:2]])
    bodies = np.zeros((1, K.N_BODY))
    bodies[0, [K.MASS, K.INERTIA_PER_MASS, K.LAW, K.REACH, K.REST_RULE, K.SHAPE_FIRST, K.SHAPE_END, K.STAGGERED,
               K.HELD]] = \
        1.0, 0.0067, K.LAW_DRY, 0.15, 1.0, ranges[0, 0], ranges[0, 1], 1.0, -1.0
    i64 = np.zeros(1, dtype=np.int64)
    qpos, qvel = np.array([0.0, 0.0, 0.01, 1.0, 0.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0, 0.0, 0.0, 2.0])
    frame, xfrc, user = np.eye(3), np.zeros((1, 6)), np.zeros((1, 6))
    contacts = np.zeros(1, dtype=np.int32)  # MuJoCo's contact fields (int32), copied contiguous by the adapter
    got, load = np.zeros((1, 7)), np.zeros(1)
    MK.gather(i64, i64, i64, np.zeros((1, 3)), np.array([[1.0, 0.0, 0.0]]), frame, np.array([0.0, 0.0, -9.81]),
              np.full(1, 0.5), np.full(1, 0.5), np.full(2, -1, dtype=np.int64), 0, qpos, qvel, np.zeros(6), xfrc,
              np.zeros(1), contacts, contacts, contacts, 1, bodies, got, load, 1e-3)
    MK.set_planar(0, got[0, 1], got[0, 2], got[0, 3], i64, i64, np.zeros((1, 3)), frame, qpos, qvel)
    K.body_accel(0, got[0, 0], got[0, 1], got[0, 2], got[0, 3], bodies, shapes, geo, np.zeros((0, 3)))
    cache = np.zeros((3, K.N_STATUS), dtype=np.int64)
    ids = np.ones(1, dtype=np.int64)
    lookup = np.array([[1], [0]], dtype=np.int64)
    K.plane_step(got, ids, lookup, cache, bodies, shapes, geo, np.zeros((0, 3)), 0.0, 1e-3, np.zeros((1, 3)),
                 *NO_ACTIVE)
    MK.scatter(i64, i64, i64, np.zeros((1, 3)), frame, bodies, qpos, qvel, xfrc, user, got, np.zeros(1, dtype=bool),
               np.zeros(1), 0.0, 1e-3)
    MK.unapply(i64, xfrc, user)
    MK.hold(i64, i64, np.zeros((1, 3)), frame, np.array([[1.0, 0.0, 0.0]]), np.full(1, 0.15), np.zeros((1, 3)),
            np.zeros(1), qpos, qvel, np.full((1, 4), np.nan))
    # the coverage of the gymnasium environments (rrbody.envs.pusht): two T's of two bars each
    from rrbody.physics.overlap import overlap_area, pieces_area

    tee = np.array([[[-60.0, 30.0], [60.0, 30.0], [60.0, 0.0], [-60.0, 0.0]],
                    [[-15.0, 30.0], [-15.0, 120.0], [15.0, 120.0], [15.0, 30.0]]])
    overlap_area(tee, tee + 1.0) / pieces_area(tee)


def run_extras() -> None:
    """The workload outside the command line (the plugin, the batched wrench and the MuJoCo adapter's
    kernels, the stand-alone right-hand sides), in this process."""
    _plugin_workload()
    _planar_workload()
    _rhs_workload()


def run_command(argv: list[str]) -> None:
    """One command of the workload in this process, its output discarded; a failure raises."""
    from rrbody.cli.main import main as cli_main

    with contextlib.redirect_stdout(io.StringIO()):
        code = cli_main(list(argv))
    if code != 0:
        raise RuntimeError(f"prebuild: 'rrbody {' '.join(argv)}' exited {code}")


def run_all() -> None:
    """Every job of the workload, one after the other in this process (the prebuild's check pass):
    one start-up instead of one per job, and a kernel a race lost is compiled here."""
    for argv in COMMANDS:
        run_command(argv)
    run_extras()
    run_movie_s1()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m rrbody.cli.workload", description=__doc__.split("\n\n")[0])
    group = ap.add_mutually_exclusive_group(required=True)
    group.add_argument("--job", type=int, choices=range(len(COMMANDS)), help="run command I of COMMANDS")
    group.add_argument("--extras", action="store_true", help="the plugin and the stand-alone right-hand sides")
    group.add_argument("--movie-s1", action="store_true", help="what `rrbody demo` computes (the part demo)")
    group.add_argument("--all", action="store_true", help="everything, in this process")
    args = ap.parse_args(argv)
    if args.job is not None:
        run_command(COMMANDS[args.job])
    elif args.extras:
        run_extras()
    elif args.movie_s1:
        run_movie_s1()
    else:
        run_all()
    return 0


if __name__ == "__main__":
    sys.exit(main())
