"""analysis.error_estimate (issue 35 item 1): the global error estimate at t_end of --check-tolerance.

The estimate is the run as asked against a run that truly is tighter, in tolerance units.  The planted
miss: a Taylor row of fixed order and step factor (the auto engine's rows) takes the same steps at rtol / 100,
so "the tighter run" would estimate 0 whatever the error; `reference_row` must then give a finer row, and
must not where the tighter run already aims finer (the controls).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis import error_estimate as ee
from adbgen.analysis.engines.taylor import nominal_error


def test_the_estimate_is_in_tolerance_units_and_wraps_angles():
    y_t = np.array([1.0, 0.0, -100.0])
    assert ee.estimate_ratio(y_t, y_t, 1e-8, 1e-10) == 0.0
    assert ee.estimate_ratio(y_t + [0, 1e-10, 0], y_t, 1e-8, 1e-10) == pytest.approx(1.0)
    assert ee.estimate_ratio(y_t + [0, 0, 1e-6], y_t, 1e-8, 1e-10) == pytest.approx(1e-6 / (1e-10 + 1e-6))
    # one turn apart on an angle (state 0): the same configuration when the model says state 0 is an angle
    turned = y_t + [2 * math.pi + 1e-8, 0, 0]
    assert ee.estimate_ratio(turned, y_t, 1e-8, 1e-10, angles=(0,)) == pytest.approx(1e-8 / (1e-10 + 1e-8), rel=1e-5)
    assert ee.estimate_ratio(turned, y_t, 1e-8, 1e-10) > 1e8  # negative control: not an angle, not wrapped
    rec = ee.estimate(turned, y_t, 1e-8, 1e-10, (0,), against="tighter run")
    assert rec["exceeded"] is False and rec["bound"] == ee.BOUND == 10.0 and rec["flag_above"] == 2.0
    assert ee.estimate(y_t + [0, 3e-10, 0], y_t, 1e-8, 1e-10, against="x")["exceeded"] is True  # 3 units: above 2
    rec = ee.estimate(y_t + [0, 2e-9, 0], y_t, 1e-8, 1e-10, against="tighter run")
    assert rec["exceeded"] is True and ee.reason(rec).startswith("error estimate: 20 tolerance units at t_end")


def test_a_fixed_row_gets_its_own_finer_reference_and_a_finer_tighter_run_does_not():
    row = {"engine": "taylor", "order": 20, "step_factor": 1.5}  # the auto engine's row from rtol 1e-6 down
    # planted miss: the tighter run is the same row (same steps, same end state): the estimate would be 0
    got = ee.reference_row(row, dict(row), 100.0)
    assert got is not None and got[1] == 1.0 and got[0] >= 20
    assert nominal_error(*got) <= nominal_error(20, 1.5) / 100  # truly finer, by the factor asked
    # controls: a tighter run that aims finer (factor 1 at order 20: 3300x), and an engine of another method
    assert ee.reference_row(row, {"order": 20, "step_factor": 1.0}, 100.0) is None
    assert ee.reference_row({"engine": "rk-dop853"}, {"engine": "rk-dop853"}, 100.0) is None
    assert ee.reference_row(None, None, 100.0) is None
    # heyoka's rule (the plain taylor engine): rtol 1e-8 -> order 10, its tighter run order 13: finer, kept
    assert ee.reference_row({"order": 10, "step_factor": 1.0}, {"order": 13, "step_factor": 1.0}, 100.0) is None
    # an order-18 row at factor 1.5 whose tighter run is order 18 too: a finer order is asked
    o, f = ee.reference_row({"order": 18, "step_factor": 1.5}, {"order": 18, "step_factor": 1.5}, 100.0)
    assert o > 18 and f == 1.0 and nominal_error(o, f) <= nominal_error(18, 1.5) / 100
    assert ee.reference_engine((20, 1.0)).settings(1e-8, 1e-10) == (20, 1.0)


def test_an_estimate_that_cannot_be_finer_is_not_made_and_says_so():
    """At double precision's reach (the auto engine's order-20, factor-1 row at rtol 1e-14, its tighter run
    clamped to the same rtol) no finer row exists: the estimate is not made, and the reason says so rather
    than reporting the 0 of a run against itself (the negative control: a finer row is finer)."""
    row = {"order": 20, "step_factor": 1.0}
    ref = ee.reference_row(row, dict(row), 1.0)
    assert ref == (20, 1.0) and not ee.finer(row, ref)
    assert ee.finer({"order": 20, "step_factor": 1.5}, ref) and ee.finer(None, ref)
    rec = ee.not_made("Taylor order 20, step factor 1", ref, "no finer row")
    assert rec["ratio"] is None and rec["exceeded"] is None and "not made (no finer row)" in ee.reason(rec)


def _departure(y0, lam: float, t: float):
    """The exact flow of x' = lam (x - 1), v' = -v (a departure from the equilibrium x = 1, the shape of the
    benchmark's ill-conditioned transients), evaluated in double: a 'run' whose only error is y0's rounding
    and the double arithmetic, as both the run as asked and the tighter run of a converged engine are."""
    x, v = np.asarray(y0, float)
    return np.array([1.0 + (x - 1.0) * math.exp(lam * t), v * math.exp(-t)])


def test_the_conditioning_probe_catches_a_planted_ill_conditioned_transient_the_estimate_misses():
    """Planted: x(0) = 1 + 1e-12 (not a double), lam t = 22: the rounding of x(0) to double (8.9e-17) grows
    e^22 = 3.6e9-fold, so the double result misses the exact one (mpmath, from the decimal start) by more than
    the bound while the run as asked and the tighter run agree exactly (estimate 0: the silent miss).  The
    probe must flag it; the control (lam t = -22, the same start: well-conditioned) it must not."""
    mpmath = pytest.importorskip("mpmath")
    rtol, atol, t = 1e-8, 1e-10, 1.0
    mpmath.mp.dps = 50
    for lam, ill in ((22.0, True), (-22.0, False)):
        y0 = np.array([1 + 1e-12, 0.5])
        y = _departure(y0, lam, t)  # the run as asked; the tighter run ends at the same double state
        exact = [float(1 + mpmath.mpf("1e-12") * mpmath.exp(lam * t)), float(mpmath.mpf("0.5") * mpmath.exp(-t))]
        true = ee.estimate_ratio(y, exact, rtol, atol)
        record = ee.estimate(y, _departure(y0, lam, t), rtol, atol, against="tighter run")
        assert record["ratio"] == 0.0 and record["exceeded"] is False  # the difference cannot see round-off
        probe = ee.probe_state(y0, rtol, atol)
        assert probe[0] > y0[0] and probe[1] < y0[1]  # alternating signs, every component moved
        assert np.allclose(probe, y0, rtol=2 * ee.PROBE_ULPS * np.finfo(float).eps, atol=0)
        cond = ee.conditioning(_departure(probe, lam, t), y, rtol, atol)
        got = ee.with_conditioning(record, cond)
        assert got["estimate_exceeded"] is False and got["ratio"] == 0.0 and got["conditioning"] is cond
        if ill:
            assert true > ee.BOUND  # the planted miss is real: the double run errs beyond the bound
            assert cond["ratio"] >= true / 10 and cond["exceeded"] is True and got["exceeded"] is True
            assert "conditioning probe" in ee.reason(got) and f"{cond['ratio']:.3g}" in ee.reason(got)
        else:
            assert true < 1e-3 and cond["ratio"] < 1e-3 and cond["exceeded"] is False and got["exceeded"] is False


def test_a_failed_probe_is_flagged_and_an_exceeded_estimate_is_named_first():
    record = ee.estimate([1.0], [1.0], 1e-8, 1e-10, against="tighter run")
    failed = ee.with_conditioning(record, ee.conditioning(None, [1.0], 1e-8, 1e-10, status="max_steps"))
    assert failed["conditioning"]["ratio"] is None and failed["exceeded"] is None  # not known: flagged
    assert "conditioning probe" in ee.reason(failed) and "max_steps" in ee.reason(failed)
    big = ee.estimate([1.0 + 5e-8], [1.0], 1e-8, 1e-10, against="tighter run")  # 5 units
    both = ee.with_conditioning(big, ee.conditioning([1.0], [1.0], 1e-8, 1e-10))
    assert both["exceeded"] is True and both["conditioning"]["exceeded"] is False
    assert ee.reason(both).startswith("error estimate: 4.95 tolerance units at t_end against the tighter run")


def test_the_probe_moves_identical_balls_started_together_alike_and_only_them():
    """An exchange of identical balls whose fixed set holds y0 (with p as it asks) gets a probe on that set:
    components the exchange maps onto each other move alike, one mapped onto its own negative not at all; a
    start off the set, other parameters, or another kind of symmetry leave the alternating signs as they are."""
    swap = {"kind": "identical-balls", "states": (0, 2, 1, 3), "signs": (1, 1, 1, 1), "params": (0, 1),
            "param_signs": (1, 1)}
    alternating = np.array([1.0, -1.0, 1.0, -1.0])
    together, p = np.array([0.3, 1.0, 1.0, 0.0]), np.array([2.0, 2.0])
    assert ee.symmetric_signs(alternating, together, (swap,), p).tolist() == [1.0, -1.0, -1.0, -1.0]
    probe = ee.probe_state(together, 1e-8, 1e-10, symmetries=(swap,), p=p)
    assert probe[1] == probe[2] != together[1] and probe[0] != together[0] and probe[3] != together[3]
    for y0, q, sym in ((np.array([0.3, 1.0, 1.5, 0.0]), p, swap),  # off the set
                       (together, np.array([2.0, 3.0]), {**swap, "params": (1, 0)}),  # unequal balls
                       (together, p, {**swap, "kind": "reflection"})):  # not an exchange of balls
        assert ee.symmetric_signs(alternating, y0, (sym,), q).tolist() == alternating.tolist()
    flip = {**swap, "states": (0, 1, 2, 3), "signs": (1, 1, 1, -1)}  # y[3] = -y[3] on the set: y[3] = 0
    assert ee.symmetric_signs(alternating, together, (flip,), p).tolist() == [1.0, -1.0, 1.0, 0.0]
    assert ee.probe_state(together, 1e-8, 1e-10).tolist() == (together + alternating * ee.PROBE_ULPS
                                                               * np.finfo(float).eps * (together + 1e-2)).tolist()


def test_identical_balls_started_together_are_not_a_false_alarm_of_the_probe():
    """Thesis n = 2 from rest, both balls at one angle: the engines keep them together bit for bit, so round-off
    cannot part them; the probe used to (alternating signs: phi_1 up, phi_2 down) and read 6.6e7 units at
    t = 200, flagging a run whose estimate is 4e-4.  Balls apart, the probe is as before."""
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from adbgen.analysis.tolerance import check_simulation

    model = load_model("thesis_rotating_n2")
    p = model.params()
    for y0 in ({}, {"phi_1": 1.0, "phi_2": -1.0}):  # together (from rest), and apart
        start = model.state(y0)
        sim = simulate(model, p, start, t_end=200.0, threshold=0.3, check=False)
        check = check_simulation(model, p, start, sim, t_end=200.0, threshold=0.3, estimate=True, label=False)
        cond = check.error_estimate["conditioning"]
        assert cond["exceeded"] is False and cond["ratio"] < 1.0, cond
    i, j = model.state_names.index("phi_1"), model.state_names.index("phi_2")
    moved = ee.probe_state(model.state({}), 1e-8, 1e-10, symmetries=model.symmetries, p=p)
    assert moved[i] == moved[j] != 0.0  # together, and moved
    apart = model.state({"phi_1": 1.0, "phi_2": -1.0})
    assert ee.probe_state(apart, 1e-8, 1e-10, symmetries=model.symmetries, p=p).tolist() == \
        ee.probe_state(apart, 1e-8, 1e-10).tolist()
