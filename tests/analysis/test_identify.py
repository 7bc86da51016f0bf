"""Which labelled steady state a state is, and a start on the wrong state refused (issue 34 item 4,
adbgen/analysis/identify.py; the ties re-solving the state: orbits/equilibrium.carried_start)."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis import identify, steady
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.orbits.equilibrium import carried_start, homotopy
from adbgen.analysis.orbits.parameters import ParameterMap

# paper Fig. 14(a)'s set-up (docs/orbits.md): eps/R = chi, m/M = eps/R + chi, c_b/m = 0.01, beta = 1
TIES = ["chi=epsilon/R_t", "m_2=M*2*epsilon/R_t", "m_3=m_2", "m_4=m_2", "m_1=m_2", "c_bt=0.01*m_2", "c_bb=c_bt"]


@pytest.mark.parametrize("name", ["thesis_rotating_n2", "thesis_rotating_n3"])
def test_every_closed_form_is_told_as_itself_and_a_displaced_state_as_none(name):
    m = load_model(name)
    p = m.params()
    for label in m.steady_states:
        y = m.steady_state(label, p)
        assert identify.identify(m, steady.newton(m, p, y)[0], p).label == label
        moved = y.copy()
        moved[m.index("x")] += 1e-4  # negative control: the rotor displaced
        if identify.rotor_size(m, y) == 0.0:
            assert identify.identify(m, moved, p).label is None
        else:
            assert identify.identify(m, moved, p).label != label
    assert identify.default_label(m) == "1"


def test_the_balanced_state_is_told_where_its_closed_form_is_not_given():
    """two_plane_rotating's B has a closed form only for chi = 0; under a couple imbalance it is still the state
    with the rotor at rest."""
    m = load_model("two_plane_rotating")
    p = m.params({"chi": 1e-3})
    assert m.steady_state("B", p) is None
    y, _ = steady.newton(m, p, m.module.START)
    found = identify.identify(m, y, p)
    assert found.label == "B" and found.how.startswith("rotor at rest") and found.rotor < 1e-15


def test_ties_re_solve_the_state_and_a_start_on_another_state_is_refused():
    """The documented eps = 5e-5 command: a straight homotopy from START to the tied parameters lands on an
    off-centre state (x = 2.8e-5): refused in one line naming it; carried along the ties, START stays B."""
    m = load_model("two_plane_rotating")
    base = m.params({"Omega": 4.0, "beta": 1.0, "epsilon": 5e-5})
    pmap = ParameterMap(m, base, ["Omega"], ties=TIES)
    p = pmap([4.0])
    straight = homotopy(m, np.array(m.module.START, float), m.module.START_PARAMETERS, p)
    off = identify.identify(m, straight, p)
    assert off.label is None and 1e-5 < abs(straight[m.index("x")]) < 1e-4
    with pytest.raises(AnalysisError) as err:
        identify.check(m, straight, p, "B")
    assert "is not state B" in str(err.value) and "none of the labelled ones" in str(err.value)
    assert "\n" not in str(err.value)
    carried = carried_start(m, p, pmap)
    assert identify.check(m, carried, p, "B").label == "B"
    assert np.max(np.abs(steady.residual(m, carried, p))) < 1e-12
