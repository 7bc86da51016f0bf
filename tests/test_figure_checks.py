"""The figure checks (tests/figure_checks.py) pass on the figure a command saves and fail on a planted
wrong one: each check has its negative control here."""

from __future__ import annotations

import numpy as np
import pytest

import figure_checks as fc
from adbgen.analysis.figure_style import amplitude_panel, angle_panel, pyplot
from adbgen import outputs

T = np.linspace(0.0, 10.0, 101)
R = 1e-2 * np.exp(-T)


def _drawn(tmp_path, saved_figures, r=R, t_dec=4.6):
    """A transient drawn as the commands draw it, saved through save_figure (so caught)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1)
    amplitude_panel(a1, T, r, 1e-4, t_dec, "m", "s")
    angle_panel(a2, T, np.vstack([T, -T]), ["phi_1", "phi_2"])
    a2.set_xlabel("$t$ (s)")
    a1.set_title("rig\nOmega = 3")
    outputs.save_figure(fig, tmp_path / "transient.png")
    return fc.figure(saved_figures, "transient.png").axes


def test_the_saved_figure_is_caught_and_still_written(tmp_path, saved_figures):
    a1, a2 = _drawn(tmp_path, saved_figures)
    assert (tmp_path / "transient.png").read_bytes()[:4] == b"\x89PNG"
    fc.assert_line(a1, "$r$", T, R)
    fc.assert_peak(a1, "$r$", 1e-2, rel=1e-12)
    fc.assert_hline(a1, "threshold", 1e-4)
    fc.assert_vline(a1, "$t_{dec}$", 4.6)
    fc.assert_labels(a1, ylabel="$r$ (m)")
    fc.assert_labels(a2, xlabel="$t$ (s)", ylabel="ball angle (rad, wrapped)")
    fc.assert_legend(a2, ["$\\phi_{1}$", "$\\phi_{2}$"])
    fc.assert_title(a1, "rig", "Omega = 3")
    assert fc.vertical_lines(a1) == [4.6] and fc.vertical_lines(a2) == []
    with pytest.raises(AssertionError, match="no figure saved as 'scan.png'"):
        fc.figure(saved_figures, "scan.png")


@pytest.mark.parametrize("check, match", [
    (lambda a1, a2: fc.assert_line(a1, "$r$", T, R * 1.001), "y differs"),
    (lambda a1, a2: fc.assert_line(a1, "$r$", T[:-1], R[:-1]), "draws"),
    (lambda a1, a2: fc.assert_line(a1, "r", T, R), "0 lines labelled 'r'"),
    (lambda a1, a2: fc.assert_peak(a1, "$r$", 2e-2, rel=1e-3), "peaks at"),
    (lambda a1, a2: fc.assert_hline(a1, "threshold", 1e-3), "at y ="),
    (lambda a1, a2: fc.assert_vline(a1, "$t_{dec}$", 4.7), "at x ="),
    (lambda a1, a2: fc.assert_vline(a1, "threshold", 1e-4), "not vertical"),
    (lambda a1, a2: fc.assert_labels(a1, ylabel="$r$"), "y label"),
    (lambda a1, a2: fc.assert_labels(a2, xlabel="$t$"), "x label"),
    (lambda a1, a2: fc.assert_legend(a2, ["$\\phi_{1}$"]), "legend"),
    (lambda a1, a2: fc.assert_title(a1, "Omega = 4"), "lacks"),
], ids=["line-data", "line-length", "line-label", "peak", "hline", "vline", "vline-shape", "ylabel", "xlabel",
        "legend", "title"])
def test_each_check_fails_on_a_planted_wrong_figure(tmp_path, saved_figures, check, match):
    a1, a2 = _drawn(tmp_path, saved_figures)
    with pytest.raises(AssertionError, match=match):
        check(a1, a2)


def test_a_figure_drawn_from_the_wrong_run_fails(tmp_path, saved_figures):
    """The figure of another run (r doubled, t_dec elsewhere) fails the checks this run passes."""
    a1, _ = _drawn(tmp_path, saved_figures, r=2 * R, t_dec=5.3)
    with pytest.raises(AssertionError):
        fc.assert_peak(a1, "$r$", float(R.max()), rel=1e-9)
    with pytest.raises(AssertionError):
        fc.assert_vline(a1, "$t_{dec}$", 4.6)


def test_a_figure_saved_straight_by_savefig_is_caught_too(tmp_path, saved_figures):
    """Figures written with Figure.savefig to a named file (not through save_figure) are caught by name;
    one written to an open file has no name and is not."""
    plt = pyplot()
    fig, ax = plt.subplots()
    ax.plot([0.0, 1.0], [2.0, 3.0], label="x")
    fig.savefig(tmp_path / "straight.png")
    with open(tmp_path / "handle.png", "wb") as fh:
        fig.savefig(fh, format="png")
    assert fc.figure(saved_figures, "straight.png") is fig and "handle.png" not in saved_figures
    fc.assert_line(fig.axes[0], "x", [0.0, 1.0], [2.0, 3.0])
    with pytest.raises(AssertionError, match="x differs"):
        fc.assert_line(fig.axes[0], "x", [0.0, 2.0], [2.0, 3.0])
    plt.close(fig)


def test_vertical_lines_find_each_axvline_and_only_those(tmp_path, saved_figures):
    """A vertical segment in data coordinates is no axvline (it need not span the axes), nor is a sloped
    line; a planted second mark is found."""
    a1, _ = _drawn(tmp_path, saved_figures)
    a1.plot([2.0, 2.0], [0.0, 1.0])
    a1.plot([1.0, 2.0], [0.0, 1.0])
    assert fc.vertical_lines(a1) == [4.6]
    a1.axvline(7.0)
    assert fc.vertical_lines(a1) == [4.6, 7.0]
