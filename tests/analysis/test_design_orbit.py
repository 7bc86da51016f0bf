"""The design of a forced model (issue 39, analysis/design_orbit.py): the balancing orbit of a rotor in the fixed
frame, checked over one period, its Floquet margin in decay-rate units.  On an isotropic rotor the forced model's
design equals the rotating-frame model's (Floquet-Lyapunov: mu = exp(lambda T)); negative controls: a speed range
containing the stability boundary, an imbalance above the capacity, a state that is not an orbit, an anisotropic
rotor, the balancing family's multipliers 1 left in."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.design import Axis, Problem, assess, capacity, solve
from adbgen.analysis.design_orbit import balancing_orbit, family_tangent
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.windows import SolveFailed

# paper B (two_plane_rotating) at the defaults (c_b = 3e-5) loses stability below Omega ~ 2.9 by a complex pair
# (tests/analysis/test_design.py); eps = 0.001 as there
EPS = 0.001


@pytest.fixture(scope="module")
def rot():
    return load_model("two_plane_rotating")


@pytest.fixture(scope="module")
def fixed():
    return load_model("two_plane_fixed")


def isotropic(rot, fixed, **extra):
    """The fixed-frame parameters of the rotating model's rotor (k_1X = k_1Y = k_1, ...), and the rotating ones."""
    pr = rot.params({"epsilon": EPS, **extra})
    values = dict(zip(rot.param_names, map(float, pr)))
    for k in ("k_1", "k_2", "c_1", "c_2"):
        values[k + "X"] = values[k + "Y"] = values[k]
    return fixed.params({n: values[n] for n in fixed.param_names if n in values}), pr


def test_the_isotropic_forced_design_is_the_rotating_frames(rot, fixed):
    pf, pr = isotropic(rot, fixed)
    # Floquet-Lyapunov at one design: the orbit's log max|mu| / T is B's leading real part
    at = {"Omega": 3.5}
    vf = assess(Problem(fixed, pf, [Axis("Omega", 3.5, 3.5)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"}),
                [3e-5])
    vr = assess(Problem(rot, pr, [Axis("Omega", 3.5, 3.5)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"}),
                [3e-5])
    assert vf.feasible and vr.feasible and vf.worst == vr.worst == {**at, "epsilon": EPS}
    assert vf.margin == pytest.approx(vr.margin, abs=1e-9) and vf.margin_uncertainty < 1e-9
    assert vf.period == pytest.approx(2 * math.pi / 3.5) and math.isnan(vr.period)
    # the feasible speed interval, the speed varied: the same to the design's resolution (both ends located by
    # Brent's method on margins that agree to the integration's accuracy)
    df = solve(Problem(fixed, pf, [], [Axis("Omega", 2.6, 4.0)]))
    dr = solve(Problem(rot, pr, [], [Axis("Omega", 2.6, 4.0)]))
    (a, b), = df.feasible_intervals
    (c, d), = dr.feasible_intervals
    assert b == d == 4.0 and 2.6 < c < 3.2
    assert abs(a - c) <= 1e-6 * df.resolution["Omega"]
    assert [x.kind for x in dr.boundaries] == ["Hopf"] and [x.kind for x in df.boundaries] == ["torus"]
    # negative control: an anisotropic rotor (k_1Y = 2 k_1X) is another problem: its boundary is elsewhere
    aniso = pf.copy()
    aniso[fixed.param_names.index("k_1Y")] *= 2.0
    aniso[fixed.param_names.index("k_2Y")] *= 2.0
    (e, _), = solve(Problem(fixed, aniso, [], [Axis("Omega", 2.6, 4.0)])).feasible_intervals
    assert abs(e - c) > 10 * df.resolution["Omega"]


def test_a_speed_range_containing_the_boundary_is_infeasible(rot, fixed):
    pf, _ = isotropic(rot, fixed)
    inside = Problem(fixed, pf, [Axis("Omega", 2.6, 4.0)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"})
    v = assess(inside, [3e-5])
    assert v.exists and not v.feasible and v.unstable_at and v.margin > 0 and v.crossing == "torus"
    above = Problem(fixed, pf, [Axis("Omega", 3.2, 4.0)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"})
    w = assess(above, [3e-5])  # the control: the range above it
    assert w.feasible and w.margin < -w.margin_uncertainty and not w.unstable_at


def test_an_imbalance_above_the_capacity_is_infeasible(fixed):
    # paper: B exists for M eps <= 4 m R, eps <= 0.012 at m = 0.003, R = 1, M = 1 (the fixed frame's closed form)
    base = fixed.params()
    over = Problem(fixed, base, [Axis("Omega", 3.5, 3.5), Axis("epsilon", 0.0, 0.02)], [Axis("m_1", 0.001, 0.01)],
                   ties={"m_2": "m_1", "m_3": "m_1", "m_4": "m_1"})
    assert capacity(over, [0.003]) == pytest.approx(0.012, rel=1e-10)
    v = assess(over, [0.003])
    assert not v.exists and not v.feasible
    under = Problem(fixed, base, [Axis("Omega", 3.5, 3.5), Axis("epsilon", 0.0, 0.01)], [Axis("m_1", 0.001, 0.01)],
                    ties={"m_2": "m_1", "m_3": "m_1", "m_4": "m_1"})
    assert assess(under, [0.003]).exists  # the control


def test_a_state_that_is_not_an_orbit_is_refused(fixed):
    p = fixed.params({"Omega": 3.5})
    y = fixed.steady_state("B", p)
    assert balancing_orbit(fixed, p, y).residual < 1e-12
    moved = y.copy()
    moved[fixed.index("alpha_1")] += 0.1  # negative control: a ball off its balancing angle
    with pytest.raises(SolveFailed, match="not an orbit"):
        balancing_orbit(fixed, p, moved)


def test_the_balancing_familys_multipliers_are_removed():
    # three balls in one plane: the balanced states (thesis (3.6)) are a one-parameter family at fixed parameters,
    # so the monodromy matrix has a multiplier 1 along it; two balls: isolated
    n3, n2 = load_model("single_plane_fixed_n3"), load_model("single_plane_fixed_n2")
    for model, k in ((n3, 1), (n2, 0)):
        p = model.params({"g": 0.0, "eps": 0.0005})
        o = balancing_orbit(model, p, model.steady_state("1", p))
        assert o.trivial == k and len(o.multipliers) == model.n_states - k
        if k:
            assert o.trivial_error < 1e-8
    # negative control: without the removal the leading multiplier is the family's 1 (margin 0: never feasible)
    p = n3.params({"g": 0.0, "eps": 0.0005})
    o = balancing_orbit(n3, p, n3.steady_state("1", p))
    assert o.stable
    y = n3.steady_state("1", p)
    V = family_tangent(n3, y, p, o.period)
    from adbgen.analysis.orbits.flow import Flow

    _, Phi, _ = Flow(n3).arcs(y, 0.0, o.period, p, phi=True)
    full = np.abs(np.linalg.eigvals(Phi[0]))
    assert abs(np.max(full) - 1.0) < 1e-8 and np.allclose(Phi[0] @ V, V, atol=1e-8)


def test_gravity_has_no_closed_form_and_is_refused():
    n2 = load_model("single_plane_fixed_n2")
    with pytest.raises(AnalysisError, match="no closed-form balancing state at these parameters"):
        Problem(n2, n2.params(), [Axis("omega", 300.0, 500.0)], [Axis("D", 1e-5, 1e-3)])
    Problem(n2, n2.params({"g": 0.0}), [Axis("omega", 300.0, 500.0)], [Axis("D", 1e-5, 1e-3)])  # the control
