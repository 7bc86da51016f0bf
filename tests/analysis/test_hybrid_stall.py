"""The start that stalled the stick/slip engine (issue 37; adbgen.analysis.engines.hybrid, docs/friction.md).

`adbgen bench friction`'s rotor (an unbalanced free rotor, eps = 1e-3 m, started at 100 rad/s with both balls at
rest on the race; mu_r = 0.002, mu_s = 0.005) from phi = (1, 4) rad ran into the engine's 10^7-step limit at
t = 0.76 s: ball 2 came to rest in backward slip where kinetic friction could hold it, and the friction in
the field, along sign(phi_2'), flipped inside every step that crossed phi_2' = 0, so the solution chattered at
|phi_2'| ~ 1e-11 without crossing 0 at a step's end (no event) while the step size shrank.  Now a slipping
ball's friction acts along its mode (slip_dir), the field is smooth in each mode, and the stop is an event.

The bound is taken from the run itself, not from a timing: the same start on the same model and engine
without friction (mu_r = mu_s = 0, where every ball slips and only reverses) sets the step count a run of that
length needs, and the run with stiction must take at most twice as many steps (measured: 2074 against 2475;
over a 21 x 21 grid of starts at most 1.06 times).  Negative control: the old field (the planted driver
hybrid_old_field.c, which puts the rate's sign in the mode before each rhs call) is stopped by that bound.

Events located to the engine's tolerance, on the same start (21 events: stops from forward and backward slip,
releases both ways): at rtol = 1e-9 (atol = rtol / 100) the run has the events of a run at rtol = 1e-12, in the
same order, each within T_END * rtol (the integrator keeps each step's local error to rtol of the state, and
the error a run carries is of that order over the run's length; measured over rtol = 1e-7 ... 1e-11 against
1e-13: 0.08 to 0.19 of T_END * rtol).  Negative control: the driver compiled with no bisection
(HY_LOCATE_ITERATIONS = 0: every event at the end of the step it falls in) is outside that bound.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from adbgen.analysis.engines import hybrid
from adbgen.analysis.engines.compiled import compile_cached
from adbgen.analysis.engines.rk import CFLAGS, _sizes
from stick_slip_scene import braked_model

# benchmarks/friction.py's rotor and friction (ROTOR, FRICTION, START) on the shared stick/slip scene
ROTOR = {"eps": 1e-3, "tau0": 0.0, "kappa": 0.0}
FRICTION = {"mu_r": 0.002, "mu_s": 0.005}
STALLED = (1.0, 4.0)  # phi_1, phi_2 (rad)
T_END, SPEED = 10.0, 100.0
BOUND = 2.0  # steps with stiction / steps without friction
PLANTED = Path(__file__).with_name("hybrid_old_field.c")


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    return braked_model(tmp_path_factory)


def _run(model, friction: dict, max_steps: int = 10_000_000, rtol: float = 1e-10):
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_1")], y0[model.index("phi_2")] = STALLED
    y0[model.index("psi_dot")] = SPEED
    return hybrid.run(model, model.params({**ROTOR, **friction}), y0, 0.0, T_END, max_steps=max_steps, rtol=rtol,
                      atol=rtol / 100)


def _old_field_library(model):
    """The hybrid driver compiled with the planted field (hybrid_old_field.c)."""
    import ctypes

    sw = hybrid.switching(model)
    source = model.c_source()

    def array(values):
        return "{" + ",".join(map(str, values)) + "}"

    defines = [f'-DADB_MODEL_SOURCE="{source.name}"', f"-DMODEL_RHS={model.name}_rhs", "-DADB_RHS=old_field_rhs",
               f"-DADB_MEASURE={model.name}_measure", *_sizes(model), f"-DPLANT_NB={len(sw.stuck)}",
               f"-DPLANT_RATE={array(sw.rate_state)}", f"-DPLANT_DIR={array(sw.slip_dir)}",
               f"-DPLANT_STUCK={array(sw.stuck)}"]
    lib = ctypes.CDLL(str(compile_cached(model, PLANTED, source, CFLAGS, defines, [], "hybrid_old_field",
                                         "planted hybrid driver")))
    lib.adb_hybrid_run.restype = ctypes.c_int
    return lib


@pytest.fixture(scope="module")
def frictionless_steps(model):
    """Steps the start needs without friction (the same model and engine at mu_r = mu_s = 0)."""
    run = _run(model, {"mu_r": 0.0, "mu_s": 0.0})
    assert run.status == "success", run.status
    return run.steps


def test_the_stalled_start_runs_to_the_end_within_the_bound(model, frictionless_steps):
    run = _run(model, FRICTION)
    assert run.status == "success" and run.t_end == T_END, (run.status, run.t_end)
    assert run.steps <= BOUND * frictionless_steps, (run.steps, frictionless_steps)
    modes = [mode for _, _, mode in run.events]
    assert "stick" in modes and "slip-" in modes, run.events  # the stop in backward slip that stalled
    assert run.modes(2) == ("stick", "stick"), run.events  # both balls at rest: a residual imbalance to count


# more of the bench's kind of start: the same rotor with mu_r close to mu_s, and the braked eccentric rotor of the
# stick/slip energy balance (measured over 60 random starts each: all to the end, at most 1.30 times the steps)
OTHER_ROTORS = {"mu_r close to mu_s": {**ROTOR, "mu_r": 0.0049, "mu_s": 0.005},
                "braked": {"eps": 2e-3, "tau0": -0.01, "kappa": 0.0, "D": 1e-5, **FRICTION}}


def _random_starts(model, values):
    """(the run with friction, capped at BOUND times the frictionless run's steps; the frictionless steps) for 12
    random starts of the bench's kind on the rotor `values`, to t = 5 s."""
    rng = np.random.default_rng(37)
    for phi in rng.uniform(0.0, 2 * np.pi, (12, 2)):
        y0 = np.zeros(model.n_states)
        y0[model.index("phi_1")], y0[model.index("phi_2")] = phi
        y0[model.index("psi_dot")] = SPEED

        def run(friction, max_steps):
            return hybrid.run(model, model.params({**values, **friction}), y0, 0.0, 5.0, rtol=1e-9, atol=1e-11,
                              max_steps=max_steps)
        free = run({"mu_r": 0.0, "mu_s": 0.0}, 200_000)
        assert free.status == "success", (phi, free.status)
        yield run({}, int(BOUND * free.steps)), free.steps


@pytest.mark.parametrize("name", sorted(OTHER_ROTORS))
def test_random_starts_run_within_the_bound(model, name):
    for run, free_steps in _random_starts(model, OTHER_ROTORS[name]):
        assert run.status == "success", (run.status, run.t_end, run.steps, free_steps)


def test_random_starts_with_the_old_field_stall(model, monkeypatch):
    """Measured: 11 of the 12 starts with mu_r close to mu_s stall on the old field."""
    monkeypatch.setattr(hybrid, "library", _old_field_library)
    statuses = [run.status for run, _ in _random_starts(model, OTHER_ROTORS["mu_r close to mu_s"])]
    assert statuses.count("max_steps") >= 6, statuses


def test_the_old_field_is_stopped_by_the_bound(model, frictionless_steps, monkeypatch):
    monkeypatch.setattr(hybrid, "library", _old_field_library)
    cap = int(BOUND * frictionless_steps)
    run = _run(model, FRICTION, max_steps=cap)
    assert run.status == "max_steps" and run.t_end < T_END, (run.status, run.t_end, run.steps)


RTOL_EVENTS, RTOL_REFERENCE = 1e-9, 1e-12


def _event_errors(model, reference) -> tuple[bool, float]:
    """Whether a run at RTOL_EVENTS has the reference's events in kind and order, and max |t - t_ref| over the
    events the two have in common before they part."""
    run = _run(model, FRICTION, rtol=RTOL_EVENTS)
    assert run.status == "success", run.status
    common = 0
    for a, b in zip(run.events, reference.events):
        if a[1:] != b[1:]:
            break
        common += 1
    same = common == len(run.events) == len(reference.events)
    return same, max(abs(a[0] - b[0]) for a, b in zip(run.events[:common], reference.events[:common]))


@pytest.fixture(scope="module")
def reference(model):
    run = _run(model, FRICTION, rtol=RTOL_REFERENCE)
    assert run.status == "success" and len(run.events) > 10, (run.status, run.events)
    return run


def test_events_are_located_to_the_engines_tolerance(model, reference):
    same, error = _event_errors(model, reference)
    assert same and error <= T_END * RTOL_EVENTS, (same, error)


def test_events_at_the_steps_end_are_caught(model, reference, monkeypatch):
    unlocated = hybrid.library
    monkeypatch.setattr(hybrid, "library", lambda m: unlocated(m, ("-DHY_LOCATE_ITERATIONS=0",)))
    _, error = _event_errors(model, reference)
    assert error > T_END * RTOL_EVENTS, error  # already before the events part
