"""adbgen/cli/arguments.py: the option parsers the commands share (`quantity_pair`: --range2, --scan, design's
LOW:HIGH read by one function)."""

from __future__ import annotations

import math

import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.cli.arguments import quantity_pair


def test_a_pair_is_two_quantities_in_the_unit():
    assert quantity_pair("0.5:2", "1", "--x", "LO:HI", ("--x LO", "--x HI")) == (0.5, 2.0)
    assert quantity_pair("pi/2:-pi", "rad", "--x", "LO:HI", ("--x LO", "--x HI")) == (math.pi / 2, -math.pi)
    a, b = quantity_pair("3000rpm:400", "rad/s", "--x", "LO:HI", ("--x LO", "--x HI"))
    assert a == pytest.approx(100 * math.pi) and b == 400.0  # a value with a unit converted, a number taken as is
    # the order is the caller's: a pair may run downwards (--scan FROM:TO)
    assert quantity_pair("2:1", "1", "--x", "LO:HI", ("--x LO", "--x HI")) == (2.0, 1.0)


@pytest.mark.parametrize("text, message", [
    ("1", "--scan: expected NAME=FROM:TO, got '1'"),  # no colon: the option's own form
    ("x:1", "--scan Omega FROM: cannot read 'x'"),    # each side named by its label
    ("1:2mm", "--scan Omega TO: '2mm' is not in rad/s"),
])
def test_a_bad_pair_is_one_line_naming_the_side(text, message):
    with pytest.raises(AnalysisError) as exc:
        quantity_pair(text, "rad/s", "--scan", "NAME=FROM:TO", ("--scan Omega FROM", "--scan Omega TO"))
    assert str(exc.value).startswith(message) and "\n" not in str(exc.value)
