"""benchmarks/study_recheck.py: the comparison of a re-run case with the committed one (planted distributions; the
re-run itself needs the study's stick/slip model, whose first generation is minutes, and runs with the command)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from adbgen.analysis.residual import AT_REST, distribution
from benchmarks import study_recheck as sr


def _case(r, below=0):
    r = np.asarray(r, float)
    return {"distribution": distribution(r, np.full(r.size, AT_REST)), "below_target": below}


def test_the_same_results_have_not_moved():
    r = np.linspace(1e-5, 5e-4, 256)
    assert sr.compare(_case(r, 3), _case(r.copy(), 3)) == {"moved": [], "exact": True}


def test_a_change_below_the_pages_precision_is_not_a_move_but_is_not_exact():
    r = np.linspace(1e-5, 5e-4, 256)
    out = sr.compare(_case(r, 3), _case(r * (1 + 1e-12), 3))
    assert out == {"moved": [], "exact": False}


def test_a_moved_quantile_and_count_are_named():
    r = np.linspace(1e-5, 5e-4, 256)
    moved = r.copy()
    moved[-30:] *= 1.5  # the tail moves: 90 %, 99 % and max change, the median not
    out = sr.compare(_case(r, 3), _case(moved, 4))
    assert not out["exact"]
    assert [m.split(" ")[0] for m in out["moved"]] == ["below", "90", "99", "max"]  # max moves the bins' edges too


def test_starts_that_change_bin_are_counted():
    r = np.linspace(1e-5, 5e-4, 256)
    moved = r.copy()
    moved[:5] += 2e-5  # five of the smallest residuals one bin up; quantiles and max kept
    out = sr.compare(_case(r), _case(moved))
    assert out["moved"] == ["histogram: 5 starts in another bin"] and not out["exact"]


def test_an_unknown_case_is_refused_in_one_line(tmp_path, capsys):
    path = tmp_path / "study.json"
    path.write_text(json.dumps({"cases": [{"name": "no reduction"}], "starts": 4}))
    assert sr.main(["--json", str(path), "--case", "depth 9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "has no case 'depth 9'; its cases: no reduction" in err


@pytest.mark.parametrize("x, page", [(1.3703e-4, 1.37e-4), (5.4249e-4, 5.42e-4), (None, None)])
def test_rounded_to_the_pages_digits(x, page):
    assert sr._rounded(x) == page
