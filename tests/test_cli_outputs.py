"""Finding class "outputs": an output path that is not a regular file or absent
is refused, with or without --force: FIFO, directory, device, socket, a link to one, a dangling link.
Exit 2, one line naming the option, no traceback, nothing written: in-process (:func:`tests.clirun.run_here`),
the first case of each test also through the real command in a subprocess, which must answer the same."""

from __future__ import annotations

import os
import socket
import stat
from pathlib import Path

import pytest

from .clirun import assert_bad_input, run_here, run_many

SIM = ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1"]
SWEEP = ["sweep", "--H", "0.2", "--k", "0.05", "--axis", "omega=0.6,0.7", "--workers", "0"]


def _specials(d: Path) -> dict[str, Path]:
    # names end in .csv so that the sweep's suffix check passes and the file type is what is refused
    os.mkfifo(d / "fifo.csv")
    (d / "dir.csv").mkdir()
    (d / "link-to-fifo.csv").symlink_to("fifo.csv")
    (d / "link-to-dir.csv").symlink_to("dir.csv")
    (d / "dangling.csv").symlink_to("nowhere")
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(d / "sock.csv"))
    s.close()
    return {n: d / n for n in ("fifo.csv", "dir.csv", "link-to-fifo.csv", "link-to-dir.csv", "dangling.csv",
                               "sock.csv")}


@pytest.mark.parametrize("force", [False, True])
def test_special_files_are_refused(tmp_path: Path, force: bool) -> None:
    paths = _specials(tmp_path)
    before = {p.name for p in tmp_path.iterdir()}
    argvs, options = [], []
    for p in paths.values():
        for base, opt in ((SIM, "--out"), (SWEEP, "--out")):
            argvs.append([*base, "--out", str(p), *(["--force"] if force else [])])
            options.append(opt)
    argvs.append([*SIM, "--out", "/dev/null", *(["--force"] if force else [])])
    options.append("--out")
    for r, opt in zip(run_here(argvs, cwd=tmp_path), options):
        assert_bad_input(r, opt, tmp_path, before)
        assert "regular file" in r.err or "dangling" in r.err
    assert stat.S_ISFIFO((tmp_path / "fifo.csv").lstat().st_mode)  # still a FIFO, not replaced by a file
    assert (tmp_path / "dir.csv").is_dir() and list((tmp_path / "dir.csv").iterdir()) == []


def test_movie_and_rerun_paths_are_checked_before_the_run(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "m.mp4")
    (r,) = run_many([[*SIM, "--out", str(tmp_path / "t.csv"), "--movie", str(tmp_path / "m.mp4"), "--force"]])
    assert_bad_input(r, "--movie", tmp_path, {"m.mp4"})  # the trajectory was not written either


def test_missing_folder_names_the_option(tmp_path: Path) -> None:
    rs = run_here([[*SIM, "--out", str(tmp_path / "no" / "t.csv")],
                   [*SWEEP, "--out", str(tmp_path / "no" / "s.csv")],
                   [*SWEEP, "--out", str(tmp_path / "no" / "s.csv"), "--resume"]], cwd=tmp_path)
    for r in rs:
        assert_bad_input(r, "--out", tmp_path, set())
        assert "does not exist" in r.err


def test_link_to_a_regular_file_writes_the_target(tmp_path: Path) -> None:
    (tmp_path / "real.csv").write_text("old")
    (tmp_path / "link.csv").symlink_to("real.csv")
    (r,) = run_here([[*SIM, "--out", str(tmp_path / "link.csv"), "--force"]], cwd=tmp_path, real=0)
    assert r.code == 0, r.err
    assert (tmp_path / "link.csv").is_symlink()  # the link survives; its target holds the trajectory
    assert (tmp_path / "real.csv").read_text().startswith("# rrbody-meta")


def test_movie_and_recording_suffixes_are_checked_before_the_run(tmp_path: Path) -> None:
    rs = run_here([[*SIM, "--out", str(tmp_path / "t.csv"), "--movie", str(tmp_path / "m.avi")],
                   [*SIM, "--out", str(tmp_path / "t.csv"), "--rerun", str(tmp_path / "r.txt")]], cwd=tmp_path)
    assert_bad_input(rs[0], "--movie", tmp_path, set())  # the trajectory CSV was not written either
    assert_bad_input(rs[1], "--rerun", tmp_path, set())
