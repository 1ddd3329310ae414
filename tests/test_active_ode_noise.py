"""The active effect's Langevin noise on the ODE path (rrbody.integrate.sde: SRA1, fixed steps, seeded).

Exact references (docs/active.md, "Noise on the ODE path"):

- Rotational noise with rotational drag g only: the spin w is an Ornstein-Uhlenbeck process,
  dw = -g w dt + g sqrt(2 D_r) dW, stationary variance D_r g and correlation e^{-g |s|}. The angle's
  increment over a lag t from a stationary start is Gaussian (a linear functional of a Gaussian
  process) with variance
      V(t) = 2 D_r g int_0^t (t - s) e^{-g s} ds = 2 D_r (t - (1 - e^{-g t}) / g),
  so <cos(alpha(t0 + t) - alpha(t0))> = exp(-V / 2) = exp(-D_r (t - (1 - e^{-g t}) / g)).
  The run starts at w = 0; from t0 >= 0.5 s on (g t0 = 10) w's variance is D_r g (1 - e^{-2 g t0}):
  stationary to 2e-9, far below the statistical errors.
- Translational noise with drag g only: each velocity component is an OU process of variance D_t g.

The statistics come from one long run per seed, sampled in windows 2.5 s apart (more than 10 / g):
the samples are independent to e^{-10} = 5e-5, so the standard error of a mean is sd / sqrt(N).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pymunk
import pytest

import rrbody.integrate.sde as sde_module
from rrbody.analysis.simulate import simulate
from rrbody.integrate.chunks import run_in_chunks
from rrbody.model.active import Active
from rrbody.model.bodies import Disk, RodMass
from rrbody.model.friction import Friction
from rrbody.model.scene import Scene
from rrbody.plugin import PlaneFriction

M, R = 0.2, 0.05  # kg, m: the test disk


def _disk_scene(act: Active, **kw: object) -> Scene:
    return Scene(body=Disk(R=R, mass=M), drive=None, active=act, **kw)  # type: ignore[arg-type]


# ---- exact references ---------------------------------------------------------------------------
@pytest.mark.parametrize("seed", [1, 2])
def test_rotational_noise_orientation_autocorrelation_matches_its_closed_form(seed: int) -> None:
    D, G = 0.5, 20.0  # rad^2/s, 1/s
    burn, width, n = 0.5, 2.5, 8000  # s, s, windows: lags up to 2 s, then 0.5 s (g * 0.5 = 10) to the next
    dt_out = 0.25
    sc = _disk_scene(Active(force=0.0, rot_drag=G, rot_diffusion=D), seed=seed)
    tr = simulate(sc, method="ode", t_max=burn + width * n, dt_out=dt_out)
    assert tr.meta["dt"] == 0.05 / G  # the default step: 0.05 over the fastest rate
    i0 = np.round((burn + width * np.arange(n)) / dt_out).astype(int)
    a = tr.body_angle
    for lag in (0.25, 0.5, 1.0, 2.0):
        d = a[i0 + int(round(lag / dt_out))] - a[i0]
        V = 2 * D * (lag - (1 - math.exp(-G * lag)) / G)
        c = np.cos(d)
        se = c.std(ddof=1) / math.sqrt(n)  # N independent windows (module docstring)
        # 4 standard errors: the scheme's own bias (the spin's variance off by (g h)^2 / 6 = 4e-4,
        # rrbody.integrate.sde) is below 0.1 of them
        assert abs(c.mean() - math.exp(-V / 2)) < 4 * se, (lag, c.mean(), math.exp(-V / 2), se)
        # the increment's variance itself: a Gaussian sample variance has relative sd sqrt(2 / N) = 1.6 %
        assert abs(d.var() / V - 1) < 4 * math.sqrt(2 / n), (lag, d.var(), V)
    w = tr.spin[i0]
    assert abs(w.var() / (D * G) - 1) < 4 * math.sqrt(2 / n), w.var()  # the OU spin's stationary variance
    assert np.all(tr.x_cm == 0.0) and np.all(tr.y_cm == 0.0)  # no force: the centre stays put exactly


def _sra1_variance_ratio(x: float) -> float:
    """SRA1's stationary variance of the OU process v' = -g v + s xi at the step h = x / g, over the exact
    s^2 / (2 g). One step (rrbody.integrate.sde) is v_new = a v + s (dW - x I10 / h), a = 1 - x + x^2/2,
    whose noise has variance s^2 h (1 - x + x^2/3) (E dW^2 = h, E dW I10 = h^2/2, E I10^2 = h^3/3); the
    stationary variance solves V = a^2 V + that: 2 (1 - x + x^2/3) / ((1 - x/2)(2 - x + x^2/2)) of the
    exact, 1 - x^2/6 + O(x^3): weak order 2."""
    return 2.0 * (1.0 - x + x * x / 3.0) / ((1.0 - 0.5 * x) * (2.0 - x + 0.5 * x * x))


@pytest.mark.parametrize("x", [0.5, 0.25])
def test_large_steps_give_the_schemes_own_stationary_variance(x: float) -> None:
    """The OU spin (no propulsion, rotational drag g and noise only) at steps h = x / g: its variance is
    SRA1's exact stationary value, D_r g rho(x) (:func:`_sra1_variance_ratio`; -4.3 % at x = 0.5, -1.1 %
    at 0.25), the error of a weak-order-2 scheme; at x = 0.5 distinct from the exact D_r g."""
    D, G, n = 0.5, 20.0, 60000  # rad^2/s, 1/s, samples 0.15 s = 3 / g apart (correlation e^-3: nearly independent)
    sc = _disk_scene(Active(force=0.0, rot_drag=G, rot_diffusion=D), seed=5, noise_dt=x / G)
    tr = simulate(sc, method="ode", t_max=0.15 * (n + 10), dt_out=0.15)
    assert math.isclose(tr.meta["dt"], x / G, rel_tol=1e-12)  # (0.15 / 6: the step divides the output interval)
    w = tr.spin[10:]  # after 1.5 s = 30 / g: stationary
    # a sample variance's relative sd: sqrt(2 / N) = 0.58 % (N = 60,000; the e^-3 correlation adds 0.25 % of it)
    se = math.sqrt(2.0 / n)
    assert abs(w.var() / (D * G * _sra1_variance_ratio(x)) - 1.0) < 4 * se, (w.var(), D * G * _sra1_variance_ratio(x))
    if x == 0.5:  # the step's bias is resolved: the exact continuous variance is 7.4 standard errors off
        assert abs(w.var() / (D * G) - 1.0) > 4 * se


@pytest.mark.parametrize("seed", [3, 4])
def test_translational_noise_gives_velocity_variance_dt_gamma_per_component(seed: int) -> None:
    D, G = 1e-3, 20.0  # m^2/s, 1/s: kT/m = D G = 0.02 m^2/s^2
    gap, n = 0.5, 8000  # s between samples (g * gap = 10: independent to 5e-5)
    sc = _disk_scene(Active(force=0.0, drag=G, diffusion=D), seed=seed)
    tr = simulate(sc, method="ode", t_max=gap * n, dt_out=gap)
    vx, vy = tr.vx_cm[1:], tr.vy_cm[1:]  # from t = 0.5 s: stationary to e^{-20}
    for v in (vx, vy):
        assert abs(v.var() / (D * G) - 1) < 4 * math.sqrt(2 / n), v.var()  # Gaussian sample variance, 4 sd
        assert abs(v.mean()) < 4 * math.sqrt(D * G / n), v.mean()  # mean 0 within 4 standard errors
    # the components are independent: their correlation coefficient within 4 / sqrt(N)
    assert abs(np.corrcoef(vx, vy)[0, 1]) < 4 / math.sqrt(n)
    assert np.all(tr.spin == 0.0) and np.all(tr.body_angle == tr.body_angle[0])  # no torque, no turn


# ---- reproducibility -----------------------------------------------------------------------------
NOISY = Active(force=0.02, angle=0.3, point=(0.0, 0.01), drag=5.0, rot_drag=5.0, diffusion=1e-3, rot_diffusion=0.3)


def _state(tr) -> np.ndarray:  # noqa: ANN001
    return np.column_stack([tr.t, tr.x_cm, tr.y_cm, tr.body_angle, tr.vx_cm, tr.vy_cm, tr.spin])


def test_the_same_seed_gives_bit_identical_runs_whatever_the_chunking(monkeypatch: pytest.MonkeyPatch) -> None:
    sc = _disk_scene(NOISY, friction=Friction("viscous", 1.0), seed=12)
    a = _state(simulate(sc, method="ode", t_max=3.0, dt_out=0.01))
    b = _state(simulate(sc, method="ode", t_max=3.0, dt_out=0.01))
    assert np.array_equal(a, b)
    # the normal numbers drawn 7 steps at a time: the same stream, the same run
    monkeypatch.setattr(sde_module, "run_in_chunks", functools.partial(run_in_chunks, chunk=7))
    assert np.array_equal(a, _state(simulate(sc, method="ode", t_max=3.0, dt_out=0.01)))
    monkeypatch.undo()
    c = _state(simulate(sc.with_(seed=13), method="ode", t_max=3.0, dt_out=0.01))
    assert not np.array_equal(a, c) and np.array_equal(a[0], c[0])  # another seed, another run
    assert a[-1, 0] == 3.0 and len(a) == 301


def test_the_engine_path_reads_the_scene_seed() -> None:
    """``simulate(..., method="engine")`` seeds its plugin's noise with ``Scene.seed``: the same seed the
    same run, another seed another run."""
    sc = _disk_scene(NOISY, friction=Friction("viscous", 1.0), seed=7)
    a = _state(simulate(sc, method="engine", t_max=0.5, dt_out=0.05))
    assert np.array_equal(a, _state(simulate(sc, method="engine", t_max=0.5, dt_out=0.05)))
    assert not np.array_equal(a, _state(simulate(sc.with_(seed=8), method="engine", t_max=0.5, dt_out=0.05)))


# ---- the two paths agree statistically -------------------------------------------------------------
def _ends(x: np.ndarray, y: np.ndarray, da: np.ndarray) -> dict[str, np.ndarray]:
    return {"x": x, "y": y, "cos": np.cos(da), "sin": np.sin(da), "r2": x * x + y * y}


def test_ode_and_plugin_paths_agree_statistically() -> None:
    """A chiral noisy disk (the propulsion 0.01 m off the centre: a terminal spin of 0.16 rad/s), both
    noises, the medium's drag, no plane friction, t = 2 s: 1000 ODE runs (seeds 0-999) against 1000
    plugin bodies (one space, 1 m apart: they never touch; seed 5). The means of x, y, cos and sin of the
    turn and r^2 agree within 4 combined standard errors: each mean is over independent realisations,
    so the difference of the two has sd sqrt(se_ode^2 + se_plugin^2), and 4 sd bounds a correct pair at
    ~6e-5 per quantity, while a doubled D_t would move the mean r^2 (~0.008 m^2, 4 D_t t at most) by
    ~0.007 m^2, ~20 of them (sd ~3.6e-4 m^2). The
    schemes' own biases are far below: the plugin's Euler-Maruyama spin variance g dt / 2 = 0.25 % at
    dt = 1 ms, SRA1's (g h)^2 / 6 = 4e-4 at h = 10 ms, the deterministic parts second order (1e-6 m)."""
    T, n = 2.0, 1000
    ode: dict[str, list[float]] = {k: [] for k in ("x", "y", "cos", "sin", "r2")}
    sc = _disk_scene(NOISY)
    for s in range(n):
        tr = simulate(sc.with_(seed=s), method="ode", t_max=T, dt_out=T)
        for k, v in _ends(tr.x_cm[-1:], tr.y_cm[-1:], tr.body_angle[-1:] - tr.body_angle[0]).items():
            ode[k].append(float(v[0]))
    space = pymunk.Space()
    pf = PlaneFriction(space)
    pf.seed(5)
    bodies = []
    for k in range(n):
        b = pymunk.Body()
        shape = pymunk.Circle(b, R)
        shape.mass = M
        b.position = (float(k % 40), float(k // 40))
        space.add(b, shape)
        pf.add(b, mu=0.0)
        pf.activate(b, NOISY)
        bodies.append(b)
    x0 = np.array([tuple(b.position) for b in bodies])
    for _ in range(2000):
        pf.step(T / 2000)
    pos = np.array([tuple(b.position) for b in bodies]) - x0
    eng = _ends(pos[:, 0], pos[:, 1], np.array([b.angle for b in bodies]))
    for k in ode:
        a, b = np.array(ode[k]), eng[k]
        sd = math.hypot(a.std(ddof=1), b.std(ddof=1)) / math.sqrt(n)
        assert abs(a.mean() - b.mean()) < 4 * sd, (k, a.mean(), b.mean(), sd)
    # and the noise acts on both: the spread of the turn is the noise's, not the propulsion's
    assert np.std(ode["sin"]) > 0.3 and np.std(eng["sin"]) > 0.3


# ---- the deterministic limit ---------------------------------------------------------------------
DET = Active(force=0.2, angle=math.pi / 2, point=(0.02, 0.0), drag=0.5, rot_drag=0.5)  # tests/test_active_ode.py's


def _end(tr) -> np.ndarray:  # noqa: ANN001
    return np.array([tr.x_cm[-1], tr.y_cm[-1], tr.body_angle[-1]])


# dry: mu g = 0.3 < F/m, it slides on; the bound on the error at h = 1/400 s is ~1.3-2x the measured one
# (4.8e-7 viscous; 7.6e-5 dry, the angle's after 16 rad turned: dry friction's torque turns the spin faster)
@pytest.mark.parametrize("law,coeff,bound", [("viscous", 2.0, 1e-6), ("dry", 0.3, 1e-4)])
def test_without_noise_the_fixed_steps_converge_to_the_deterministic_ode_result(law: str, coeff: float,
                                                                                  bound: float) -> None:
    sc = Scene(body=Disk(R=R, mass=M), drive=None, friction=Friction(law, coeff), v0=(0.1, 0.0), spin0=1.0, active=DET)
    T = 2.0
    tr = simulate(sc, method="ode", t_max=T, dt_out=T, rtol=1e-11)
    assert "scheme" not in tr.meta  # diffusion 0 and no noise_dt: the adaptive path, as before
    ref = _end(tr)
    hs = [1 / 100, 1 / 200, 1 / 400]
    ends = [_end(simulate(sc.with_(noise_dt=h), method="ode", t_max=T, dt_out=T)) for h in hs]
    errs = [float(np.max(np.abs(e - ref))) for e in ends]
    order = float(np.polyfit(np.log(hs), np.log(errs), 1)[0])
    # the drift part of SRA1 is Ralston's second-order method (measured orders 1.99-2.00 down to h = 1/800 s);
    # the adaptive reference (rtol 1e-11) is good to ~1e-10, far below the smallest error here
    assert abs(order - 2.0) < 0.1, (errs, order)
    assert errs[-1] < bound, errs
    # a vanishing noise enters continuously: D = 1e-24 moves the run by ~ g sqrt(2 D T) = 1e-12
    tiny = Active(**{**vars(DET), "point": DET.point, "diffusion": 1e-24, "rot_diffusion": 1e-24})
    noisy = _end(simulate(sc.with_(active=tiny, noise_dt=hs[-1], seed=1), method="ode", t_max=T, dt_out=T))
    assert 0.0 < float(np.max(np.abs(noisy - ends[-1]))) < 1e-10


# ---- bad input -----------------------------------------------------------------------------------
@pytest.mark.parametrize("kw,match", [
    ({"noise_dt": 0.0}, r"noise_dt must be in \(0, 0.025\] s"),      # 0.5 / (rot_drag 20)
    ({"noise_dt": 0.03}, r"noise_dt must be in \(0, 0.025\] s"),
    ({"noise_dt": math.nan}, "noise_dt must be"),
    ({"seed": -1}, r"seed must be an integer in \[0, 9223372036854775807\]"),
    ({"seed": 1.5}, "seed must be an integer"),
])
def test_bad_noise_settings_name_themselves(kw: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        _disk_scene(Active(force=0.0, drag=5.0, rot_drag=20.0, rot_diffusion=0.1), **kw)


def test_settings_without_their_active_body_and_unsupported_cases_are_refused() -> None:
    with pytest.raises(ValueError, match="seed applies to an active body's noise.*no active body"):
        Scene(body=Disk(R=R), drive=None, seed=3)
    with pytest.raises(ValueError, match="seed applies to an active body's noise.*without noise"):
        _disk_scene(Active(force=1.0), seed=3)
    with pytest.raises(ValueError, match="noise_dt applies to an active body"):
        Scene(body=Disk(R=R), drive=None, noise_dt=0.01)
    with pytest.raises(ValueError, match="rot_diffusion must be 0 for a rod body"):
        Scene(body=RodMass(l=0.1), drive=None, active=Active(force=1.0, rot_drag=1.0, rot_diffusion=0.1))
    with pytest.raises(ValueError, match="stepper must be 'auto' for an active body with noise"):
        simulate(_disk_scene(NOISY), method="ode", t_max=1.0, stepper="rodas")
    # dry friction its propulsion cannot overcome: no rest rule on the ODE path, noise or not
    weak = Active(force=0.05, drag=1.0, diffusion=1e-3)  # F/m = 0.25 < mu g = 0.3 m/s^2
    with pytest.raises(ValueError, match="active force must exceed the dry friction"):
        simulate(_disk_scene(weak, friction=Friction("dry", 0.3)), method="ode", t_max=1.0)


def test_a_noisy_scene_describes_and_reloads_itself() -> None:
    sc = _disk_scene(NOISY, seed=9, noise_dt=0.004)
    again = Scene.from_description(sc.describe())
    assert again.describe() == sc.describe() and (again.seed, again.noise_dt) == (9, 0.004)
    assert "seed" not in _disk_scene(DET).describe()  # descriptions of runs without noise stay as they were
