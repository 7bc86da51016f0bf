"""`adbgen bench tolerance` (issue 35 item 1): the held-out scenes are the seeded generator's, cover what
the issue asks (both families, thesis and SI units, isotropic and anisotropic supports, forced, run-up and
torque-driven, n = 2..6, at least 40) and repeat neither learning problem; the ratio is the error in
tolerance units, and a cell whose references disagree is not counted."""

from __future__ import annotations

import json

import numpy as np
import pytest

from benchmarks import tolerance, tolerance_scenes
from benchmarks.precision import PROBLEMS


def test_the_committed_scenes_are_the_generators_and_a_changed_one_is_caught(tmp_path):
    committed = tolerance_scenes.load()
    assert committed == tolerance_scenes.generate(tolerance_scenes.SEED)
    assert committed != tolerance_scenes.generate(tolerance_scenes.SEED + 1)  # negative control: another seed
    tolerance_scenes.write_files(folder=tmp_path)
    first = sorted(tmp_path.glob("*.json"))[0]
    planted = json.loads(first.read_text())
    planted["t_end"] *= 2
    first.write_text(json.dumps(planted))
    assert tolerance_scenes.load(tmp_path) != committed


def test_the_scenes_cover_the_issue_and_none_is_a_learning_problem():
    scenes = tolerance_scenes.load()
    assert len(scenes) >= 40
    assert {s["family"] for s in scenes} == {"single_plane", "two_plane"}
    assert {s["units"] for s in scenes} == {"thesis", "SI"}
    assert {s["support"] for s in scenes} == {"isotropic", "anisotropic"}
    assert {s["drive"] for s in scenes} == {"forced", "run-up", "torque"}
    assert {s["n"] for s in scenes} == {2, 3, 4, 5, 6}
    learning = [(p.problem.model, p.problem.params, p.problem.y0) for p in PROBLEMS.values()]
    assert all((s.get("model"), s["set"], s["y0"]) not in learning for s in scenes)
    from benchmarks.engine_table import CHECK_SCENES

    held_in = [(c.get("model"), c.get("set", {}), c["y0"]) for c in CHECK_SCENES]
    assert all((s.get("model"), s["set"], s["y0"]) not in held_in for s in scenes)
    a = PROBLEMS["A"].problem  # negative control: problem A as a scene is caught
    assert (a.model, a.params, a.y0) in learning
    for s in scenes:
        if "scene" in s:
            assert (tolerance_scenes.FOLDER / s["scene"]).is_file()


def test_ratio_is_the_error_in_tolerance_units():
    y_ref = np.array([1.0, 0.0, -100.0])
    assert tolerance.ratio(y_ref, y_ref, 1e-8, 1e-10) == 0.0
    # 1e-10 off a zero component is one atol; 1e-6 off -100 is one rtol x 100 (+ atol)
    assert tolerance.ratio(y_ref + [0, 1e-10, 0], y_ref, 1e-8, 1e-10) == pytest.approx(1.0)
    assert tolerance.ratio(y_ref + [0, 0, 1e-6], y_ref, 1e-8, 1e-10) == pytest.approx(1e-6 / (1e-10 + 1e-6))
    assert tolerance.ratio(y_ref + [0, 1e-9, 0], y_ref, 1e-8, 1e-10) > tolerance.TARGET - 1e-9
    assert tolerance.t_dec_ratio(None, None, 1e-8, 100.0) is None
    assert tolerance.t_dec_ratio(5.0, None, 1e-8, 100.0) == float("inf")
    assert tolerance.t_dec_ratio(50.0 + 1e-6, 50.0, 1e-8, 100.0) == pytest.approx(1.0)


def test_summary_counts_decided_cells_only():
    scene = {"family": "two_plane", "units": "thesis", "drive": "torque"}
    cells = [{"rtol": 1e-6, "ratio": 3.0, "decided": True, "reference_ratio": 1e-3},
             {"rtol": 1e-12, "ratio": 500.0, "decided": False, "reference_ratio": 60.0}]
    s = tolerance.summary({"x": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE}})
    assert s["worst"] == 3.0 and s["met"] and s["over_target"] == []
    assert s["missed_beyond_reference"] == []  # 500 is within 10x the references' disagreement of 60
    cells[1]["reference_ratio"] = 20.0  # undecided still, but the engine misses 25x farther than they differ
    s = tolerance.summary({"x": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE}})
    assert s["met"] and s["missed_beyond_reference"][0]["ratio"] == 500.0
    cells[1]["decided"] = True  # negative control: the same cell, decided, misses the target
    s = tolerance.summary({"x": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE}})
    assert s["worst"] == 500.0 and not s["met"] and s["over_target"][0]["rtol"] == 1e-12


def test_the_page_shows_each_scene_and_marks_undecided_cells():
    scene = {"family": "two_plane", "units": "thesis", "drive": "torque"}
    cells = [{"rtol": 1e-6, "ratio": 3.0, "decided": True, "status": "success"},
             {"rtol": 1e-12, "ratio": 500.0, "decided": False, "status": "success"}]
    result = {"scenes": {"36_two_plane_torque": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE}}, "rtols": [1e-6, 1e-12],
              "reference": {"engine": "cyrk-vern8", "rtol": 1e-14, "atol": 1e-18, "limit": 1.0,
                            "check": {"engine": "taylor", "order": 20, "step_factor": 1.0}},
              "machine": {}, "date": "d", "engine": "auto", "seed": 35, "atol_ratio": 1e-2, "target": 10.0}
    text = tolerance.page(result)
    assert "| 36_two_plane_torque | 3 | (500) |" in text and "| two_plane / thesis / torque | 3 |" in text
    assert "Decided cells: 1 of 2; scenes without one (their" in text and "every rtol, so they grade nothing): 0." in text
    cells[0]["decided"] = False  # negative control: a scene with no decided cell is named
    assert "every rtol, so they grade nothing): 1: 36_two_plane_torque." in tolerance.page(result)


def test_the_page_shows_a_recorded_diagnosis_and_only_then():
    scene = {"family": "single_plane", "units": "thesis", "drive": "forced"}
    result = {"scenes": {"00_x": {"scene": scene, "cells": [], "reference_rule": tolerance.RULE}}, "rtols": [1e-4],
              "reference": {"engine": "cyrk-vern8", "rtol": 1e-14, "atol": 1e-18, "limit": 1.0,
                            "check": {"engine": "taylor", "order": 20, "step_factor": 1.0}},
              "machine": {}, "date": "d", "engine": "auto", "seed": 35, "atol_ratio": 1e-2, "target": 10.0}
    assert "## Why cells miss" not in tolerance.page(result)  # negative control: nothing recorded, no section
    runs = [{"t_end": 1000.0, "variant": "picked", "order": 10, "step_factor": 2.5, "n_steps": 4812, "ratio": 97.6,
             "reference_ratio": 2e-5, "nominal_error": 9e-6, "amplification": 1085.0},
            {"t_end": 1000.0, "variant": "cyrk-dop853", "order": None, "step_factor": None, "n_steps": 3036,
             "ratio": None, "reference_ratio": 2e-5}]
    result["diagnosis"] = {"00_x@0.0001": {"runs": runs}}
    text = tolerance.page(result)
    assert "| 00_x@0.0001 | 1000 | picked | 10 | 2.5 | 4812 | 97.6 | 1.1e+03 | 2e-05 |" in text
    assert "| 00_x@0.0001 | 1000 | cyrk-dop853 |  |  | 3036 | failed |  | 2e-05 |" in text


def test_diagnose_refuses_an_unknown_scene():
    from adbgen.cli_types import UsageError

    with pytest.raises(UsageError, match="unknown scene"):
        tolerance.diagnose("no_such_scene", 1e-4)
    with pytest.raises(UsageError, match="positive"):
        tolerance._positive("-1")


def test_a_scene_measured_under_another_table_is_stale_remeasured_and_not_counted(tmp_path, monkeypatch):
    """The auto engine's table is recorded per scene (`table_id`, the table file's hash); a resumed run
    remeasures the scenes recorded under another table and skips the current ones, and the summary and the
    page count only the current ones.  Negative control: the same scenes recorded under the current table
    are skipped and counted."""
    now = tolerance.table_id("auto")
    assert now and tolerance.table_id("cyrk-dop853") is None
    scene = {"family": "two_plane", "units": "thesis", "drive": "torque"}
    bad = [{"rtol": 1e-4, "ratio": 500.0, "decided": True, "status": "success", "reference_ratio": 1e-3}]
    good = [{"rtol": 1e-4, "ratio": 2.0, "decided": True, "status": "success", "reference_ratio": 1e-3}]
    old = {"36_two_plane_torque": {"scene": scene, "cells": bad, "table": "0" * 12, "reference_rule": tolerance.RULE},
           "37_two_plane_torque": {"scene": scene, "cells": good, "table": now, "reference_rule": tolerance.RULE}}
    s = tolerance.summary(old, now)
    assert s["met"] and s["measured"] == 1 and s["stale"] == ["36_two_plane_torque"]
    assert not tolerance.summary({k: {**v, "table": now} for k, v in old.items()}, now)["met"]  # negative control
    measured = []
    monkeypatch.setattr(tolerance, "measure_scene", lambda sc, engine, rtols, progress=print, previous=None: measured.append(
        sc["name"]) or {"scene": scene, "cells": good, "table": now, "reference_rule": tolerance.RULE, "measured_at": "2026-11-29T04:30:00+00:00",
                        "load_average": [9.0, 9.0, 9.0]})
    out = tmp_path / "tolerance.json"
    result = {"benchmark": "tolerance", "engine": "auto", "rtols": [1e-4], "machine": {}, "scenes": old,
              "reference": {"engine": "cyrk-vern8", "rtol": 1e-14, "atol": 1e-18, "limit": 1.0,
                            "check": {"engine": "taylor", "order": 20, "step_factor": 1.0}},
              "date": "2026-11-29T01:20:00+00:00", "seed": 35, "atol_ratio": 1e-2, "target": 10.0}
    out.write_text(json.dumps(result))
    res = tolerance.bench_tolerance(str(out), names=["36_two_plane_torque", "37_two_plane_torque"], rtols=[1e-4],
                                    progress=lambda line: None)
    assert measured == ["36_two_plane_torque"]  # the stale one only
    assert res["summary"]["measured"] == 2 and res["summary"]["stale"] == [] and res["summary"]["met"]
    text = tolerance.page(res)
    assert "2 of 46 scenes measured under the auto engine's current table" in text and "earlier table" not in text
    res["scenes"]["37_two_plane_torque"]["table"] = "f" * 12  # a stale scene is marked on the page
    res["summary"] = tolerance.summary(res["scenes"], now)
    assert "| 37_two_plane_torque (earlier table, not counted) |" in tolerance.page(res)


def test_a_scene_graded_by_the_earlier_rule_is_stale_and_the_page_says_how_cells_are_graded():
    """Cells are graded by the extended reference's own convergence (`RULE`); a scene graded by the earlier
    double-precision rule (no reference_rule) is stale: not counted, marked on the page, remeasured.
    Negative control: the same scene under the current rule counts."""
    scene = {"family": "single_plane", "units": "SI", "drive": "forced"}
    cells = [{"rtol": 1e-4, "ratio": 50.0, "decided": True, "status": "success", "reference_ratio": 0.01,
              "vern8_ratio": 3.0, "taylor20_ratio": 4.0, "double_reference_ratio": 7.0}]
    old = {"11_single_plane_fixed_n3": {"scene": scene, "cells": cells}}
    s = tolerance.summary(old)
    assert s["measured"] == 0 and s["stale"] == ["11_single_plane_fixed_n3"] and s["over_target"] == []
    new = {"11_single_plane_fixed_n3": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE,
                                        "extended_reference": {"fp_type": "real128", "tol": 1.9e-33, "order": 39,
                                                               "steps": 800, "cpu_s": 4.0, "breakpoints": []},
                                        "t_dec_ref": None, "vern8_t_dec": None}}
    s = tolerance.summary(new)
    assert s["over_target"][0]["ratio"] == 50.0 and not s["met"]
    assert not s["over_target"][0]["double_floor"]  # Vern8 and Taylor 20 resolve it: the engine's own miss
    cells[0]["vern8_ratio"], cells[0]["taylor20_ratio"] = 40.0, 12.0  # both doubles miss too: the floor
    assert tolerance.summary(new)["over_target"][0]["double_floor"]
    cells[0]["taylor20_ratio"] = 4.0
    result = {"scenes": old, "rtols": [1e-4], "machine": {}, "date": "d", "engine": "auto", "seed": 35,
              "atol_ratio": 1e-2, "target": 10.0,
              "reference": {"engine": "cyrk-vern8", "rtol": 1e-14, "atol": 1e-18, "limit": 1.0,
                            "check": {"engine": "taylor", "order": 20, "step_factor": 1.0},
                            **tolerance.reference_header()}}
    assert "| 11_single_plane_fixed_n3 (earlier reference, not counted) |" in tolerance.page(result)
    result["scenes"] = new
    text = tolerance.page(result)
    assert f"Reference (rule `{tolerance.RULE}`)" in text and "within 0.1 tolerance unit" in text
    assert "| 11_single_plane_fixed_n3 | real128, tol 1.9e-33 | 39, 800, 4 | none | 0.01 / 0.01 | 40 / 40 |" in text
    assert "11_single_plane_fixed_n3 at 0.0001 (50)." in text  # Taylor 20 resolves it: no floor mark


class _Model:
    """A scene's model as `measure_scene` uses it: two states, one parameter."""
    name, amplitude_indices = "m", (0, 1)

    def params(self, _):
        return [1.0]

    def state(self, _):
        return [0.0, 0.0]


def test_measure_scene_grades_by_the_extended_reference_and_falls_back_to_the_double_rule(monkeypatch):
    """A cell counts where the extended reference agrees with itself (at a 1000x looser tol) within a tenth of
    a unit; the double references become checks (their distances recorded).  Where the extended reference
    cannot be had, the earlier rule grades: Vern8 against Taylor 20 within one unit.  Negative control: the
    extended reference's check a third of a unit off grades nothing."""
    y = np.array([1.0, 2.0])

    def fake(y_end, t_dec=None):
        return {"status": "success", "y_end": np.asarray(y_end, float), "n_steps": 10, "t_dec": t_dec, "picked": None}

    monkeypatch.setattr(tolerance, "scene_model", lambda scene: _Model())
    monkeypatch.setattr(tolerance, "table_id", lambda engine: None)
    monkeypatch.setattr(tolerance, "references", lambda *a: (fake(y + 1e-9), fake(y - 1e-9)))
    monkeypatch.setattr(tolerance, "_run", lambda model, eng, p, y0, t_end, rtol, atol: fake(y + 3 * rtol))
    check = [1e-12]
    monkeypatch.setattr(tolerance, "extended_references",
                        lambda *a: (fake(y), fake(y + check[0]), {"fp_type": "real128", "breakpoints": []}))
    scene = {"name": "x", "t_end": 1.0}
    res = tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None)
    assert res["reference_rule"] == tolerance.RULE and res["reference_fallback"] is None
    a, b = res["cells"]
    assert a["decided"] and b["decided"] and a["ratio"] == pytest.approx(3e-4 / (1e-6 + 1e-4))
    assert a["vern8_ratio"] == pytest.approx(1e-9 / (1e-6 + 1e-4)) and b["double_reference_ratio"] > 1
    check[0] = 1e-9 * 0.33 * 2  # a third of a unit at rtol 1e-9: the reference cannot grade that cell
    b = tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None)["cells"][1]
    assert not b["decided"]

    def unavailable(*a):
        raise tolerance_peers().PeerUnavailable("no heyoka")

    monkeypatch.setattr(tolerance, "extended_references", unavailable)
    res = tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None)
    assert res["reference_fallback"].startswith("PeerUnavailable") and res["extended_reference"] is None
    a, b = res["cells"]
    assert a["decided"] and not b["decided"]  # the doubles differ by 2e-9: within a unit at 1e-4, not at 1e-9
    assert "vern8_ratio" not in a


def test_a_rerun_under_another_table_keeps_the_references_grading_and_reruns_the_engine(monkeypatch):
    """A scene graded by the extended rule is remeasured under a new table without its double references or
    the extended reference's check (they do not depend on the table): each cell keeps its reference_ratio and
    is decided by it, the engine is rerun and graded against the extended reference's final state, rerun once
    where the record lacks it (then recorded) and not at all where it has it.  A rerun reference other than the
    one recorded stops the run.  Negative control: a record of another scene (or a fallback) is not reused."""
    y = np.array([1.0, 2.0])
    calls = []

    def fake(y_end, steps=10):
        return {"status": "success", "y_end": np.asarray(y_end, float), "n_steps": steps, "t_dec": None, "picked": None}

    def ext(*a, factors=(tolerance.EXT_TOL, tolerance.EXT_CHECK_TOL)):
        calls.append(("extended", factors))
        info = {"fp_type": "real128", "breakpoints": []}
        return (fake(y), info) if len(factors) == 1 else (fake(y), fake(y), info)

    monkeypatch.setattr(tolerance, "scene_model", lambda scene: _Model())
    monkeypatch.setattr(tolerance, "table_id", lambda engine: "new")
    monkeypatch.setattr(tolerance, "references", lambda *a: calls.append("doubles") or (fake(y), fake(y)))
    monkeypatch.setattr(tolerance, "_run", lambda model, eng, p, y0, t_end, rtol, atol: fake(y + 3 * rtol))
    monkeypatch.setattr(tolerance, "extended_references", ext)
    scene = {"name": "x", "t_end": 1.0}
    old = [{"rtol": r, "reference_ratio": rr, "vern8_ratio": 5.0, "ratio": 99.0} for r, rr in ((1e-4, 0.01), (1e-9, 0.5))]
    previous = {"scene": scene, "reference_rule": tolerance.RULE, "extended_reference": {"fp_type": "real128"},
                "reference_fallback": None, "reference_steps": 10, "t_dec_ref": None, "cells": old, "table": "old",
                "measured_at": "then"}
    res = tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None, previous=previous)
    assert calls == [("extended", (tolerance.EXT_TOL,))]  # no doubles, no extended check
    a, b = res["cells"]
    assert a["ratio"] == pytest.approx(3e-4 / (1e-6 + 1e-4)) and a["decided"] and a["vern8_ratio"] == 5.0
    assert not b["decided"] and b["reference_ratio"] == 0.5  # graded as recorded: above the self limit
    assert res["table"] == "new" and res["references_from"] == "then" and res["reference_y_end"] == [1.0, 2.0]
    calls.clear()
    again = tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None, previous=res)
    assert calls == [] and again["cells"][0]["ratio"] == a["ratio"] and again["references_from"] == "then"
    with pytest.raises(RuntimeError, match="differs from the one recorded"):
        tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None,
                                previous={**previous, "reference_steps": 11})
    calls.clear()
    tolerance.measure_scene(scene, "auto", [1e-4, 1e-9], progress=lambda line: None,
                            previous={**previous, "scene": {"name": "y", "t_end": 1.0}})
    assert calls == ["doubles", ("extended", (tolerance.EXT_TOL, tolerance.EXT_CHECK_TOL))]  # measured afresh
    assert tolerance.reusable({**previous, "reference_fallback": "PeerUnavailable"}, scene, [1e-4, 1e-9]) is None


def test_a_scene_whose_rows_the_new_table_keeps_is_carried_over_without_its_estimates(tmp_path, monkeypatch):
    """A stale scene (another table) whose every cell ran what the current table picks for its model there
    is carried over: its cells kept, their error estimates dropped (their tighter runs may take new rows),
    the earlier table named.  Negative control: one cell whose pick changed and the scene is remeasured."""
    scene = {"name": "17_thesis_rotating_n4", "family": "single_plane", "units": "thesis", "drive": "forced"}
    pick = {"engine": "taylor", "order": 20, "step_factor": 1.5, "rtol": 1e-6, "atol": 1e-8}
    cells = [{"rtol": 1e-6, "atol": 1e-8, "ratio": 0.3, "decided": True, "status": "success", "picked": pick,
              "reference_ratio": 1e-3, "flagged": False, "error_estimate": {"ratio": 0.2}}]
    old = {"scene": scene, "cells": cells, "table": "a" * 12, "reference_rule": tolerance.RULE,
           "extended_reference": {"fp_type": "real128"}, "reference_fallback": None, "measured_at": "then"}
    now = [dict(pick)]

    class Auto:
        def picked(self, rtol, atol, model):
            return None, rtol, atol, now[0]

    monkeypatch.setattr(tolerance, "load", lambda: [scene])
    monkeypatch.setattr(tolerance, "scene_model", lambda sc: object())
    monkeypatch.setattr(tolerance, "table_id", lambda engine: "b" * 12)
    monkeypatch.setattr("adbgen.analysis.engines.engine", lambda name: Auto())
    measured = []
    monkeypatch.setattr(tolerance, "measure_scene", lambda sc, engine, rtols, progress=print, previous=None:
                        measured.append(sc["name"]) or {**old, "table": "b" * 12})
    out = tmp_path / "tolerance.json"
    head = {"benchmark": "tolerance", "engine": "auto", "rtols": [1e-6], "machine": {}, "date": "d", "seed": 35,
            "atol_ratio": 1e-2, "target": 10.0, "reference": {"engine": "cyrk-vern8", "rule": tolerance.RULE}}
    out.write_text(json.dumps({**head, "scenes": {scene["name"]: old}}))
    res = tolerance.bench_tolerance(str(out), rtols=[1e-6], progress=lambda line: None)
    got = res["scenes"][scene["name"]]
    assert measured == [] and got["table"] == "b" * 12 and got["table_carried_from"] == "a" * 12
    assert got["cells"][0]["ratio"] == 0.3 and "flagged" not in got["cells"][0] and "error_estimate" not in got["cells"][0]
    assert res["summary"]["measured"] == 1
    now[0] = {**pick, "step_factor": 1.0}  # the new table picks another row: remeasured
    out.write_text(json.dumps({**head, "scenes": {scene["name"]: old}}))
    tolerance.bench_tolerance(str(out), rtols=[1e-6], progress=lambda line: None)
    assert measured == [scene["name"]]


def tolerance_peers():
    from benchmarks import peers

    return peers


def test_the_summary_counts_silent_misses_and_false_alarms_of_the_estimate():
    """The restated promise: a cell above the target must be flagged by --check-tolerance's estimate; one that
    is not is a silent miss, a flagged cell within 2 units a false alarm.  Planted: four cells, one of each
    kind and a flagged miss; negative controls: flagging the silent one leaves none, and cells without an
    estimate (not measured so) are not counted."""
    scene = {"family": "single_plane", "units": "thesis", "drive": "forced"}

    def cell(rtol, ratio, estimate, flagged):
        return {"rtol": rtol, "ratio": ratio, "decided": True, "status": "success", "reference_ratio": 0.0,
                "error_estimate": {"ratio": estimate, "bound": 10.0}, "flagged": flagged,
                "estimate_rule": tolerance.ESTIMATE_RULE}

    cells = [cell(1e-4, 30.0, 25.0, True),  # a miss, flagged: the promise kept
             cell(1e-5, 40.0, 3.0, False),  # a miss the estimate does not see: SILENT
             cell(1e-6, 1.5, 12.0, True),  # flagged though within 2 units: a false alarm
             cell(1e-7, 5.0, 4.0, False),  # within the target, not flagged
             {"rtol": 1e-8, "ratio": 90.0, "decided": True, "status": "success", "reference_ratio": 0.0}]
    scenes = {"09_x": {"scene": scene, "cells": cells, "reference_rule": tolerance.RULE}}
    e = tolerance.summary(scenes)["estimate"]
    assert e["cells"] == 4 and e["flagged"] == 2 and not e["met"]
    assert [(o["rtol"], o["ratio"], o["estimate"]) for o in e["silent_misses"]] == [(1e-5, 40.0, 3.0)]
    assert [o["rtol"] for o in e["false_alarms"]] == [1e-6]
    result = {"scenes": scenes, "rtols": [1e-4, 1e-5, 1e-6, 1e-7, 1e-8], "machine": {}, "date": "d", "engine": "auto",
              "seed": 35, "atol_ratio": 1e-2, "target": 10.0,
              "reference": {"engine": "cyrk-vern8", "rtol": 1e-14, "atol": 1e-18, "limit": 1.0,
                            "check": {"engine": "taylor", "order": 20, "step_factor": 1.0}}}
    text = tolerance.page(result)
    assert "silent misses (true ratio above 10, not flagged; target: none): 1: 09_x at 1e-05 (40 / 3)" in text
    assert "| 09_x | 30 / 25 ! | 40 / 3 | 1.5 / 12 ! | 5 / 4 |  |" in text
    cells[1]["flagged"] = True  # negative control: flagged, the miss is no longer silent
    e = tolerance.summary(scenes)["estimate"]
    assert e["silent_misses"] == [] and e["met"]
    cells[1]["flagged"], cells[1]["estimate_rule"] = False, "tighter-run"  # an earlier rule's estimate: not counted
    e = tolerance.summary(scenes)["estimate"]
    assert e["cells"] == 3 and e["earlier_rule_cells"] == 1 and e["silent_misses"] == []
    for c in cells:  # no cell measured with the estimate: nothing counted, no section on the page
        c.pop("flagged", None)
    assert tolerance.summary(scenes)["estimate"]["cells"] == 0
    assert "## The promise restated" not in tolerance.page(result)


def test_add_estimates_fills_current_cells_only_and_not_a_rerun_that_differs(tmp_path, monkeypatch):
    """`--estimates` adds the estimate to the graded cells of the scenes measured under the current table,
    without rerunning the references; a rerun that takes other steps than the run graded is not counted
    (negative control), and a stale scene is left alone."""
    from adbgen.cli_types import UsageError

    class Model:
        def params(self, _):
            return [1.0]

        def state(self, _):
            return [0.0]

    now = tolerance.table_id("auto")
    scene = {"name": "x", "family": "single_plane", "units": "thesis", "drive": "forced", "t_end": 1.0}
    cells = [{"rtol": 1e-4, "atol": 1e-6, "ratio": 30.0, "decided": True, "status": "success", "n_steps": 10,
              "reference_ratio": 0.0},
             {"rtol": 1e-5, "atol": 1e-7, "ratio": 3.0, "decided": True, "status": "success", "n_steps": 99,
              "reference_ratio": 0.0}]
    stale = [dict(cells[0])]
    result = {"engine": "auto", "scenes": {
        "x": {"scene": scene, "cells": cells, "table": now, "reference_rule": tolerance.RULE},
        "y": {"scene": scene, "cells": stale, "table": "0" * 12, "reference_rule": tolerance.RULE}}}
    out = tmp_path / "tolerance.json"
    out.write_text(json.dumps(result))
    monkeypatch.setattr(tolerance, "scene_model", lambda s: Model())
    monkeypatch.setattr(tolerance, "cell_estimate", lambda model, p, y0, t_end, engine, rtol, atol: {
        "error_estimate": {"ratio": 25.0, "exceeded": True}, "flagged": True, "rerun_steps": 10, "rerun_picked": None})
    res = tolerance.add_estimates(str(out), progress=lambda line: None)
    a, b = res["scenes"]["x"]["cells"]
    assert a["flagged"] and a["error_estimate"]["ratio"] == 25.0
    assert a["estimate_rule"] == tolerance.ESTIMATE_RULE
    assert "flagged" not in b and b["rerun_differs"] == 10  # 10 steps against the 99 graded: not counted
    assert "flagged" not in res["scenes"]["y"]["cells"][0]
    assert res["summary"]["estimate"]["cells"] == 1 and res["summary"]["estimate"]["met"]
    assert json.loads(out.read_text())["scenes"]["x"]["cells"][0]["flagged"] is True
    # a cell estimated by an earlier rule (the tighter run alone) is remeasured; one by the current rule is not
    result["scenes"]["x"]["cells"][0].update(flagged=False, error_estimate={"ratio": 1.0}, estimate_rule="tighter-run")
    out.write_text(json.dumps(result))
    res = tolerance.add_estimates(str(out), progress=lambda line: None)
    assert res["scenes"]["x"]["cells"][0]["flagged"] is True and res["scenes"]["x"]["cells"][0]["error_estimate"]["ratio"] == 25.0
    redone = []  # the rerun that differed (rtol 1e-5) is tried again; the current cell (1e-4) is not
    monkeypatch.setattr(tolerance, "cell_estimate", lambda model, p, y0, t_end, engine, rtol, atol: redone.append(rtol)
                        or {"error_estimate": None, "flagged": True, "rerun_steps": 10, "rerun_picked": None})
    res = tolerance.add_estimates(str(out), names=["x"], progress=lambda line: None)
    assert redone == [1e-5] and res["summary"]["estimate"]["cells"] == 1
    with pytest.raises(UsageError, match="not a scene measured"):
        tolerance.add_estimates(str(out), names=["y"], progress=lambda line: None)
    empty = tmp_path / "none.json"
    with pytest.raises(UsageError, match="no tolerance results"):
        tolerance.add_estimates(str(empty), progress=lambda line: None)
