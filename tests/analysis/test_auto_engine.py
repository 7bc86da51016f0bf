"""The `auto` engine's shipped table (adbgen/analysis/engines/auto_table.json) is safe beyond the two
problems it was measured on: every row's Taylor step aims below a tenth of its tolerance
(`benchmarks.engine_table.admissible`), and on a third scene, derivation notebook 06's five-ball SI scene (omega =
400 rad/s, errors amplified ~1e3-fold by the transient), `auto` is as accurate as DOP853 at the same rtol.
Negative control: the table withdrawn on 2026-11-27 (chosen by measured error alone) fails both."""

from __future__ import annotations

import contextlib
import json
import io
from pathlib import Path

import numpy as np
import pytest

from adbgen.analysis.engines import ENGINES
from adbgen.analysis.engines.by_tolerance import TABLE, AutoEngine, load_table
from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate
from adbgen.cli import main
from benchmarks.engine_table import SAFETY, admissible

WITHDRAWN = Path(__file__).resolve().parents[2] / "benchmarks" / "withdrawn" / "auto-2026-11-27T1909.json"


def _rows(table: dict) -> list[dict]:
    return table["rows"] + [r for p in table.get("by_problem", {}).values() for r in p["rows"]]


def test_each_model_takes_the_rows_of_the_problem_measured_on_its_kind_of_machine():
    """The table is keyed by problem, with the problem's model's kinds of coordinate (no family named in
    the package's data); every generated model takes the rows of the problem measured on a model of its
    own family (problem A's: single plane, B's: two planes), read here from the models' FAMILY and the
    benchmark's problems; a family no problem was measured on takes the rows of a problem whose kinds of
    coordinate its model has.  Negative control: with problem B's kinds planted wrong (a coordinate no model
    has), the two-plane models fall to problem A's rows."""
    from adbgen.analysis.engines.by_tolerance import table_rows
    from adbgen.analysis.loading import available_models
    from benchmarks.precision import PROBLEMS

    table = load_table(str(TABLE))
    assert set(table["by_problem"]) == {"A", "B"} and "by_family" not in table
    family_of = {label: load_model(PROBLEMS[label].problem.model).family for label in table["by_problem"]}
    models = [load_model(name) for name in available_models()]
    assert set(family_of.values()) <= {m.family for m in models}
    for m in models:
        label = next((k for k, fam in family_of.items() if fam == m.family), None)
        if label is not None:
            assert table_rows(table, m.roles) == table["by_problem"][label]["rows"], m.name
        else:  # a family no problem was measured on (flexible): the rows of a problem whose kinds it has
            known = [p["rows"] for p in table["by_problem"].values()] + [table["rows"]]
            assert table_rows(table, m.roles) in known, m.name
    planted = json.loads(json.dumps(table))
    planted["by_problem"]["B"]["roles"].append("no_such_role")
    hill = load_model(PROBLEMS["B"].problem.model)
    assert table_rows(planted, hill.roles) == table["by_problem"]["A"]["rows"] != table["by_problem"]["B"]["rows"]
    assert table_rows(table, ["no_such_role"]) == table_rows(table, None) == table["rows"]


def test_every_row_of_the_shipped_table_aims_below_a_tenth_of_its_tolerance():
    rows = _rows(load_table(str(TABLE)))
    assert rows and SAFETY >= 10
    bad = [(r["rtol"], r.get("order"), r.get("step_factor")) for r in rows if not admissible(r, r["rtol"])]
    assert bad == []
    withdrawn = load_table(str(WITHDRAWN))["rows"]  # negative control: order 18, factor 3 at 1e-8 aims at 4.3e-8
    assert not all(admissible(r, r["rtol"]) for r in withdrawn)


@pytest.fixture(scope="module")
def five_balls(tmp_path_factory):
    """Notebook 06's scene: the default single-plane scene with five unequal balls, in SI units."""
    work = tmp_path_factory.mktemp("five-balls")
    scene = work / "five_balls.toml"
    scene.write_text('n = 5\nball_mass = [0.05, 0.045, 0.04, 0.035, 0.03]\n')
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["regenerate", "--scene", str(scene), "--name", "five_balls", "--out", str(work / "gen"),
                     "--quiet"]) == 0
    model = load_model(work / "gen" / "five_balls")
    y0 = {f"phi_{i + 1}": a for i, a in enumerate([0.3, 1.5, 2.9, 4.2, 5.5])}
    ref = simulate(model, None, y0, t_end=1.0, rtol=1e-13, atol=1e-16, engine="cyrk-vern8", keep_trajectory=False)
    return model, y0, ref.y_end


def _error(model, y0, ref, engine, rtol) -> float:
    run = simulate(model, None, y0, t_end=1.0, rtol=rtol, atol=rtol * 1e-2, engine=engine, keep_trajectory=False)
    assert run.ok
    return float(np.max(np.abs(run.y_end - ref) / np.maximum(1.0, np.abs(ref))))


@pytest.mark.parametrize("rtol", [1e-8, 1e-10])
def test_auto_is_as_accurate_as_dop853_on_a_scene_it_was_not_measured_on(five_balls, rtol):
    """Measured: 7.2e-6 against DOP853's 1.7e-5 at 1e-8; 2.2e-7 against 1.35e-7 at 1e-10 (the reference,
    Vern8 at 1e-13, is 2.5e-8 from heyoka's rule at 1e-14: the scene amplifies errors)."""
    model, y0, ref = five_balls
    dop = _error(model, y0, ref, "cyrk-dop853", rtol)
    assert _error(model, y0, ref, "auto", rtol) <= 3 * dop
    if rtol == 1e-8:  # negative control: the withdrawn table (order 18, factor 3) misses by ~6e-3
        withdrawn = AutoEngine(ENGINES, table=str(WITHDRAWN))
        assert _error(model, y0, ref, withdrawn, rtol) > 30 * dop


NB06_BOUND = 1e-6  # derivation notebook 06: the default engine against SciPy's DOP853 at rtol 1e-10, atol 1e-12


def test_auto_meets_notebook_06s_bound_with_a_factor_of_10_to_spare(five_balls, tmp_path):
    """Issue 35: at notebook 06's tolerances the default engine ends within a tenth of the notebook's bound
    of the reference (Vern8 at 1e-13; its own distance from the Taylor engine at order 20 is ~2.7e-8 here),
    and within the bound of SciPy's DOP853 (the notebook's own check; DOP853 is itself 1.35e-7 from the
    reference, so the tenth is asked of the error, not of the difference).  Negative control: problem A's
    1e-10 row as learned before the check scene (order 16, factor 1.5: 2.2e-7) misses the tenth."""
    model, y0, ref = five_balls
    assert _error(model, y0, ref, "auto", 1e-10) <= NB06_BOUND / 10
    auto = simulate(model, None, y0, t_end=1.0, rtol=1e-10, atol=1e-12, keep_trajectory=False)
    sp = simulate(model, None, y0, t_end=1.0, rtol=1e-10, atol=1e-12, engine="scipy-dop853", keep_trajectory=False)
    assert np.max(np.abs(auto.y_end - sp.y_end) / np.maximum(1.0, np.abs(sp.y_end))) < NB06_BOUND
    planted = json.loads(TABLE.read_text())
    for rows in [planted["rows"]] + [p["rows"] for p in planted["by_problem"].values()]:
        for r in rows:
            if r["rtol"] == pytest.approx(1e-10):
                r.update(key="taylor:o16:f1.5", order=16, step_factor=1.5)
    path = tmp_path / "planted.json"
    path.write_text(json.dumps(planted))
    assert _error(model, y0, ref, AutoEngine(ENGINES, table=str(path)), 1e-10) > NB06_BOUND / 10
