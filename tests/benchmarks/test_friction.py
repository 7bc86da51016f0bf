"""`adbgen bench friction` (issue 37's speed target): the two sweeps' set-up, the target decided only on the
full 10,000 starts, and the page saying so.  No timing is asserted."""

from __future__ import annotations

import tomllib

import pytest

from benchmarks import friction
from benchmarks.registry import REGISTRY


def test_the_benchmark_is_registered_and_its_scene_has_stiction():
    assert REGISTRY["friction"] == "benchmarks.friction:BENCHMARK"
    scene = tomllib.loads(friction.SCENE.read_text())
    assert scene["static_friction"] > scene["rolling_resistance"] > 0


def test_the_sweep_without_stiction_is_the_same_scene_without_friction():
    text = friction.SCENE.read_text()
    free = tomllib.loads(friction.frictionless(text))
    full = tomllib.loads(text)
    assert not set(friction.FRICTION_KEYS) & set(free)
    assert {k: v for k, v in full.items() if k not in friction.FRICTION_KEYS} == free
    # negative control: a scene that is not changed keeps its friction (the comparison would be void)
    assert set(friction.FRICTION_KEYS) <= set(full)


@pytest.mark.parametrize("asked, points", [(10_000, 10_000), (400, 400), (10, 9), (3, 4)])
def test_the_starts_are_a_square_grid(asked, points):
    n, axes = friction.grid(asked)
    assert n == points and len(axes) == 2 and all(a.endswith(f":{round(points ** 0.5)}") for a in axes)


@pytest.mark.parametrize("ratio, points, met", [
    (2.0, 10_000, True),
    (3.5, 10_000, False),  # negative control: above 3x fails
    (2.0, 400, None),      # a reduced run decides nothing
])
def test_the_target_is_decided_on_the_full_sweep_only(ratio, points, met):
    assert friction.verdict(ratio, points) is met


def _result(points):
    dist = {"at_rest": points - 1, "not_at_rest": 1, "failed": 0,
            "quantiles": {"50": 1e-4, "90": 2e-4, "99": 3e-4, "max": 4e-4}, "histogram": {"edges": [], "counts": []}}
    return {"date": "2026-11-29T01:00:00", "machine": {"cpu": "cpu", "load_average_at_start": [1, 1, 1],
                                                       "load_average_at_end": [1, 1, 1]},
            "scene": "benchmarks/friction_scene.toml", "rotor": friction.ROTOR, "friction": friction.FRICTION,
            "grid": friction.grid(points)[1], "starts": points, "starts_asked": points,
            "default_starts": friction.DEFAULT_STARTS, "reduced": points < friction.DEFAULT_STARTS, "t_end": 10.0,
            "with_stiction": {"engine": "hybrid-dop853", "wall_s": 2.0, "integrated": points, "residual": dist},
            "without_stiction": {"engine": "auto", "wall_s": 1.0, "integrated": points},
            "ratio": 2.0, "target": "ratio <= 3", "target_met": friction.verdict(2.0, points)}


def test_the_page_says_a_reduced_run_and_counts_the_runs_not_at_rest_apart():
    text = friction.page(_result(400))
    assert "Reduced run: 400 starts" in text and "not decided by this run" in text
    assert "1 with a ball still slipping" in text and "max 0.0004" in text
    full = friction.page(_result(10_000))
    assert "Reduced run" not in full and "; met)" in full  # negative control: the full run is not called reduced


def test_the_page_calls_a_run_quiet_only_when_nothing_else_ran_and_says_the_median():
    loaded = friction.page(_result(10_000))  # load average 1 at the start: something else was running
    assert "not a quiet machine" in loaded and "indicative only" in loaded
    quiet = _result(10_000)
    quiet["machine"]["load_average_at_start"] = [0.1, 0.5, 0.9]
    quiet.update(repeats=3)
    quiet["with_stiction"]["runs_wall_s"], quiet["without_stiction"]["runs_wall_s"] = [2.0, 2.1, 1.9], [1.0, 1.1, 0.9]
    text = friction.page(quiet)
    assert "nothing else running on the machine at the start" in text and "indicative only" not in text
    assert "median of 3 alternated runs" in text and "--repeats 3" in text
