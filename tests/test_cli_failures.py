"""Every failure issue 24 found, as a table (item 5): one line `adbgen: error: ...`, the right exit
status, checked before the work (the clock says so), and nothing lost (what was there is still there).

The rows are the issue's findings: --out onto a file or a read-only place (simulate, regenerate after
7 s of derivation, stability --scan, demo, and the other commands that write), Ctrl-C, --workers 0,
--set of a negative mass, a scene error listing the other family's complaints, values with the wrong
unit; and exit status 3 for a scan that stops short.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from adbgen.cli import EXIT_STATUS, main

ADBGEN = [sys.executable, "-m", "adbgen.cli"]
READ_ONLY = "/sys/adbgen-test-out"  # creating anything there fails, even for root (sysfs)


def run(capsys, *argv: str) -> tuple[int, str, str, float]:
    start = time.perf_counter()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err, time.perf_counter() - start


@pytest.fixture()
def places(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("keep me")
    folder = tmp_path / "folder"
    folder.mkdir()
    (folder / "inside").write_text("keep me too")
    scene = tmp_path / "sp.toml"
    scene.write_text("n = 2\nball_mass = -0.01\n")
    return {"FILE": str(afile), "DIR": str(folder), "RO": READ_ONLY, "SCENE": str(scene)}


# argv (placeholders FILE, DIR, RO, SCENE), exit status, what the one line says
TABLE = [
    (["simulate", "thesis_rotating_n2", "--out", "FILE"], 2, "--out FILE: is a file, not a folder"),
    (["simulate", "thesis_rotating_n2", "--out", "FILE/sub"], 2, "is a file, not a folder"),
    (["simulate", "thesis_rotating_n2", "--out", "RO"], 2, "cannot write in /sys"),
    (["regenerate", "--out", "FILE"], 2, "--out FILE: is a file, not a folder"),
    (["regenerate", "--n", "2", "--out", "RO"], 2, "cannot write in /sys"),
    (["stability", "thesis_rotating_n2", "--scan", "Omega=4:3.9", "--out", "FILE"], 2, "is a file, not a folder"),
    (["demo", "--out", "FILE"], 2, "--out FILE: is a file, not a folder"),
    (["sweep", "thesis_rotating_n2", "--grid", "phi_1=0:1:2", "--measure", "r_max", "--out", "FILE"], 2, "is a file"),
    (["continue", "thesis_rotating_n2", "--par", "Omega", "--keep", "FILE"], 2, "--keep FILE: is a file"),
    (["reproduce", "--out", "DIR"], 2, "--out DIR: is a folder, not a file"),
    (["reproduce", "--out", "RO/x.md"], 2, "cannot write in /sys"),
    (["bench", "derive", "--out", "DIR"], 2, "--out DIR: is a folder, not a file"),
    (["sweep", "thesis_rotating_n2", "--grid", "phi_1=0:1:2", "--measure", "r_max", "--out", "DIR", "--workers", "0"],
     2, "argument --workers: must be at least 1, got 0"),
    (["simulate", "thesis_rotating_n2", "--set", "mu=-0.05"], 2, "--set mu: must be positive, got -0.05"),
    (["simulate", "single_plane_fixed_n2", "--set", "m=-0.01"], 2, "--set m: must be positive, got -0.01 kg"),
    (["simulate", "single_plane_fixed_n2", "--set", "k_X=-1"], 2, "--set k_X: must be non-negative"),
    (["simulate", "thesis_rotating_n2", "--set", "Omega=1e400"], 2, "--set Omega: "),
    (["simulate", "thesis_rotating_n2", "--t-end", "20s"], 2, "runs in dimensionless time"),
    (["simulate", "single_plane_fixed_n2", "--t-end", "20kg"], 2, "--t-end: '20kg' is not in s"),
    (["simulate", "single_plane_fixed_n2", "--set", "omega=3000kg"], 2, "--set omega: '3000kg' is not in rad/s"),
    (["simulate", "single_plane_fixed_n2", "--threshold=-1mm"], 2, "--threshold must be > 0"),
    (["regenerate", "--scene", "SCENE", "--out", "DIR"], 2, "scene.ball_mass: must be positive, got -0.01"),
    (["simulate", "--scene", "SCENE"], 2, "scene.ball_mass: must be positive, got -0.01"),
]


@pytest.mark.parametrize("argv, status, message", TABLE, ids=[" ".join(a)[:60] for a, _, _ in TABLE])
def test_failure_table(capsys, places, argv, status, message, tmp_path):
    argv = [places.get(a, a) if "/" not in a else places.get(a.split("/")[0], a.split("/")[0]) + "/" + a.split("/", 1)[1]
            for a in argv]
    message = message.replace("FILE", places["FILE"]).replace("DIR", places["DIR"])
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    code, out, err, seconds = run(capsys, *argv)
    assert code == status, (code, err)
    assert err.count("\n") == 1 and err.startswith("adbgen: error: ") and message in err, err
    assert "two-plane" not in err  # a scene error names only the family the scene is for
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before  # nothing lost
    assert seconds < 20, f"refused after {seconds:.1f} s: the check must come before the work"


def test_the_bad_output_of_regenerate_is_refused_before_the_derivation(capsys, places):
    """The issue: regenerate failed on --out after 7 s of derivation; now at once."""
    code, _, err, seconds = run(capsys, "regenerate", "--out", places["FILE"])
    assert code == 2 and seconds < 2, (seconds, err)


def test_ctrl_c_is_one_line_and_exit_130(tmp_path):
    """A real SIGINT to a running command (the scipy engine: Python runs between steps)."""
    proc = subprocess.Popen(ADBGEN + ["simulate", "thesis_rotating_n2", "--y0", "phi_1=1", "--engine", "scipy-dop853",
                                      "--t-end", "1e7", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=dict(os.environ, ADBGEN_PROGRESS="0"),
                            # a shell's background job inherits SIGINT ignored: give the command a terminal's default
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(6)  # past the imports, inside the integration
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    assert err == "adbgen: error: interrupted\n", err


def test_an_error_of_adbgen_itself_is_one_line(capsys, monkeypatch):
    from adbgen.cli import simulate as commands

    def broken(args):
        raise KeyError("planted")
    import adbgen.cli as cli

    parser = cli.build_parser()
    parser._subparsers._group_actions[0].choices["simulate"].set_defaults(fn=broken)
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    code, out, err, _ = run(capsys, "simulate", "thesis_rotating_n2")
    assert code == 70 and err == "adbgen: error: internal error: KeyError: 'planted' (ADBGEN_TRACEBACK=1 shows where)\n"
    monkeypatch.setenv("ADBGEN_TRACEBACK", "1")
    with pytest.raises(KeyError):
        main(["simulate", "thesis_rotating_n2"])
    assert commands.run_simulate is not broken


def test_a_scan_that_stops_short_exits_3_and_says_where(capsys):
    """The issue: `stability --scan omega=400:100` stopped at its step cap and printed a stable interval
    with exit 0.  Now: exit 3, a line naming why and where, JSON complete false."""
    code, out, err, _ = run(capsys, "stability", "thesis_rotating_n2", "--scan", "Omega=4:0.5", "--max-steps", "20",
                            "--json")
    data = json.loads(out)
    assert code == 3 == max(k for k in EXIT_STATUS if k < 70)
    assert data["complete"] is False and data["end"] == "step limit" and data["steps"] == 21
    assert 3.5 < data["end_at"] < 4.0 and data["stable_intervals"] == [[data["end_at"], 4.0]]
    assert err.startswith("adbgen: ended early: Omega reached 3.") and "step limit (20 steps" in err
    code, out, err, _ = run(capsys, "stability", "thesis_rotating_n2", "--scan", "Omega=4:3.5", "--json")
    assert code == 0 and json.loads(out)["complete"] is True and err == ""  # negative control


def test_exit_statuses_are_in_the_help(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "exit status: 0 done" in " ".join(out.split()) and "3 a scan or continuation ended before its range" in " ".join(out.split())
