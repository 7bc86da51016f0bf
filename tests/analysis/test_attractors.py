"""The attractor classifier (adbgen/analysis/attractors.py): its band test for limit cycles."""

from __future__ import annotations


def test_a_limit_cycle_is_one_whatever_engine_integrates_on():
    """Fig. 5.4(b)'s end state (n = 2, (5.1), phi(0) = (pi/4, -pi/4), t = 3000) is on the stable cycle
    (period 6.2105, `adbgen orbit`): every engine's continuation labels it so.  The band test had read r
    at the engine's step points only, and the auto engine's long Taylor steps put the band over its 1 %
    ("unsettled")."""
    import math

    from adbgen.analysis.attractors import classifier
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.results import SUCCESS
    from adbgen.analysis.simulate import simulate

    m = load_model("thesis_rotating_n2")
    p = m.params()
    end = simulate(m, p, m.state({"phi_1": math.pi / 4, "phi_2": -math.pi / 4}), t_end=3000.0, rtol=1e-10,
                   atol=1e-12, engine="cyrk-dop853", keep_trajectory=False).y_end
    clf = classifier(m, p)
    for engine in ("auto", "taylor", "cyrk-dop853", "rk-dop853"):
        assert clf.label(SUCCESS, end, -1, engine=engine, rtol=1e-12, atol=1e-14) == "limit cycle", engine


def _launch_n3(k: int = 2, t_end: float = 3000.0):
    """Fig. 5.11's n = 3 launch k of 100 (balls equidistant, released at phi' = -Omega), (5.1), rtol 1e-10."""
    import math

    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate

    m = load_model("thesis_rotating_n3")
    phi = 2 * math.pi * k / 100
    y0 = m.state({"phi_1": phi, "phi_2": phi + 2 * math.pi / 3, "phi_3": phi - 2 * math.pi / 3,
                  "phi_1_dot": -4.0, "phi_2_dot": -4.0, "phi_3_dot": -4.0})
    sim = simulate(m, m.params(), y0, t_end=t_end, rtol=1e-10, atol=1e-12, engine="cyrk-dop853")
    return m, sim


def test_a_slow_balanced_run_is_decided_by_its_exponential_approach_and_never_balanced_above_the_criterion():
    """Launch 2 of Fig. 5.11 (n = 3) ends at t = 3000 with r ~ 5e-5, 1.3e-3 rad from a stable member of the
    balanced family: the direct tests name nothing (it was "unsettled"); carried on to 6000, r decays
    exponentially at the family member's slowest rate (its spectrum's abscissa, -2.1e-3): balanced 1.
    Negative control: with a balanced criterion below the r it reaches, the same run is undecided (r decays
    but is above the criterion), never balanced."""
    import pytest

    from adbgen.analysis import attractors

    m, sim = _launch_n3()
    clf = attractors.classifier(m, m.params())
    assert clf._named(sim.y_end) is None and clf._oscillation(sim.y_end, "cyrk-dop853", 1e-10, 1e-12) == ""
    out = clf.decide(sim.status, sim.y_end, -1, engine="cyrk-dop853", rtol=1e-10, atol=1e-12, t=3000.0,
                     threshold=1e-3)
    assert (out.label, out.approach, out.reason, out.t_decided) == ("balanced 1", "exponential", "", 6000.0)
    assert out.tail.rate == pytest.approx(-2.1e-3, rel=0.05) and out.windings == (0, 0, 0)
    assert out.to_json()["approach"] == "exponential" and out.to_json()["undecided_reason"] is None
    strict = clf.decide(sim.status, sim.y_end, -1, engine="cyrk-dop853", rtol=1e-10, atol=1e-12, t=3000.0,
                        threshold=1e-12)
    # Newton names the carried-on end (balanced): the direct name stands, whatever the criterion
    assert strict.label == "balanced 1"
    clf_named = clf._named
    try:  # plant: no direct name at the cap either, so only the criterion can call it balanced
        clf._named = lambda y: None
        strict = clf.decide(sim.status, sim.y_end, -1, engine="cyrk-dop853", rtol=1e-10, atol=1e-12, t=3000.0,
                            threshold=1e-12)
        loose = clf.decide(sim.status, sim.y_end, -1, engine="cyrk-dop853", rtol=1e-10, atol=1e-12, t=3000.0,
                           threshold=1e-3)
    finally:
        clf._named = clf_named
    assert strict.label == "undecided" and strict.reason_code == 1 and "criterion r < 1e-12" in strict.reason
    assert loose.label == "balanced 1" and loose.approach == "exponential"


def test_a_drifting_run_is_undecided_and_a_lapping_one_desynchronised(monkeypatch):
    """Planted carried-on runs (the integration replaced): r growing slowly with the balls still is undecided
    ("still drifting"), never balanced; r wandering with a ball lapping is desynchronised, with its windings."""
    import math
    from types import SimpleNamespace

    import numpy as np

    from adbgen.analysis import attractors, simulate as simulate_module
    from adbgen.analysis.loading import load_model

    m = load_model("thesis_rotating_n3")
    clf = attractors.classifier(m, m.params())
    ix, iy, ixd, iyd = m.amplitude_indices
    angles = attractors.balls(m)
    t = np.linspace(0.0, 3000.0, 30_001)

    def planted(amplitude, d_amplitude, lap):
        def fake(model, p, y0, *, t_end, **kw):
            y = np.zeros((m.n_states, t.size))
            a, da = amplitude(t), d_amplitude(t)
            y[ix], y[iy] = a * np.cos(4 * t), a * np.sin(4 * t)
            y[ixd] = da * np.cos(4 * t) - 4 * a * np.sin(4 * t)
            y[iyd] = da * np.sin(4 * t) + 4 * a * np.cos(4 * t)
            for k, b in enumerate(angles):
                y[b] = (0.3, 1.7, 4.0)[k] + (lap * t if k == 0 else 0.0)
                y[m.rate_index(b)] = lap if k == 0 else 0.0
            return SimpleNamespace(ok=True, status="success", t=t, y=y, y_end=y[:, -1])
        return fake

    monkeypatch.setattr(attractors.Classifier, "_named", lambda self, y: None)
    monkeypatch.setattr(simulate_module, "simulate", planted(lambda s: 1e-4 * np.sqrt(1 + s / 3000),
                                                             lambda s: 1e-4 * 0.5 / (3000 * np.sqrt(1 + s / 3000)), 0.0))
    drift = clf._carry_on(np.zeros(m.n_states), 3000.0, None, 1e-10, 1e-12, 1e-3)
    assert drift.label == "undecided" and drift.reason_code == 2 and "still drifting" in drift.reason
    assert drift.label not in attractors.balanced_labels(m)
    wander = (lambda s: 0.1 * (1 + 0.3 * np.sin(2 * math.pi * s / 700)),
              lambda s: 0.03 * 2 * math.pi / 700 * np.cos(2 * math.pi * s / 700))
    monkeypatch.setattr(simulate_module, "simulate", planted(*wander, -0.01))
    lapping = clf._carry_on(np.zeros(m.n_states), 3000.0, None, 1e-10, 1e-12, 1e-3)
    assert lapping.label == "desynchronised" and lapping.windings == (-4, 0, 0)
    monkeypatch.setattr(simulate_module, "simulate", planted(*wander, 0.0))  # the same r, no ball lapping
    assert clf._carry_on(np.zeros(m.n_states), 3000.0, None, 1e-10, 1e-12, 1e-3).label == "undecided"
