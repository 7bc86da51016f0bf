"""The thesis' chapter-5 sweeps (`science/sweeps.py`): the long runs are `adbgen reproduce`'s; here every
sweep it asks for is checked by the real sweep front end (grid, --set, --y0, --tie parsed as `adbgen sweep`
parses them, the engine named), and compute -> draw -> lines runs end to end on synthetic results, so a bad
sweep specification or a formatting slip fails here in seconds, not after an hour of `adbgen reproduce`."""

from __future__ import annotations

from pathlib import Path

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
    assert len(calls) > 50 and {c.engine for c in calls} == {"cyrk-dop853", "matlab-ode45"}
    # the thesis' solver beside the converged launches only, at its defaults, without early stop
    ode45 = [c for c in calls if c.engine == "matlab-ode45"]
    assert len(ode45) == 3 and all(c.rtol == 1e-3 and c.atol == 1e-6 and not c.early_stop for c in ode45)
    assert "ode45 at its defaults (the thesis' solver)" in text
    # Fig. 5.23: the thesis' grid points run and the sentence read on its grid
    assert "| starts balancing of 10 at 1.6327 / 1.8 / 2.0408 |" in text
    # the launches' local scans: a grid of 41 starts about a start whose label changes with the tolerance
    local = [c for c in calls if c.grid[0].startswith("phi_1=") and c.grid[0].endswith(":41")]
    assert local and all(c.rtol == sweeps.LAUNCH_RTOLS[-1] for c in local)


def test_the_fake_front_end_refuses_what_adbgen_sweep_refuses():
    """Negative control: the grid the first version of the launches' local scan wrote (numpy's repr)."""
    run = fake_sweep([])
    with pytest.raises(AnalysisError, match="np.float64"):
        run("thesis_rotating_n2", [f"phi_1={np.float64(0.5)!r}:{np.float64(0.6)!r}:41"], "attractor")


def test_the_thesis_2_04_is_a_point_of_its_50_point_grid():
    """Fig. 5.23's "Omega < 2.04": 2.0408 = 20 * 5/49, the grid point below is 1.6327 (issue 36)."""
    lo, hi = sweeps.thesis_grid_bracket(1.6939634814894133)  # H1 of n = 2 at mu = 0.03
    assert round(lo, 4) == 1.6327 and round(hi, 4) == 2.0408
    assert sweeps.thesis_grid_bracket(1.547)[1] == pytest.approx(1.6326530612)  # n = 3's H1 lies below 1.6327


def test_the_sentence_holds_on_the_grid_only_if_starts_fail_below_and_all_balance_at_2_04():
    ok = {1.6327: {"balanced": 2, "starts": 10}, 1.8: {"balanced": 10, "starts": 10},
          2.0408: {"balanced": 10, "starts": 10}}
    assert sweeps.consistent_with_grid(ok)
    # negative controls: every start already balances below 2.04; or one fails at 2.0408
    assert not sweeps.consistent_with_grid({**ok, 1.6327: {"balanced": 10, "starts": 10}})
    assert not sweeps.consistent_with_grid({**ok, 2.0408: {"balanced": 9, "starts": 10}})


def test_panel_titles_are_wrapped_to_the_panel():
    longest = max(sweeps.PANELS, key=lambda p: len(p.text))
    title = sweeps.panel_title(longest)
    assert "\n" in title and all(len(line) <= sweeps.PANEL_TITLE_WIDTH for line in title.splitlines())
    assert title.replace("\n", " ").startswith("(c), 2pi/3 phi_2")


def test_figs_5_23_to_5_25_draw_r_max_on_a_linear_axis():
    v = {"Omega": np.linspace(0.5, 20, 4), "r_max": np.ones((4, 10)), "t_dec": np.ones((4, 10))}
    fig = sweeps.parameter_sweep_figure({2: v, 3: v, 4: v}, "Omega", "Fig. 5.23")
    assert {ax.get_yscale() for ax in fig.axes} == {"linear"}


def test_fig_5_25s_common_deltas_are_matched_by_value():
    small = {"delta": 0.03 / 20 * np.arange(1, 21), "r_max": np.ones((20, 10)), "t_dec": np.full((20, 10), 100.0)}
    large = {"delta": 0.12 / 20 * np.arange(1, 21), "r_max": np.full((20, 10), 1.1), "t_dec": np.full((20, 10), 100.0)}
    rows = sweeps.common_deltas(small, large)
    assert [round(r["delta"], 6) for r in rows] == [0.006, 0.012, 0.018, 0.024, 0.03]
    assert all(r["rel"]["r_max"] == pytest.approx(0.1) and r["rel"]["t_dec"] == 0.0 for r in rows)
    # negative control: grids with no delta in common give no row
    assert sweeps.common_deltas(small, {**large, "delta": large["delta"] + 1e-4}) == []


def test_balanced_runs_where_no_member_is_stable_are_explained_and_only_then():
    def basin(zeta, n_balanced, lead):
        return {"zeta": zeta, "balanced": n_balanced, "diagonal_balanced": 0, "undecided": 0, "points": 1600,
                "counts": {"balanced 1": n_balanced, "limit cycle": 1600 - n_balanced}, "family": (lead, 0.0)}

    res = sweeps.Everything(basins_n3=[basin(0.01, 1500, -0.002), basin(0.1, 2, 0.015), basin(0.2, 0, 0.03),
                                       basin(0.25, 0, 0.04)], family_limit=0.0211)
    text = "\n".join(sweeps.basins_n3_lines(res))
    assert "From zeta = 0.0211 on" in text and "2 counted balanced at zeta = 0.1 (published: 2 of 1600);" in text
    assert "met the balanced criterion (r < 1e-3, decaying) by its end" in text
    assert "At zeta = 0.01 members are stable and 1500 of 1600 runs balance on them." in text
    res.basins_n3[1]["balanced"] = 0  # control: no balanced run where no member is stable
    assert "met the balanced criterion (r < 1e-3, decaying)" not in "\n".join(sweeps.basins_n3_lines(res))


def test_the_launches_table_compares_the_published_count_with_our_range_and_ode45():
    def labels(k):
        return ["balanced 1"] * k + ["limit cycle"] * (100 - k)

    v = {"labels": {1e-6: labels(27), 1e-8: labels(29), 1e-10: labels(28)}, "ode45": labels(32), "changes": [0.1],
         "local": [], "command": "adbgen sweep x"}
    res = sweeps.Everything(launches={3: v})
    text = "\n".join(sweeps.launches_lines(res, {"5.11": Path("/r/fig5_11.png")}, Path("/r")))
    assert "| rtol 1e-6 | rtol 1e-8 | rtol 1e-10 |" in text
    assert "| 3 | 28 | 27 | 29 | 28 | 32 | 1 | — |" in text
    assert "* n = 3: published 28; ours 27 to 29 over rtol 1e-6 to 1e-10 (the published count inside that range), " \
           "ode45 32." in text
    v["labels"] = {r: labels(20) for r in v["labels"]}  # control: a range that misses the published count
    assert "inside that range" not in "\n".join(sweeps.launches_lines(res, {"5.11": Path("/r/fig5_11.png")}, Path("/r")))


def test_fig_5_23_n2_starts_fail_at_1_6327_and_balance_at_2_0408():
    """The runs behind the "consistent" column (issue 36: at 1.6327 all ten n = 2 starts fail, at 1.8 and 2.0408
    all balance)."""
    points = sweeps.grid_points_check(2)
    assert [x["balanced"] for x in points.values()] == [0, 10, 10]
    assert sweeps.consistent_with_grid(points)


# the committed docs/reproduction.md's scan rows: panel -> (balanced, {other label: count}, min / median / max)
SCANS = {"5.5(a)": (89, {"limit cycle": 11}, (0.00522, 0.3057, 0.5219)),
         "5.5(b)": (100, {}, (0.04754, 0.04776, 0.04838)),
         "5.7(a1)": (99, {"limit cycle": 1}, (0.002386, 0.2606, 0.722)),
         "5.7(a2)": (98, {"in-line 3(3-2)-": 2}, (0.006033, 0.2597, 0.6318)),
         "5.7(b1)": (99, {"in-line 3(3-2)-": 1}, (0.2579, 0.2724, 0.284)),
         "5.7(b2)": (98, {"in-line 3(3-2)-": 2}, (0.1672, 0.1809, 0.1852)),
         "5.7(c)": (100, {}, (0.4, 0.442, 0.4818)),
         "5.7(c), 2pi/3": (100, {}, (0.04279, 0.04318, 0.04456)),
         "5.9(a1)": (96, {"limit cycle": 4}, (0.04557, 0.4479, 0.93)),
         "5.9(a2)": (96, {"in-line 3(4-3)-": 1, "limit cycle": 3}, (0.001249, 0.3717, 0.828)),
         "5.9(a3)": (99, {"in-line 3(4-3)-": 1}, (0.004812, 0.3011, 0.48)),
         "5.9(b1)": (99, {"in-line 3(4-3)-": 1}, (0.4593, 0.4871, 0.5125)),
         "5.9(b2)": (98, {"in-line 3(4-3)-": 2}, (0.3837, 0.4014, 0.4086)),
         "5.9(b3)": (100, {}, (0.04102, 0.04435, 0.04557)),
         "5.9(c)": (100, {}, (0.04442, 0.04444, 0.04445)),
         "5.9(d)": (100, {}, (0.04176, 0.04497, 0.04764))}
# where the named starts (grid points 0, 23, 83, 99 of pi k/99) ended in the committed run
NAMED_ENDS = {("5.7(a1)", 0): "limit cycle", ("5.7(a2)", 99): "in-line 3(3-2)-", ("5.7(a2)", 0): "in-line 3(3-2)-",
              ("5.7(b2)", 0): "in-line 3(3-2)-", ("5.9(a1)", 0): "limit cycle", ("5.9(a2)", 99): "in-line 3(4-3)-",
              ("5.9(a3)", 0): "in-line 3(4-3)-", ("5.9(b1)", 0): "in-line 3(4-3)-", ("5.9(b2)", 0): "in-line 3(4-3)-"}


def _scan(panel):
    """A scan with the committed row's counts, the named starts' ends and its balanced runs' min / median / max."""
    count, others, (lo, mid, hi) = SCANS[panel.figure]
    labels = ["balanced 1"] * 100
    for (figure, k), label in NAMED_ENDS.items():
        if figure == panel.figure:
            labels[k] = label
    free = (k for k in range(40, 80))
    for label, n in others.items():
        for _ in range(n - sum(1 for (f, _), x in NAMED_ENDS.items() if f == panel.figure and x == label)):
            labels[next(free)] = label
    half = (count - 1) // 2
    values = iter([lo] * half + [mid] * (count - 2 * half) + [hi] * half)
    r_max = [next(values) if label == "balanced 1" else 1.0 for label in labels]
    return {"panel": panel, "labels": labels, "r_max": r_max, "phi_1": np.linspace(0.0, np.pi, 100),
            "command": "adbgen sweep thesis_rotating_n2 --grid phi_1=0:pi:100 --tie phi_2=-phi_1 --measure r_max "
                       "--t-end 3000"}


def _damping():
    """The committed damping maps' rows: n -> (corners of r_max, of t_dec, the not-balanced cells (zeta, beta
    indices), undecided cells)."""
    nan = float("nan")
    rows = {2: ((0.0484, 0.0329, 0.0447, 0.0315), (462.5, 88.3, 409.7, 15.8), [], []),
            3: ((0.0436, 0.1916, 0.0421, 0.0325), (776.0, nan, 425.3, 32.5),
                [(i, j) for i in range(1, 13) for j in range(5)][:37], [(12, 12), (12, 11), (11, 12), (11, 11)]),
            4: ((0.0444, 0.1663, 0.0429, 0.0323), (499.2, nan, 441.2, 41.4), [(i, 0) for i in range(7, 13)], [])}
    out = {}
    for n, (r, t, bad, open_) in rows.items():
        labels = np.full((13, 13), "balanced 1", dtype=object)
        for ij in bad:
            labels[ij] = "limit cycle"
        for ij in open_:
            labels[ij] = "undecided"
        r_max, t_dec = np.zeros((13, 13)), np.zeros((13, 13))
        for (i, j), x, y in zip([(0, 0), (-1, 0), (0, -1), (-1, -1)], r, t):
            r_max[i, j], t_dec[i, j] = x, y
        out[n] = {"labels": labels, "r_max": r_max, "t_dec": t_dec, "zeta": np.linspace(0.01, 0.25, 13),
                  "beta": np.linspace(0.01, 0.25, 13),
                  "command": f"adbgen sweep thesis_rotating_n{n} --grid zeta=0.01:0.25:13 --grid beta=0.01:0.25:13 "
                             "--y0 phi_1=pi/2 --y0 phi_2=-pi/2 --measure attractor --t-end 3000"}
    return out


LYAPUNOV = {"5.12(b), n = 2": (0.001, 0.001, 0.0002, 0.237), "5.13(b), n = 3": (0.058, 0.061, 0.056, 0.431),
            "5.14(b), n = 4": (0.048, 0.053, 0.043, 0.493),
            "5.4(b), n = 2 (control: a limit cycle)": (0.0002, 0.001, 0.0001, 0.161)}


def test_the_scan_lyapunov_and_damping_sections_render_the_published_lines(published_section):
    """templates/scans.md.j2, lyapunov.md.j2, damping_maps.md.j2 from the committed run's values give its lines
    exactly.  Controls: a named start that ends elsewhere is said "**no**"; halves of an exponent above 0.01 make
    the run chaotic; a damping map balanced everywhere says "—"."""
    root = Path("docs")
    paths = {k: root / "reproduction" / name for k, name in
             (("5.5", "fig5_5.png"), ("5.7", "fig5_7.png"), ("5.9", "fig5_9.png"), ("5.20", "fig5_20_22.png"))}
    res = sweeps.Everything(scans=[_scan(p) for p in sweeps.PANELS], zeta_beta=_damping())
    assert sweeps.scans_lines(res, paths, root) == published_section(
        "## Thesis, Figs. 5.5, 5.7, 5.9: r_max against the starting position")
    lyapunov = {k: dict(zip(("exponent", "first_half", "second_half", "r_window"), v)) for k, v in LYAPUNOV.items()}
    assert sweeps.lyapunov_lines(lyapunov) == published_section(
        "## Thesis, Figs. 5.12-5.14 (b): the motion at Omega = 1.6")
    assert sweeps.damping_lines(res, paths, root) == published_section("## Thesis, Figs. 5.20-5.22: damping maps")
    res.scans[0]["labels"][0] = "limit cycle"  # 5.7(a1)'s is at index 0 of its own scan; 5.5(a) names none
    res.scans[2]["labels"][0] = "balanced 1"
    row = "| 5.7(a1) | phi_1 = phi_2 = phi_3 = 0: a limit cycle | balanced 1 (phi_1(0) = 0.00000000000000) | **no** |"
    assert row in sweeps.scans_lines(res, paths, root)
    lyapunov["5.12(b), n = 2"].update(first_half=0.02, second_half=0.03)
    assert sweeps.lyapunov_lines(lyapunov)[6].endswith("| chaotic (positive exponent) |")
    lyapunov["5.12(b), n = 2"].update(exponent=0.007, first_half=0.001, second_half=0.02)
    assert sweeps.lyapunov_lines(lyapunov)[6].endswith("| undecided |")
    res.zeta_beta[3]["labels"][:] = "balanced 1"
    assert sweeps.damping_lines(res, paths, root)[7].startswith("| 3 | 169 | — |")
