"""Figures checked by what they draw (issue 33 item 5), not by the size of the PNG: the Figure a command
saves is caught on its way through `adbgen.outputs.save_figure` (the one place every figure of the
analysis layer is written), and its axes are read back: labels, titles, legend entries and the data of
each labelled line.  A check that finds something else raises AssertionError saying what it found
(tests/test_figure_checks.py plants a wrong figure for each check).

    saved_figures(monkeypatch)            {file name: Figure} of every figure saved from then on (through
                                          save_figure, or by Figure.savefig to a named file)
    line(ax, label)                       the one line labelled so (an axhline/axvline too)
    assert_line(ax, label, x, y)          the line draws exactly (x, y) (NaN where y is NaN)
    assert_peak(ax, label, value, rel)    the line's largest y is value (the run's r_max, say)
    assert_hline(ax, prefix, y)           a horizontal line labelled prefix... at height y
    assert_vline(ax, prefix, x)           a vertical line labelled prefix... at x
    assert_labels(ax, xlabel, ylabel)     the axis labels, exactly
    assert_legend(ax, entries)            the legend's entries, in order
    assert_title(ax, *parts)              each part is in the axes' title
    vertical_lines(ax)                    where the axes' full-height vertical lines stand (axvline)
"""

from __future__ import annotations

import numpy as np


def saved_figures(monkeypatch) -> dict:
    """Record every Figure passed to `adbgen.outputs.save_figure` (which still writes it) by file name, and
    every Figure saved straight to a named file with Figure.savefig (the figures not written through
    save_figure).  The commands import save_figure when they run, so the patched one is the one they call."""
    import os

    from matplotlib.figure import Figure

    from adbgen import outputs

    seen: dict = {}
    original, savefig = outputs.save_figure, Figure.savefig

    def recording(fig, path, *args, **kwargs):
        seen[os.path.basename(os.fspath(path))] = fig
        return original(fig, path, *args, **kwargs)

    def recording_savefig(fig, fname, *args, **kwargs):
        if isinstance(fname, (str, os.PathLike)):  # save_figure hands it an open temporary file
            seen[os.path.basename(os.fspath(fname))] = fig
        return savefig(fig, fname, *args, **kwargs)

    monkeypatch.setattr(outputs, "save_figure", recording)
    monkeypatch.setattr(Figure, "savefig", recording_savefig)
    return seen


def figure(seen: dict, name: str):
    assert name in seen, f"no figure saved as {name!r} (saved: {sorted(seen)})"
    return seen[name]


def _labels(ax) -> list[str]:
    return [ln.get_label() for ln in ax.get_lines()]


def line(ax, label: str):
    """The one line of ax whose label is `label`."""
    found = [ln for ln in ax.get_lines() if ln.get_label() == label]
    assert len(found) == 1, f"{len(found)} lines labelled {label!r} (lines: {_labels(ax)})"
    return found[0]


def _starting(ax, prefix: str):
    found = [ln for ln in ax.get_lines() if ln.get_label().startswith(prefix)]
    assert len(found) == 1, f"{len(found)} lines labelled {prefix!r}... (lines: {_labels(ax)})"
    return found[0]


def assert_line(ax, label: str, x, y, rtol: float = 0.0) -> None:
    """The line draws the points (x, y): the same number of points, each equal (to rtol), NaN where y is."""
    ln = line(ax, label)
    xd, yd = np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float)
    x, y = np.asarray(x, float), np.asarray(y, float)
    assert xd.shape == x.shape and yd.shape == y.shape, \
        f"{label!r} draws {xd.shape} x by {yd.shape} y points, expected {x.shape} by {y.shape}"
    assert np.allclose(xd, x, rtol=rtol, atol=0, equal_nan=True), f"{label!r}: x differs from the result"
    assert np.allclose(yd, y, rtol=rtol, atol=0, equal_nan=True), f"{label!r}: y differs from the result"


def assert_peak(ax, label: str, value: float, rel: float) -> None:
    """The largest y the line draws is `value` to `rel` (a run's r_max against its plotted r)."""
    peak = float(np.nanmax(np.asarray(line(ax, label).get_ydata(), float)))
    assert abs(peak - value) <= rel * abs(value), f"{label!r} peaks at {peak!r}, the result says {value!r}"


def assert_hline(ax, prefix: str, y: float, rel: float = 1e-12) -> None:
    ln = _starting(ax, prefix)
    yd = np.asarray(ln.get_ydata(), float)
    assert len(yd) == 2 and yd[0] == yd[1], f"{ln.get_label()!r} is not horizontal"
    assert abs(yd[0] - y) <= rel * abs(y), f"{ln.get_label()!r} at y = {yd[0]!r}, expected {y!r}"


def assert_vline(ax, prefix: str, x: float, rel: float = 1e-12) -> None:
    ln = _starting(ax, prefix)
    xd = np.asarray(ln.get_xdata(), float)
    assert len(xd) == 2 and xd[0] == xd[1], f"{ln.get_label()!r} is not vertical"
    assert abs(xd[0] - x) <= rel * abs(x), f"{ln.get_label()!r} at x = {xd[0]!r}, expected {x!r}"


def assert_labels(ax, xlabel: str | None = None, ylabel: str | None = None) -> None:
    if xlabel is not None:
        assert ax.get_xlabel() == xlabel, f"x label {ax.get_xlabel()!r}, expected {xlabel!r}"
    if ylabel is not None:
        assert ax.get_ylabel() == ylabel, f"y label {ax.get_ylabel()!r}, expected {ylabel!r}"


def assert_legend(ax, entries: list[str]) -> None:
    legend = ax.get_legend()
    assert legend is not None, "the axes have no legend"
    shown = [t.get_text() for t in legend.get_texts()]
    assert shown == list(entries), f"legend {shown}, expected {list(entries)}"


def assert_title(ax, *parts: str) -> None:
    text = ax.get_title()
    missing = [p for p in parts if p not in text]
    assert not missing, f"title {text!r} lacks {missing}"


def vertical_lines(ax) -> list[float]:
    """The x of each line drawn across the whole height of ax (an axvline: x constant, y 0 to 1 of the axes)."""
    found = []
    for ln in ax.get_lines():
        x, y = np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float)
        spans = ln.get_transform() == ax.get_xaxis_transform()  # y in axes fractions: as axvline draws it
        if spans and len(x) == 2 and x[0] == x[1] and list(y) == [0.0, 1.0]:
            found.append(float(x[0]))
    return found
