"""The generated modules describe themselves (issue 19, item 1): FAMILY, KIND, units, roles, ANGLES,
AMPLITUDE, MEASURES, FORCING_FREQUENCY, SYMMETRIES, PARAMETER_SETS, SCALES and the closed-form
STEADY_STATES, declared once by the family and checked against the rendered rhs before writing.

Here: every committed module carries the contract; the compiled functions (numba, C) do what the
declarations say, independently of the pre-write checks (the numba rhs, the thesis' own existence
criteria, SymPy's expressions); and every kind of wrong declaration is refused before anything is
written (negative controls: a check that cannot fail proves nothing).
"""

from __future__ import annotations

import ctypes
import dataclasses
import importlib
import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from adbgen import families
from adbgen.analysis.loading import load_model
from adbgen.codegen.passes.checks import CheckFailed, _project, check_description
from adbgen.codegen.passes.description import DescriptionError
from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.codegen.render_and_import import import_numba, render_into
from adbgen.codegen.spec import build as build_ir
from adbgen.core.description import ROLES, Symmetry
from adbgen.families.single_plane import models as sp_models
from adbgen.families.single_plane import steady_states as ss
from adbgen.families.two_plane import models as tp_models
from toolchain import STRICT_CFLAGS, require_tool, which

MODELS = sorted(p.name for p in DEFAULT_OUT.iterdir() if (p / "__init__.py").is_file())
CONTRACT = ("FAMILY", "KIND", "TIME_UNIT", "STATE_UNITS", "STATE_ROLES", "PARAM_DOMAINS", "ANGLES", "AMPLITUDE",
            "MEASURES", "FORCING_FREQUENCY", "SYMMETRIES", "PARAMETER_SETS", "SCALES", "STEADY_STATES",
            "STEADY_STATE_NOTES", "RESIDUAL_MEASURE")


def module(name):
    return importlib.import_module(f"generated.{name}")


@pytest.mark.parametrize("name", MODELS)
def test_every_generated_module_carries_the_contract(name):
    m = module(name)
    assert all(hasattr(m, a) for a in CONTRACT), [a for a in CONTRACT if not hasattr(m, a)]
    assert m.FAMILY in families.names() and m.KIND and m.TIME_UNIT in ("s", "1")
    assert len(m.STATE_UNITS) == len(m.STATE_ROLES) == m.N_STATES and len(m.PARAM_DOMAINS) == len(m.PARAM_NAMES)
    n = m.N_STATES // 2
    assert all(r in ROLES for r in m.STATE_ROLES[:n]) and m.STATE_ROLES[n:] == tuple(r + "_rate" for r in m.STATE_ROLES[:n])
    assert set(m.ANGLES) == {s for s, r in zip(m.STATE_NAMES, m.STATE_ROLES) if r in ("ball_angle", "spin_angle")}
    assert len(m.AMPLITUDE) == 2 and set(m.AMPLITUDE) <= set(m.STATE_NAMES[:n]) and m.MEASURES[0] == "r"
    assert m.FORCING_FREQUENCY in ("",) + m.PARAM_NAMES and (m.FORCING_FREQUENCY == "") == (m.AUTONOMOUS or "ramp" in name
                                                                                          or "hill" in name)
    assert set(m.SCALES) <= {"eccentricity", "speed"} and set(m.SCALES.values()) <= set(m.PARAM_NAMES)
    # the residual imbalance: one of its measures; a two-plane rotor's A (r misses a couple), r elsewhere
    assert m.RESIDUAL_MEASURE in m.MEASURES and m.RESIDUAL_MEASURE == ("A" if m.FAMILY == "two-plane" else "r")
    for values in m.PARAMETER_SETS.values():
        assert set(values) <= set(m.PARAM_NAMES)
    for s in m.SYMMETRIES:
        assert sorted(s["states"]) == list(range(m.N_STATES)) and sorted(s["params"]) == list(range(len(m.PARAM_NAMES)))
        assert set(s["signs"]) | set(s["param_signs"]) <= {1, -1}
    assert set(m.STEADY_STATE_NOTES) == set(m.STEADY_STATES)


def test_the_thesis_labels_are_the_analysis_layers():
    """"1", "2+", "2-", "3(k)+", "3(k)-" (k balls opposite), as analysis/closed_forms.py named them."""
    for n in (2, 3, 4):
        labels = module(f"thesis_rotating_n{n}").STEADY_STATES
        assert labels == ("1", "2+", "2-") + tuple(f"3({k}){s}" for k in range(1, n) for s in "+-")
    assert module("two_plane_rotating").STEADY_STATES == ("B", "C3") and module("two_plane_fixed").STEADY_STATES == ("B",)


# -- the compiled steady states: zeros of the compiled rhs, given exactly where the thesis says

def _residual(m, y, p, t=0.0):
    return float(np.max(np.abs(m.rhs(t, y, p))))


@settings(max_examples=60, deadline=None)
@given(n=st.sampled_from([2, 3, 4]), mu=st.floats(0.001, 0.2), delta=st.floats(0.001, 0.05),
       Omega=st.floats(0.2, 8.0), zeta=st.floats(0.001, 0.3), beta=st.floats(0.0, 0.3))
def test_thesis_steady_states_are_zeros_and_exist_where_the_thesis_says(n, mu, delta, Omega, zeta, beta):
    m = module(f"thesis_rotating_n{n}")
    p = m.params(mu=mu, delta=delta, Omega=Omega, zeta=zeta, beta=beta)
    for label in m.STEADY_STATES:
        y = m.steady_state(label, p)
        if label == "1":
            exists = ss.balanced_exists(n, mu, delta)
        else:
            k = 0 if label.startswith("2") else int(label[2:label.index(")")])
            exists = ss.inline_exists(n, n - k, mu, Omega, zeta, delta)
        assert (y is not None) == exists, (label, p)
        if y is not None:
            assert _residual(m, y, p) <= 1e-11, label
            assert np.all(y[m.N_STATES // 2:] == 0.0)


def test_the_balanced_state_where_neither_of_the_thesis_patterns_solves(tmp_path):
    """n = 8, delta/mu = 3: phi_3.. = pi gives A = 3, pi, 0, pi, ... gives A = -3 (no solution, |A| > 2:
    analysis/closed_forms.py had no state there); the third pattern (pairs, then j balls at pi) gives one."""
    spec = sp_models.thesis_rotating(8)
    folder = render_into(build_ir(spec), tmp_path / "out", ("numba",))
    m = import_numba(folder, "_adbgen_test_balanced_n8")
    p = m.params(mu=0.01, delta=0.03)
    y = m.steady_state("1", p)
    assert y is not None and _residual(m, y, p) <= 1e-12
    assert ss.balanced_exists(8, 0.01, 0.03)
    assert m.steady_state("1", m.params(mu=0.01, delta=0.081)) is None  # mu < delta/n: none exists (3.14)


def test_two_plane_closed_forms_are_zeros_of_the_compiled_rhs():
    """B (9) in the rotating frame and as an equilibrium of the forced fixed frame (at any t), C3 of
    (29)-(30) in the undamped symmetric set-up, and None where their closed forms do not apply."""
    rot, fixed = module("two_plane_rotating"), module("two_plane_fixed")
    for m, ts in ((rot, (0.0,)), (fixed, (0.0, 0.01, 0.4))):
        p = m.params()
        y = m.steady_state("B", p)
        a = math.acos(p[m.PARAM_NAMES.index("M")] * p[m.PARAM_NAMES.index("epsilon")] / (4 * 0.003 * 1.0))
        assert y[m.STATE_NAMES.index("alpha_1")] == pytest.approx(math.pi + a)
        assert max(_residual(m, y, p, t) for t in ts) <= 1e-15
        assert m.steady_state("B", m.params(m_1=0.004)) is None  # unequal balls: the closed form does not apply
        assert m.steady_state("B", m.params(**{f"m_{k}": 0.002 for k in range(1, 5)})) is None  # m < m_c
    assert rot.steady_state("C3", rot.params()) is None  # damped: (29)-(30) is not exact
    p = rot.params(c_1=0.0, c_2=0.0)
    y = rot.steady_state("C3", p)
    assert y is not None and _residual(rot, y, p) <= 1e-14
    x, phi_y = y[rot.STATE_NAMES.index("x")], y[rot.STATE_NAMES.index("phi_y")]
    assert phi_y == pytest.approx(x / 2.0) and y[rot.STATE_NAMES.index("alpha_1")] == y[rot.STATE_NAMES.index("alpha_2")]


# -- measures and symmetries on the compiled code

def test_measures_equal_their_expressions():
    """r = hypot(AMPLITUDE); A (two-plane) = the mean of |q1 +- q2| as two_plane_runs computes it; the run-up's
    spin_rate = its law (the ramp: Omega_max t/t_ramp, then Omega_max; Hill (45))."""
    rng = np.random.default_rng(3)
    for name in ("thesis_rotating_n3", "two_plane_rotating", "two_plane_fixed", "two_plane_ramp", "two_plane_hill"):
        m = module(name)
        p = m.DEFAULTS * rng.uniform(0.5, 1.5, m.DEFAULTS.size)
        for _ in range(5):
            t, y = float(rng.uniform(0, 9000)), rng.uniform(-0.2, 0.2, m.N_STATES)
            a, b = (y[m.STATE_NAMES.index(s)] for s in m.AMPLITUDE)
            assert m.measure("r", t, y, p) == pytest.approx(math.hypot(a, b), rel=1e-15)
            if "A" in m.MEASURES:
                X, Y, px, py = y[:4]
                q1, q2 = X + 1j * Y, py - 1j * px
                assert m.measure("A", t, y, p) == pytest.approx(0.5 * (abs(q1 + q2) + abs(q1 - q2)), rel=1e-14)
            if "spin_rate" in m.MEASURES:
                get = dict(zip(m.PARAM_NAMES, p))
                if "t_ramp" in get:
                    law = get["Omega_max"] * min(t / get["t_ramp"], 1.0)
                else:
                    tb = get["Omega_cyl"] * t
                    law = get["Omega_max"] * tb**3 / (get["t_half"] ** 3 + tb**3)
                assert m.measure("spin_rate", t, y, p) == pytest.approx(law, rel=1e-13)
            every = np.empty(m.N_MEASURES)
            m.measures_inplace(t, y, p, every)
            assert list(every) == [m.measure(k, t, y, p) for k in m.MEASURES]
    with pytest.raises(KeyError, match="measures: r"):
        module("thesis_rotating_n2").measure("A", 0.0, np.zeros(8), module("thesis_rotating_n2").DEFAULTS)


@pytest.mark.parametrize("name", ["thesis_rotating_n4", "single_plane_fixed_n3", "two_plane_rotating", "two_plane_ramp",
                                  "two_plane_torque"])
def test_symmetries_hold_on_the_compiled_rhs(name):
    """rhs(t, S y, p) = S rhs(t, y, p) at random states and symmetric parameters; identical balls exactly
    (bitwise) where the exchanged balls coincide."""
    m = module(name)
    rng = np.random.default_rng(4)
    assert m.SYMMETRIES
    for s in m.SYMMETRIES:
        S, signs = list(s["states"]), np.array(s["signs"], dtype=float)
        for _ in range(3):
            t, y = float(rng.uniform(0, 5)), rng.uniform(-1, 1, m.N_STATES)
            p = _project(m.DEFAULTS * rng.uniform(0.5, 1.5, m.DEFAULTS.size), s["params"], s["param_signs"])
            lhs, rhs = m.rhs(t, signs * y[S], p), signs * m.rhs(t, y, p)[S]
            assert np.max(np.abs(lhs - rhs)) <= 1e-12 * np.max(np.abs(rhs))
            if s["kind"] == "identical-balls":
                fixed = _project(y, S, s["signs"])
                f = m.rhs(t, fixed, p)
                assert np.array_equal(f, signs * f[S])


def test_a_broken_symmetry_is_seen_by_the_test_above():
    """Negative control: the race swap with the ball masses not swapped does not hold once they differ."""
    m = module("two_plane_rotating")
    s = next(s for s in m.SYMMETRIES if s["kind"] == "race-swap")
    p = _project(m.DEFAULTS.copy(), s["params"], s["param_signs"])
    p[m.PARAM_NAMES.index("m_1")] *= 1.5  # breaks the swap's parameter condition
    y = np.random.default_rng(5).uniform(-1, 1, m.N_STATES)
    S, signs = list(s["states"]), np.array(s["signs"], dtype=float)
    assert np.max(np.abs(m.rhs(0.0, signs * y[S], p) - signs * m.rhs(0.0, y, p)[S])) > 1e-6


# -- the C library carries the same (header data, functions), bitwise equal to numba

def test_the_c_library_describes_itself_as_the_numba_module(tmp_path):
    require_tool(which("gcc") is not None, "gcc")
    import subprocess

    rng = np.random.default_rng(6)
    for name in ("thesis_rotating_n3", "two_plane_rotating"):
        m = module(name)
        so = tmp_path / f"{name}.so"
        r = subprocess.run([which("gcc"), *STRICT_CFLAGS, "-fPIC", "-shared", "-o", str(so),
                            str(DEFAULT_OUT / name / f"{name}.c"), "-lm"], capture_output=True, text=True)
        assert r.returncode == 0 and r.stderr == "", r.stderr
        lib = ctypes.CDLL(str(so))
        D = ctypes.POINTER(ctypes.c_double)
        steady = getattr(lib, f"{name}_steady_state")
        steady.argtypes, steady.restype = [ctypes.c_int, D, D], ctypes.c_int
        measure = getattr(lib, f"{name}_measure")
        measure.argtypes, measure.restype = [ctypes.c_int, ctypes.c_double, D, D], ctypes.c_double
        labels = ctypes.c_char_p * len(m.STEADY_STATES)
        assert [s.decode() for s in labels.in_dll(lib, f"{name}_steady_state_labels")] == list(m.STEADY_STATES)
        for _ in range(10):
            p = m.DEFAULTS * np.exp(rng.uniform(-1, 1, m.DEFAULTS.size))
            if name.startswith("two"):
                p = m.params(**{**dict(zip(m.PARAM_NAMES, p)), "c_1": 0.0, "c_2": 0.0, "chi": 0.0, "beta": 0.0})
                p = _project(p, *next((s["params"], s["param_signs"]) for s in m.SYMMETRIES if s["kind"] == "race-swap"))
                for k in (2, 3, 4):
                    p[m.PARAM_NAMES.index(f"m_{k}")] = p[m.PARAM_NAMES.index("m_1")]
            for k, label in enumerate(m.STEADY_STATES):
                y = np.empty(m.N_STATES)
                found = steady(k, p.ctypes.data_as(D), y.ctypes.data_as(D))
                ref = m.steady_state(label, p)
                assert bool(found) == (ref is not None) and (np.array_equal(y, ref) if found else np.isnan(y).all())
            y = rng.uniform(-0.3, 0.3, m.N_STATES)
            for k, mname in enumerate(m.MEASURES):
                assert measure(k, 0.5, y.ctypes.data_as(D), p.ctypes.data_as(D)) == m.measure(mname, 0.5, y, p)


# -- the analysis layer's view (loading.Model)

def test_model_properties_read_the_self_description():
    m = load_model("two_plane_ramp")
    # dimensionless, as the paper's sets (issue 34 item 5: a unit only where the model has one)
    assert (m.family, m.kind, m.time_unit, m.forcing_frequency) == ("two-plane", "two_plane_ramp", "1", "")
    assert m.angles == ("theta_1", "theta_2", "theta_3", "theta_4") and m.amplitude == ("X", "Y")
    assert m.amplitude_indices == (0, 1, 8, 9) and m.angle_indices == (4, 5, 6, 7)
    assert m.measures == ("r", "A", "spin_angle", "spin_rate") and m.scales == {"eccentricity": "epsilon", "speed": "Omega_max"}
    Y = np.zeros((m.n_states, 3))
    assert m.measure("spin_rate", np.array([0.0, 3000.0, 9000.0]), Y, m.params()) == pytest.approx([0.0, 1.8, 3.6], rel=1e-15)
    t = load_model("thesis_rotating_n2")
    assert t.steady_states[:3] == ("1", "2+", "2-") and t.roles[:3] == ("translation", "translation", "ball_angle")
    assert t.steady_state("2+", t.params({"zeta": 0.0})) is None and "thesis (5.1)" in t.parameter_sets
    assert np.max(np.abs(t.module.rhs(0.0, t.steady_state("2+", t.params()), t.params()))) < 1e-14
    from adbgen.analysis.loading import AnalysisError

    with pytest.raises(AnalysisError, match="closed-form steady states: 1, 2\\+"):
        t.steady_state("B", t.params())


# -- wrong declarations are refused before anything is written

def _redeclared(spec, **changes):
    """The spec with its description changed (`changes`: {field: value or function of the description})."""
    original = spec.describe

    def describe(system):
        d = original(system)
        return dataclasses.replace(d, **{k: (v(d, system) if callable(v) else v) for k, v in changes.items()})
    return dataclasses.replace(spec, describe=describe)


def _check(spec):
    system = spec.system()
    return check_description(build_ir(spec, system), system)


def test_a_correct_declaration_passes_the_checks():
    assert _check(sp_models.thesis_rotating(2))["steady_states"] < 1e-12


@pytest.mark.parametrize("spec", [sp_models.thesis_rotating(4), sp_models.single_plane_fixed(3),
                                  tp_models.two_plane_rotating(), tp_models.two_plane_fixed()], ids=lambda s: s.name)
def test_every_default_label_is_exercised_by_the_check(spec):
    """Each steady state of the default set is given (and so shown a zero of the rhs) at some of the
    check's random parameter points."""
    assert _check(spec)["unexercised"] == ()


def test_a_wrong_steady_state_is_refused():
    def shifted(d, system):
        form = d.closed_forms[1]
        cand = form.candidates[0]
        return (d.closed_forms[0], dataclasses.replace(form, candidates=(dataclasses.replace(
            cand, values={**cand.values, "x": cand.values["x"] * 1.001}),)))
    with pytest.raises(CheckFailed, match="not a zero of the rhs"):
        _check(_redeclared(sp_models.thesis_rotating(2), closed_forms=shifted))


def test_a_wrong_existence_guard_is_refused():
    """The arccosine's domain dropped from 2+-'s guards (a state given where it does not exist: NaN)."""
    def unguarded(d, system):
        form = d.closed_forms[1]
        cand = form.candidates[0]
        return (d.closed_forms[0], dataclasses.replace(form, candidates=(dataclasses.replace(cand, guards=cand.guards[:3]),)))
    with pytest.raises(CheckFailed):
        _check(_redeclared(sp_models.thesis_rotating(2), closed_forms=unguarded))


def test_a_wrong_existence_criterion_is_refused():
    def doubled(d, system):
        from adbgen.families.single_plane.symbols import delta, mu

        first = dataclasses.replace(d.steady_states[0], exists=sp.Ge(mu, 4 * delta / 2))
        return (first,) + d.steady_states[1:]
    with pytest.raises(CheckFailed, match="criterion"):
        _check(_redeclared(sp_models.thesis_rotating(2), steady_states=doubled))


def test_a_wrongly_rendered_measure_is_refused(monkeypatch):
    """A measure is checked against its SymPy expression: a kernel that computes A with a tilt's sign
    flipped (what a printing or lowering error would do) is caught."""
    from adbgen.codegen.passes import description as describe_module

    measures = describe_module._measures

    def flipped(names, exprs):
        wrong = [e.xreplace({s: -s for s in e.free_symbols if s.name == "phi_x"}) if n == "A" else e
                 for n, e in zip(names, exprs)]
        return measures(names, wrong)
    spec = tp_models.two_plane_rotating()
    assert _check(spec)["measures"] <= 1e-15
    monkeypatch.setattr(describe_module, "_measures", flipped)
    with pytest.raises(CheckFailed, match="measure A"):
        _check(spec)


def test_a_residual_measure_the_model_does_not_have_is_refused():
    # the residual imbalance must name one of the model's measures (r, or its family's own): a planted "A" on the
    # single-plane model (which has r only) is refused before anything is written, in one line
    with pytest.raises(DescriptionError, match="residual imbalance 'A' is not one of its measures") as info:
        _check(_redeclared(sp_models.thesis_rotating(2), residual="A"))
    assert "\n" not in str(info.value)


def test_a_wrong_symmetry_is_refused():
    """The race swap without reversing the tilt."""
    def untilted(d, system):
        swap = d.symmetries[-1]
        coords = {k: (v[0], 1) for k, v in swap.coordinates.items()}
        return d.symmetries[:-1] + (dataclasses.replace(swap, coordinates=coords),)
    with pytest.raises(CheckFailed, match="gamma_r"):
        _check(_redeclared(tp_models.two_plane_rotating(), symmetries=untilted))


def test_an_identical_ball_exchange_that_forgets_the_masses_is_refused():
    def massless(d, system):
        return (Symmetry("exchange alpha_1, alpha_3", "identical-balls", {"alpha_1": ("alpha_3", 1), "alpha_3": ("alpha_1", 1)}),)
    with pytest.raises(CheckFailed, match="does not hold"):
        _check(_redeclared(tp_models.two_plane_rotating(), symmetries=massless))


def test_a_translation_declared_as_an_angle_is_refused():
    roles = lambda d, system: {**d.roles, "x": "ball_angle"}  # noqa: E731
    with pytest.raises(CheckFailed, match="not 2 pi-periodic in the declared angle x"):
        _check(_redeclared(sp_models.thesis_rotating(2), roles=roles, angles=lambda d, s: ("x",) + d.angles))
    with pytest.raises(CheckFailed, match="angles"):  # and an angle must have an angle's role
        _check(_redeclared(sp_models.thesis_rotating(2), angles=lambda d, s: ("x",) + d.angles))


def test_a_wrong_forcing_frequency_is_refused():
    with pytest.raises(CheckFailed, match="periodically forced at Omega"):
        _check(_redeclared(tp_models.two_plane_fixed(), forcing_frequency=""))
    with pytest.raises(CheckFailed, match="is not periodically forced"):
        _check(_redeclared(sp_models.thesis_rotating(2), forcing_frequency="Omega"))


def test_names_the_model_does_not_have_are_refused():
    with pytest.raises(DescriptionError, match="role"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), roles=lambda d, s: {**d.roles, "z": "translation"}))
    with pytest.raises(DescriptionError, match="not a parameter"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), forcing_frequency="omega"))
    with pytest.raises(DescriptionError, match="parameter set"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), parameter_sets={"x": {"nu": 1.0}}))


def test_state_names_are_the_models_and_a_wrong_one_is_refused():
    """The thesis' names of its steady states are what the generated modules say about themselves (the
    attractor labels are made from them); the two-plane models name none.  Negative controls: an unknown
    configuration and a template with another field are refused."""
    from adbgen.analysis import attractors

    for n in (2, 3, 4):
        assert module(f"thesis_rotating_n{n}").STEADY_STATE_NAMES == {"rest": "balanced 1", "together": "coincident 2",
                                                              "opposed": "in-line 3({n}-{m})"}
    m = load_model("thesis_rotating_n3")
    assert attractors.labels(m)[:7] == ["balanced 1", "coincident 2-", "coincident 2+", "coincident 2",
                                        "in-line 3(3-2)-", "in-line 3(3-2)+", "in-line 3(3-2)"]
    assert module("two_plane_rotating").STEADY_STATE_NAMES == {}
    assert attractors.rest_name(load_model("two_plane_rotating")) == "rotor at rest"
    with pytest.raises(DescriptionError, match="configurations are rest, together, opposed"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), steady_state_names={"spinning": "x"}))
    with pytest.raises(DescriptionError, match="a template in"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), steady_state_names={"opposed": "3({n}-{j})"}))


def test_regenerate_refuses_a_wrong_declaration_and_writes_nothing(tmp_path, capsys):
    from adbgen.cli import main

    spec = _redeclared(sp_models.thesis_rotating(2), forcing_frequency="Omega")

    @dataclasses.dataclass(frozen=True)
    class WronglyDescribed(type(families.get("single-plane"))):
        name: str = "wrongly-described"

        def models(self):
            return [spec]

        def register_commands(self, subparsers):
            pass

    families.register(WronglyDescribed())
    try:
        out = tmp_path / "out"
        assert main(["regenerate", "--family", "wrongly-described", "--out", str(out), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("adbgen: error: ") and err.count("\n") == 1 and "forced" in err
        assert not out.exists()
    finally:
        families.unregister("wrongly-described")


# ----------------------------------------------------------------------- the manifold of equilibria

def test_the_manifold_of_equilibria_is_checked_and_emitted():
    """thesis_rotating_n3 declares (3.6): its tangent annihilates the jac at the balanced state (the check
    passes); a wrong manifold (one constraint, sum cos phi_i + delta/mu, whose tangent is two-dimensional and
    leaves the equilibria) is refused by the check (negative control)."""
    from adbgen.core.description import Equilibria
    from adbgen.families.single_plane.symbols import delta, mu

    spec = sp_models.thesis_rotating(3)
    assert _check(spec)["equilibria"] < 1e-12

    def one_constraint(d, system):
        phis = [system.coordinates[k].q for k in system.solve.leaves]
        return Equilibria("too big", ("x", "y"), (sp.Add(*map(sp.cos, phis)) + delta / mu,))
    with pytest.raises(CheckFailed, match="manifold of equilibria 'too big' is not one"):
        _check(_redeclared(spec, equilibria=one_constraint))


def test_a_manifold_naming_what_the_model_does_not_have_is_refused():
    from adbgen.core.description import Equilibria

    with pytest.raises(DescriptionError, match="not coordinates"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), equilibria=Equilibria("e", ("z",), (sp.Integer(1),))))
    with pytest.raises(DescriptionError, match="not the free coordinates"):
        build_ir(_redeclared(sp_models.thesis_rotating(2), equilibria=lambda d, s: Equilibria(
            "e", ("x", "y"), (s.coordinates[0].qd,))))
