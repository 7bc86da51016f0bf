"""hybrid_driver.c decides the balls at rest at the start (and the balls that switch together) from one state,
`decide_set`: the outcome depends neither on the order of the balls nor on the modes the caller's parameters
give a ball at rest (hybrid.py: "the parameters' values given for stuck_k and slip_dir_k are ignored").

Why the order can matter: the braked free rotor of test_hybrid_engine.py (two equal balls half a turn apart,
torque tau0 < 0) holds both balls while |psi''| <= mu_s psi'^2, with psi'' = tau0 / (I_z + 2 m R^2) when both
are stuck.  Ball 1's required force m R psi'' depends on ball 2's mode: with ball 2 slipping backwards its
friction brakes the race further and ball 1 no longer has its inertia, so |psi''| is larger.  Started just
above the release speed W, both stuck is consistent (both margins >= 0), but ball 1 decided against ball 2's
*given* mode slip- is released, and ball 2 then decided against ball 1's slip+ is released too: both slip where
both stuck holds, chosen by the order and by a parameter value the docstring says is ignored.
Before `decide_set` four of the five given sets below failed so ({1: slip+, 2: slip+}); the premise is checked too.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines import hybrid
from stick_slip_scene import I_Z, MASS, MU_S, R, TAU0, braked_model


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    return braked_model(tmp_path_factory)


def _start(model, margin=1e-3):
    """Both balls at rest on the race, half a turn apart, the rotor at (1 + margin) W: just above release."""
    W = math.sqrt(abs(TAU0 / (I_Z + 2 * MASS * R**2)) / MU_S)
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_2")] = math.pi
    y0[model.rate_index(model.index("psi"))] = (1 + margin) * W
    return y0


def _given(model, modes):
    """The parameters with the modes `modes` = {ball: (stuck, slip_dir)} written in (what the caller gives)."""
    p = np.array(model.params(), dtype=float)
    for ball, (stuck, direction) in modes.items():
        p[model.param_names.index(f"stuck_{ball}")] = stuck
        p[model.param_names.index(f"slip_dir_{ball}")] = direction
    return p


def _start_modes(model, p):
    run = hybrid.run(model, p, _start(model), 0.0, 1e-3, rtol=1e-10, atol=1e-12)
    return {b: m for t, b, m in run.events if t == 0.0}


def test_the_start_is_in_the_band_where_ball_2s_mode_decides_ball_1s(model):
    """The premise: ball 1's stick margin is >= 0 with ball 2 stuck, < 0 with ball 2 slipping backwards."""
    y0 = _start(model)
    both = hybrid.measure(model, "stick_margin_1", 0.0, y0, _given(model, {1: (1, 0), 2: (1, 0)}))
    other_slips = hybrid.measure(model, "stick_margin_1", 0.0, y0, _given(model, {1: (1, 0), 2: (0, -1)}))
    assert both >= 0.0 > other_slips, (both, other_slips)


@pytest.mark.parametrize("given", [{1: (1, 0), 2: (1, 0)}, {1: (1, 0), 2: (0, -1)}, {1: (0, 1), 2: (0, -1)},
                                   {1: (0, -1), 2: (0, 1)}, {1: (1, 0), 2: (0, 1)}])
def test_the_start_modes_ignore_the_given_modes(model, given):
    """Every given set of modes gives the consistent one: both stuck (both margins >= 0 there)."""
    assert _start_modes(model, _given(model, given)) == {1: "stick", 2: "stick"}


def test_a_start_below_release_releases_both_balls_together(model):
    """Negative control of the decision itself: below W no ball can be held, and both slip forward, whatever
    is given (a decide_set that kept every ball stuck would fail here)."""
    y0 = _start(model, margin=-1e-3)
    for given in ({1: (1, 0), 2: (1, 0)}, {1: (1, 0), 2: (0, -1)}):
        run = hybrid.run(model, _given(model, given), y0, 0.0, 1e-3, rtol=1e-10, atol=1e-12)
        assert {b: m for t, b, m in run.events if t == 0.0} == {1: "slip+", 2: "slip+"}, run.events


def test_the_driver_entry_refuses_a_wrong_argument(model):
    """adb_hybrid_run is typed (hybrid.RUN_ARGTYPES): a float where the driver takes the state's pointer is refused
    by ctypes, not read as an address; the run above passes the same 28 arguments, typed."""
    import ctypes

    lib = hybrid.library(model)
    assert len(lib.adb_hybrid_run.argtypes) == 28
    with pytest.raises(ctypes.ArgumentError):
        lib.adb_hybrid_run(1.0, *([None] * 27))
