"""Ball-race friction in the two-plane family (issue 37 items 1 and 2): scene keys, zero-friction limit, normal
force, the stick phase's rows and required force."""

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


def test_static_friction_key():
    scene = TwoPlaneScene.from_mapping({"rolling_resistance": 0.01, "static_friction": [0.02, 0.03, 0.04, 0.05]})
    assert scene.stiction and scene.static_frictions() == (0.02, 0.03, 0.04, 0.05)
    s = TwoPlaneSymbols.for_scene(scene)
    assert len(set(s.mu_s)) == 4 and len(set(s.mu_r)) == 1
    names = {p.name for p in s.parameters}
    assert {"stuck_1", "stuck_4", "slip_dir_1", "slip_dir_4"} <= names
    plain = TwoPlaneSymbols.for_scene(TwoPlaneScene.from_mapping({"rolling_resistance": 0.01}))
    assert plain.mu_s == plain.stuck == plain.slip_dir == ()  # negative control: no stiction, no modes


@pytest.mark.parametrize("mapping, why", [
    ({"static_friction": 0.02}, "needs rolling_resistance"),
    ({"rolling_resistance": 0.02, "static_friction": 0.01}, "ball 1"),
    ({"rolling_resistance": [0.01, 0.01, 0.03, 0.01], "static_friction": 0.02}, "ball 3"),
    ({"rolling_resistance": 0.01, "static_friction": -0.1}, "static_friction"),
])
def test_static_friction_below_rolling_resistance_is_refused_per_ball(mapping, why):
    """mu_r > mu_s leaves a ball with no consistent mode (it can neither stick nor slip): refused in one line,
    naming the ball; mu_s = mu_r is allowed (the control beside each refusal)."""
    with pytest.raises(SceneError, match=why) as err:
        TwoPlaneScene.from_mapping(mapping)
    assert "\n" not in str(err.value)
    if "rolling_resistance" in mapping:
        TwoPlaneScene.from_mapping({**mapping, "static_friction": mapping["rolling_resistance"]})


def test_a_stiction_scene_gets_the_stick_model():
    """kind stick_<law>, its checks include the stick rows and force; without static_friction (the control) the
    slip model, without modes."""
    from adbgen.families.two_plane.models import for_scene

    spec = for_scene(TwoPlaneScene.from_mapping({"rolling_resistance": 0.01, "static_friction": 0.02}))
    assert "stick_constant" in spec.name and any("friction_stick_rows" in c.key for c in spec.checks)
    plain = for_scene(TwoPlaneScene.from_mapping({"rolling_resistance": 0.01}))
    assert "friction_constant" in plain.name and not any("friction_stick_rows" in c.key for c in plain.checks)


@pytest.mark.parametrize("check", [verify.friction_zero_limit, verify.friction_normal_force,
                                   verify.friction_stick_rows, verify.friction_stick_force])
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
