"""Continuation on the generated code: the stability window of the balanced state (thesis ch. 4),
Hopf points against an independent eigenvalue crossing, folds against the closed-form critical
speeds (3.16), and the stable intervals."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from adbgen.analysis import continuation, steady
from adbgen.analysis.starts import labelled_state
from adbgen.analysis.loading import AnalysisError

from analysis_helpers import CH4


def _leading(m, omega):
    """Largest real part of the transverse spectrum of START at Omega (START is a steady state for every
    Omega: (3.6) does not involve Omega), and the imaginary part of that eigenvalue."""
    p = m.params({"Omega": omega, **CH4})
    y = np.array(m.module.START)
    ev = steady.transverse_spectrum(steady.jacobian(m, y, p), steady.balanced_family_tangent(m, y))
    z = ev[np.argmax(ev.real)]
    return z.real, abs(z.imag)


def test_n2_stability_window_and_hopf_points(balanced_scan, thesis):
    """n = 2: loses stability at H1 going down, regains it in the window H2 > Omega > H3 (Fig. 4.2(a))."""
    s = balanced_scan(2)
    hopf = [b for b in s.points if b.kind == "hopf"]
    assert [b.kind for b in s.points] == ["hopf"] * 3 and not s.branch_points
    assert [b.direction for b in hopf] == ["destabilising", "stabilising", "destabilising"]
    values = [b.value for b in hopf]
    assert values == pytest.approx([1.8822393, 1.0936343, 1.0296942], abs=1e-7)
    # independently: the leading eigenvalue's real part changes sign there (brentq on a fixed grid)
    m = thesis[2]
    for b in hopf:
        root = brentq(lambda w: _leading(m, w)[0], b.value - 1e-3, b.value + 1e-3, xtol=1e-14)
        assert abs(root - b.value) < 1e-9
        assert b.frequency == pytest.approx(_leading(m, root)[1], rel=1e-7)
    # flattened: pytest >= 9.2 refuses approx over nested sequences
    assert len(s.stable_intervals) == 2
    assert [v for iv in s.stable_intervals for v in iv] == pytest.approx([values[2], values[1], values[0], 4.0], abs=1e-12)
    assert s.end_reason == "left the range"


@pytest.mark.parametrize("n, count", [(3, 3), (4, 3)])
def test_n3_n4_hopf_points_and_stable_intervals(balanced_scan, thesis, n, count):
    s = balanced_scan(n)
    hopf = [b for b in s.points if b.kind == "hopf"]
    assert len(hopf) == count
    m = thesis[n]
    for b in hopf:  # a pair on the imaginary axis at the frequency reported (not always the leading pair)
        p = m.params({"Omega": b.value, **CH4})
        y = np.array(m.module.START)
        ev = steady.transverse_spectrum(steady.jacobian(m, y, p), steady.balanced_family_tangent(m, y))
        near = ev[np.argsort(np.abs(ev.real))[:2]]
        assert np.all(np.abs(near.real) < 1e-10) and np.allclose(np.abs(near.imag), b.frequency, rtol=1e-9)
        assert abs(b.n_unstable_after - b.n_unstable_before) == 2
    first = hopf[0]
    assert first.direction == "destabilising" and first.n_unstable_before == 0
    assert s.stable_intervals[-1] == pytest.approx((first.value, 4.0))
    if n == 3:  # stable only beyond H1 (Fig. 4.6(a)); the README's 1.87537
        assert first.value == pytest.approx(1.87537, abs=1e-5) and len(s.stable_intervals) == 1
    else:  # n = 4: a window below H1 as for n = 2 (Fig. 4.11(a))
        assert len(s.stable_intervals) == 2


def test_coincident_state_folds_at_the_critical_speeds(thesis):
    """n = 2, state 2- from Omega = 0.5 upwards: the saddle-node at Omega_c1 of (3.16)."""
    from adbgen.families.single_plane.steady_states import critical_speeds

    m = thesis[2]
    p = m.params({"Omega": 0.5, **CH4})
    s = continuation.scan(m, p, labelled_state(m, "2-", p), "Omega", 0.5, 1.5)
    folds = [b for b in s.points if b.kind == "fold"]
    assert len(folds) == 1 and folds[0].frequency is None
    expected = critical_speeds(2, 2, CH4["mu"], CH4["zeta"], CH4["delta"])[0]
    assert abs(folds[0].value - expected) < 1e-9, (folds[0].value, expected)
    assert folds[0].direction == "destabilising"  # 2- (stable) turns into 2+ (unstable) at the fold
    # located on the tangent (d Omega/ds = 0); there a real eigenvalue of the spectrum is zero
    q = m.params({"Omega": folds[0].value, **CH4})
    ev = steady.transverse_spectrum(steady.jacobian(m, folds[0].y, q), np.zeros((m.n_states, 0)))
    assert np.min(np.abs(ev)) < 1e-7 and abs(ev[np.argmin(np.abs(ev))].imag) == 0
    assert s.stable_intervals == [pytest.approx((0.5, folds[0].value))]


def test_bad_scans(thesis):
    m = thesis[2]
    with pytest.raises(AnalysisError, match="not a parameter"):
        continuation.scan(m, m.params(), m.module.START, "Omega_x", 4.0, 3.0)
    with pytest.raises(AnalysisError, match="empty scan range"):
        continuation.scan(m, m.params(), m.module.START, "Omega", 4.0, 4.0)


def test_a_change_that_root_finding_cannot_locate_is_reported_with_its_step(thesis, monkeypatch):
    """If brentq fails (no sign change on the chord), the point is still reported, with the step
    [a, b] it lies in as `bracket`, never dropped and never a traceback."""
    m = thesis[2]

    def fail(*args, **kwargs):
        raise ValueError("f(a) and f(b) must have different signs")
    from adbgen.analysis.orbits import continuer

    monkeypatch.setattr(continuer, "brentq", fail)
    s = continuation.scan(m, m.params({"Omega": 2.0, **CH4}), m.module.START, "Omega", 2.0, 1.8)
    (hopf,) = s.points
    lo, hi = sorted(hopf.bracket)
    assert hopf.kind == "hopf" and lo <= 1.8822393 <= hi and hi - lo <= 0.011
    assert s.to_json()["points"][0]["bracket"] == list(hopf.bracket)


def test_a_located_zero_that_changes_no_stability_is_no_point():
    """The continuer's "real" test changes sign at the turn of the balanced branch at mu_c (PF1,2) without the
    unstable count changing: the scan lists the fold only, as before; a real zero that changes the count is a
    branch point (the control)."""
    from types import SimpleNamespace

    from adbgen.analysis.continuation import BranchPoint, _bifurcations
    from adbgen.analysis.orbits.continuer import Special

    def pt(lam, unstable, turn=1.0):
        return BranchPoint(lam, np.array([lam]), np.array([0.0, turn]), np.array([-1.0]), unstable, "")

    def special(name, lam, i):
        return Special(name, np.array([lam, lam]), None, {"kind": {"real": "branch"}.get(name, name)}, i)
    branch = [pt(0.0, 0), pt(1.0, 0), pt(2.0, 1)]
    run = SimpleNamespace(specials=[special("real", 0.5, 0), special("real", 1.5, 1)])
    (found,) = _bifurcations(branch, run, 0.0, 2.0)
    assert found[0] == 1 and found[1].kind == "branch" and found[1].value == 1.5
    assert found[1].direction == "destabilising" and found[1].bracket is None
