"""benchmarks/machines2020_extension.py: its cases and their t_end (the sweeps need the study's stick/slip model,
whose first generation is minutes, and run with the command)."""

from __future__ import annotations

import pytest

from benchmarks import friction_studies as fs
from benchmarks import machines2020 as m20
from benchmarks import machines2020_extension as ext


@pytest.fixture(scope="module")
def base():
    return fs.scene_values(m20.SCENE)


def test_each_case_changes_only_the_reduction(base):
    cases = ext.cases(base)
    assert len({c["name"] for c in cases}) == len(ext.CASES)
    for case, (depth, plateau, recovery) in zip(cases, ext.CASES):
        v = case["values"]
        assert (v["depth"], v["t_plateau"], v["recovery_rate"]) == (depth, plateau, recovery)
        assert {k: x for k, x in v.items() if k not in ("depth", "t_plateau", "recovery_rate")} == \
            {k: x for k, x in base.items() if k not in ("depth", "t_plateau", "recovery_rate")}


def test_t_end_is_the_grids_unless_the_schedule_ends_later(base):
    assert ext.t_end_for({**base, "depth": 0.5, "t_plateau": 0.5, "recovery_rate": 5.0}) == ext.GRID_T_END
    # depth 0.5 of 100 rad/s back at 1 rad/s^2: 50 s of recovery after 4 + 2.5 + 0.5 s
    slow = {**base, "depth": 0.5, "t_plateau": 0.5, "recovery_rate": 1.0}
    assert ext.t_end_for(slow) == pytest.approx(4.0 + 2.5 + 0.5 + 50.0 + m20.SETTLE)
    # the grid's own longest schedule gives its t_end: the constant is the committed study's
    longest = {**base, "depth": max(m20.DEPTHS), "t_plateau": max(m20.PLATEAUS)}
    assert fs.schedule_end(longest) + m20.SETTLE == ext.GRID_T_END
