"""windows.certify: a planted narrow stable window is found at the stated resolution and missed without the
refinement (the negative control); a sign change of the margin that is no change of stability is not
reported; a not-computed sample splits the line instead of being read as physics."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.windows import Sample, SolveFailed, certify, margin_of, narrowest_missed

# the margin of two crossing eigenvalue branches (a pair leaving as another arrives, as B's multipliers near
# the critical speed): stable only on (C1, C2), a window of 0.01, far narrower than the grid's 0.05625
C1, C2 = 1.723, 1.733


def margin(x: float) -> float:
    return min(max(3.0 * (C1 - x), 5.0 * (x - C2)), 0.4 * (4.0 - x))  # and stable again above 4


def sample(x: float) -> Sample:
    m = margin(x)
    return Sample(float(x), m, int(m > 0), np.array([x]), np.array([m]))


def solve(x, near):
    return sample(x)


GRID = np.linspace(0.5, 5.0, 81)
RES = (GRID[1] - GRID[0]) / 8


def test_planted_window_found_at_the_stated_resolution():
    line = certify([sample(x) for x in GRID], solve, RES)
    assert not narrowest_missed([(C1, C2), (4.0, 5.0)], line.windows, RES)
    (a, b), = [w for w in line.windows if w[1] < 3]
    assert a == pytest.approx(C1, abs=1e-9) and b == pytest.approx(C2, abs=1e-9)
    assert [c.stable_below for c in line.changes] == [False, True, False]
    assert line.inserted > 0


def test_without_refinement_the_window_is_missed():
    line = certify([sample(x) for x in GRID], solve, RES, refine=False)
    assert narrowest_missed([(C1, C2)], line.windows, RES) == [(C1, C2)]


def test_a_window_narrower_than_the_resolution_is_not_claimed():
    assert narrowest_missed([(C1, C2)], [], 0.02) == []  # not certified at 0.02: not counted as missed


def test_unstable_on_both_sides_is_not_a_change():
    # the count goes 2 -> 4 across x = 1 (a pair crosses while another stays outside): the margin stays > 0
    def s(x):
        return Sample(float(x), 0.5 + 0.1 * x, 2 if x < 1 else 4)
    line = certify([s(x) for x in np.linspace(0, 2, 11)], lambda x, near: s(x), 0.01)
    assert line.changes == [] and line.windows == []
    # negative control: a margin that does cross gives a change
    line = certify([sample(x) for x in np.linspace(3.5, 4.5, 11)], solve, 0.01)
    assert [round(c.x, 9) for c in line.changes] == [4.0]


def test_spurious_root_rejected_when_both_sides_agree():
    # the stable flag flips between the samples (a count by tolerance) but the margin found at the sides does
    # not change stability: rejected, not reported
    calls = []

    def s(x):
        calls.append(x)
        return Sample(float(x), x - 0.5, int(x > 0.5) if x in (0.0, 1.0) else 1)
    line = certify([s(0.0), s(1.0)], lambda x, near: s(x), 0.01)
    assert line.changes == [] and line.rejected and line.rejected[0]["why"] == "unstable on both sides"


def test_not_computed_splits_the_line():
    def failing(x, near):
        raise SolveFailed("Newton failed")
    samples = [sample(x) for x in GRID]
    k = int(np.searchsorted(GRID, 1.7))
    samples[k] = None
    line = certify(samples, failing, RES)
    assert all(s.x != GRID[k] for s in line.samples)
    assert line.failures  # the refinement's failures are recorded, with why
    assert all("Newton failed" in why for _, why in line.failures)


def test_margin_of():
    assert margin_of(np.array([-1 + 2j, -0.5]), orbit=False) == -0.5
    assert margin_of(np.array([0.9j, 0.3]), orbit=True) == pytest.approx(-0.1)


def test_a_torus_point_of_an_unstable_orbit_is_no_change_of_stability():
    """A special point between two orbits with multipliers outside the unit circle on both sides (Fig. 11's
    1.00248 at eps = 1e-6) has stability_change false; one with a stable side (negative control) true."""
    from types import SimpleNamespace

    from adbgen.analysis.orbits.branches import _special_json

    def pt(*mu):
        return SimpleNamespace(data=SimpleNamespace(nontrivial=np.array(mu, complex)))
    sp = SimpleNamespace(data=SimpleNamespace(multipliers=np.array([1.0 + 0j]), lam=1.0, T=6.0), info={"kind": "torus"},
                         index=0)
    out = _special_json("Omega", None, sp, [pt(1.2, 0.99 + 0.01j, 0.99 - 0.01j), pt(1.2, 1.01j, -1.01j)])
    assert (out["unstable_before"], out["unstable_after"], out["stability_change"]) == (1, 3, False)
    out = _special_json("Omega", None, sp, [pt(0.9, 0.99 + 0.01j, 0.99 - 0.01j), pt(0.9, 1.01j, -1.01j)])
    assert (out["unstable_before"], out["unstable_after"], out["stability_change"]) == (0, 2, True)
