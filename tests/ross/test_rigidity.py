"""adbgen.ross.rigidity: the rigid scene's critical speeds against ROSS's Campbell diagram (issue 38 item 2)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from adbgen.families.two_plane.critical_speeds import critical_speeds
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.ross import from_ross
from adbgen.ross.rigidity import campbell_crossings, verdict
from adbgen.ross.scene import scene_mapping

TOP = 545.0  # rad/s: about 1.5 x the rigid model's highest critical speed of the example (363 rad/s)


@pytest.fixture(scope="module")
def bridged(example):
    return scene_mapping(example, [2, 4], 2, 0.05, 0.1, TOP)


@pytest.fixture(scope="module")
def rigid(bridged):
    return critical_speeds(bridged.scene, with_balls=False)


@pytest.fixture(scope="module")
def stiff_crossings(stiff, rigid):
    return [c.speed for c in campbell_crossings(stiff, 1.2 * max(rigid))]


def test_rigid_scene_equals_ross_with_a_stiff_shaft(rigid, stiff_crossings):
    """The example's shaft made stiff (E x 1e3): its four lowest Campbell crossings are the rigid
    scene's undamped critical speeds (anisotropic bearings: forward and backward) to 1e-3."""
    assert len(rigid) == 4 and len(stiff_crossings) == 4
    for ours, theirs in zip(rigid, stiff_crossings):
        assert abs(ours / theirs - 1) < 1e-3, (rigid, stiff_crossings)


def _off(mapping: dict, rigid_ross: list[float]) -> float:
    crit = critical_speeds(TwoPlaneScene.from_mapping(mapping), with_balls=False)
    return max(abs(a / b - 1) for a, b in zip(crit, rigid_ross))


def test_a_wrong_inertia_or_bearing_position_is_caught(bridged, stiff_crossings):
    """Negative controls: J_t 2 % off, or bearing 1 moved by 1 cm, miss ROSS's modal results by > 1e-3."""
    m = bridged.mapping
    assert _off({**m, "transverse_inertia": m["transverse_inertia"] * 1.02}, stiff_crossings) > 1e-3
    assert _off({**m, "bearing_1": {**m["bearing_1"], "position": m["bearing_1"]["position"] + 0.01}},
                stiff_crossings) > 1e-3


def test_stiff_example_is_enough_and_the_example_is_not(example, stiff, rigid):
    ok = verdict(stiff, rigid, TOP)
    assert ok.enough and ok.bending is None, ok.line()
    no = verdict(example, rigid, TOP)
    assert not no.enough
    # ROSS's example as it is: its lowest crossings 91.8, 96.3, 271, 300 rad/s against the rigid 135,
    # 151, 317, 363; the fifth (the first bending) at 636 rad/s, 1.17 x the top speed, below 2 x
    assert [round(c.speed, 1) for c in no.ross[:5]] == [91.8, 96.3, 271.3, 300.4, 636.0]
    assert no.bending == pytest.approx(636.0, rel=1e-3)
    assert "rigid is not enough" in no.line() and "\n" not in no.line()
    # the margin rule alone: at a top speed of 300 rad/s the margin 2 asks for 600 < 636
    assert not any("bending" in r for r in verdict(example, rigid, 300.0).reasons)


def test_from_ross_with_the_default_speed(stiff):
    res = from_ross(stiff, [2], 2, 0.05, 0.1)
    assert res.verdict.enough
    assert res.bridged.speed == pytest.approx(1.5 * max(res.verdict.rigid))
    races = res.bridged.scene.races
    assert races[0].z == pytest.approx(-0.25) and races[1].masses == () and races[1].z == pytest.approx(0.25)


def test_speed_dependent_bearings_need_a_speed(ross, example):
    from adbgen.ross import RotorError, operating_speed

    b = lambda n: ross.BearingElement(n, kxx=[1e6, 2e6], cxx=[0.0, 0.0], frequency=[0.0, 1000.0])  # noqa: E731
    rotor = ross.Rotor(example.shaft_elements, example.disk_elements, [b(0), b(6)])
    with pytest.raises(RotorError, match="give --speed"):
        operating_speed(rotor, None, [2], 2, 0.05, 0.1)
    assert operating_speed(rotor, 300.0, [2], 2, 0.05, 0.1) == (300.0, None)  # the control: with a speed
    k300 = scene_mapping(rotor, [2], 2, 0.05, 0.1, 300.0).bearings[0].k
    k600 = scene_mapping(rotor, [2], 2, 0.05, 0.1, 600.0).bearings[0].k
    assert 1e6 < k300[0] < k600[0] < 2e6  # read at the operating speed
