"""`adbgen two-plane ...` and `adbgen verify --model two-plane`."""

import json

from adbgen.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_derive_json(capsys):
    code, out, err = run(capsys, "two-plane", "derive", "--form", "fixed", "--format", "json", "--preset", "paper-43")
    data = json.loads(out)
    assert code == 0 and data["coordinates"][:4] == ["X", "Y", "phi_X", "phi_Y"] and "k_1Y" in data["parameters"]


def test_derive_first_order_picks_the_rotating_frame_when_autonomous(capsys):
    code, out, _ = run(capsys, "two-plane", "derive", "--format", "json")
    assert code == 0 and json.loads(out)["states"][:4] == ["x", "y", "phi_x", "phi_y"]


def test_steady_reports_normal_form(capsys):
    code, out, _ = run(capsys, "two-plane", "steady", "--m", "0.003")
    assert code == 0
    # regression value: a_1 of the derived normal form at (10), Omega = 3 (README; the paper prints no
    # number; (33) is checked as an identity by verify's normal-form check)
    assert "a_1 = 0.00188043" in out and "B stable (38)" in out and "full model: stable" in out


def test_steady_between_critical_speeds(capsys):
    code, out, _ = run(capsys, "two-plane", "steady", "--Omega", "1.4", "--m", "0.003")
    assert code == 0 and "B unstable (38), C3 stable (37)" in out and "full model: unstable" in out


def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path):
    code, out, err = run(capsys, "two-plane", "steady", "--eps", "-1")
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("adbgen: error: scene.eccentricity")
    path = tmp_path / "s.toml"
    path.write_text("misalignment = 2.0\n")
    code, out, err = run(capsys, "two-plane", "derive", "--scene", str(path))
    assert code == 2 and err.startswith("adbgen: error: scene.misalignment") and err.count("\n") == 1


def test_verify_two_plane(capsys):
    code, out, _ = run(capsys, "verify", "--model", "two-plane")
    assert code == 0 and "0 failed" in out and "FAIL" not in out
