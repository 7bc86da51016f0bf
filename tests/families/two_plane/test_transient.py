"""Run-ups: the fixed frame through a ramp agrees with the rotating frame afterwards; the Hill profile (45)."""

import numpy as np

from adbgen.families.two_plane import transient as tr
from adbgen.families.two_plane.scene import TwoPlaneScene


def test_fixed_frame_after_a_ramp_equals_the_rotating_frame():
    """Ramp to Omega = 3 in 30 time units, then constant: the fixed-frame run, turned into the rotating frame
    at t = 30 and t = 40, equals a rotating-frame run started at t = 30 (max difference <= 1e-8)."""
    common = {"misalignment": 0.002, "imbalance_phase": 0.7}
    ramp = TwoPlaneScene.from_mapping({**common, "speed": {"law": "ramp", "omega_max": 3.0, "t_ramp": 30.0}})
    const = TwoPlaneScene.from_mapping({**common, "speed": {"law": "constant", "omega": 3.0}})
    f, g = tr.fixed_frame_rhs(ramp), tr.rotating_frame_rhs(const)
    y0 = np.zeros(2 * f.n)
    y0[f.index("theta_3")] = y0[f.index("theta_4")] = np.pi
    run = tr.simulate(f, y0, (0, 40.0), t_eval=[30.0, 40.0], rtol=1e-11)
    angle = lambda t: 3.0 * (t - 15.0)  # theta_0 after the ramp  # noqa: E731
    start = tr.to_rotating(run.y[:, 0], run.state_names, angle(30.0), 3.0)
    rot = tr.simulate(g, [start[n] for n in g.state_names], (30.0, 40.0), t_eval=[40.0], rtol=1e-11)
    end = tr.to_rotating(run.y[:, 1], run.state_names, angle(40.0), 3.0)
    assert np.abs(np.array([end[n] for n in g.state_names]) - rot.y[:, 0]).max() <= 1e-8


def _hill_run(cb_over_m: float):
    """Section 6: dynamic imbalance eps/R = chi = 5e-5, beta = 1, m/M = eps/R + chi, Hill profile (45) with
    (3.6, 200, 3), rotor at rest, balls at rest on opposite sides of each race."""
    m = 1e-4
    race = lambda z: {"z": z, "radius": 1.0, "masses": [m, m], "damping": cb_over_m * m}  # noqa: E731
    scene = TwoPlaneScene.from_mapping({"eccentricity": 5e-5, "misalignment": 5e-5, "imbalance_phase": 1.0,
                                        "races": [race(2.0), race(-2.0)], "speed": {"law": "hill"}})
    f = tr.fixed_frame_rhs(scene)
    y0 = np.zeros(2 * f.n)
    y0[f.index("theta_2")] = y0[f.index("theta_4")] = np.pi
    grid = np.array([250.0, 300.0])
    run = tr.simulate(f, y0, (0, 300.0), t_eval=grid, rtol=1e-9)
    omega = 3.6 * grid**3 / (200.0**3 + grid**3)
    speeds = np.array([run[f"theta_{k}_dot"] for k in range(1, 5)])
    return omega, speeds


def test_hill_run_up_balls_lag_and_race_damping_helps():
    """Paper section 6, Figure 16: past the critical speeds (tb = 250) the balls lag the rotor; with the higher
    race damping c_b/m = 0.1 they are much closer to the rotor speed (lag at tb = 300 at least 3x smaller)."""
    lags = {}
    for cb in (0.01, 0.1):
        omega, speeds = _hill_run(cb)
        assert np.all(speeds < omega), (cb, speeds, omega)
        lags[cb] = float(np.mean(omega[1] - speeds[:, 1]))
    assert lags[0.1] * 3 < lags[0.01], lags
