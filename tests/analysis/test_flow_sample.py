"""Flow.sample (the variational driver's CyRK t_eval on its dense output): how densely a trajectory is sampled
must not change it, and it must agree with `simulate` (issue: thesis n = 4 past H1 reported lapping balls at
one sampling and a slow drift at another; the cause was the start, not the sampler: see below)."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.loading import load_model
from adbgen.analysis.orbits.flow import Flow
from adbgen.analysis.simulate import simulate

from analysis_helpers import CH4

T_END = 300.0
RTOL, ATOL = 1e-11, 1e-12


@pytest.fixture(scope="module")
def case():
    m = load_model("thesis_rotating_n4")
    p = m.params({"Omega": 2.1666, **CH4})
    # a generic start: no two balls at the same angle (see the last test for why that matters)
    y = m.state({"x": 1e-3, "phi_1": 0.45, "phi_2": -0.45, "phi_3": 3.0, "phi_4": 3.3})
    return m, p, y


def _bound(a, b):
    """Tolerance-scaled: a few hundred times (rtol |y| + atol), the error control's per-step scale summed."""
    return 300 * (RTOL * np.maximum(np.abs(a), np.abs(b)) + ATOL)


def test_sampling_density_does_not_change_the_trajectory(case):
    m, p, y = case
    flow = Flow(m, rtol=RTOL, atol=ATOL)
    coarse = flow.sample(y, 0.0, np.linspace(T_END / 20, T_END, 20), p)
    fine = flow.sample(y, 0.0, np.linspace(T_END / 2000, T_END, 2000), p)
    common = fine[99::100]  # the fine grid's times that are the coarse grid's
    assert np.all(np.abs(common - coarse) <= _bound(common, coarse))
    # the end agrees with an arc's end (t_eval at the end alone) and with simulate on the same solver
    assert np.all(np.abs(flow.end(y, 0.0, T_END, p) - coarse[-1]) <= _bound(coarse[-1], coarse[-1]))
    sim = simulate(m, p, y, t_end=T_END, rtol=RTOL, atol=ATOL, engine="cyrk-dop853", check=False,
                   keep_trajectory=False)
    assert np.all(np.abs(sim.y_end - coarse[-1]) <= _bound(sim.y_end, coarse[-1]))
    # negative control: the fine samples one step off the coarse times are caught
    shifted = fine[98::100]
    assert not np.all(np.abs(shifted - coarse) <= _bound(shifted, coarse))


def test_sampled_trajectory_agrees_with_a_tighter_simulation(case):
    """Against a different engine setting (DOP853 at rtol 1e-13): agreement to the looser tolerance's scale."""
    m, p, y = case
    t = np.linspace(T_END / 20, T_END, 20)
    s = Flow(m, rtol=RTOL, atol=ATOL).sample(y, 0.0, t, p)
    sim = simulate(m, p, y, t_end=T_END, rtol=1e-13, atol=1e-14, engine="cyrk-dop853", check=False,
                   keep_trajectory=False)
    err = np.max(np.abs(sim.y_end - s[-1]) / (1e-8 * np.abs(s[-1]) + 1e-8))
    assert err <= 1.0
    # negative control: a start moved by 1e-6 in x is caught
    moved = Flow(m, rtol=RTOL, atol=ATOL).end(y + 1e-6 * np.eye(len(y))[0], 0.0, T_END, p)
    assert np.max(np.abs(sim.y_end - moved) / (1e-8 * np.abs(moved) + 1e-8)) > 1.0


def test_coincident_balls_are_an_unstable_invariant_set(case):
    """Why the reported disagreement happened: drift_past_h1's start has two balls at the same angle
    (phi_3 = phi_4 = pi).  phi_3 = phi_4 is invariant but unstable: an exactly symmetric start stays on it in
    floating point at some tolerances and leaves it by round-off at others, so such a start's long-run answer
    is decided by round-off.  A 1e-9 split grows by orders of magnitude within T_END."""
    m, p, _ = case
    i3, i4 = m.state_names.index("phi_3"), m.state_names.index("phi_4")
    base = {"x": 1e-3, "phi_1": 0.45, "phi_2": -0.45, "phi_3": np.pi, "phi_4": np.pi}
    flow = Flow(m, rtol=RTOL, atol=ATOL)
    on = flow.end(m.state(base), 0.0, T_END, p)
    assert on[i3] == on[i4]  # exactly symmetric start: stays on the set (the rhs is symmetric in the balls)
    split = flow.end(m.state({**base, "phi_4": np.pi + 1e-9}), 0.0, T_END, p)
    assert abs(split[i3] - split[i4]) > 1e-6  # grown by > 1e3
