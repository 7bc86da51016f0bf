"""The stuck-equilibrium band of the thesis model (issue 37, item 3; science.stiction_band).

The closed form is checked against the emitted friction model of the default scene (parameters (5.1), n = 2,
omega = 400 rad/s, rotating frame, with stiction): at the closed form's stuck state the model's rhs vanishes
with both balls stuck, and its own measures normal_force_k, stick_force_k, stick_margin_k equal the closed
form's N_k, F_k, mu_s N_k - |F_k| (times m R omega^2).  Negative control: the normal force without the
displacement term (N = m R omega^2) is caught.  Then the first-order closed forms (width, largest r) against
the exact band, and the stuck states' stability against the model's Jacobian.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from adbgen.analysis.loading import load_model
from adbgen.families.single_plane.science import stiction_band as sb

MU_R, MU_S = 0.01, 0.02
SCENE = f"""n = 2
rolling_resistance = {MU_R}
static_friction = {MU_S}
[speed]
omega = 400.0
"""
ROTOR = sb.Rotor()  # (5.1): the default scene over its scalings (2.15)-(2.19)
R, MASS, OMEGA, OMEGA_N = 0.05, 0.05, 400.0, 100.0


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    out = Path(tmp_path_factory.mktemp("stiction_band"))
    (out / "band.toml").write_text(SCENE)
    subprocess.run([sys.executable, "-m", "adbgen.cli", "regenerate", "--scene", str(out / "band.toml"), "--name",
                    "band", "--out", str(out), "--targets", "numba", "c", "--quiet"], check=True)
    return load_model(out / "band")


def _stuck_state(model, phis):
    z = sb.displacement(ROTOR, phis)
    y = np.zeros(model.n_states)
    y[model.index("x")], y[model.index("y")] = R * z.real, R * z.imag
    for k, phi in enumerate(phis, 1):
        y[model.index(f"phi_{k}")] = phi
    return y, model.params({"stuck_1": 1.0, "stuck_2": 1.0})


PHIS = np.random.default_rng(37).uniform(-np.pi, np.pi, (40, 2))
SCALE = MASS * R * OMEGA**2  # m R omega^2, the closed form's unit of force


def _measured(model, phis):
    y, p = _stuck_state(model, phis)
    got = {name: np.array([model.measure(f"{name}_{k}", 0.0, y, p) for k in (1, 2)]) / SCALE
           for name in ("normal_force", "stick_force", "stick_margin")}
    return y, p, got


def test_the_closed_form_is_the_models_stuck_state(model):
    assert dict(zip(model.param_names, model.params()))["mu_s"] == MU_S
    for phis in PHIS:
        y, p, got = _measured(model, phis)
        assert np.max(np.abs(model.module.rhs(0.0, y, p))) < 1e-9  # x'', y'' (m/s^2), phi'' = 0: at rest
        F, N = sb.loads(ROTOR, phis)
        assert np.allclose(got["normal_force"], N, rtol=0, atol=1e-12), (got["normal_force"], N)
        assert np.allclose(got["stick_force"], F, rtol=0, atol=1e-12), (got["stick_force"], F)
        assert np.allclose(got["stick_margin"], MU_S * N - np.abs(F), rtol=0, atol=1e-12)
        assert np.isclose(got["stick_margin"].min(), sb.margin(ROTOR, phis, MU_S), rtol=0, atol=1e-12)


def test_a_normal_force_without_the_displacement_is_caught(model):
    """N = m R omega^2 (the ball on a centred race): off the model's by |Re(z e^{-i phi})| ~ 1e-3 of it."""
    worst = 0.0
    for phis in PHIS:
        _, _, got = _measured(model, phis)
        worst = max(worst, float(np.max(np.abs(got["normal_force"] - 1.0))))
    assert worst > 1e-4, worst


def test_band_membership_matches_the_models_margins(model):
    """Inside (both margins >= 0) or not, on a line across the band, the same by the model and the closed form."""
    th = ROTOR.theta_star
    lo, hi = sb.symmetric_interval(ROTOR, MU_S)
    signs = []
    for theta in np.linspace(lo - 0.1, hi + 0.1, 41):
        _, _, got = _measured(model, [theta, -theta])
        signs.append((got["stick_margin"].min() >= 0, lo <= theta <= hi))
    assert all(a == b for a, b in signs) and sum(a for a, _ in signs) > 5, signs
    assert lo < th < hi


def test_stuck_states_are_stable_as_the_models_jacobian_says(model):
    """The rotor block of the emitted Jacobian with both balls stuck (time in s) = stuck_eigenvalues
    (time over 1 / omega_n) times omega_n; every real part negative."""
    y, p = _stuck_state(model, [ROTOR.theta_star + 0.05, -ROTOR.theta_star])
    J = np.asarray(model.module.jac(0.0, y, p))
    rotor = [model.index(s) for s in ("x", "y", "x_dot", "y_dot")]
    got = np.sort_complex(np.linalg.eigvals(J[np.ix_(rotor, rotor)]))
    want = np.sort_complex(sb.stuck_eigenvalues(ROTOR) * OMEGA_N)
    assert np.allclose(got, want, rtol=1e-9), (got, want)
    assert np.all(want.real < 0)
    balls = [model.index(s) for s in ("phi_1_dot", "phi_2_dot")]
    assert np.max(np.abs(J[balls, :])) < 1e-6 * OMEGA_N**2  # stuck: phi'' = 0 (to rounding: (1 - stuck) times the slip row)


@pytest.mark.parametrize("mu_s", [1e-5, 1e-4])
def test_first_order_closed_forms(mu_s):
    lo, hi = sb.symmetric_interval(ROTOR, mu_s, step=mu_s)
    assert abs((hi - lo) / sb.width_first_order(ROTOR, mu_s) - 1) < 30 * mu_s
    exact, closed = sb.r_max(ROTOR, mu_s)
    assert closed and abs(exact / sb.r_max_first_order(ROTOR, mu_s) - 1) < 100 * mu_s, exact


def test_first_order_r_max_with_the_wrong_side_of_the_rhombus_is_caught():
    """mu_s / max(|cos|, |sin|) (the near vertex) is ten times too small for (5.1)."""
    th = ROTOR.theta_star
    exact, _ = sb.r_max(ROTOR, 1e-5)
    assert abs(exact * max(abs(np.cos(th)), abs(np.sin(th))) / 1e-5 - 1) > 0.5


def test_grid_band_and_exact_reach_agree():
    """At mu_s = 0.02 the grid's largest r on the band's component and the rays' exact one agree to the grid."""
    _, area, r_grid, _ = sb.band(ROTOR, 0.02, points=721)
    exact, closed = sb.r_max(ROTOR, 0.02, directions=360)
    assert closed and 0 < area < 1 and r_grid <= exact * (1 + 1e-9) and r_grid > 0.97 * exact, (r_grid, exact)
