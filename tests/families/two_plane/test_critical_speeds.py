"""Critical speeds: (11), (32) exactly; the values quoted for (10), (42), (43) numerically."""

import pytest

from adbgen.families.two_plane import critical_speeds as cs
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.scene import TwoPlaneScene


def test_symbolic_11_and_32():
    result = verify.critical_speeds_symbolic()
    assert result.passed, result.detail


@pytest.mark.parametrize("result", verify.critical_speed_numbers(), ids=lambda r: r.name)
def test_printed_critical_speeds(result):
    assert result.passed, result.detail


def test_balls_lower_the_critical_speeds_as_32_says():
    """(32): Omega_cyl = sqrt(2k/(M + 4m)) = 1/sqrt(1.01) and Omega_con = sqrt(9/(2.75 + 16 m)) at m = 0.0025."""
    got = cs.critical_speeds(TwoPlaneScene())
    assert got == pytest.approx([1 / 1.01**0.5, (9 / (2.75 + 16 * 0.0025)) ** 0.5], rel=1e-12)


def test_disc_rotor_has_no_conical_critical_speed():
    """J_p > J_t ('disc', section 5): only the cylindrical whirl has a critical speed."""
    disc = TwoPlaneScene.from_mapping({"transverse_inertia": 0.5, "polar_inertia": 1.0})
    assert len(cs.critical_speeds(disc, with_balls=False)) == 1
