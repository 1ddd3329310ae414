"""Batch mode under hostile input: a line obeys exactly the rules of the command line,
bytes that are not UTF-8 spoil only their line (from a file as from stdin), an endless line is read
with bounded memory, and an output that is the batch input itself is refused before anything runs.
Real CLI in subprocesses; the lines that compute use the draft preset (each a few ms warm)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

from rrbody.cli.batch import MAX_LINE_BYTES

from .clirun import RRBODY, assert_bad_input, env, run_many

GOOD = {"H": 0.2, "k": 0.05, "omega": 0.6, "accuracy": "draft"}
SIM = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1", "--json"]


def _answers(out: str) -> list[dict]:
    return [json.loads(ln) for ln in out.splitlines()]


def test_latin1_bytes_spoil_only_their_line_in_a_file_and_on_stdin(tmp_path: Path) -> None:
    good = json.dumps(GOOD).encode()
    latin1 = '{"H": 0.2, "k": 0.05, "omega": 0.6, "friction": "café"}'.encode("latin-1")  # 0xe9, not UTF-8
    comment = "# Grüße, in Latin-1".encode("latin-1")  # a comment is no line to answer, whatever its bytes
    data = b"\xef\xbb\xbf" + good + b"\n" + latin1 + b"\n" + comment + b"\n" + good + b"\r\n"  # a BOM, CRLF
    f = tmp_path / "in.jsonl"
    f.write_bytes(data)
    from_file = subprocess.run([*RRBODY, "flip-time", "--batch", str(f)], capture_output=True, env=env(),
                               cwd=tmp_path, timeout=300)
    from_stdin = subprocess.run([*RRBODY, "flip-time", "--batch", "-"], input=data, capture_output=True, env=env(),
                                cwd=tmp_path, timeout=300)
    for r in (from_file, from_stdin):
        assert r.returncode == 2 and b"Traceback" not in r.stderr, r.stderr
        out = _answers(r.stdout.decode())
        assert [o.get("line") for o in out] == [None, 2, None]  # the good lines 1 and 4 ran, in order
        assert "not UTF-8" in out[1]["error"] and "0xe9" in out[1]["error"]
        assert out[0]["t_f"] == out[2]["t_f"] is not None
    assert _answers(from_file.stdout.decode())[0]["t_f"] == _answers(from_stdin.stdout.decode())[0]["t_f"]


def _peak_rss_kib(cmd: list[str], **kw: Any) -> tuple[subprocess.CompletedProcess[bytes], int]:
    """Run ``cmd`` and return it with its peak resident memory (KiB, Linux ru_maxrss).

    RUSAGE_CHILDREN reports the largest of the waited-for children, so the child is run from a
    fresh Python process of its own, which waits for it alone and prints its maximum."""
    code = ("import resource, subprocess, sys\n"
            "p = subprocess.run(sys.argv[1:], stdin=sys.stdin, stdout=subprocess.PIPE, stderr=subprocess.PIPE)\n"
            "sys.stderr.buffer.write(p.stderr)\n"
            "sys.stdout.buffer.write(p.stdout)\n"
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n"
            "sys.exit(p.returncode)\n")
    kw.setdefault("stdin", subprocess.DEVNULL)
    r = subprocess.run([sys.executable, "-c", code, *cmd], capture_output=True, env=env(), **kw)
    *err, peak = r.stderr.decode().splitlines()
    r.stderr = "\n".join(err).encode()
    return r, int(peak)


def test_endless_line_is_read_with_bounded_memory(tmp_path: Path) -> None:
    # the baseline: the same process on a one-line good batch (interpreter, numpy, numba, one flip time)
    small = tmp_path / "one.jsonl"
    small.write_text(json.dumps(GOOD) + "\n")
    base, base_peak = _peak_rss_kib([*RRBODY, "flip-time", "--batch", str(small)], cwd=tmp_path, timeout=300)
    assert base.returncode == 0, base.stderr
    # /dev/zero is one endless line: an error for it, then reading stops (exit 2), never 4 GB in 12 s
    zero, zero_peak = _peak_rss_kib([*RRBODY, "flip-time", "--batch", "/dev/zero"], cwd=tmp_path, timeout=120)
    # a 50 MB line on stdin (no newline for 50 MB), then a good line: the long line is skipped, the next runs
    long_line = tmp_path / "long.jsonl"
    with open(long_line, "wb") as fh:
        fh.write(b'{"H": "' + b"9" * (50 << 20) + b'"}\n' + json.dumps(GOOD).encode() + b"\n")
    with open(long_line, "rb") as stdin:
        big, big_peak = _peak_rss_kib([*RRBODY, "flip-time", "--batch", "-"], stdin=stdin, cwd=tmp_path,
                                      timeout=300)
    assert zero.returncode == 2 and b"Traceback" not in zero.stderr, zero.stderr
    (z,) = _answers(zero.stdout.decode())
    assert z["line"] == 1 and "stopped reading" in z["error"]
    assert big.returncode == 2 and b"Traceback" not in big.stderr, big.stderr
    first, second = _answers(big.stdout.decode())
    assert first["line"] == 1 and f"at most {MAX_LINE_BYTES} bytes" in first["error"]
    assert second["t_f"] is not None
    # the bound: a line costs at most a few copies of the 1 MiB cap; 16 MiB of slack above the
    # baseline covers the allocator's noise and is a third of the 50 MB a whole-line read would take
    assert zero_peak - base_peak < 16 * 1024, (zero_peak, base_peak)
    assert big_peak - base_peak < 16 * 1024, (big_peak, base_peak)


def test_a_line_obeys_the_command_line_rules(tmp_path: Path) -> None:
    g = {"H": 0.2, "k": 0.05, "omega": 0.6}
    lines = [
        '{"H": 0.2, "H": 0.3, "k": 0.05, "omega": 0.6}',                   # 1 a key twice
        '{"H": 0.2, "k": 0.05, "omega": 0.6, "t_max": 5, "t-max": 6}',     # 2 one option in two spellings
        '{"H": [0.2, 0.3], "k": 0.05, "omega": 0.6}',                      # 3 a list for one value
        '{"H": 1e400, "k": 0.05, "omega": 0.6}',                           # 4 beyond the float range
        '{"H": 0.2, "k": 0.05, "omega": NaN}',                             # 5 not a number
        '{"H": 0.2, "k": 1e-400, "omega": 0.6}',                           # 6 underflows to 0 (no friction!)
        '{"H": true, "k": 0.05, "omega": 0.6}',                            # 7 a flag's value for a number
        '{"H": false, "k": 0.05, "omega": 0.6}',                           # 8 (was: silently ignored)
        json.dumps({**g, "json": "yes"}),                                  # 9 a string for a flag
        json.dumps({**g, "friction": 3}),                                  # 10 a number for a choice
        json.dumps({**g, "v0": [1, 2, 3], "no-drive": True}),               # 11 three numbers for two
        json.dumps({**g, "phi0": {"deg": 90}}),                            # 12 an object for a value
        json.dumps({**g, "omgea": 0.6}),                                   # 13 misspelled
        json.dumps({**g, "phi0": "1e-300pi/1e300"}),                       # 14 a silent 0 from a quotient
        json.dumps({**g, "friction": "none"}),                             # 15 contradicts k
        "[" * 100_000 + "]" * 100_000,                                     # 16 deeper than the parser goes
        json.dumps({**g, "accuracy": "draft"}),                            # 17 good
    ]
    f = tmp_path / "in.jsonl"
    f.write_text("\n".join(lines) + "\n")
    (r,) = run_many([["flip-time", "--batch", str(f)]], cwd=tmp_path)
    assert r.code == 2 and "Traceback" not in r.err, r.err
    out = _answers(r.out)
    errors = {o["line"]: o["error"] for o in out if "error" in o}
    assert sorted(errors) == list(range(1, 17)) and out[-1]["t_f"] is not None
    expect = {1: "given twice", 2: "--t-max is given twice", 3: "--H takes one value", 4: "beyond the float range",
              5: "NaN is not a finite number", 6: "underflows to 0", 7: "--H takes a value", 8: "--H takes a value",
              9: "--json is a flag", 10: "--friction takes a string", 11: "--v0 must be 2", 12: "--phi0 takes one",
              13: "did you mean --omega?", 14: "--phi0: '1e-300pi/1e300' underflows", 15: "--friction none and --k",
              16: "nested too deeply"}
    for n, words in expect.items():
        assert words in errors[n], (n, errors[n])


def test_an_output_that_is_the_batch_input_is_refused_at_once(tmp_path: Path) -> None:
    src = tmp_path / "in.jsonl"
    text = json.dumps({"H": 0.2, "k": 0.05, "omega": 0.6, "t-max": 1}) + "\n"
    src.write_text(text)
    os.link(src, tmp_path / "hard.jsonl")
    before = {p.name for p in tmp_path.iterdir()}
    rs = run_many([[*SIM, "--batch", str(src), "--out", str(src), "--force"],
                   [*SIM, "--batch", str(src), "--out", str(tmp_path / "." / "in.jsonl"), "--force"],
                   [*SIM, "--batch", str(src), "--out", str(tmp_path / "hard.jsonl"), "--force"]], cwd=tmp_path)
    for r in rs:
        assert_bad_input(r, "--batch", tmp_path, before)
        assert "--out is the input" in r.err
    with open(src, "rb") as stdin:  # the same through stdin: the file behind it
        p = subprocess.run([*RRBODY, *SIM, "--batch", "-", "--out", str(src), "--force"], stdin=stdin, env=env(),
                           capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert p.returncode == 2 and "--out is the input" in p.stderr and p.stdout == "", p.stderr
    # a line whose own output is the batch input: an error for that line, the input untouched
    src.write_text(json.dumps({"H": 0.2, "k": 0.05, "omega": 0.6, "t-max": 1, "out": str(src), "force": True}) + "\n")
    (r,) = run_many([[*SIM, "--batch", str(src)]], cwd=tmp_path)
    (o,) = _answers(r.out)
    assert r.code == 2 and o["line"] == 1 and "--out is the input" in o["error"]
    assert src.read_text().startswith('{"H": 0.2') and (tmp_path / "hard.jsonl").read_text() == src.read_text()
