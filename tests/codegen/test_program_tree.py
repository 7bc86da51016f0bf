"""The rhs as data (`codegen.program_tree`, program.json): evaluated on floats, its trees are the generated
rhs itself, operation for operation (bitwise), so the benchmarks' peers get the generated equations
without reading the generated source (issue 33 item 2)."""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
import sympy as sp

from adbgen.codegen import program_tree
from adbgen.codegen.plain_python import compile_program
from adbgen.codegen.printers import BallInvariantOrder
from adbgen.codegen.spec import build as build_ir
from adbgen.families.single_plane import models as sp_models


def evaluate(data: dict, y, p, t: float) -> np.ndarray:
    """The trees on floats (math's functions, Python's conditional)."""
    functions = {name: getattr(math, name) for name in ("sin", "cos", "tan", "exp", "log", "sqrt", "atan")}
    functions.update(select=lambda c, a, b: a if c else b, less=lambda a, b: a < b)
    return np.array(program_tree.evaluate(data["statements"], dict(enumerate(data["outputs"])), list(y), list(p),
                                          t, functions))


@pytest.fixture(scope="module")
def thesis2():
    return build_ir(sp_models.thesis_rotating(2))


def test_the_trees_are_the_generated_rhs_bitwise(thesis2):
    data = json.loads(program_tree.program_json(thesis2, "0123abcd"))
    assert data["source_hash"] == "0123abcd" and data["states"] == thesis2.n_states and len(data["outputs"]) == thesis2.n_states
    names = [name for name, _ in data["statements"]]
    assert len(names) == len(set(names)) and data["statements"][0] == ["x", ["y", 0]]
    rhs = compile_program(thesis2, "rhs")
    rng = np.random.default_rng(5)
    p0 = np.array([q.default for q in thesis2.parameters])
    for _ in range(10):
        y, p = rng.uniform(-1, 1, thesis2.n_states), p0 * rng.uniform(0.5, 1.5, p0.size)
        assert np.array_equal(evaluate(data, y, p, 0.0), rhs(0.0, y, p))
    # negative control: one output's tree with a planted sign error is caught
    wrong = copy.deepcopy(data)
    wrong["outputs"][-1] = ["neg", wrong["outputs"][-1]]
    assert not np.array_equal(evaluate(wrong, y, p, 0.0), rhs(0.0, y, p))


def test_what_the_trees_cannot_express_is_refused_not_approximated():
    x = sp.Symbol("x", real=True)
    trees = program_tree._Trees(BallInvariantOrder(), {x: ["y", 0]})
    assert trees(sp.sin(x) ** 2) == ["*", ["sin", ["y", 0]], ["sin", ["y", 0]]]
    with pytest.raises(program_tree.ProgramError, match="floor"):
        trees(sp.floor(x))
    with pytest.raises(program_tree.ProgramError, match="unsupported condition"):
        trees(sp.Piecewise((x, x <= 1), (0, True)))


def test_the_time_is_the_models_time_symbol_not_any_symbol_named_t():
    """The time is the IR's symbol (`ModelIR.time`), not a name: another symbol called t is unknown."""
    from adbgen.codegen.ir.model import TIME

    trees = program_tree._Trees(BallInvariantOrder(), {})
    assert trees(TIME) == ["t"]
    with pytest.raises(program_tree.ProgramError, match="unknown symbol t"):
        trees(sp.Symbol("t", positive=True))


def test_every_committed_model_has_its_rhs_as_data():
    """Every model of generated/ has a program.json (none refused: the run-ups' conditions in t too) that
    is its numba rhs bit for bit, at random states, parameters and times on both sides of a run-up's switch."""
    from adbgen.analysis.loading import available_models, load_model

    rng = np.random.default_rng(11)
    for name in available_models():
        model = load_model(name)
        data = json.loads((model.folder / "program.json").read_text())
        assert "error" not in data, (name, data.get("error"))
        for t in (0.0, 0.5, 7000.0):
            y = rng.uniform(-0.5, 0.5, model.n_states)
            p = model.params()
            assert np.array_equal(evaluate(data, y, p, t), np.asarray(model.module.rhs(t, y, p))), (name, t)
