"""Ball-race friction in the two-plane family (issue 37 item 1): scene key, zero-friction limit, normal force."""

import pytest

from adbgen.errors import SceneError
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.families.two_plane.symbols import TwoPlaneSymbols


def test_rolling_resistance_key():
    scene = TwoPlaneScene.from_mapping({"rolling_resistance": 0.02})
    assert scene.friction and scene.rolling_resistances() == (0.02,) * scene.n
    assert len(set(TwoPlaneSymbols.for_scene(scene).mu_r)) == 1
    each = TwoPlaneScene.from_mapping({"rolling_resistance": [0.01, 0.02, 0.03, 0.04]})
    assert len(set(TwoPlaneSymbols.for_scene(each).mu_r)) == 4
    assert not TwoPlaneScene.from_mapping({}).friction
    assert TwoPlaneSymbols.for_scene(TwoPlaneScene.from_mapping({})).mu_r == ()
    with pytest.raises(SceneError):  # negative control: a negative coefficient
        TwoPlaneScene.from_mapping({"rolling_resistance": -0.01})
    with pytest.raises(SceneError):  # one value per ball or one for all
        TwoPlaneScene.from_mapping({"rolling_resistance": [0.01, 0.02]})


@pytest.mark.parametrize("check", [verify.friction_zero_limit, verify.friction_normal_force])
def test_friction_checks_and_their_wrong_variants(check):
    assert check().passed
    assert not check(wrong=True).passed


def test_a_friction_scene_gets_the_fixed_frame_model_with_friction():
    from adbgen.families.two_plane.models import for_scene

    scene = TwoPlaneScene.from_mapping({
        "rolling_resistance": 0.01, "speed": {"law": "torque", "tau0": 0.036, "motor_slope": 0.01},
        "races": [{"z": 2.0, "radius": 1.0, "masses": [0.0025], "damping": 2.5e-5},
                  {"z": -2.0, "radius": 1.0, "masses": [0.0025], "damping": 2.5e-5}]})
    spec = for_scene(scene)
    system = spec.system()
    names = {p.name for p in system.parameters}
    assert "mu_r" in names and spec.continuation is None
    assert spec.start(system)[0] is None
    # negative control: the same scene without friction gets a model without mu_r
    plain = for_scene(TwoPlaneScene.from_mapping({"speed": {"law": "torque", "tau0": 0.036, "motor_slope": 0.01},
                                                  "races": [dict(r) for r in ({"z": 2.0, "radius": 1.0, "masses": [0.0025], "damping": 2.5e-5},
                                                                             {"z": -2.0, "radius": 1.0, "masses": [0.0025], "damping": 2.5e-5})]}))
    assert "mu_r" not in {p.name for p in plain.system().parameters}
