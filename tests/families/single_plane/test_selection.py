"""The smallest exact model is chosen for each scene."""

import pytest

from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.selection import smallest_model


@pytest.mark.parametrize("data, kind, n_states", [
    ({"n": 2}, "rotating-frame", 8),
    ({"n": 2, "gravity": True}, "fixed-frame", 8),
    ({"n": 3, "stiffness": [1e4, 2e4]}, "fixed-frame", 10),
    ({"n": 2, "ball_mass": [0.05, 0.04]}, "rotating-frame-dimensional", 8),
    ({"n": 2, "speed": {"law": "profile", "omega": "400*(1 - exp(-t))"}}, "fixed-frame", 8),
    ({"n": 2, "speed": {"law": "torque", "tau0": 1.0}}, "fixed-frame-torque", 10),
])
def test_smallest_model(data, kind, n_states):
    chosen = smallest_model(Scene.from_mapping(data))
    assert chosen.kind == kind
    assert len(chosen.system.states) == n_states
    if kind.startswith("rotating-frame"):
        assert "t" not in {s.name for e in chosen.system.rhs()[:4] for s in e.free_symbols}
