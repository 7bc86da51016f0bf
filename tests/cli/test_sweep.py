"""`adbgen sweep` (adbgen/cli/sweep.py): a scene file instead of a model (issue 37 item 4: a speed schedule's
values are parameters, swept with --grid and fixed with --set), and its one-line refusals."""

from __future__ import annotations

import pytest

from adbgen.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("argv, message", [
    (("thesis_rotating_n2", "--scene", "rotor.toml"), "give a model name or --scene, not both"),
    ((), "no model given"),
    (("--scene", "no-such-scene.toml"), "no-such-scene.toml"),
])
def test_sweep_needs_exactly_one_of_model_and_scene(capsys, tmp_path, argv, message):
    code, out, err = run(capsys, "sweep", *argv, "--grid", "depth=0:0.5:2", "--measure", "r_max",
                         "--out", str(tmp_path / "out"))
    lines = err.strip().splitlines()
    assert code != 0 and out == "" and len(lines) == 1 and message in lines[0], err


def test_residual_measure_only_with_measure_residual(capsys, tmp_path):
    # --residual-measure names the residual of --measure residual; with another measure it is refused in one line
    code, out, err = run(capsys, "sweep", "thesis_rotating_n2", "--grid", "phi_1=0:1:2", "--measure", "r_max",
                         "--residual-measure", "r", "--t-end", "1", "--out", str(tmp_path / "ok"), "--json")
    assert code == 0, err  # the default name is accepted everywhere
    code, out, err = run(capsys, "sweep", "thesis_rotating_n2", "--grid", "phi_1=0:1:2", "--measure", "r_max",
                         "--residual-measure", "A", "--out", str(tmp_path / "out"))
    lines = err.strip().splitlines()
    assert code != 0 and out == "" and len(lines) == 1 and "--measure residual only" in lines[0], err
