"""A ball with no consistent stick/slip mode (hybrid_driver.c, HY_NO_MODE; issue 37): with mu_r > mu_s a ball
whose stiction breaks (margin < 0) decelerates at once in the slip it is given, so it can neither stick nor
slip; the driver sees its slip end within 64 ulp of the time it was decided, and the ball decided into slip again.  The scene refuses mu_r > mu_s per ball (single_plane.scene, tests/families/single_plane/test_scene.py);
a parameter set by hand (`--set mu_r=...`) reaches the driver, which then stops with the status
`no_consistent_mode`, said in `simulate --json`, instead of looping through events that do not advance time to
max_events (what it did before; the negative control plants that driver, HY_MODE_CHECK = 0).

The model is the braked rotor of test_hybrid_engine.py (the scene cache's), both balls stuck at 100 rad/s and
released at t = 9.0509 s, where mu_s psi'^2 falls below the deceleration."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from adbgen.analysis.engines import hybrid
from adbgen.cli import main
from stick_slip_scene import MU_S, TORQUE_SCENE, braked_model

T_END = 12.0
RELEASE = 9.0508623  # the closed form's release time (test_hybrid_engine.braked)


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    return braked_model(tmp_path_factory)


def _start(model):
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_2")] = math.pi
    y0[model.rate_index(model.index("psi"))] = 100.0
    return y0


def test_rolling_resistance_above_stiction_stops_with_its_own_status(model):
    run = hybrid.run(model, model.params({"mu_r": 1.6 * MU_S}), _start(model), 0.0, T_END)
    assert run.status == "no_consistent_mode", run.status
    assert run.t_end == pytest.approx(RELEASE, abs=1e-6) and len(run.events) <= 6, (run.t_end, run.events)


def test_at_mu_r_equal_to_mu_s_the_slip_holds(model):
    """The boundary the scene allows (mu_s >= mu_r): the slip's acceleration is 0 to rounding there, which the
    driver must not take for a missing mode."""
    for mu_r in (MU_S, 0.5 * MU_S):
        run = hybrid.run(model, model.params({"mu_r": mu_r}), _start(model), 0.0, T_END)
        assert run.status == "success" and run.modes(2) == ("slip+", "slip+"), (mu_r, run.status, run.events)


def test_without_the_check_the_driver_loops_to_max_events(model, monkeypatch):
    """Negative control: the driver without HY_MODE_CHECK spends every event at the release time."""
    checked = hybrid.library
    monkeypatch.setattr(hybrid, "library", lambda m: checked(m, ("-DHY_MODE_CHECK=0",)))
    run = hybrid.run(model, model.params({"mu_r": 1.6 * MU_S}), _start(model), 0.0, T_END, max_events=200)
    assert run.status == "max_events" and run.t_end < RELEASE + 1e-6, (run.status, run.t_end)


def _simulate(tmp_path, capsys, scene_text, *more):
    path = tmp_path / "braked.toml"
    path.write_text(scene_text)
    code = main(["simulate", "--scene", str(path), "--y0", "phi_2=pi", "--y0", "psi_dot=100", "--t-end",
                 str(T_END), "--json", "--quiet", *more])
    out, err = capsys.readouterr()
    return code, out, err


def test_simulate_json_says_the_status_and_exits_non_zero(model, tmp_path, capsys):
    code, out, err = _simulate(tmp_path, capsys, TORQUE_SCENE, "--set", f"mu_r={1.6 * MU_S}")
    assert code == 1 and json.loads(out)["status"] == "no_consistent_mode", (code, out)
    assert "neither stick nor slip" in err and err.count("\n") == 1
    code, out, _ = _simulate(tmp_path, capsys, TORQUE_SCENE)  # the scene's own mu_r < mu_s: runs
    assert code == 0 and json.loads(out)["status"] == "success"


def test_a_scene_with_mu_r_above_mu_s_is_refused_in_one_line(tmp_path, capsys):
    bad = TORQUE_SCENE.replace(f"static_friction = {MU_S}", "static_friction = 0.01")
    assert bad != TORQUE_SCENE
    code, out, err = _simulate(tmp_path, capsys, bad)
    assert code != 0 and out == "" and "static_friction" in err and "ball 1" in err and err.count("\n") == 1, err
