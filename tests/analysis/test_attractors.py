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
