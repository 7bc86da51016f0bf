"""Periodically forced models on the command line (adbgen.analysis.auto_orbits, issue 24 item 3).

`stability` on a forced model gives its periodic response and the Floquet multipliers; `continue`
runs both stages of its AUTO-07p files.  Checked here: the response is a closed orbit of the generated
forced model (a direct integration over one period returns to it), its multipliers agree with AUTO's
own stability along the branch and with the transient (the response of a stable orbit attracts a
perturbed start), a planted wrong orbit is refused (negative control), and the stages reach their ends.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from adbgen.analysis import auto_orbits
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.cli import main

from analysis_helpers import require_auto  # this folder is on sys.path: see conftest.py


@pytest.fixture(scope="module")
def fixed():
    require_auto()
    return load_model("single_plane_fixed_n2")


@pytest.fixture(scope="module")
def response(fixed):
    return auto_orbits.forced_response(fixed, fixed.params())


def test_the_files_stages_are_read(fixed):
    st = auto_orbits.stages(fixed)
    assert fixed.param_names[st.first] == "g" and st.first_target == pytest.approx(9.80665)
    assert fixed.param_names[st.second] == "omega" and st.start_parameters[st.first] == 0.0
    assert np.allclose(st.start[-2:], [0.0, 1.0])  # the oscillator at t = 0


def test_the_response_is_a_closed_orbit_of_the_forced_model(fixed, response):
    p = fixed.params()
    sol = solve_ivp(lambda t, y: fixed.module.rhs(t, y, p), (response.t0, response.t0 + response.period), response.y0,
                    method="DOP853", rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(sol.y[:, -1] - response.y0)) < 1e-9
    assert response.period == pytest.approx(2 * math.pi / 400)
    assert response.route and response.route[0]["parameter"] == "g"  # stage 1 carried it from g = 0
    # gravity sags the rotor: about M g / k_Y = 0.8 mm, under the 0.9 mm r_max that the issue saw
    assert 7e-4 < response.amplitude_max < 1.0e-3


def test_a_stable_response_attracts_the_transient(fixed, response):
    """The multipliers say stable at the defaults; a perturbed start falls back onto the orbit, and
    over the last thousand periods at a rate between the smallest and the largest multiplier's."""
    assert response.classification == "stable" and np.max(np.abs(response.multipliers)) < 1
    p = fixed.params()
    y0 = response.y0 + 1e-4 * np.r_[1.0, -1.0, 0.02, -0.02, np.zeros(fixed.n_states - 4)]
    ts = response.t0 + response.period * np.array([0, 1000, 2000])
    sol = solve_ivp(lambda t, y: fixed.module.rhs(t, y, p), (ts[0], ts[-1]), y0, method="DOP853", rtol=1e-11,
                    atol=1e-14, t_eval=ts)
    gaps = np.max(np.abs(sol.y - response.y0[:, None]), axis=0)
    assert gaps[2] < 1e-4 * gaps[0]
    size = np.abs(response.multipliers)
    assert size.min() ** 1000 / 10 < gaps[2] / gaps[1] < 10 * size.max() ** 1000, (gaps, size)


def test_the_multipliers_cross_where_auto_loses_stability(fixed):
    """Continuing omega down from 400 rad/s the response loses stability at a torus bifurcation
    (a complex pair through the unit circle); the period map's multipliers agree on each side."""
    run = auto_orbits.continue_orbit(fixed, "omega", fixed.params(), to=180.0)
    out = run.to_json()
    assert out["complete"] and [s["parameter"] for s in out["stages"]] == ["g", "omega"]
    crossings = [pt for pt in out["points"] if pt["type"] == "TR"] + out["unlabelled"]
    assert len(crossings) == 1
    at = crossings[0]["omega"]
    assert 195 < at < 206
    for omega, verdict in ((at + 3, "stable"), (at - 3, "unstable")):
        r = auto_orbits.forced_response(fixed, fixed.params({"omega": omega}))
        assert r.classification == verdict, (omega, np.abs(r.multipliers))
        if verdict == "unstable":
            lost = r.multipliers[np.abs(r.multipliers) > 1]
            assert len(lost) == 2 and abs(lost[0].imag) > 1e-3  # a complex pair: a torus (Neimark-Sacker)


def test_a_start_that_is_no_orbit_is_refused(fixed):
    """Negative control: the AUTO files' start orbit is the balanced state at eps = 0.5 mm; with eps
    doubled the balls no longer balance the rotor and the start is no orbit."""
    with pytest.raises(AnalysisError, match=r"with eps changed it is no orbit"):
        auto_orbits.forced_response(fixed, fixed.params({"eps": 1e-3}))


def test_the_command_line_on_forced_models(fixed, capsys):
    code = main(["stability", "single_plane_fixed_n2", "--set", "omega=300rad/s", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["kind"] == "periodic orbit (forced response)" and out["classification"] == "stable"
    assert out["period"] == pytest.approx(2 * math.pi / 300) and len(out["multipliers"]) == fixed.n_states
    code = main(["continue", "single_plane_fixed_n2", "--par", "omega", "--to", "350", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["complete"] and out["points"][-1]["type"] == "UZ"
    assert out["points"][-1]["omega"] == pytest.approx(350, rel=1e-7) and out["units"]["omega"] == "rad/s"
    assert main(["stability", "single_plane_fixed_n2", "--scan", "omega=400:300"]) == 2
    assert "adbgen continue" in capsys.readouterr().err


def test_a_continuum_of_orbits_stops_auto_and_says_so(tmp_path, capsys):
    """n = 3 on an anisotropic support: the balanced orbits are a one-dimensional continuum; stability
    reports one multiplier 1 along it and the rest transverse; AUTO-07p cannot continue it (exit 3)."""
    require_auto()
    scene = tmp_path / "three.toml"
    scene.write_text("n = 3\nball_mass = [0.05, 0.04, 0.03]\nstiffness = [1.0e4, 1.2e4]\ndamping = [2.0, 2.4]\n")
    assert main(["stability", "--scene", str(scene), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["neutral_multipliers"]) == 1 and out["classification"] == "stable"
    assert main(["continue", "--scene", str(scene), "--par", "omega", "--to", "300"]) == 3
    err = capsys.readouterr().err
    assert err.startswith("adbgen: ended early:") and "continuum of balanced orbits" in err


def test_a_known_orbit_needs_no_auto_route():
    """`response_at` from the flexible Jeffcott model's closed-form balanced state (exact at every omega)
    gives the multipliers `forced_response` finds after AUTO-07p carried its start orbit from 400 to
    300 rad/s.  Negative control: the same start at 310 rad/s gives other multipliers (the comparison
    sees a 3 % change of the forcing)."""
    require_auto()
    flex = load_model("flexible_jeffcott_n2")
    p = flex.params({"omega": 300.0})
    routed = auto_orbits.forced_response(flex, p)
    direct = auto_orbits.response_at(flex, p, flex.steady_state("B", p), 0.0)
    assert routed.route and not direct.route
    gap = np.remainder(direct.y0 - routed.y0 + math.pi, 2 * math.pi) - math.pi  # the angles modulo 2 pi
    assert np.max(np.abs(gap)) < 1e-9
    key = lambda z: (round(abs(z), 6), round(z.imag, 6))  # noqa: E731
    a, b = sorted(routed.multipliers, key=key), sorted(direct.multipliers, key=key)
    assert np.max(np.abs(np.array(a) - np.array(b))) < 1e-8
    assert direct.classification == routed.classification
    assert direct.margin.value == pytest.approx(routed.margin.value, abs=1e-8)
    p2 = flex.params({"omega": 310.0})
    other = sorted(auto_orbits.response_at(flex, p2, flex.steady_state("B", p2), 0.0).multipliers, key=key)
    assert np.max(np.abs(np.array(other) - np.array(b))) > 1e-3
