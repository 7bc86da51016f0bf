"""`adbgen bench design` (issue 39's speed target): the design timed is a two-parameter one on the thesis
model, the target is decided only on two cores, and the warm-up is not counted.  No timing is asserted."""

from __future__ import annotations

import pytest

from benchmarks import design
from benchmarks.registry import REGISTRY


def test_the_benchmark_is_registered_and_times_a_two_parameter_thesis_design():
    assert REGISTRY["design"] == "benchmarks.design:BENCHMARK"
    assert design.DESIGN[0].startswith("thesis_")
    assert design.varied(design.DESIGN) == ["beta", "mu"]
    # negative control: a one-parameter design is not what the target names
    assert design.varied(("thesis_rotating_n3", "--vary", "beta=0:1")) == ["beta"]


@pytest.mark.parametrize("seconds, cores, passed", [
    ([50.0, 70.0, 60.0], 2, True),
    ([130.0, 125.0, 60.0], 2, False),  # negative control: a median above 2 minutes fails
    ([50.0], 8, None),                 # more cores than the target's machine: not decided
    ([50.0], None, None),
])
def test_verdict_is_the_median_against_two_minutes_on_two_cores(seconds, cores, passed):
    row = design.verdict(seconds, cores)
    assert row["passed"] is passed
    assert row["median_s"] == sorted(seconds)[len(seconds) // 2]


def test_bench_runs_one_warm_up_then_the_timed_runs(monkeypatch):
    times = iter([1000.0, 3.0, 5.0, 4.0])  # the warm-up's 1000 s is not counted
    calls = []

    def fake():
        calls.append(1)
        return next(times), {"method": "chart", "feasible": True, "other": 1}
    monkeypatch.setattr(design, "run_once", fake)
    monkeypatch.setattr(design.os, "cpu_count", lambda: 2)
    out = design.bench_design(3, progress=lambda s: None)
    assert len(calls) == 4
    assert out["targets"][0]["runs_s"] == [3.0, 5.0, 4.0] and out["targets"][0]["median_s"] == 4.0
    assert out["answer"] == {"method": "chart", "feasible": True}
    assert "load_average_at_start" in out["machine"] and "load_average_at_end" in out["machine"]


def test_a_planted_one_parameter_design_is_refused(monkeypatch):
    monkeypatch.setattr(design, "DESIGN", ("thesis_rotating_n3", "--vary", "beta=0.01:1", "--json"))
    with pytest.raises(ValueError, match="two parameters"):
        design.bench_design(1, progress=lambda s: None)
