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
