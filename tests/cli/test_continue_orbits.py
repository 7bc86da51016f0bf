"""adbgen/cli/continue_orbits.py: the periodic-orbit glue of `adbgen continue` (issue 33 item 3: command glue in
cli/, the computing in analysis/orbits); the command's runs are in tests/cli/test_stability.py and
tests/analysis/test_orbits.py, test_orbit_charts.py."""

from __future__ import annotations

import ast
import math
import re
from argparse import Namespace
from pathlib import Path

import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.cli import continue_orbits as glue


def _args(**kw):
    base = dict(orbits=False, from_hopf=None, par2=None, range2=None, tie=[], plot=None, log2=False, grid=None)
    return Namespace(**{**base, **kw})


def test_range2_is_parsed_and_refused_when_malformed():
    assert glue.parse_range2("0.5:2", "1") == (0.5, 2.0)
    # in --par2's unit, as the autonomous and the forced paths of `continue` both read it (one parser)
    assert glue.parse_range2("1000rpm:2000rpm", "rad/s") == pytest.approx((1000 * math.pi / 30, 2000 * math.pi / 30))
    for bad, why in (("0.5", "expected LO:HI"), ("2:0.5", "LO must be below HI"), ("1:1", "LO must be below HI"),
                     ("1:x", "--range2 HI: cannot read"), ("1mm:2mm", "--range2 LO: '1mm' is not in rad/s")):
        with pytest.raises(AnalysisError, match=re.escape(why)):
            glue.parse_range2(bad, "rad/s")


def test_range2_needs_par2_on_either_path():
    with pytest.raises(AnalysisError, match="--range2 needs --par2"):
        glue.range2_option(_args(range2="0:1"), model=None)
    assert glue.range2_option(_args(), model=None) is None


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

    from adbgen.analysis.orbits import auto_cycles

    for fn in (run_points.add_lyapunov, run_points.add_margins, hopf.refine_hopf, branches.plot_branches,
               auto_cycles.auto_branches):
        assert "args" not in inspect.signature(fn).parameters, fn.__qualname__
    with pytest.raises(ImportError):
        from adbgen.analysis.orbits import continue_command  # noqa: F401


def analysis_functions_reading_the_command_line(root: Path) -> list[str]:
    """Functions under `root` with a parameter named `args` (the parsed command line; `*args` is not it) or a
    `getattr(args, ...)`."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                a = node.args
                if any(x.arg == "args" for x in (*a.posonlyargs, *a.args, *a.kwonlyargs)):
                    found.append(f"{path.relative_to(root)}:{node.name}")
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "getattr"
                  and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == "args"):
                found.append(f"{path.relative_to(root)}:{node.lineno}")
    return found


def test_no_analysis_function_takes_the_parsed_command_line(tmp_path):
    """The analysis layer takes values (issue 33): no function of adbgen/analysis reads an argparse namespace."""
    import adbgen.analysis

    assert analysis_functions_reading_the_command_line(Path(adbgen.analysis.__file__).parent) == []
    # negative control: the signature auto_branches had, and its getattr, are found
    planted = tmp_path / "planted.py"
    planted.write_text("def auto_branches(model, name, args=None, nmx=200):\n"
                       "    return getattr(args, 'max_points', None) or nmx\n"
                       "def fine(*args, **kw):\n    return args\n")
    assert analysis_functions_reading_the_command_line(tmp_path) == ["planted.py:auto_branches", "planted.py:2"]
