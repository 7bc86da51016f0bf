"""The example rotor run up through its first critical speeds (adbgen.ross.run_up, issue 38 "what must be
shown": a transient through the first bending critical): the speed law the run follows, the band its peak
must fall in, and the committed runs' numbers (docs/figures/flexible_run_up.json, drawn by
`python3 -m adbgen.ross.run_up docs/figures`)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from adbgen.ross import run_up as ru

RECORD = Path(__file__).parents[2] / "docs" / "figures" / "flexible_run_up.json"


def test_speed_at_is_the_ramp_then_the_hold():
    t = np.array([0.0, ru.ramp_time() / 2, ru.ramp_time(), ru.ramp_time() + 10.0])
    assert ru.speed_at(t).tolist() == [ru.OMEGA_START, (ru.OMEGA_START + ru.OMEGA) / 2, ru.OMEGA, ru.OMEGA]


def test_critical_band_widens_with_the_rate():
    """The band: the pair's half-power half-widths, plus the lag rate / (zeta w) above the upper one; a faster
    ramp moves its top up (and only its top)."""
    low, high = ru.critical_band(90.0, 100.0, 0.02, 0.01, 0.5)
    assert low == pytest.approx(88.2) and high == pytest.approx(101.0 + 0.5)
    fast = ru.critical_band(90.0, 100.0, 0.02, 0.01, 5.0)
    assert fast[0] == low and fast[1] == pytest.approx(101.0 + 5.0)


def reduced(run: dict, reference: dict, factor: float = 0.5) -> bool:
    """The balancer's effect after the critical speeds: the node's displacement at the end of the ramp (160
    rad/s, above the pair and the balanced state's stability boundary, 111 rad/s) and at the end of the hold
    below `factor` x the reference run's there."""
    return all(run[key] < factor * reference[key] for key in ("node_at_ramp_end", "node_last_window"))


@pytest.fixture(scope="module")
def record():
    return json.loads(RECORD.read_text())


def _runs(record):
    trapped, carried, absent = (next(r for r in record["runs"] if (r["balls"], r["drag"]) == key)
                                for key in ((True, 1.0), (True, 100.0), (False, 1.0)))
    return trapped, carried, absent


def test_the_committed_run_up_peaks_at_the_first_critical_pair(record):
    """The balancer-free run and the balls with drag 100 D peak inside the band the ramp rate allows around the
    first critical pair (91.89 B, 96.37 F rad/s); the run is the module's (its rate, its ends).  Negative
    control: the band of a critical pair 10 % higher does not hold the peaks."""
    assert record["rate"] == ru.RATE and record["omega_start"] == ru.OMEGA_START and record["omega"] == ru.OMEGA
    low, high = record["peak_band"]
    pair = [c["speed"] for c in record["critical_speeds"]]
    assert (low, high) == pytest.approx(ru.critical_band(*pair, *record["damping_ratios"], record["rate"]))
    wrong = ru.critical_band(*(1.1 * np.array(pair)), *record["damping_ratios"], record["rate"])
    assert all(r["status"] == "success" for r in record["runs"])
    for run in _runs(record)[1:]:
        assert low <= run["peak_speed"] <= high
        assert not wrong[0] <= run["peak_speed"] <= wrong[1]


def test_the_balls_reduce_the_node_after_the_critical_speeds_and_without_them_it_stays(record):
    """With drag 100 D the balls bring the node below half the balancer-free run's after the critical pair;
    the balancer-free run itself (negative control) does not pass, and neither do the balls with section 5's
    drag D, which the node's whirl keeps turning near the critical pair (their mean speed at the end of the
    hold within 5 % of the backward critical speed, not the spin's 160 rad/s)."""
    trapped, carried, absent = _runs(record)
    assert reduced(carried, absent) and not reduced(absent, absent) and not reduced(trapped, absent)
    assert abs(trapped["ball_speed_end"] - record["critical_speeds"][0]["speed"]) < 0.05 * record["critical_speeds"][0]["speed"]
    assert carried["ball_speed_end"] == pytest.approx(record["omega"], rel=1e-6)
