"""adbgen/cli/orbit.py: the options `continue` gains for periodic orbits (`add_continue_options`)."""

from __future__ import annotations

import pytest

from adbgen.cli import build_parser, main


@pytest.mark.parametrize("value, message", [
    ("1", "argument --max-points: must be at least 2, got 1"),
    ("0", "argument --max-points: must be at least 2, got 0"),
    ("many", "argument --max-points: not a whole number: 'many'"),
])
def test_max_points_below_two_is_one_line_from_the_parser(capsys, value, message):
    """A branch needs its start and one more point: refused by the option's type, one line, exit 2, before
    any model is loaded (the model named here does not exist)."""
    code = main(["continue", "no_such_model", "--par", "Omega", "--orbits", "--max-points", value])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err == f"adbgen: error: {message}\n"


def test_max_points_keeps_its_default_and_takes_two():
    parse = build_parser().parse_args
    assert parse(["continue", "thesis_rotating_n2", "--par", "Omega"]).max_points == 200
    assert parse(["continue", "thesis_rotating_n2", "--par", "Omega", "--max-points", "2"]).max_points == 2


def test_continue_tie_help_says_it_takes_an_expression_with_an_example():
    """`continue --tie` is NAME=EXPR and `design --tie` NAME=VARIED (tests/cli/test_design.py): each help says its own."""
    sub = build_parser()._subparsers._group_actions[0].choices["continue"]
    tie = next(a for a in sub._actions if "--tie" in a.option_strings)
    assert tie.metavar == "NAME=EXPR"
    assert "EXPR an expression in parameter names" in tie.help and "e.g. --tie m_1=epsilon*M/R_t" in tie.help
    assert "design's --tie takes NAME=VARIED" in tie.help
