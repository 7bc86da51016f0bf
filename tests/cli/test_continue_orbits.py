"""adbgen/cli/continue_orbits.py: the periodic-orbit glue of `adbgen continue` (issue 33 item 3: command glue in
cli/, the computing in analysis/orbits); the command's runs are in tests/cli/test_stability.py and
tests/analysis/test_orbits.py, test_orbit_charts.py."""

from __future__ import annotations

from argparse import Namespace

import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.cli import continue_orbits as glue


def _args(**kw):
    base = dict(orbits=False, from_hopf=None, par2=None, tie=[], plot=None, log2=False, grid=None)
    return Namespace(**{**base, **kw})


def test_range2_is_parsed_and_refused_when_malformed():
    assert glue.parse_range2(None) is None
    assert glue.parse_range2("0.5:2") == (0.5, 2.0)
    for bad in ("0.5", "2:0.5", "1:1"):  # planted: no colon, reversed, empty
        with pytest.raises(AnalysisError, match="--range2"):
            glue.parse_range2(bad)


def test_which_continuation_the_options_ask_for():
    assert not glue.wants_orbits(_args()) and glue.wants_orbits(_args(orbits=True))
    assert glue.wants_orbits(_args(from_hopf="1.2"))  # --from-hopf implies --orbits
    assert not glue.wants_chart(_args(par2="mu"))  # AUTO-07p's curves
    assert glue.wants_chart(_args(par2="mu", tie=["m_1=mu"])) and glue.wants_chart(_args(par2="mu", log2=True))
    assert not glue.wants_chart(_args(tie=["m_1=mu"]))  # no second parameter: no chart


def test_the_analysis_layer_keeps_no_command_glue():
    """The orbit computing modules the glue calls take values, not the parsed command line."""
    import inspect

    from adbgen.analysis.orbits import branches, hopf, run_points

    for fn in (run_points.add_lyapunov, run_points.add_margins, hopf.refine_hopf, branches.plot_branches):
        assert "args" not in inspect.signature(fn).parameters, fn.__qualname__
    with pytest.raises(ImportError):
        from adbgen.analysis.orbits import continue_command  # noqa: F401
