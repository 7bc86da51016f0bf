"""Units of a generated model and values with units (adbgen.analysis.units, issue 24 item 1)."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from hypothesis import given, settings, strategies as st

from adbgen.analysis import units
from adbgen.analysis.loading import AnalysisError, load_model


@pytest.fixture(scope="module")
def thesis():
    return load_model("thesis_rotating_n2")


@pytest.fixture(scope="module")
def si():
    return load_model("single_plane_fixed_n2")


def test_units_from_the_module(thesis, si):
    t, s = units.units(thesis), units.units(si)
    assert (t.time, t.length, t.states["phi_1"], t.scales) == ("1", "1", "rad", {"eccentricity": "delta", "speed": "Omega"})
    assert (s.time, s.length, s.states["X_dot"], s.states["phi_1_dot"]) == ("s", "m", "m/s", "rad/s")
    assert s.scales == {"eccentricity": "eps", "speed": "omega"} and s.params["omega"] == "rad/s"


@pytest.mark.parametrize("text, unit, value", [
    ("300rad/s", "rad/s", 300.0), ("3000rpm", "rad/s", 100 * math.pi), ("3000 rpm", "rad/s", 100 * math.pi),
    ("0.5mm", "m", 5e-4), ("90deg", "rad", math.pi / 2), ("3*pi/4", "rad", 3 * math.pi / 4), ("1e4", "N/m", 1e4),
    ("10 kN/m", "N/m", 1e4), ("50 g", "kg", 0.05), ("2", "1", 2.0),
])
def test_quantities_convert_to_the_models_unit(text, unit, value):
    assert units.quantity(text, unit, "--set x") == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text, unit, message", [
    ("300rad/s", "1", "is dimensionless: give a number"), ("20kg", "s", "is not in s"), ("1 furlongs/fortnight", "m", "not in m"),
    ("3 blarg", "m", "cannot read"), ("1/0 m", "m", "cannot read"), ("nan", "m", "cannot read 'nan'"),
    ("nan m", "m", "not a finite number"), ("1e400 m", "m", "not a finite number"),
])
def test_bad_quantities_are_one_line(text, unit, message):
    with pytest.raises(AnalysisError, match=message) as err:
        units.quantity(text, unit, "--set x")
    assert "\n" not in str(err.value)


def test_durations_in_time_and_revolutions(thesis, si):
    p = si.params()
    assert units.duration("20s", si, p) == 20.0 and units.duration("2 min", si, p) == 120.0
    assert units.duration("640rev", si, p) == pytest.approx(640 * 2 * math.pi / 400)
    assert units.duration("1000", thesis, thesis.params()) == 1000.0
    assert units.duration("2 turn", thesis, thesis.params({"Omega": 2.0})) == pytest.approx(2 * math.pi)
    with pytest.raises(AnalysisError, match="dimensionless time"):
        units.duration("20s", thesis, thesis.params())


def test_defaults_scale_with_the_model(thesis, si):
    """The thesis keeps its t = 1000 and threshold 1e-3 exactly; the SI model gets 10 s at 400 rad/s
    and a tenth of its 0.5 mm eccentricity (not 1000 s and 1 mm, the issue's finding)."""
    assert units.default_t_end(thesis, thesis.params())[0] == 1000.0
    assert units.default_threshold(thesis, thesis.params())[0] == 1e-3
    assert units.default_t_end(si, si.params())[0] == 10.0
    assert units.default_threshold(si, si.params())[0] == 5e-5
    assert units.default_t_end(si, si.params({"omega": 200.0}))[0] == 20.0  # the same number of revolutions


@settings(max_examples=50, deadline=None)
@given(st.floats(1e-6, 1e6), st.sampled_from([("mm", 1e-3), ("um", 1e-6), ("km", 1e3), ("cm", 1e-2)]))
def test_lengths_round_trip(value, prefix):
    suffix, factor = prefix
    assert units.quantity(f"{value!r} {suffix}", "m", "x") == pytest.approx(value * factor, rel=1e-12)


@pytest.mark.parametrize("value, unit, text", [
    (0.0104, "m", "10.4 mm"), (5.46e-5, "m", "54.6 \u00b5m"), (5.458, "s", "5.458 s"), (1000.0, "1", "1000"),
    (400.0, "rad/s", "400 rad/s"), (None, "m", "-"), (float("nan"), "s", "-"),
])
def test_show(value, unit, text):
    assert units.show(value, unit) == text


def test_domains_refuse_what_a_scene_refuses(thesis, si):
    with pytest.raises(AnalysisError, match="--set mu: must be positive, got -0.05"):
        units.params(thesis, {"mu": -0.05})
    with pytest.raises(AnalysisError, match="--set m: must be positive"):
        units.params(si, {"m": 0.0})
    with pytest.raises(AnalysisError, match="--set k_X: must be non-negative"):
        units.params(si, {"k_X": -1.0})
    assert units.params(si, {"k_X": 0.0, "m": 0.01})[si.param_names.index("m")] == 0.01  # negative control


def test_pint_is_imported_only_for_a_unit():
    """The command line's start-up: a plain number never imports pint."""
    code = ("import sys; from adbgen.analysis import units; units.quantity('3*pi/4', 'rad', 'x'); "
            "a = 'pint' in sys.modules; units.quantity('3 mm', 'm', 'x'); print(a, 'pint' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.stdout.split() == ["False", "True"], r.stderr
