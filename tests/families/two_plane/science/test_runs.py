"""Brute-force vibration (Figure 12(a)) and run-ups (section 6): the two-plane science's runs."""

import math

import numpy as np
import pytest

from adbgen.families.two_plane.science import runs as tr
from adbgen.analysis.loading import load_model


def test_vibration_is_the_mean_at_the_two_points_one_unit_from_the_midspan():
    model = load_model("two_plane_fixed")
    y = np.zeros((model.n_states, 2))
    y[model.index("X"), 0] = 3e-4  # translation: both points move by 3e-4
    y[model.index("phi_Y"), 1] = 2e-4  # tilt: the points move by -+2e-4
    y[model.index("Y"), 1] = 1e-4
    A = tr.vibration(model, 0.0, y, model.params())
    assert A[0] == pytest.approx(3e-4)
    assert A[1] == pytest.approx(0.5 * (math.hypot(2e-4, 1e-4) + math.hypot(2e-4, 1e-4)))
    assert A[1] != pytest.approx(math.hypot(1e-4, 0))  # centre only: wrong


def test_settled_plain_rotor_is_the_linear_response():
    """Plain rotor at Omega = 5, static imbalance (43): the orbit X = Re(eps W^2 e^{iWt}/(k_X - W^2 + i c_X W)),
    Y = Re(-i eps W^2 e^{iWt}/(k_Y - W^2 + i c_Y W)); A_bar = its largest radius (64 samples a period: 1e-3)."""
    model = load_model("two_plane_fixed")
    values = {"epsilon": 1e-4, "chi": 0.0, "beta": 0.0, **tr._ball_values(tr.PLAIN_MASS, 0.01)}
    o = tr.settled_vibration(model, values, 5.0, 2000.0)
    w = 5.0
    ph = np.exp(1j * np.linspace(0, 2 * np.pi, 100001))
    X = (1e-4 * w**2 / (1.0 - w**2 + 0.02j * w) * ph).real
    Y = (-1j * 1e-4 * w**2 / (5.0 - w**2 + 0.1j * w) * ph).real
    assert o.A_bar == pytest.approx(np.hypot(X, Y).max(), rel=1e-3)
    assert o.A_bar != pytest.approx(np.abs(X).max(), rel=1e-2)  # the X response alone


def test_balls_balance_above_the_highest_critical_speed_and_not_at_2():
    """With the exactly race-symmetric integration the symmetric start balances at 4.5 and also at 4.0, where
    B's unstable multiplier is gamma_r-odd (the plain engine's rounding excited it there before); at 2.0, between
    the resonances, the balls run behind the rotor."""
    model = load_model("two_plane_fixed")
    values = {"epsilon": 1e-4, "chi": 0.0, "beta": 0.0, **tr._ball_values(1e-4, 0.01)}
    assert tr.settled_vibration(model, values, 4.5, 4000.0).A_bar < 1e-9
    assert tr.settled_vibration(model, values, 4.0, 4000.0).A_bar < 1e-9
    assert tr.settled_vibration(model, values, 2.0, 4000.0).A_bar > 1e-5


def test_ramp_stalls_with_low_race_damping_and_resynchronises_with_high():
    """Figure 15: c_b/m = 0.01 never synchronised by the end of the ramp, 0.1 synchronised."""
    low, high = (tr.run_up("two_plane_ramp", r, 6000.0, samples=6001) for r in (0.01, 0.1))
    assert tr.synchronised_from(low) is None
    assert tr.synchronised_from(high) is not None
    assert np.all(low.end_speeds < 0.995 * low.end_spin)  # behind the rotor at the end


def test_hill_run_up_synchronises_sooner_with_high_race_damping():
    """Figure 16: both synchronise with the Hill profile (45); 0.1 sooner than 0.01."""
    low, high = (tr.run_up("two_plane_hill", r, 3000.0, samples=6001) for r in (0.01, 0.1))
    t_low, t_high = tr.synchronised_from(low), tr.synchronised_from(high)
    assert t_low is not None and t_high is not None and t_high < t_low


@pytest.mark.parametrize("name", ["two_plane_hill", "two_plane_ramp"])
def test_spin_law_is_the_generated_models_spin(name):
    """Omega(t) of `spin_law` (the module's measure spin_rate) = the spin inside the generated rhs: with
    eps = chi = 0 and the balls in opposite pairs at one speed s the rotor is not forced, and (4) gives
    theta_k'' = -c_b (s - Omega)/(m R^2); its angle is the speed's integral."""
    model = load_model(name)
    m, cb = 1e-4, 1e-5
    p = model.params({"epsilon": 0.0, "chi": 0.0, **tr._ball_values(m, cb / m)})
    t = np.array([50.0, 200.0, 700.0, 2500.0, 7000.0])  # (the ramp holds Omega_max after t_ramp = 6000)
    _, speed = tr.spin_law(model, p, t)
    s = 0.7
    y = model.state({"theta_2": math.pi, "theta_4": math.pi,
                     **{f"theta_{k}_dot": s for k in range(1, 5)}})
    k = model.index("theta_1_dot")
    inside = [s + model.module.rhs(tk, y, p)[k] * m / cb for tk in t]
    assert np.allclose(speed, inside, rtol=1e-9, atol=1e-12)
    assert not np.allclose(speed * 1.001, inside, rtol=1e-9, atol=1e-12)
    from scipy.integrate import quad

    angle, _ = tr.spin_law(model, p, t)
    rate = lambda s: float(tr.spin_law(model, p, np.array([s]))[1][0])  # noqa: E731
    assert np.allclose(angle, [quad(rate, 0.0, tk, limit=200)[0] for tk in t], rtol=1e-8)


def test_peaks_refines_a_parabola():
    x = np.linspace(0, 2, 21)
    assert tr.peaks(x, -(x - 1.234) ** 2) == pytest.approx([1.234])


def test_to_rotating_is_the_familys_frame_change():
    """(5)-(6) of the analysis layer = the family's `to_rotating` (SymPy side) at a random state; a frame
    turned the wrong way differs."""
    from adbgen.families.two_plane.transient import to_rotating as family

    fixed, rotating = load_model("two_plane_ramp"), load_model("two_plane_rotating")
    rng = np.random.default_rng(3)
    y = rng.normal(size=fixed.n_states)
    ours = tr.to_rotating(fixed, y, 0.7, 1.3, rotating)
    ref = family(y, fixed.state_names, 0.7, 1.3)
    assert np.allclose(ours, rotating.state(ref), rtol=0, atol=1e-14)
    assert not np.allclose(tr.to_rotating(fixed, y, -0.7, 1.3, rotating), ours, atol=1e-6)


def test_coincident_from_needs_exact_equality():
    t = np.arange(5.0)
    angles = np.zeros((4, 5))
    angles[1, :2] = [1.0, 1e-300]
    run = tr.RunUp("x", 0.1, t, t, angles, angles, t, np.zeros(4), 0.0)
    assert tr.coincident_from(run) == 2.0
    angles[3, -1] = 1e-300  # apart again at the end
    assert tr.coincident_from(run) is None


def test_after_the_ramp_the_coincident_balls_are_held_by_symmetry_only():
    """Figure 15(b): the balls of each race meet exactly; the state they sit on is unstable, and a 1e-9 kick
    of one ball in each race lets the balancer balance (the study of docs/reproduction.md)."""
    o = tr.after_ramp(0.1, t_more=3000.0)
    assert o["coincident_from"] is not None
    assert o["unstable"] == 2 and all(z.real > 0.01 for z in o["leading"])
    assert o["as_is"]["A_end"] > 1e-4
    assert o["kicked"]["A_end"] < 1e-5


def test_floquet_of_B_along_figure_12a():
    """B of two_plane_fixed is a constant solution at every time; its Floquet multipliers: stable at
    Omega = 5, unstable at 4.4 by a gamma_r-odd mode (the one the symmetric start of Figure 12(a) cannot
    excite, the paper's explanation of its brute-force/Figure 11 discrepancy)."""
    from adbgen.families.two_plane.science.exchange import race_swap

    model = load_model("two_plane_fixed")
    values = {"epsilon": 1e-4, "chi": 0.0, "beta": 0.0, **tr._ball_values(1e-4, 0.01)}
    y = tr.balanced_orbit(model, values)
    p = model.params(dict(values, Omega=4.4))
    assert max(np.abs(model.module.rhs(t, y, p)).max() for t in (0.0, 0.3, 1.1)) < 1e-15
    wrong = y.copy()
    wrong[model.index("alpha_2")] += 0.01
    assert np.abs(model.module.rhs(0.3, wrong, p)).max() > 1e-8
    mu, _ = tr.floquet(model, values, 5.0)
    assert np.abs(mu).max() < 1
    mu, V = tr.floquet(model, values, 4.4)
    k = int(np.argmax(np.abs(mu)))
    assert abs(mu[k]) > 1
    P = race_swap(model)
    assert (np.vdot(V[:, k], P @ V[:, k]) / np.vdot(V[:, k], V[:, k])).real == pytest.approx(-1.0)


def test_figure_15b_is_not_balanced_by_its_own_run_nor_by_an_offset_start():
    """The balls of each race meet to the last bit even from a start 1e-6 rad off opposite (A stays 3.87e-4 at
    t = 6000); balls alike only to 1e-6 in mass cannot meet, and A falls below 1e-4 by then (issue 36)."""
    exact = tr.run_up("two_plane_ramp", 0.1, 6000.0, samples=6001, rtol=1e-11)
    off = tr.run_up("two_plane_ramp", 0.1, 6000.0, samples=6001, rtol=1e-11, offset=1e-6)
    mass = tr.run_up("two_plane_ramp", 0.1, 6000.0, samples=6001, rtol=1e-11, mass_spread=1e-6)
    assert exact.A[-1] == pytest.approx(3.87e-4, rel=5e-3) and off.A[-1] == pytest.approx(3.87e-4, rel=5e-3)
    assert tr.coincident_from(off) is not None
    assert tr.coincident_from(mass) is None and mass.A[-1] < 1e-4
