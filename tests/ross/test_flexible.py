"""The flexible scene from ROSS (issue 38 items 3-4): modal truncation of the example rotor's lateral
matrices, its critical speeds against ROSS's Campbell diagram, modal convergence."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from adbgen.families.flexible.critical_speeds import crossings
from adbgen.families.flexible.scene import FlexibleScene
from adbgen.ross.flexible import convergence, lateral_dofs, node_shape, reduce, scene_mapping, shape_mismatch
from adbgen.ross.rigidity import campbell_crossings
from adbgen.ross.rotor import RotorError

NODE, SPEED, TOP = 2, 500.0, 1000.0  # the example's first disk; its bearings do not depend on speed


@pytest.fixture(scope="module")
def ross_crossings(example):
    return campbell_crossings(example, TOP, frequencies=10)


@pytest.fixture(scope="module")
def ross_forward(example, ross_crossings):
    """ROSS's forward-whirl critical speeds; a crossing ROSS calls "Mixed" is judged by the full reduced
    model's whirl at the same crossing (equal to ROSS's elsewhere: the first test)."""
    full = crossings(modal(example, len(lateral_dofs(example)[0]) - 1), TOP)
    assert len(full) == len(ross_crossings)
    return [c.speed for c, f in zip(ross_crossings, full)
            if c.whirl == "Forward" or (c.whirl == "Mixed" and f.whirl == "forward")]


def modal(example, k, node=NODE):
    return FlexibleScene.from_mapping(scene_mapping(example, node, k, 2, 0.05, 0.05, SPEED)).modal


def test_full_lateral_model_has_rosss_critical_speeds(example, ross_crossings):
    """Every lateral mode kept: the reduction is exact, so every crossing and its whirl are ROSS's."""
    full = len(lateral_dofs(example)[0]) - 1
    ours = crossings(modal(example, full), TOP)
    assert [c.speed for c in ours] == pytest.approx([c.speed for c in ross_crossings], rel=1e-7)
    theirs = [c.whirl.lower() for c in ross_crossings]
    assert all(w == t for w, t in zip((c.whirl for c in ours), theirs) if t != "mixed")


def test_wrong_gyroscopic_sign_is_caught(example, ross_forward):
    """Negative control: G_q with the opposite sign (the spin reversed against the balls') moves them."""
    full = len(lateral_dofs(example)[0]) - 1
    m = modal(example, full)
    wrong = dataclasses.replace(m, gyroscopic=tuple(tuple(-v for v in row) for row in m.gyroscopic))
    ours = crossings(wrong, TOP)
    forward = [c.speed for c in ours if c.whirl == "forward"]
    assert max(abs(a / b - 1) for a, b in zip(forward, ross_forward)) > 1e-2


def test_converged_model_first_three_forward_critical_speeds_within_1e_3(example, ross_forward):
    conv = convergence(example, NODE, SPEED, TOP)
    ross_forward = ross_forward[:3]
    assert conv.k is not None and len(ross_forward) == 3
    ours = conv.speeds[conv.k]
    assert max(abs(a / b - 1) for a, b in zip(ours, ross_forward)) < 1e-3
    # the criterion is not met one k earlier (the fewest modes), and that k is off ROSS by more
    earlier = max(k for k in conv.speeds if k < conv.k)
    assert max(abs(a / b - 1) for a, b in zip(conv.speeds[earlier], ross_forward)) > max(
        abs(a / b - 1) for a, b in zip(ours, ross_forward))


def test_node_shape_is_the_basis_row_and_scene_reads_back(example):
    mapping = scene_mapping(example, NODE, 6, 2, 0.05, 0.05, SPEED)
    scene = FlexibleScene.from_mapping(mapping)
    assert scene.k == 6 and scene.n == 2 and scene.modal.reduction.startswith("modal truncation")
    M = np.array(scene.modal.mass)
    assert np.count_nonzero(M - np.diag(np.diag(M))) == 0  # orthogonal modes: a diagonal M_q, no zero symbols
    other = FlexibleScene.from_mapping(scene_mapping(example, NODE + 1, 6, 2, 0.05, 0.05, SPEED))
    assert not np.allclose(scene.modal.node_shape, other.modal.node_shape)  # the node's rows, not another's


def test_bad_requests_are_refused(example):
    with pytest.raises(RotorError, match="not a node"):
        scene_mapping(example, 99, 4, 2, 0.05, 0.05, SPEED)
    with pytest.raises(RotorError, match="splits a pair"):
        scene_mapping(example, NODE, 23, 2, 0.05, 0.05, SPEED)
    with pytest.raises(RotorError, match="balancer node"):
        from adbgen.ross.rotor import Unbalance

        scene_mapping(example, NODE, 4, 2, 0.05, 0.05, SPEED, Unbalance(4, 1e-4, 0.0))


SECOND = 4  # the example's second disk (disks at nodes 2 and 4, bearings at 0 and 6)


@pytest.fixture(scope="module")
def ross_modes_at_rest(example):
    """ROSS's own modal analysis of the rotor at rest (no spin, and the example has no damping): its undamped
    modes, the reduction's basis (the example's bearings do not depend on speed)."""
    return example.run_modal(speed=0, num_modes=12)


def test_second_node_shapes_are_rosss_mode_shapes_there(example, ross_modes_at_rest):
    """Two balancer nodes: [node_2]'s shape entries are the same reduction's basis rows at node 4, and equal
    ROSS's mode shapes there (scaled the bridge's way) to round-off, jointly with node 2's; its race is the
    first's.  Negative control: node 3's shapes written as node 4's are caught by the same check."""
    k = 6
    mapping = scene_mapping(example, NODE, k, 2, 0.05, 0.05, SPEED, node_2=SECOND)
    scene = FlexibleScene.from_mapping(mapping)
    assert scene.node_2 is not None and scene.balls == 4 and scene.node_2.race_radius == 0.05
    red = reduce(example, NODE, k, SPEED)
    assert mapping["node_2"]["node_shape"] == node_shape(red, example, SECOND)
    assert np.asarray(ross_modes_at_rest.wn[:k]) == pytest.approx(red.frequencies, rel=1e-8)  # same modes, same order
    shapes = {NODE: mapping["modal"]["node_shape"], SECOND: mapping["node_2"]["node_shape"]}
    assert shape_mismatch(example, shapes, ross_modes_at_rest.evectors) < 1e-8
    assert shape_mismatch(example, {SECOND: shapes[SECOND]}, ross_modes_at_rest.evectors) < 1e-8
    wrong = {NODE: shapes[NODE], SECOND: node_shape(red, example, 3)}
    assert shape_mismatch(example, wrong, ross_modes_at_rest.evectors) > 1e-2


def test_one_node_scene_has_no_second_node(example):
    mapping = scene_mapping(example, NODE, 4, 2, 0.05, 0.05, SPEED)
    assert "node_2" not in mapping and ", balancer at node 2 (z = " in mapping["modal"]["reduction"]


def test_bad_two_node_requests_are_refused(example):
    from adbgen.ross.rotor import Unbalance

    with pytest.raises(RotorError, match="node 99 is not a node"):
        scene_mapping(example, NODE, 4, 2, 0.05, 0.05, SPEED, node_2=99)
    with pytest.raises(RotorError, match="different nodes"):
        scene_mapping(example, NODE, 4, 2, 0.05, 0.05, SPEED, node_2=NODE)
    with pytest.raises(RotorError, match="give --plane 4 first"):
        scene_mapping(example, NODE, 4, 2, 0.05, 0.05, SPEED, Unbalance(SECOND, 1e-4, 0.0), node_2=SECOND)
