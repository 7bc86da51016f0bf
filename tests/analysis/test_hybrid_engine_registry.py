"""The stick-slip engine in the registry (adbgen/analysis/engines/hybrid_engine.py, engines.engine_for): a model
with stick/slip modes gets `hybrid-dop853` by default, another engine asked for it is refused in one line, and
a run says per ball whether it ended stuck and the residual imbalance r at t_end.

The model is test_hybrid_engine.py's braked-rotor scene (generated once into the scene cache,
`load_model(scene=...)`), run with its parameters changed: an unbalanced free rotor (eps = 1e-3 m, tau0 = 0)
at 100 rad/s whose balls start at rest on the race.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines import capabilities, engine_for, hybrid
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.simulate import simulate, simulate_many
from stick_slip_scene import TORQUE_SCENE

FRICTION = {"eps": 1e-3, "tau0": 0.0, "kappa": 0.0, "mu_r": 0.002, "mu_s": 0.005}
START = {"phi_1": 1.0, "phi_2": 2.5, "psi_dot": 100.0}
T_END = 10.0


@pytest.fixture(scope="module")
def stick_model(tmp_path_factory):
    path = tmp_path_factory.mktemp("stick") / "braked.toml"
    path.write_text(TORQUE_SCENE)  # the same bytes as test_hybrid_engine.py's: one cached model for both
    return load_model(scene=path)


def test_a_stick_slip_model_runs_on_the_hybrid_engine_by_default(stick_model):
    m = stick_model
    s = simulate(m, FRICTION, START, t_end=T_END)
    assert s.engine == "hybrid-dop853" and "stick-slip" in capabilities(engine_for(m, None))
    assert s.status == "success" and s.stuck == (True, True)
    ix, iy, _, _ = m.amplitude_indices
    assert s.r_end == math.hypot(s.y_end[ix], s.y_end[iy]) and 0 < s.r_end < s.r_max
    direct = hybrid.run(m, m.params(FRICTION), m.state(START), 0.0, T_END, rtol=1e-8, atol=1e-10)
    assert np.array_equal(direct.y_end, s.y_end)  # the adapter runs the engine as it is
    assert s.to_json()["stuck"] == [True, True] and s.to_json()["r_end"] == s.r_end


def test_without_friction_the_balls_do_not_end_stuck(stick_model):
    """Negative control of `stuck`: mu_r = mu_s = 0, the stiction cone is empty and the balls keep moving."""
    s = simulate(stick_model, {**FRICTION, "mu_r": 0.0, "mu_s": 0.0}, START, t_end=T_END)
    assert s.status == "success" and s.stuck == (False, False)


def test_another_engine_for_a_stick_slip_model_is_refused_in_one_line(stick_model):
    with pytest.raises(AnalysisError, match="stick/slip modes") as err:
        simulate(stick_model, FRICTION, START, t_end=1.0, engine="rk-dop853")
    assert "\n" not in str(err.value) and "hybrid-dop853" in str(err.value)
    assert simulate(stick_model, FRICTION, START, t_end=0.1, engine="hybrid-dop853").engine == "hybrid-dop853"


def test_a_batch_is_its_runs_one_by_one(stick_model):
    m = stick_model
    Y0 = np.repeat(m.state(START)[None], 2, axis=0)
    Y0[1, m.index("phi_2")] = 3.0
    ens = simulate_many(m, m.params(FRICTION), Y0, t_end=T_END)
    assert ens.engine == "hybrid-dop853" and ens.stuck.shape == (2, 2)
    for k in range(2):
        one = simulate(m, FRICTION, Y0[k], t_end=T_END, keep_trajectory=False)
        assert np.array_equal(ens.y_end[k], one.y_end) and ens.r_end[k] == one.r_end
        assert tuple(ens.stuck[k]) == one.stuck
    assert ens.r_end[0] != ens.r_end[1]  # row 1 is another start, not row 0 again


def test_a_failed_run_reports_r_max_of_what_it_reached(stick_model):
    """A run stopped by its step limit reports r_max over the part integrated, the state it stopped at included,
    as every engine does (tests/analysis/test_simulate.py); it reported NaN before."""
    m = stick_model
    s = simulate(m, FRICTION, START, t_end=T_END, max_steps=50, check=False, keep_trajectory=False)
    ix, iy, _, _ = m.amplitude_indices
    assert s.status == "max_steps" and 0 < s.t_fail < T_END and s.t_dec is None
    assert s.r_max >= math.hypot(s.y_end[ix], s.y_end[iy]) > 0
