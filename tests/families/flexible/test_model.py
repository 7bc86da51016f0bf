"""The flexible-rotor family against the single-plane model where they overlap (issue 38 item 4)."""

import pytest
import sympy as sp

from adbgen.errors import SceneError
from adbgen.families.flexible.model import derive
from adbgen.families.flexible.scene import FlexibleScene
from adbgen.families.flexible.verify import RHS_TOLERANCE, rhs_difference, single_plane_limit, single_plane_scenes, wrong_shape


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
