"""The two-plane scene: presets reproduce the paper's matrices, bad input is one clear error."""

import pytest
import sympy as sp

from adbgen.errors import SceneError
from adbgen.references import two_plane_2011 as paper
from adbgen.families.two_plane.scene import PRESETS, TwoPlaneScene
from adbgen.families.two_plane.symbols import TwoPlaneSymbols


def _matrices(name):
    scene = TwoPlaneScene.preset(name)
    s = TwoPlaneSymbols.for_scene(scene)
    values = {p.symbol: p.default for p in s.parameters}
    return {k: v.xreplace(values) for k, v in paper.matrices(s, scene.n).items() if k in ("K_X", "K_Y", "C_X", "C_Y")}


@pytest.mark.parametrize("name, KX, KY, CX, CY", [
    ("paper-41", [[1, 0], [0, 9]], [[1, 0], [0, 9]], [[0.02, 0], [0, 0.18]], [[0.02, 0], [0, 0.18]]),
    ("paper-42", [[1, 3], [3, 45]], [[1, 3], [3, 45]], [[0.02, 0.06], [0.06, 0.90]], [[0.02, 0.06], [0.06, 0.90]]),
    ("paper-43", [[1, 0], [0, 9]], [[5, 0], [0, 45]], [[0.02, 0], [0, 0.18]], [[0.1, 0], [0, 0.9]]),
])
def test_presets_give_the_printed_support_matrices(name, KX, KY, CX, CY):
    """(1) evaluated for the presets equals (41), (42), (43) to 1e-12."""
    got = _matrices(name)
    for key, want in (("K_X", KX), ("K_Y", KY), ("C_X", CX), ("C_Y", CY)):
        assert (got[key] - sp.Matrix(want)).norm() < 1e-12, (name, key, got[key])


def test_paper_10_values():
    scene = TwoPlaneScene.preset("paper-10")
    assert scene.symmetric and scene.isotropic and scene.n == 4
    assert (scene.rotor_mass, scene.transverse_inertia, scene.polar_inertia) == (1.0, 3.25, 0.5)
    assert [r.z for r in scene.races] == [2.0, -2.0] and scene.races[0].radius == 1.0
    assert scene.races[0].damping / scene.races[0].masses[0] == pytest.approx(0.01)  # c_b/m of (10)
    assert all(name in PRESETS for name in ("paper-10", "paper-41", "paper-42", "paper-43"))


def test_any_count_per_race_and_overrides():
    scene = TwoPlaneScene.from_mapping({"races": [{"z": 1, "radius": 1, "masses": [0.1, 0.2, 0.3], "damping": 0},
                                                  {"z": -3, "radius": 2, "masses": [0.4]}],
                                        "misalignment": 0.001})
    assert scene.n == 4 and scene.ball_race == (0, 0, 0, 1) and not scene.symmetric


@pytest.mark.parametrize("data, field", [
    ({"preset": "paper-99"}, "preset"),
    ({"rotor_mass": -1}, "rotor_mass"),
    ({"misalignment": 1.0}, "misalignment"),
    ({"races": [{"z": 1, "radius": 1, "masses": [0.1]}]}, "races"),
    ({"races": [{"z": 1, "radius": 1, "masses": [0.1]}, {"z": 1, "radius": 1, "masses": [0.1]}]}, "races[1].z"),
    ({"races": [{"z": 1, "radius": 1, "masses": []}, {"z": 2, "radius": 1, "masses": []}]}, "races"),
    ({"races": [{"z": 1, "radius": 0, "masses": [0.1]}, {"z": 2, "radius": 1, "masses": [0.1]}]}, "races[0].radius"),
    ({"races": [{"z": 1, "radius": 1, "masses": [0.1, -2]}, {"z": 2, "radius": 1, "masses": [0.1]}]},
     "races[0].masses[1]"),
    ({"bearing_1": {"position": 3, "stiffness": [1, 2, 3]}}, "bearing_1.stiffness"),
    ({"bearing_1": {"position": -1, "stiffness": 1}}, "bearing_1.position"),
    ({"bearing_1": {"position": 0, "stiffness": 0}, "bearing_2": {"position": 0, "stiffness": 0}}, "bearing_2.position"),
    ({"speed": {"law": "warp"}}, "speed.law"),
    ({"speed": {"law": "hill", "n": 8}}, "speed.n"),
    ({"speed": {"law": "ramp", "t_ramp": 0}}, "speed.t_ramp"),
    ({"speed": {"law": "constant", "tau0": 1}}, "speed.tau0"),
    ({"speed": {"law": "schedule", "omega": 3.6}}, "speed.ramp_time"),
    ({"speed": {"law": "schedule", "omega": 3.6, "ramp_time": 100, "reduction_depth": 1.2}}, "speed.reduction_depth"),
    ({"speed": {"law": "schedule", "omega": 3.6, "ramp_time": 100, "t_half": 1}}, "speed.t_half"),
    ({"colour": "red"}, "colour"),
])
def test_bad_input_names_the_field(data, field):
    with pytest.raises(SceneError) as info:
        TwoPlaneScene.from_mapping(data)
    message = str(info.value)
    assert message.startswith(f"scene.{field}: ") and "\n" not in message


def test_load_toml(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('preset = "paper-42"\neccentricity = 0.02\n[speed]\nlaw = "torque"\ntau0 = 0.5\n')
    scene = TwoPlaneScene.load(path)
    assert scene.bearing_1.position == 9.0 and scene.eccentricity == 0.02 and scene.speed.law == "torque"
    with pytest.raises(SceneError, match="scene.<file>"):
        TwoPlaneScene.load(tmp_path / "missing.toml")


def test_a_schedule_is_validated_and_becomes_parameters():
    """Issue 37 item 4: a two-plane schedule's values (defaults filled in) are parameters of the model, the
    final speed under the family's name Omega; the spin law is the shared one (its check is the
    single-plane family's `speed schedule`)."""
    from adbgen.families.two_plane.symbols import TwoPlaneSymbols

    scene = TwoPlaneScene.from_mapping({"speed": {"law": "schedule", "omega": 3.6, "ramp_time": 300.0,
                                                  "reduction_depth": 0.4, "plateau_time": 50.0}})
    values = dict(scene.speed.schedule)
    assert values["hold_time"] == 0.0 and values["reduction_rate"] == values["recovery_rate"] == 3.6 / 300.0
    params = {p.name: p.default for p in TwoPlaneSymbols.for_scene(scene).parameters}
    assert params["Omega"] == 3.6 and params["t_ramp"] == 300.0 and params["depth"] == 0.4
    assert params["t_plateau"] == 50.0 and "Omega_max" not in params
