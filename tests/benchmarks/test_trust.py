"""`adbgen bench trust` (issue 34's cost targets): the pairing of the two sides and the baseline checkout."""

from __future__ import annotations

import math

import pytest

from benchmarks import trust
from adbgen.cli_types import UsageError


def test_paired_alternates_the_sides_after_a_warm_up_and_compares_medians():
    calls = []
    b_times = iter([100.0, 1.0, 3.0, 2.0])  # the warm-up (100) is not counted
    a_times = iter([100.0, 2.0, 9.0, 4.0])

    def before():
        calls.append("b")
        return next(b_times)

    def after():
        calls.append("a")
        return next(a_times)
    row = trust.paired(before, after, 3)
    assert calls == ["b", "a"] * 4
    assert row["before_s"] == [1.0, 3.0, 2.0] and row["before_median_s"] == 2.0 and row["after_median_s"] == 4.0
    assert row["ratio"] == 2.0


def test_a_baseline_that_is_not_a_commit_is_refused_in_one_line():
    with pytest.raises(UsageError, match="--baseline no-such-rev"):
        with trust.Baseline("no-such-rev"):
            pass


def test_the_baseline_checkout_is_the_named_commit_and_is_removed(tmp_path):
    import subprocess

    with trust.Baseline("HEAD") as path:
        head = subprocess.run(["git", "-C", str(trust.ROOT), "rev-parse", "HEAD"], capture_output=True, text=True)
        there = subprocess.run(["git", "-C", str(path), "rev-parse", "HEAD"], capture_output=True, text=True)
        assert there.stdout == head.stdout and (path / "adbgen" / "__init__.py").is_file()
    assert not path.exists()


def test_the_tolerance_commands_name_the_thesis_panels():
    from adbgen.families.single_plane.science.sensitivity import RUNS

    panels = {r.figure: r for r in RUNS}
    for figure, argv, n in trust.SIMULATIONS:
        run = panels[figure]
        assert argv[0] == f"thesis_rotating_n{run.n}" and n == run.n
        given = dict(a.split("=") for a in argv if a.startswith("phi_"))
        assert [eval(given[f"phi_{i + 1}"], {"pi": math.pi}) for i in range(n)] == pytest.approx(run.phi0)
        assert run.rate == -4.0  # the command adds phi_i_dot = -4 (at rest in the fixed frame at Omega = 4)
