"""Finding class "late validation": a sweep checks every option and every axis
value before any work (exit 2, one line naming the option, no checkpoint, no output), like flip-time.
Also sweeps over any scene. In-process (:func:`tests.clirun.run_here`): the first bad input of each
test also through the real command in a subprocess, which must answer the same."""

from __future__ import annotations

import json
import math
from pathlib import Path

from .clirun import assert_bad_input, run_here

ROD = ["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omega=0.6,0.7", "--workers", "0"]


def test_bad_options_and_axes_fail_before_any_work(tmp_path: Path) -> None:
    out = ["--out", str(tmp_path / "s.csv")]
    cases = [
        ([*ROD, "--rtol", "1", *out], "--rtol"),
        ([*ROD, "--rtol", "0", *out], "--rtol"),
        ([*ROD, "--t-max", "-1", *out], "--t-max"),
        ([*ROD, "--t-max", "1e-320", *out], "--t-max"),
        (["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omega=0.6", "--axis", "omega=1,2", *out], "--axis omega"),
        (["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omega=0.6,-1", *out], "--axis omega"),
        (["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omega=1e-320,1", *out], "--axis omega"),
        (["sweep", "--H", "0.2", "--omega", "0.6", "--axis", "k=0.1,-0.1", *out], "--axis k"),
        (["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omgea=1,2", *out], "did you mean omega"),
        (["sweep", "--k", "0.05", "--axis", "omega=1,2", *out], "--H"),
        (["sweep", "--H", "-0.2", "--k", "0.05", "--axis", "omega=1,2", *out], "--H"),
        (["sweep", "--body", "ellipse", "--R0", "0.3", "--l", "0.2", "--k", "0.01", "--omega", "0.6", "--axis",
          "delta=0,1.5", *out], "--axis delta"),
        ([*ROD, "--workers", "-1", *out], "--workers"),
        ([*ROD, "--batch-size", "0", *out], "--batch-size"),
        ([*ROD, "--out", str(tmp_path / "s.txt")], "--out"),
        ([*ROD, "--quantity", "rest", "--t-max", "10", *out], "free body"),
        ([*ROD, "--phi0", "pi/0", *out], "--phi0"),
    ]
    for r, (_, opt) in zip(run_here([a for a, _ in cases], cwd=tmp_path), cases):
        assert_bad_input(r, opt, tmp_path, set())  # no checkpoint, no output, no sidecar


def test_any_body_and_any_parameter(tmp_path: Path) -> None:
    """An ellipse over delta, a disk over l, a free disk over spin0: each point equals the single call."""
    rs = run_here([
        ["sweep", "--body", "ellipse", "--R0", "0.3", "--l", "0.2", "--k", "0.05", "--omega", "0.6", "--axis",
         "delta=-0.5,0.5", "--workers", "0", "--accuracy", "draft", "--out", str(tmp_path / "e.csv")],
        ["sweep", "--body", "disk", "--R0", "0.2", "--k", "0.05", "--omega", "0.6", "--axis", "l=0.1,0.3", "--axis",
         "phi0=-pi/2,pi", "--workers", "0", "--accuracy", "draft", "--out", str(tmp_path / "d.csv")],
        ["sweep", "--quantity", "rest", "--no-drive", "--body", "disk", "--R0", "0.1", "--k", "2", "--v0", "1,0",
         "--t-max", "10", "--axis", "spin0=0,5", "--workers", "0", "--out", str(tmp_path / "f.csv")],
        ["flip-time", "--body", "ellipse", "--R0", "0.3", "--l", "0.2", "--k", "0.05", "--omega", "0.6", "--delta",
         "0.5", "--accuracy", "draft", "--json"],
        ["flip-time", "--body", "disk", "--R0", "0.2", "--k", "0.05", "--omega", "0.6", "--l", "0.3", "--phi0",
         "-pi/2", "--accuracy", "draft", "--json"],
        ["simulate", "--no-drive", "--body", "disk", "--R0", "0.1", "--k", "2", "--v0", "1,0", "--spin0", "5",
         "--t-max", "10", "--dt-out", "10", "--json"],
    ], cwd=tmp_path, real=0)  # they write: the bad inputs above run the real command
    assert all(r.code == 0 for r in rs), [r.err for r in rs if r.code]
    from rrbody.analysis.sweep import load_sweep, read_meta

    e = load_sweep(tmp_path / "e.csv")
    assert [float(x["delta"]) for x in e] == [-0.5, 0.5]
    assert read_meta(tmp_path / "e.csv")["spec"]["base"]["body"] == "ellipse"
    assert float(e[1]["t_f"]) == json.loads(rs[3].out)["t_f"]  # the same computation, bit for bit
    d = load_sweep(tmp_path / "d.csv")
    assert [(float(x["l"]), float(x["phi0"])) for x in d] == [(0.1, -math.pi / 2), (0.1, math.pi),
                                                             (0.3, -math.pi / 2), (0.3, math.pi)]
    assert float(d[2]["t_f"]) == json.loads(rs[4].out)["t_f"]
    f = load_sweep(tmp_path / "f.csv")
    assert f[0]["status"] == "came to rest" and float(f[0]["t_stop"]) > 0
    assert float(f[1]["t_stop"]) == json.loads(rs[5].out)["t_stop"]


CHAOS = ["sweep", "--quantity", "chaos", "--H", "0.5", "--friction", "none", "--axis", "tilt=0,0.5", "--axis",
         "omega=1,2", "--workers", "0"]


def test_chaos_options_fail_before_any_work(tmp_path: Path) -> None:
    out = ["--out", str(tmp_path / "c.csv")]
    cases = [
        ([*CHAOS, "--t-max", "0", *out], "--t-max"),
        ([*CHAOS, "--transient", "-1", *out], "--transient"),
        ([*CHAOS, "--transient", "1e7", *out], "--transient"),
        ([*CHAOS, "--estimate", "qr", *out], "--estimate"),
        ([*CHAOS, "--d0", "1", *out], "--d0"),
        ([*CHAOS, "--accuracy", "draft", *out], "--accuracy"),
        ([*CHAOS, "--plot", str(tmp_path / "c.svg"), *out], "--plot"),
        ([*CHAOS, "--list", "--plot", str(tmp_path / "c.png"), *out], "--plot"),
        ([*ROD, "--transient", "10", *out], "--transient"),
        (["sweep", "--quantity", "chaos", "--H", "0.5", "--k", "0.1", "--friction", "dry", "--axis", "omega=1,2",
          "--estimate", "tangent", *out], "--estimate"),
    ]
    for r, (_, opt) in zip(run_here([a for a, _ in cases], cwd=tmp_path), cases):
        assert_bad_input(r, opt, tmp_path, set())  # no checkpoint, no output, no sidecar, no figure


def test_chaos_sweep_and_its_plot(tmp_path: Path) -> None:
    """The command's table is the library's, bit for bit, and --plot writes the map."""
    from rrbody.analysis.sweep import load_sweep, run_sweep
    from rrbody.analysis.sweep_spec import Sweep

    opts = ["--t-max", "15", "--transient", "1.5"]
    (r,) = run_here([[*CHAOS, *opts, "--out", str(tmp_path / "c.csv"), "--plot", str(tmp_path / "c.png"),
                      "--json"]], cwd=tmp_path, real=0)
    assert r.code == 0, r.err
    assert json.loads(r.out)["plot"] == str(tmp_path / "c.png")
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    sw = Sweep(base={"H": 0.5, "friction": "none", "d": 1.0, "phi0": math.pi}, axes={"tilt": (0.0, 0.5),
               "omega": (1.0, 2.0)}, quantity="chaos", options={"t_max": 15.0, "transient": 1.5})
    ref = load_sweep(run_sweep(sw, tmp_path / "ref.csv", workers=0, progress=False))
    got = load_sweep(tmp_path / "c.csv")
    assert [row["lambda_max"] for row in got] == [row["lambda_max"] for row in ref]
    assert [row["rr_fraction"] for row in got] == [row["rr_fraction"] for row in ref]


def test_a_file_beside_the_output_is_never_replaced_without_force(tmp_path: Path) -> None:
    """The sidecar a sweep writes beside its table (``y.csv.json``) is an output too: a file of the
    user's in its place is refused without --force (and with --resume when there is nothing to resume),
    one line naming it, nothing written; --force replaces it, as it would the table."""
    side = tmp_path / "y.csv.json"
    side.write_text("notes\n")
    out = ["--out", str(tmp_path / "y.csv")]
    rs = run_here([[*ROD, *out], [*ROD, *out, "--resume"]], cwd=tmp_path)
    for r in rs:
        assert_bad_input(r, "--out", tmp_path, {"y.csv.json"})
        assert "y.csv.json" in r.err and "--force" in r.err, r.err
    assert side.read_text() == "notes\n"
    (r,) = run_here([[*ROD, *out, "--force"]], cwd=tmp_path, real=0)
    assert r.code == 0, r.err
    from rrbody.analysis.sweep import read_meta

    assert read_meta(tmp_path / "y.csv")["spec"]["axes"] == {"omega": [0.6, 0.7]}  # the sidecar is the sweep's now


def test_an_axis_the_quantity_does_not_read_is_refused(tmp_path: Path) -> None:
    """An axis that changes nothing the quantity reads from a point's scene would pair each of its values with
    an answer it had no part in: refused, one line naming the axis and why, nothing written. H_c reads k,
    omega, phi0 and the friction law (H is its answer; d only through k, when k is not given); a level
    plane has no downhill; a free body's rest has no drive."""
    out = ["--out", str(tmp_path / "s.csv")]
    hc = ["sweep", "--quantity", "critical_h", "--k", "0.01", "--omega", "0.3", "--workers", "0"]
    cases = [
        ([*hc, "--axis", "H=0.1,0.2", *out], "--axis H"),
        ([*hc, "--axis", "H=0.2", *out], "--axis H"),
        ([*hc, "--axis", "d=0.5,2", *out], "--axis d"),
        (["sweep", "--quantity", "critical_h", "--omega", "0.3", "--axis", "k=0.01,0.02", "--axis", "H=0.1,0.2",
          *out], "--axis H"),
        ([*ROD, "--axis", "downhill=0,1", *out], "--axis downhill"),
        (["sweep", "--quantity", "rest", "--no-drive", "--body", "disk", "--R0", "0.1", "--k", "2", "--v0", "1,0",
          "--t-max", "10", "--axis", "omega=0.5,1", *out], "--axis omega"),
    ]
    for r, (_, opt) in zip(run_here([a for a, _ in cases], cwd=tmp_path), cases):
        assert_bad_input(r, opt, tmp_path, set())
        assert "does not depend on" in r.err, r.err
    # the refusal is the truth: H_c computed at two H is one number
    from rrbody.analysis.sweep import evaluate_point
    from rrbody.analysis.sweep_spec import Sweep

    at = [evaluate_point(Sweep(base={"k": 0.01, "H": h}, axes={"omega": (0.3,)}, quantity="critical_h"),
                         {"omega": 0.3})["H_c"] for h in (0.1, 0.2)]
    assert at[0] == at[1] and 0.0 < at[0] < 1.0
    # the same parameters where the quantity does read them: accepted (no work is done building a Sweep)
    Sweep(base={"mu": 0.01, "omega": 0.3}, axes={"d": (0.5, 2.0)}, quantity="critical_h")  # k = mu g / d
    Sweep(base={"H": 0.2, "k": 0.05, "omega": 0.6}, axes={"tilt": (0.0, 0.3), "downhill": (0.0, 1.0)})
