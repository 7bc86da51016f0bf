"""The flexible family as registered: its model's start is an exact solution, its self-description."""

import numpy as np
import pytest

from adbgen import families
from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.flexible.models import balanced_orbit, for_scene
from adbgen.families.flexible.scene import FlexibleScene

THREE_MODES = {"n": 2, "ball_mass": 0.02, "race_radius": 0.04, "eccentricity": 2e-4, "unbalance_mass": 2.0,
               "speed": {"law": "constant", "omega": 300.0},
               "modal": {"mass": [[2.0, 0, 0], [0, 2.0, 0], [0, 0, 1.5]],
                         "stiffness": [[3e4, 0, 0], [0, 3e4, 0], [0, 0, 2e5]],
                         "damping": [[3.0, 0, 0], [0, 3.0, 0], [0, 0, 5.0]],
                         "gyroscopic": [[0, 0.01, 0], [-0.01, 0, 0], [0, 0, 0]],
                         "node_shape": [[1.0, 0.0, 0.6], [0.0, 1.0, 0.0]]}}


def test_registered_once_by_name():
    assert "flexible" in families.names()
    assert families.get("flexible").name == "flexible"
    assert "flexible_fixed" in families.kinds()


@pytest.mark.parametrize("shift", [0.0, 0.1])
def test_balanced_start_is_an_exact_solution(shift):
    """The node at rest with the balls cancelling m_u eps: every acceleration 0 at any t; a ball moved by
    0.1 rad (the negative control) leaves the node forced."""
    scene = FlexibleScene.from_mapping(THREE_MODES)
    system = for_scene(scene).system()
    state, label, _ = balanced_orbit(scene)(system)
    assert state is not None and "node at rest" in label
    y = np.array(state[:-2])  # without the oscillator's (sin, cos)
    y[system.state_names.index("phi_1")] += shift
    rhs = NumericFirstOrder(system)
    worst = max(np.max(np.abs(rhs(t, y))) for t in (0.0, 0.0123, 0.5))
    assert (worst < 1e-9) if shift == 0 else (worst > 1e-3)


def test_description_roles_and_balanced_state():
    scene = FlexibleScene.from_mapping(THREE_MODES)
    spec = for_scene(scene)
    d = spec.describe(spec.system())
    assert d.roles == {"q_1": "translation", "q_2": "translation", "q_3": "translation",
                       "phi_1": "ball_angle", "phi_2": "ball_angle"}
    assert d.forcing_frequency == "omega" and d.scales["eccentricity"] == "eps"
    assert [s.label for s in d.steady_states] == ["B"]


def test_loop_form_generates_with_mode_shapes_indexed_like_balls(tmp_path):
    """Phi_x_1, Phi_x_2 (two modes moving the node in x) look like two balls' parameters by name; the
    family gives the balls' slots itself, so the loop form (size independent of n) is emitted.  Negative
    control: the same model without the slots is refused by the loop form."""
    import dataclasses

    from adbgen.cli import main
    from adbgen.families.flexible import models

    data = {"n": 2, "modal": {"mass": [[1.0, 0.0], [0.0, 1.0]], "stiffness": [[1e4, 0.0], [0.0, 2e4]],
                              "node_shape": [[1.0, 0.5], [0.0, 1.0]]}}
    scene_file = tmp_path / "two_modes.toml"
    scene_file.write_text("n = 2\n[modal]\nmass = [[1.0, 0.0], [0.0, 1.0]]\nstiffness = [[1e4, 0.0], [0.0, 2e4]]\n"
                          "node_shape = [[1.0, 0.5], [0.0, 1.0]]\n")
    assert FlexibleScene.load(scene_file) == FlexibleScene.from_mapping(data)
    assert main(["regenerate", "--scene", str(scene_file), "--out", str(tmp_path / "gen"), "--targets", "numba",
                 "--quiet"]) == 0
    original = models.for_scene
    try:
        models.for_scene = lambda scene, name=None: dataclasses.replace(original(scene, name), balls=None)
        assert main(["regenerate", "--scene", str(scene_file), "--out", str(tmp_path / "gen2"), "--targets", "numba",
                     "--quiet", "--family", "flexible"]) != 0
    finally:
        models.for_scene = original
