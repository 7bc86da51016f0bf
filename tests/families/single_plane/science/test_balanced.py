"""The n = 3 balanced family (3.6) as a whole (issue 36): at zeta = 0.1 no member is linearly stable."""

import math

import numpy as np
import pytest

from adbgen.analysis import steady
from adbgen.analysis.loading import load_model
from adbgen.families.single_plane.science.balanced import family_margin, family_member


@pytest.fixture(scope="module")
def model():
    return load_model("thesis_rotating_n3")


@pytest.mark.parametrize("free", [math.pi, 0.0, 1.0, -2.5])
def test_every_member_is_a_steady_state(model, free):
    y = family_member(model, {}, free)
    assert np.max(np.abs(steady.residual(model, y, model.params({})))) < 1e-12


def test_at_zeta_0_1_no_member_is_stable(model):
    lead, _ = family_margin(model, {"zeta": 0.1})
    assert lead == pytest.approx(0.0153, abs=1e-4)
    assert family_margin(model, {"zeta": 0.03})[0] == pytest.approx(0.0017, abs=1e-4)


def test_at_zeta_0_01_members_are_stable(model):
    """Negative control: at (5.1) the family has stable members (the basin experiment balances)."""
    assert family_margin(model, {"zeta": 0.01})[0] < 0


def test_the_family_loses_its_last_stable_member_just_above_the_pi_members_limit(model):
    from adbgen.families.single_plane.science.balanced import family_zeta_limit

    limit = family_zeta_limit(model)
    assert 0.0206 < limit < 0.0216  # the phi_3 = pi member alone: 0.0206 (chapter 4)
    assert family_zeta_limit(model, 0.05, 0.1) is None  # negative control: no change in a range past it
