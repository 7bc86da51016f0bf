"""One suite for the engine registry (adbgen/analysis/engines/__init__.py: ENGINES, register, capabilities;
issue 33 item 5): every registered engine is put through every check its declared capabilities call for,
so a new engine is tested by registering it.  A toy engine registered from the test (the registry
monkeypatched) runs the whole suite, and a broken toy fails it (the negative control).

Problem A (thesis model n = 3, (5.1), phi(0) = (pi/3, -pi/3, pi)) over [0, 120] with the threshold
H = 0.02, which r crosses for the last time near t = 99.65: a located t_dec, not only a final state.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis import engines
from adbgen.analysis.engines import ENGINES, capabilities
from adbgen.analysis.loading import AnalysisError
from adbgen.analysis.simulate import simulate, simulate_many

PHI_A = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}
PI3 = {"phi_1": math.pi, "phi_2": math.pi, "phi_3": math.pi}
T_END, H, RTOL, ATOL = 120.0, 0.02, 1e-9, 1e-11


def _rel(a, b):
    return float(np.max(np.abs(np.asarray(a) - b)) / np.max(np.abs(b)))


@pytest.fixture(scope="module")
def reference(thesis):
    """Problem A by SciPy's DOP853 at rtol 1e-12 (numba rhs, another code path than the compiled engines)."""
    return simulate(thesis[3], None, PHI_A, t_end=T_END, rtol=1e-12, atol=1e-14, threshold=H,
                    engine="scipy-dop853", keep_trajectory=False)


# ------------------------------------------------------------------ the checks, by capability


def check_reaches_the_reference(name, thesis, reference):
    """Every engine: problem A's final state, r_max and t_dec (located on its continuous solution, or at
    its output points: matlab-ode45) as the tight reference gives them."""
    s = simulate(thesis[3], None, PHI_A, t_end=T_END, rtol=RTOL, atol=ATOL, threshold=H, engine=name,
                 keep_trajectory=False)
    assert s.status == "success"
    assert _rel(s.y_end, reference.y_end) < 2e-6
    assert s.r_max == pytest.approx(reference.r_max, rel=1e-6)
    assert reference.t_dec == pytest.approx(99.6504, abs=1e-3)  # the crossing is there to be located
    assert s.t_dec == pytest.approx(reference.t_dec, abs=0.01)


def check_exact_symmetry(name, thesis, reference):
    """"symmetric": balls started together stay together bit for bit, and n = 3 from (pi, pi, pi) ends at
    the coincident state 2- (thesis ch. 5: x = 0.1285, y = -0.0083, phi = 3.0772)."""
    s = simulate(thesis[3], None, PI3, t_end=2000.0, engine=name)
    angles, rates = s.y[2:5], s.y[7:10]
    assert np.array_equal(angles[0], angles[1]) and np.array_equal(angles[0], angles[2])
    assert np.array_equal(rates[0], rates[1]) and np.array_equal(rates[0], rates[2])
    assert s.y_end[0] == pytest.approx(0.1285, abs=5e-5)
    assert s.y_end[1] == pytest.approx(-0.0083, abs=5e-5)
    assert s.y_end[2] == pytest.approx(3.0772, abs=5e-5)


def check_batch_is_one_by_one(name, thesis, reference):
    """"batch": each row of run_many is the trajectory run alone (to 1e-7 of the state: a lane-group stepper
    may use vector math), with its own r_max and t_dec; at rtol 1e-7 (the check is of the batch path, not
    of the accuracy: the implicit SciPy engines take minutes at 1e-9)."""
    m = thesis[3]
    Y0 = np.repeat(m.state(PHI_A)[None], 2, axis=0)
    Y0[1, list(m.angle_indices)] += 0.2
    kw = dict(t_end=T_END, rtol=1e-7, atol=1e-9, threshold=H, engine=name)
    batch = simulate_many(m, m.params(), Y0, threads=2, **kw)
    assert list(batch.status) == ["success"] * 2
    for k in range(2):
        one = simulate(m, None, Y0[k], keep_trajectory=False, **kw)
        assert _rel(batch.y_end[k], one.y_end) < 1e-7
        assert batch.r_max[k] == pytest.approx(one.r_max, rel=1e-7)
        assert batch.t_dec[k] == pytest.approx(one.t_dec, abs=1e-3)
    assert _rel(batch.y_end[0], reference.y_end) < 2e-4  # row 0 is problem A itself
    assert batch.r_max[1] != batch.r_max[0]  # and row 1 another trajectory, not row 0 again


def check_dense_output(name, thesis, reference):
    """"dense": the state between the steps from the engine's own interpolant passes through its steps and
    agrees with a tight run's interpolant at the steps' midpoints."""
    m = thesis[3]
    s = simulate(m, None, PHI_A, t_end=10.0, rtol=RTOL, atol=ATOL, threshold=H, engine=name)
    eng = engines.engine(name)
    at_steps = np.asarray(eng.dense(m, m.params(), s.t, s.y, s.t[1:-1], RTOL, ATOL))
    at_steps = at_steps if at_steps.shape[0] == m.n_states else at_steps.T
    assert np.allclose(at_steps, s.y[:, 1:-1], rtol=0, atol=1e-12)
    mid = 0.5 * (s.t[1:] + s.t[:-1])
    got = np.asarray(eng.dense(m, m.params(), s.t, s.y, mid, RTOL, ATOL))
    got = got if got.shape[0] == m.n_states else got.T
    tight = simulate(m, None, PHI_A, t_end=10.0, rtol=1e-13, atol=1e-15, engine="cyrk-vern8")
    ref = np.asarray(ENGINES["cyrk-vern8"].dense(m, m.params(), tight.t, tight.y, mid, 1e-13, 1e-15))
    ref = ref if ref.shape[0] == m.n_states else ref.T
    assert len(mid) > 20 and float(np.max(np.abs(got - ref))) < 1e-7


def check_stick_slip_refuses_a_model_without_modes(name, thesis, reference):
    """"stick-slip": an engine that runs stick/slip modes refuses, in one line, a model that has none (the
    thesis model); its runs are checked on a stick-slip model in test_hybrid_engine_registry.py."""
    with pytest.raises(AnalysisError, match="no stick phase") as err:
        simulate(thesis[3], None, PHI_A, t_end=1.0, engine=name)
    assert "\n" not in str(err.value)


# (capability the check needs, or None: every engine; the check); a stick-slip engine runs only its own
SUITE = ((None, check_reaches_the_reference), ("symmetric", check_exact_symmetry),
         ("batch", check_batch_is_one_by_one), ("dense", check_dense_output),
         ("stick-slip", check_stick_slip_refuses_a_model_without_modes))


def _applies(need, caps) -> bool:
    if "stick-slip" in caps:  # the checks run the thesis model, which has no stick phase: refused
        return need == "stick-slip"
    return need is None or need in caps


def _cases():
    return [pytest.param(name, check, id=f"{check.__name__[len('check_'):]}[{name}]")
            for need, check in SUITE for name in sorted(ENGINES)
            if _applies(need, capabilities(ENGINES[name]))]


@pytest.mark.parametrize("name, check", _cases())
def test_registered_engine(name, check, thesis, reference):
    check(name, thesis, reference)


def test_every_engine_declares_what_it_can_do():
    """Every engine is a batch engine (sweeps need run_many) and at least one of each capability is
    registered, so that no check of the suite runs on nothing."""
    declared = {name: capabilities(e) for name, e in ENGINES.items()}
    assert all("batch" in c for c in declared.values())
    for need, check in SUITE:
        assert need is None or any(need in c for c in declared.values()), check.__name__


# ------------------------------------------------------------------ a toy engine through the whole suite


class ToyEngine:
    """A registered engine of the test's own: a class of its own on top of the rk-dop853 driver, which
    declares every capability (so the whole suite runs on it).  `broken` plants a wrong final state."""

    symmetric = True
    native_events = False
    description = "a toy engine (tests/analysis/test_engine_registry.py)"

    def __init__(self, name="toy", broken=False):
        self.name, self.broken, self.inner = name, broken, ENGINES["rk-dop853"]

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=0):
        out = dict(self.inner.run(model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory, samples))
        if self.broken:
            out["y_end"] = np.asarray(out["y_end"]) * (1 + 1e-4)
        return out

    def run_many(self, *args, **kw):
        return self.inner.run_many(*args, **kw)

    def dense(self, *args):
        return self.inner.dense(*args)


def _register(monkeypatch, toy):
    monkeypatch.setitem(ENGINES, toy.name, toy)


def test_a_toy_engine_registered_from_a_test_runs_the_whole_suite(monkeypatch, thesis, reference):
    toy = ToyEngine()
    _register(monkeypatch, toy)
    assert engines.engine("toy") is toy and capabilities(toy) == {"symmetric", "batch", "dense"}
    ran = [check for need, check in SUITE if _applies(need, capabilities(toy))]
    assert ran == [check for need, check in SUITE if need != "stick-slip"]  # all but the stick-slip engines'
    assert ("toy", check_reaches_the_reference) in [(p.values[0], p.values[1]) for p in _cases()]
    for check in ran:
        check("toy", thesis, reference)


def test_a_broken_toy_engine_fails_the_suite(monkeypatch, thesis, reference):
    """Negative control: a final state 1e-4 off is refused by the suite's first check."""
    _register(monkeypatch, ToyEngine(broken=True))
    with pytest.raises(AssertionError):
        check_reaches_the_reference("toy", thesis, reference)


def test_register_adds_and_refuses_a_second_engine_of_the_same_name(monkeypatch):
    monkeypatch.setattr(engines, "ENGINES", dict(ENGINES))
    toy = ToyEngine("toy-registered")
    engines.register(toy)
    assert engines.engine("toy-registered") is toy
    with pytest.raises(ValueError, match="registered already"):
        engines.register(ToyEngine("toy-registered"))
    engines.unregister("toy-registered")
    assert "toy-registered" not in engines.ENGINES
