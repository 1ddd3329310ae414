"""Property-based bad input: every public constructor rejects NaN, inf, out-of-range and wrong-type
values with a ValueError that names the parameter (never an AssertionError or a silent default)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rrbody import CircularDrive, Disk, Ellipse, Friction, RodMass, Scene, parse_angle, rod_mass_scene

bad_number = st.one_of(st.just(math.nan), st.just(math.inf), st.just(-math.inf), st.text(max_size=3),
                       st.none(), st.booleans(), st.lists(st.floats(), max_size=2))
negative = st.floats(max_value=-1e-300, allow_nan=False, allow_infinity=False)
nonpositive = st.one_of(negative, st.just(0.0), st.just(-0.0))


def _raises_naming(name: str, fn, *args, **kw) -> None:  # noqa: ANN001
    with pytest.raises(ValueError) as e:
        fn(*args, **kw)
    assert name in str(e.value)


@settings(max_examples=40, deadline=None)
@given(v=st.one_of(bad_number, nonpositive))
def test_drive(v: object) -> None:
    _raises_naming("omega", CircularDrive, omega=v)
    _raises_naming("d", CircularDrive, omega=1.0, d=v)


@settings(max_examples=40, deadline=None)
@given(v=st.one_of(bad_number, nonpositive))
def test_disk_radius_and_rod_length(v: object) -> None:
    _raises_naming("R", Disk, R=v)
    _raises_naming("l", RodMass, l=v)
    _raises_naming("mass", Disk, R=1.0, mass=v)


@settings(max_examples=40, deadline=None)
@given(v=st.one_of(bad_number, negative))
def test_negative_pivot_offset(v: object) -> None:
    _raises_naming("l", Disk, R=1.0, l=v)


@settings(max_examples=40, deadline=None)
@given(v=st.one_of(bad_number, st.floats(min_value=1.0, allow_nan=False), st.floats(max_value=-1.0, allow_nan=False)))
def test_ellipse_delta(v: object) -> None:
    _raises_naming("delta", Ellipse, R0=0.3, delta=v)


@settings(max_examples=40, deadline=None)
@given(v=st.one_of(bad_number, negative))
def test_friction_k(v: object) -> None:
    _raises_naming("k", Friction.from_k, "dry", v, 1.0)


def test_unknown_names_list_valid_ones() -> None:
    from rrbody.model.laws import LAWS

    with pytest.raises(ValueError, match=", ".join(repr(n) for n in LAWS)):  # every law of the table, listed
        Friction("wet")
    with pytest.raises(ValueError, match="'x', 'y'"):
        Ellipse(R0=0.3, orientation="z")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="'auto', 'sampled', 'icr'"):
        Scene(body=RodMass(l=0.2), drive=CircularDrive(1.0), friction_method="grid")
    from rrbody import simulate

    with pytest.raises(ValueError, match="'ode'"):
        simulate(rod_mass_scene(0.2, 0.1, 1.0), method="rk4", t_max=1.0)


@settings(max_examples=60, deadline=None)
@given(v=st.one_of(bad_number, nonpositive))
def test_scene_horizon_and_samples(v: object) -> None:
    sc = rod_mass_scene(0.2, 0.1, 1.0)
    if v is not None:  # t_max=None legitimately means "no horizon set"
        _raises_naming("t_max", sc.with_, t_max=v)
    _raises_naming("samples", sc.with_, samples=v)


@settings(max_examples=60, deadline=None)
@given(s=st.text(max_size=8).filter(lambda s: s.strip().lower() not in ("pi", "π")))
def test_angle_parser_never_crashes(s: str) -> None:
    try:
        v = parse_angle(s)
    except ValueError as e:
        assert "phi0" in str(e)
    else:
        assert math.isfinite(v)


@pytest.mark.parametrize("text,value", [("pi", math.pi), ("-pi/2", -math.pi / 2), ("3pi/4", 0.75 * math.pi),
                                        ("0.5*pi", 0.5 * math.pi), ("2.5", 2.5), ("1e-3", 1e-3), ("π/3", math.pi / 3)])
def test_angle_parser_values(text: str, value: float) -> None:
    assert parse_angle(text) == pytest.approx(value, rel=1e-15)


# ---- the CLI: every numeric option of flip-time with values outside its range -----------------
_BASE = {"--H": "0.2", "--k": "0.05", "--omega": "0.6"}
_INVALID = {
    "--H": ["0", "-1", "nan", "inf", "1e300", "abc", ""],
    "--k": ["-1", "nan", "-inf", "1e300", "x"],
    "--omega": ["0", "-0.6", "nan", "inf", "1e300", "fast"],
    "--d": ["0", "-1", "nan", "1e300"],
    "--phi0": ["nan", "inf", "1e300", "pi/0", "2pi/", "pi pi", "sin(1)", "__import__('os')"],
    "--phi-dot0": ["nan", "1e300"],
    "--rtol": ["0", "1", "-1e-9", "nan"],
    "--t-max": ["0", "-5", "nan", "1e300"],
    "--max-steps": ["0", "-3", "1.5", "x"],
    "--samples": ["0", "-1", "many"],
}


@settings(max_examples=80, deadline=None)
@given(data=st.data())
def test_cli_rejects_out_of_range_options(data) -> None:  # noqa: ANN001
    option = data.draw(st.sampled_from(sorted(_INVALID)))
    value = data.draw(st.sampled_from(_INVALID[option]))
    args = dict(_BASE)
    args[option] = value
    argv = ["flip-time"] + [x for kv in args.items() for x in kv]
    code, stdout, stderr = _run_cli(argv)
    assert code == 2, (argv, stdout)
    assert option in stderr and "Traceback" not in stderr
    assert stdout == ""


_SIM_BASE = {"--H": "0.2", "--k": "0.05", "--omega": "0.6", "--t-max": "1"}
_SIM_INVALID = {
    "--dt-out": ["0", "-0.1", "nan", "1e300"],
    "--fps": ["0", "1000", "nan"],
    "--movie-speed": ["0", "-2", "inf"],
    "--dt": ["0", "-1e-3", "nan", "1e9"],
    "--iterations": ["0", "-5", "1e9"],
    "--v0": ["1", "1,2,3", "a,b", "nan,0", "1e300,0"],
    "--spin0": ["nan", "1e300"],
    "--l": ["-1", "nan", "1e300"],
    "--R0": ["0", "-0.3", "nan"],
    "--delta": ["1", "-1", "2", "nan"],
    "--body": ["cube", ""],
    "--method": ["rk4", ""],
    "--accuracy": ["best"],
}
_CRIT_INVALID = {"--tol": ["0", "1", "nan", "-1e-9"], "--k": ["-1", "nan"], "--omega": ["0", "nan", "-1"],
                 "--phi0": ["pi/0", "x"], "--friction": ["wet"]}


def _run_cli(argv: list[str]) -> tuple[int, str, str]:
    import contextlib
    import io

    from rrbody.cli.main import main

    err = io.StringIO()
    out = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main(argv)
        except SystemExit as e:
            code = int(e.code or 0)
    return code, out.getvalue(), err.getvalue()


@settings(max_examples=80, deadline=None)
@given(data=st.data())
def test_cli_simulate_rejects_out_of_range_options(data, tmp_path_factory) -> None:  # noqa: ANN001
    option = data.draw(st.sampled_from(sorted(_SIM_INVALID)))
    value = data.draw(st.sampled_from(_SIM_INVALID[option]))
    out = tmp_path_factory.mktemp("sim") / "t.csv"
    args = dict(_SIM_BASE)
    if option in ("--l", "--R0", "--delta"):  # shape options of an extended body
        args.pop("--H")
        args.update({"--body": "ellipse", "--R0": "0.3", "--l": "0.1"})
    args[option] = value
    argv = ["simulate", "--out", str(out)] + [x for kv in args.items() for x in kv]
    code, stdout, stderr = _run_cli(argv)
    assert code == 2, (argv, stdout)
    assert option in stderr and "Traceback" not in stderr
    assert stdout == "" and not out.exists()  # nothing written


@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_cli_critical_h_rejects_out_of_range_options(data) -> None:  # noqa: ANN001
    option = data.draw(st.sampled_from(sorted(_CRIT_INVALID)))
    value = data.draw(st.sampled_from(_CRIT_INVALID[option]))
    args = {"--k": "0.01", "--omega": "0.3", option: value}
    code, stdout, stderr = _run_cli(["critical-h"] + [x for kv in args.items() for x in kv])
    assert code == 2 and option in stderr and "Traceback" not in stderr and stdout == ""


# ---- every numeric value is finite at every step of parsing ------------------------
@settings(max_examples=200, deadline=None)
@given(m=st.integers(1, 9), e=st.integers(-420, 420), form=st.sampled_from(["{x}", "{x}pi", "{x}*pi/3", "2pi/{x}",
                                                                           "{x}deg", "-{x}pi/7"]))
def test_angle_steps_are_finite_and_never_a_silent_zero(m: int, e: int, form: str) -> None:
    """A nonzero literal in any position gives a finite nonzero angle or a ValueError naming the
    parameter: never inf or nan, and never 0 from an overflow or underflow on the way."""
    from rrbody.model.angles import parse_angle

    text = form.format(x=f"{m}e{e}")
    try:
        v = parse_angle(text)
    except ValueError as err:
        assert "phi0" in str(err)
    else:
        assert math.isfinite(v) and v != 0.0, (text, v)


@pytest.mark.parametrize("text", ["1e400", "-1e400", "1e-400", "inf", "nan", "1_000", "0x10", "1e", "", " ", "٣"])
def test_number_literals_outside_the_float_range_are_refused(text: str) -> None:
    from rrbody.model.angles import parse_number

    with pytest.raises(ValueError, match="speed"):
        parse_number(text, name="speed")


def test_number_literals_as_written() -> None:
    from rrbody.model.angles import parse_number

    for text, value in (("0", 0.0), ("-0.0", 0.0), ("0e-500", 0.0), ("2.5", 2.5), (".5", 0.5), ("1E6", 1e6),
                        ("1.7976931348623157e308", 1.7976931348623157e308), ("5e-324", 5e-324)):
        assert parse_number(text, name="x") == value


@pytest.mark.parametrize("value", [10**400, -(10**400), 10**309])
def test_huge_integers_are_a_value_error_not_an_overflow(value: int) -> None:
    from rrbody.model.checks import check, check_int, check_range, check_real

    for fn in (lambda: check("omega", value), lambda: check_real("t", value), lambda: check_range("t", value, 0, 1),
               lambda: check_int("n", value, 0, 10), lambda: parse_angle(value)):
        with pytest.raises(ValueError):
            fn()
