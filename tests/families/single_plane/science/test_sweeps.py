"""The thesis' chapter-5 sweeps (`science/sweeps.py`): the long runs are `adbgen reproduce`'s; here every
sweep it asks for is checked by the real sweep front end (grid, --set, --y0, --tie parsed as `adbgen sweep`
parses them, the engine named), and compute -> draw -> lines runs end to end on synthetic results, so a bad
sweep specification or a formatting slip fails here in seconds, not after an hour of `adbgen reproduce`."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.analysis.sweep import SweepSpec, prepare
from adbgen.families.single_plane.science import sweeps

LABELS = ["balanced 1", "limit cycle", "coincident 2-", "undecided", "balanced 1 (algebraic approach)"]


def fake_sweep(calls):
    def run(model, grid, measure, *, set_=(), y0=(), tie=(), t_end=3000.0, rtol=sweeps.RTOL, atol=None,
            engine="cyrk-dop853", early_stop=True):
        spec = SweepSpec(model=model, grid=list(grid), measure=measure, set=list(set_), y0=list(y0), tie=list(tie),
                         t_end=t_end, rtol=rtol, atol=rtol * 1e-2 if atol is None else atol, engine=engine,
                         early_stop=early_stop)
        _, g = prepare(spec)  # what `adbgen sweep` would refuse, refused here
        calls.append(spec)
        coords = {a.name: a.values for a in g.axes}
        k = np.arange(g.size).reshape(g.shape)
        if measure == "attractor":
            return (k + (k % 5 == 0) * (rtol < 1e-9)) % len(LABELS), LABELS, coords  # some starts: by the tolerance
        return 1e-3 * (1 + k % 7) if measure == "r_max" else 100.0 + k % 11, None, coords
    return run


def test_every_sweep_is_valid_and_the_section_is_written(monkeypatch, tmp_path):
    calls = []
    monkeypatch.setattr(sweeps, "sweep", fake_sweep(calls))
    monkeypatch.setattr(sweeps, "stability_onset", lambda n, mu: 2.0 + n / 10)
    res = sweeps.compute()
    paths = sweeps.draw(res, tmp_path)
    assert all(p.is_file() for p in paths.values())
    text = "\n".join(sweeps.lines(res, paths, tmp_path, lyapunov={"x": {"exponent": 0.05, "first_half": 0.04,
                                                                        "second_half": 0.06, "r_window": 0.4}}))
    assert "| 5.9(d) |" in text and "chaotic (positive exponent)" in text and "np.float64" not in text
    # decided labels: both balanced labels count as balanced; undecided has its own column, never "not balanced"
    cells = next(line for line in text.splitlines() if line.startswith("| 5.7(a1) |")).split(" | ")
    labels = sweeps.named(LABELS, np.arange(100) % len(LABELS))
    assert int(cells[2]) == 40 and int(cells[4]) == 20 and "undecided" not in cells[3]
    assert cells[3] == "coincident 2- 20, limit cycle 20"
    assert sweeps.count_balanced(labels) == 40 and int(sweeps.is_open(labels).sum()) == 20
    assert len(calls) > 50 and {c.engine for c in calls} == {"cyrk-dop853"}
    # the launches' local scans: a grid of 41 starts about a start whose label changes with the tolerance
    local = [c for c in calls if c.grid[0].startswith("phi_1=") and c.grid[0].endswith(":41")]
    assert local and all(c.rtol == sweeps.LAUNCH_RTOLS[-1] for c in local)


def test_the_fake_front_end_refuses_what_adbgen_sweep_refuses():
    """Negative control: the grid the first version of the launches' local scan wrote (numpy's repr)."""
    run = fake_sweep([])
    with pytest.raises(AnalysisError, match="np.float64"):
        run("thesis_rotating_n2", [f"phi_1={np.float64(0.5)!r}:{np.float64(0.6)!r}:41"], "attractor")
