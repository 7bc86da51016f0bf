"""The flexible-rotor family against the single-plane model where they overlap (issue 38 item 4)."""

import pytest
import sympy as sp

from adbgen.errors import SceneError
from adbgen.families.flexible.model import derive
from adbgen.families.flexible.scene import FlexibleScene
from adbgen.families.flexible.verify import (RHS_TOLERANCE, rhs_difference, rigid_scene, single_plane_limit,
                                            single_plane_scenes, two_plane_difference, two_plane_scenes, wrong_shape)


@pytest.mark.parametrize("index", [0, 1])
def test_jeffcott_equals_single_plane(index):
    single = single_plane_scenes()[index]
    assert rhs_difference(single) <= RHS_TOLERANCE


@pytest.mark.parametrize("index", [0, 1])
def test_wrong_node_shape_is_caught(index):
    """Negative control: 5 % of mode 2 in the balancer node's x translation."""
    single = single_plane_scenes()[index]
    assert rhs_difference(single, wrong_shape(single)) > 1e3 * RHS_TOLERANCE


def test_registered_check_passes_and_its_wrong_variant_fails():
    assert all(r.passed for r in single_plane_limit())
    assert not any(r.passed for r in single_plane_limit(wrong=True))


def test_gyroscopic_force_does_no_work_and_zero_entries_get_no_symbol():
    data = {"n": 1, "modal": {"mass": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                              "stiffness": [[1e4, 0, 0], [0, 1e4, 0], [0, 0, 4e4]],
                              "gyroscopic": [[0, 0.1, 0], [-0.1, 0, 0], [0, 0, 0]],
                              "node_shape": [[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]}}
    eom = derive(FlexibleScene.from_mapping(data))
    names = {p.name for p in eom.parameters}
    assert {"G_q_1_2", "Phi_x_3", "K_q_3_3"} <= names and "Phi_y_3" not in names and "M_q_1_2" not in names
    rates = [c.qd for c in eom.coordinates[:3]]
    power = sp.expand(sum(qd * f for qd, f in zip(rates, eom.forcing[:3])))
    assert sp.Symbol("G_q_1_2", real=True) in eom.symbols()
    assert power.coeff(sp.Symbol("G_q_1_2", real=True)) == 0  # q'^T G q' = 0: the skew force does no work


@pytest.mark.parametrize("data, field", [
    ({"modal": {"mass": [[1.0]], "stiffness": [[1.0]], "node_shape": [[1.0], [0.0]]}, "speed": {"law": "torque"}}, "speed"),
    ({"modal": {"mass": [[1.0, 0.1], [0.0, 1.0]], "stiffness": [[1, 0], [0, 1]], "node_shape": [[1, 0], [0, 1]]}},
     "modal.mass"),
    ({"modal": {"mass": [[1.0, 0], [0, 1]], "stiffness": [[1, 0], [0, 1]], "gyroscopic": [[0, 1], [1, 0]],
                "node_shape": [[1, 0], [0, 1]]}}, "modal.gyroscopic"),
    ({"modal": {"mass": [[1.0, 0], [0, 1]], "stiffness": [[1, 0], [0, 1]], "node_shape": [[1, 0]]}}, "modal.node_shape"),
    ({"modal": {"mass": [[1.0]], "stiffness": [[1.0]], "node_shape": [[1.0], [0.0]], "extra": 1}}, "modal.extra"),
])
def test_bad_scene_names_its_field(data, field):
    with pytest.raises(SceneError) as err:
        FlexibleScene.from_mapping(data)
    assert err.value.field == field


@pytest.mark.parametrize("index", [0, 1])
def test_four_rigid_modes_equal_two_plane(index):
    """Issue 38 item 4: two nodes, four rigid-body modes = the two-plane fixed-frame model (chi = 0)."""
    assert two_plane_difference(two_plane_scenes()[index]) <= RHS_TOLERANCE


@pytest.mark.parametrize("index", [0, 1])
def test_flipped_tilt_at_second_node_is_caught(index):
    """Negative control: the second node's shape [1, 0, 0, -z], [0, 1, z, 0] instead of [1, 0, 0, z], [0, 1, -z, 0]."""
    assert two_plane_difference(two_plane_scenes()[index], tilt_2=-1.0) > 1e3 * RHS_TOLERANCE


def test_rigid_scene_refuses_what_has_no_modal_counterpart():
    from dataclasses import replace

    two = two_plane_scenes()[0]
    for bad in (replace(two, misalignment=1e-3), replace(two, eccentricity=0.01)):  # chi; unbalance off node 1
        with pytest.raises(ValueError):
            rigid_scene(bad)


def test_second_node_from_toml_and_offered_for_generation():
    from adbgen.families.flexible.models import for_scene

    data = {"n": 1, "modal": {"mass": [[1.0, 0], [0, 1]], "stiffness": [[1, 0], [0, 1]],
                              "node_shape": [[1, 0], [0, 1]]},
            "node_2": {"n": 2, "ball_mass": [0.01, 0.02], "race_radius": 0.1, "node_shape": [[0.5, 0], [0, 0.5]]}}
    scene = FlexibleScene.from_mapping(data)
    assert scene.balls == 3 and scene.ball_node() == (0, 1, 1)
    names = {p.name for p in derive(scene).parameters}
    assert {"R", "R_2", "Phi2_x_1", "m_1", "m_3", "D_3"} <= names
    spec = for_scene(scene)  # generation is offered (tests/families/flexible/test_two_nodes.py generates one)
    assert spec.name == "scene_flexible_k2_n3" and spec.n == 3
    assert [c.key for c in spec.checks] == [("flexible", "single_plane_limit"), ("flexible", "two_plane_limit")]
    with pytest.raises(SceneError) as err:
        FlexibleScene.from_mapping({**data, "node_2": {"n": 1, "node_shape": [[1, 0, 0], [0, 1, 0]]}})
    assert err.value.field == "node_2.node_shape"


def test_gyroscopic_sign_of_the_rigid_modes_matters(monkeypatch):
    """The two-plane overlap exercises G_q: its sign flipped is caught (J_p enters x'' of the tilts)."""
    from dataclasses import replace

    import adbgen.families.flexible.verify as verify

    two = two_plane_scenes()[1]
    scene = rigid_scene(two)
    flipped = replace(scene, modal=replace(scene.modal, gyroscopic=tuple(tuple(-v for v in row)
                                                                            for row in scene.modal.gyroscopic)))
    monkeypatch.setattr(verify, "rigid_scene", lambda two, tilt_2=1.0: flipped)
    assert two_plane_difference(two) > 1e3 * RHS_TOLERANCE
