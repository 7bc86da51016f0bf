"""A flexible scene with two balancer nodes generates and simulates (the rigid shaft's four rigid-body modes
of the two-plane model, `verify.rigid_scene`): its balanced start is an exact solution and the generated
model's rhs is the derived one's."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.flexible import verify
from adbgen.families.flexible.models import balanced_orbit, for_scene, self_cancelling_angles


def _scene():
    """`verify`'s second two-plane scene (race 1 at z = 0 with the unbalance, three unequal balls in race 2) with
    the eccentricity 0.002 in place of 0.02, so the race-1 balls (0.003 + 0.002 kg at R = 1) can cancel it."""
    return verify.rigid_scene(replace(verify.two_plane_scenes()[1], eccentricity=0.002))


def _lists(value):
    """Tuples (the scene's matrices) as lists, for the TOML writer."""
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    return [_lists(v) for v in value] if isinstance(value, (tuple, list)) else value


def test_self_cancelling_angles():
    """The second node's balls cancel each other; None where they cannot (one ball, or one heavier than the rest)."""
    for masses in ((1.0, 1.0), (0.002, 0.0025, 0.003), (1.0, 1.0, 1.0, 1.0)):
        a = self_cancelling_angles(masses)
        assert abs(sum(m * np.exp(1j * x) for m, x in zip(masses, a))) < 1e-12
    assert self_cancelling_angles((1.0, 3.0, 1.0)) is None and self_cancelling_angles((1.0,)) is None


@pytest.mark.parametrize("shift", [0.0, 0.1])
def test_two_node_balanced_start_is_exact(shift):
    """The node at rest, node 1's balls cancelling the unbalance and node 2's each other: every acceleration 0 at
    any t.  Negative control: a ball of the second node moved by 0.1 rad leaves the rotor forced."""
    scene = _scene()
    system = for_scene(scene).system()
    state, label, _ = balanced_orbit(scene)(system)
    y = np.array(state[:-2])
    y[system.state_names.index(f"phi_{scene.balls}")] += shift
    rhs = NumericFirstOrder(system)
    worst = max(np.max(np.abs(rhs(t, y))) for t in (0.0, 0.37, 2.0))
    assert (worst < 1e-12) if shift == 0 else (worst > 1e-4)


def test_two_node_scene_generates_and_simulates(tmp_path):
    """The scene file with [node_2] goes through `regenerate --scene` (loop form: each ball's race radius and
    node shape are its own parameters) and `simulate`; the generated rhs equals the derived model's at a
    random state."""
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from adbgen.cli import main
    from adbgen.ross.scene import to_toml

    scene = _scene()
    m = scene.modal
    mapping = {"n": scene.n, "ball_mass": list(scene.masses()), "ball_damping": list(scene.ball_dampings()),
               "race_radius": scene.race_radius, "unbalance_mass": scene.unbalance_mass,
               "eccentricity": scene.eccentricity, "speed": {"law": "constant", "omega": scene.omega},
               "modal": {"mass": m.mass, "stiffness": m.stiffness, "damping": m.damping, "gyroscopic": m.gyroscopic,
                         "node_shape": m.node_shape},
               "node_2": {"n": scene.node_2.n, "ball_mass": list(scene.node_2.masses()),
                          "ball_damping": list(scene.node_2.ball_dampings()), "race_radius": scene.node_2.race_radius,
                          "node_shape": scene.node_2.node_shape}}
    path = tmp_path / "two_nodes.toml"
    path.write_text(to_toml(_lists(mapping), "two balancer nodes"))
    out = tmp_path / "gen"
    assert main(["regenerate", "--scene", str(path), "--out", str(out), "--targets", "numba", "c", "--quiet"]) == 0
    model = load_model(next(p for p in out.iterdir() if p.is_dir() and p.name.startswith("scene_flexible")))
    assert model.name == "scene_flexible_k4_n5"
    rng = np.random.default_rng(3)
    system = for_scene(scene).system()
    y = np.concatenate([rng.normal(0, 1e-2, 4), rng.uniform(-3, 3, 5), rng.normal(0, 0.1, 4), rng.normal(0, 1, 5)])
    reference = NumericFirstOrder(system)(0.3, y)
    assert list(model.state_names) == list(system.state_names)
    generated = np.asarray(model.module.rhs(0.3, y, model.params({})))
    assert np.max(np.abs(generated - reference)) <= 1e-10 * np.max(np.abs(reference))
    sim = simulate(model, model.params({}), {"phi_1": 1.0, "phi_4": -1.0}, t_end=5.0)
    assert sim.status == "success" and np.isfinite(sim.r_max)
