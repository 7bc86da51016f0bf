"""Steady states on the generated code: Newton, the balanced family's tangent space, the transverse
spectrum (the family's zero eigenvalues removed exactly, shown against the full spectrum with a
wrong tangent as negative control), classification, and the closed-form states."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adbgen.analysis import steady
from adbgen.analysis.starts import labelled_state
from adbgen.analysis.loading import AnalysisError, load_model

from analysis_helpers import CH4  # this folder's helper (conftest.py puts it on sys.path)


def _match(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance when each eigenvalue of a is paired with its nearest remaining one of b."""
    rest, worst = list(b), 0.0
    for z in a:
        k = int(np.argmin([abs(z - w) for w in rest]))
        worst = max(worst, abs(z - rest.pop(k)))
    assert not rest
    return worst


@pytest.mark.parametrize("n", [2, 3, 4])
def test_start_is_a_steady_state_and_the_family_is_neutral_not_unstable(thesis, n):
    m = thesis[n]
    s = steady.refine(m, m.params({"Omega": 4.0, **CH4}), m.module.START)
    assert s.residual < 1e-14
    assert s.tangent.shape == (m.n_states, n - 2)
    assert s.neutral.size == n - 2 and np.all(np.abs(s.neutral) < 1e-10), s.neutral
    assert s.transverse.size == m.n_states - (n - 2)
    assert s.classification == "stable" and s.n_unstable == 0
    assert s.tangent_residual < 1e-15
    if n >= 3:
        # without the reduction the rounding of the zero eigenvalues decides: not a classification
        assert np.max(np.abs(s.eigenvalues.real)) > 0 and np.min(np.abs(s.eigenvalues)) < 1e-12
    out = s.to_json()
    assert out["family_dimension"] == n - 2 and len(out["neutral_eigenvalues"]) == n - 2
    assert out["classification"] == "stable" and out["n_unstable"] == 0


def test_unstable_between_the_hopf_points_with_counts(thesis):
    m = thesis[3]
    s = steady.refine(m, m.params({"Omega": 1.8, **CH4}), m.module.START)
    assert s.classification == "unstable" and s.n_unstable == 2
    assert np.all(np.abs(s.neutral) < 1e-10)


@pytest.mark.parametrize("n", [3, 4])
def test_tangent_is_the_null_space_and_moving_along_it_keeps_a_steady_state(thesis, n):
    m = thesis[n]
    p = m.params({"Omega": 2.5, **CH4})
    y = np.array(m.module.START)
    T = steady.balanced_family_tangent(m, y)
    J = steady.jacobian(m, y, p)
    assert np.allclose(T.T @ T, np.eye(n - 2), atol=1e-14)
    assert np.max(np.abs(J @ T)) < 1e-14 * np.max(np.abs(J))
    # the rhs along the tangent grows only quadratically (first order: J T = 0): a family, not a direction
    for eps in (1e-3, 1e-4):
        r = np.max(np.abs(steady.residual(m, y + eps * T[:, 0], p)))
        assert r < 10 * eps**2, (eps, r)
    # a transverse direction (x) is not: the rhs grows linearly
    ex = np.zeros(m.n_states)
    ex[m.index("x")] = 1
    assert np.max(np.abs(steady.residual(m, y + 1e-4 * ex, p))) > 1e-5


@pytest.mark.parametrize("n", [3, 4])
@pytest.mark.parametrize("omega", [4.0, 1.8, 1.05])
def test_transverse_spectrum_is_the_full_spectrum_minus_the_zero_eigenvalues(thesis, n, omega):
    m = thesis[n]
    p = m.params({"Omega": omega, **CH4})
    y = np.array(m.module.START)
    J = steady.jacobian(m, y, p)
    T = steady.balanced_family_tangent(m, y)
    full = np.linalg.eigvals(J)
    zeros = np.argsort(np.abs(full))[: n - 2]
    assert np.all(np.abs(full[zeros]) < 1e-10)
    rest = np.delete(full, zeros)
    reduced = steady.transverse_spectrum(J, T)
    assert _match(reduced, rest) < 1e-10
    # the deflation used in the AUTO files: the zeros go to -1, the rest stay
    deflated = np.linalg.eigvals(steady.deflated_jacobian(J, T, 1.0))
    assert _match(deflated, np.r_[rest, -np.ones(n - 2)]) < 1e-10
    # negative control: a wrong tangent (tilted towards x) changes the rest of the spectrum
    wrong = T.copy()
    wrong[m.index("x"), 0] = 0.3
    wrong, _ = np.linalg.qr(wrong)
    assert _match(steady.transverse_spectrum(J, wrong), rest) > 1e-3
    assert _match(np.linalg.eigvals(steady.deflated_jacobian(J, wrong, 1.0)), np.r_[rest, -np.ones(n - 2)]) > 1e-3


@settings(max_examples=15, deadline=None)
@given(free=st.floats(-math.pi, math.pi), ratio=st.floats(0.1, 1.5), omega=st.floats(0.3, 5.0),
       zeta=st.floats(0.001, 0.3), beta=st.floats(0.001, 0.3))
def test_reduction_is_exact_on_any_member_of_the_n3_family(free, ratio, omega, zeta, beta):
    """Property: on every balanced state (any free angle, delta/mu, Omega, damping), the transverse
    spectrum is the full spectrum without its zero eigenvalue."""
    m = load_model("thesis_rotating_n3")
    mu = 0.05
    delta = ratio * mu
    A, B = -delta / mu - math.cos(free), -math.sin(free)
    r = math.hypot(A, B) / 2
    if not 0.05 < r < 0.95:  # (3.6) has a solution with phi_1 != phi_2
        return
    alpha, gamma = math.atan2(B, A), math.acos(r)
    y = m.state({"phi_1": alpha + gamma, "phi_2": alpha - gamma, "phi_3": free})
    p = m.params({"Omega": omega, "mu": mu, "delta": delta, "zeta": zeta, "beta": beta})
    assert np.max(np.abs(steady.residual(m, y, p))) < 1e-14
    s = steady.analyse(m, p, y)
    assert s.tangent.shape[1] == 1 and abs(s.neutral[0]) < 1e-9
    full = np.linalg.eigvals(s.jacobian)
    rest = np.delete(full, np.argmin(np.abs(full)))
    assert _match(s.transverse, rest) < 1e-9 * max(1.0, np.max(np.abs(full)))


def test_newton_converges_onto_the_family_from_a_perturbed_state(thesis):
    m = thesis[3]
    p = m.params({"Omega": 3.0, **CH4})
    rng = np.random.default_rng(3)
    y0 = np.array(m.module.START) + 1e-3 * rng.standard_normal(m.n_states)
    s = steady.refine(m, p, y0)
    assert s.residual < 1e-12 and s.iterations >= 2
    assert abs(s.y[m.index("x")]) < 1e-12 and s.tangent.shape[1] == 1
    # on the family: (3.6)
    phi = s.y[list(m.angle_indices)]
    assert abs(np.sum(np.cos(phi)) + CH4["delta"] / CH4["mu"]) < 1e-12 and abs(np.sum(np.sin(phi))) < 1e-12


def test_isolated_states_have_no_neutral_directions(thesis):
    m = thesis[3]
    p = m.params({"Omega": 0.5, **CH4})
    s = steady.refine(m, p, labelled_state(m, "2-", p), label="2-")
    assert s.tangent.shape[1] == 0 and s.neutral.size == 0 and s.classification == "stable"


@pytest.mark.parametrize("n", [2, 3, 4])
def test_closed_form_states_are_zeros_of_the_generated_rhs(thesis, n):
    m = thesis[n]
    labels = list(m.steady_states)
    assert labels[:3] == ["1", "2+", "2-"] and len(labels) == 3 + 2 * (n - 1)
    for omega in (0.5, 1.5, 4.0):
        p = m.params({"Omega": omega, **CH4})
        found = 0
        for label in labels:
            try:
                y = labelled_state(m, label, p)
            except AnalysisError:  # (3.16)/(3.18): absent between the critical speeds
                continue
            found += 1
            assert np.max(np.abs(steady.residual(m, y, p))) < 1e-13, (label, omega)
        assert found >= 3


def test_closed_forms_equal_the_symbolic_ones():
    """The generated module's closed forms equal adbgen.families.single_plane.steady_states (SymPy), n = 3."""
    from adbgen.families.single_plane import steady_states as ss

    m = load_model("thesis_rotating_n3")
    values = {"Omega": 1.5, **CH4}
    p = m.params(values)
    for label, expr in (("2+", ss.coincident(3, 1)), ("2-", ss.coincident(3, -1)), ("3(1)+", ss.inline(3, 2, 1)),
                        ("3(2)-", ss.inline(3, 1, -1))):
        sym = ss.evaluate(expr, values)
        y = labelled_state(m, label, p)
        for name in ("x", "y"):
            assert math.isclose(y[m.index(name)], sym[name], rel_tol=1e-12, abs_tol=1e-12), (label, name)
        for name in ("phi_1", "phi_2", "phi_3"):  # the symbolic evaluation wraps angles into (-pi, pi]
            assert abs(np.exp(1j * y[m.index(name)]) - np.exp(1j * sym[name])) < 1e-12, (label, name)
    y = labelled_state(m, "1", p)
    sym = ss.evaluate(ss.balanced(3, [ss.sp.pi]), values)
    assert np.allclose([y[m.index(k)] for k in ("phi_1", "phi_2", "phi_3")], [sym[k] for k in ("phi_1", "phi_2", "phi_3")])


def test_forced_models_have_no_steady_states():
    m = load_model("single_plane_fixed_n2")
    with pytest.raises(AnalysisError, match="periodic orbits"):
        steady.refine(m, m.params(), np.zeros(m.n_states))


def test_newton_failure_is_an_error(thesis):
    m = thesis[2]
    with pytest.raises(steady.SteadyStateError, match="Newton did not converge"):
        steady.newton(m, m.params({"Omega": 4.0}), m.state({"x": 0.5, "phi_1": 2.0}), max_iter=2)


def test_unequal_balls_reduce_by_the_manifold_the_module_declares(tmp_path, monkeypatch):
    """Unequal balls (a scene's dimensional rotating-frame model): the balanced states weigh each ball by
    its mass, and the manifold the module declares (EQUILIBRIA: the rotor's generalised forces at rest)
    says so, so its emitted gradients give the tangent (J T = 0) and the transverse spectrum is again the
    full one minus the zero.  Negative control: the equal-ball gradients of (3.6) (-sin phi_i, cos phi_i,
    unweighted) are not the tangent there (|J T| large)."""
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path))
    scene = tmp_path / "unequal.toml"
    scene.write_text('n = 3\nball_mass = [0.05, 0.04, 0.03]\n[speed]\nlaw = "constant"\nomega = 400.0\n')
    m = load_model(scene=scene)
    p = m.params()
    assert m.equilibria is not None and m.equilibria["constraints"] == 2
    s = steady.refine(m, p, m.state({"phi_1": 1.2, "phi_2": -1.2, "phi_3": 3.1}))
    assert s.tangent.shape[1] == 1 and s.classification == "stable" and abs(s.neutral[0]) < 1e-9
    assert steady.family_residual(s.jacobian, steady.balanced_family_tangent(m, s.y, p)) < 1e-13
    angles = list(m.role_indices("ball_angle"))
    equal_balls = np.vstack([-np.sin(s.y[angles]), np.cos(s.y[angles])])
    assert steady.family_residual(s.jacobian, steady._null_in(equal_balls, angles, m.n_states)) > 1e-3
    full = np.linalg.eigvals(s.jacobian)
    rest = np.delete(full, np.argmin(np.abs(full)))
    assert _match(s.transverse, rest) < 1e-9 * np.max(np.abs(full))


def test_a_model_without_a_declared_manifold_has_no_tangent(thesis):
    """The tangent comes from the module's EQUILIBRIA only: the same balanced state of the n = 3 model with
    the declaration removed (negative control) is an ordinary state, N x 0."""
    import dataclasses
    import types

    m = thesis[3]
    y = np.array(m.module.START)
    assert steady.balanced_family_tangent(m, y).shape == (m.n_states, 1)
    bare = dataclasses.replace(m, module=types.SimpleNamespace(**{**vars(m.module), "EQUILIBRIA": None}))
    assert not steady.on_balanced_family(bare, y) and steady.balanced_family_tangent(bare, y).shape == (m.n_states, 0)


@pytest.mark.parametrize("Omega, mu", [(0.4, 0.007), (1.0, 0.004), (2.4, 0.013)])
def test_newton_from_start_does_not_depend_on_the_blas_kernels_last_bits(monkeypatch, Omega, mu):
    """The sweep's stability map (Newton from START) flipped cells by CPU type: LAPACK's last bits
    depend on the BLAS kernel, and at these points of the n = 4 (Omega, mu) map the undamped Newton
    path from START is chaotic in them.  A least-squares solver off by an ulp here and there (another
    kernel) must reach the same steady state."""
    from adbgen.analysis import attractors

    model = load_model("thesis_rotating_n4")
    p = np.array(model.module.START_PARAMETERS, float)
    p[model.param_names.index("Omega")], p[model.param_names.index("mu")] = Omega, mu
    seed = np.array(model.module.START, float)

    def outcome():
        y = attractors.newton(model, seed, p)
        assert y is not None
        return attractors.spectrum(model, y, p).unstable(), attractors.name_steady_state(model, y, p), y

    exact = outcome()
    lstsq = np.linalg.lstsq
    for k in range(4):
        rng = np.random.default_rng(k)

        def noisy(a, b, rcond=None):
            x, *rest = lstsq(a, b, rcond=rcond)
            ulps = rng.integers(-2, 3, size=x.shape)
            return (x + ulps * np.spacing(x), *rest)

        monkeypatch.setattr(np.linalg, "lstsq", noisy)
        other = outcome()
        monkeypatch.setattr(np.linalg, "lstsq", lstsq)
        assert other[:2] == exact[:2]
        assert np.max(np.abs(attractors.state_difference(model, other[2], exact[2]))) < 1e-8
