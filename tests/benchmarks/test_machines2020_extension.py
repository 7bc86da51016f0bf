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


def test_the_finer_search_is_depth_05_to_06_at_a_05_s_plateau_and_new():
    assert set(ext.FINER).isdisjoint(ext.FIRST)
    assert ext.CASES == ext.FIRST + ext.FINER
    assert all(0.5 <= d <= 0.6 and p == 0.5 and 1.5 <= a <= 3.0 for d, p, a in ext.FINER)


def test_parse_case_reads_three_numbers_and_refuses_the_rest():
    assert ext.parse_case("0.55,0.5,2") == (0.55, 0.5, 2.0)
    for bad in ("0.55,0.5", "a,b,c", "1.2,0.5,2", "0.5,-1,2", "0.5,0.5,0"):
        with pytest.raises(ValueError, match="--case"):
            ext.parse_case(bad)


def _run(names, target=5e-5, wall=1.0):
    return {"study": "machines2020_extension", "model": "m", "values": {"k": 1.0}, "starts": 4, "grid": ["a", "b"],
            "rtol": 1e-9, "atol": 1e-13, "target_m": target, "wall_s": wall,
            "cases": [{"name": n, "feasible": n.endswith("ok"), "r": i} for i, n in enumerate(names)]}


def test_merge_keeps_old_cases_replaces_same_name_and_appends_new():
    old, new = _run(["a", "b", "c"]), _run(["b ok", "b", "d"], wall=2.0)
    new["cases"][1]["r"] = 99
    merged = ext.merge(old, new)
    assert [c["name"] for c in merged["cases"]] == ["a", "b", "c", "b ok", "d"]
    assert merged["cases"][1]["r"] == 99
    assert merged["feasible_reductions"] == ["b ok"]
    assert merged["wall_s"] == 3.0


def test_merge_refuses_another_setup():
    with pytest.raises(ValueError, match="target_m"):
        ext.merge(_run(["a"]), _run(["b"], target=1e-4))


def test_main_refuses_a_bad_case_in_one_line(tmp_path, capsys):
    assert ext.main(["--out", str(tmp_path), "--case", "0.5,0.5"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --case") and "\n" not in err
    assert not (tmp_path / "machines2020_extension.json").exists()


def test_thesis_rotor_is_the_scenes_scaling(base):
    # at the balls opposite each other (0 and pi) the balls' imbalance cancels: r is the rotor's response without
    # balancing, free_response's dimensional formula (thesis (2.27)); a wrong Omega, zeta, delta or mu moves it
    from adbgen.families.single_plane.science import stiction_band as sb
    r = abs(sb.displacement(ext.thesis_rotor(base), [0.0, 3.141592653589793])) * base["R"]
    assert r == pytest.approx(fs.free_response(base), rel=1e-12)


def test_stuck_band_holds_the_balanced_state_and_reports_metres(base):
    band = ext.stuck_band(base, 1e-4, points=181)
    assert band["r_min_m"] < 0.01 * band["r_max_m"]  # the balanced state (r = 0) is on the band
    assert 0.0 < band["share_below_target"] < 1.0 and 0.0 < band["area_fraction"] < 1.0
    assert band["theta_star_deg"] == pytest.approx(120.0)  # cos theta* = -delta / (2 mu) = -1/2 here
