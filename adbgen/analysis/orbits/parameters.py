"""The parameters a continuation moves: one or two free ones, and others tied to them by expressions.

    ParameterMap(model, p, ["Omega"])                                   p(lambda) with p[Omega] = lambda
    ParameterMap(model, p, ["Omega", "epsilon"], ties=["m_1=epsilon*M/R_t", ...])
                                                                        ... and m_1 recomputed from epsilon

A tie `NAME=EXPR` (the command line's --tie) sets parameter NAME to EXPR, an expression in parameter names,
numbers and pi with + - * / ** and parentheses, evaluated after the free parameters are set, in the order
given (a tie may use parameters tied before it).  This is how the paper's charts keep the balls' mass in
proportion to the imbalance (m/M = eps/R, Figs. 10, 13, 14) without the analysis code knowing either.
d p / d lambda_j is exact: the expressions are evaluated with a complex step.
"""

from __future__ import annotations

import ast
import math
import operator

import numpy as np

from ..loading import AnalysisError, Model

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
STEP = 1e-30  # complex step


def parse_tie(text: str, model: Model) -> tuple[str, ast.Expression]:
    name, sep, expr = str(text).partition("=")
    name = name.strip()
    if not sep or not name or not expr.strip():
        raise AnalysisError(f"--tie: expected NAME=EXPRESSION, got {text!r}")
    if name not in model.param_names:
        raise AnalysisError(f"--tie: {name!r} is not a parameter of {model.name}; parameters: "
                            f"{', '.join(model.param_names)}")
    try:
        tree = ast.parse(expr.strip(), mode="eval")
    except SyntaxError:
        raise AnalysisError(f"--tie {name}: cannot read {expr.strip()!r}") from None
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id != "pi" and node.id not in model.param_names:
            raise AnalysisError(f"--tie {name}: {node.id!r} is not a parameter of {model.name}")
        if not isinstance(node, (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Name, ast.Constant, ast.Load,
                                 *_BINARY, *_UNARY)):
            raise AnalysisError(f"--tie {name}: only parameter names, numbers, pi, + - * / ** and parentheses")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise AnalysisError(f"--tie {name}: only numbers as constants")
    return name, tree


def _evaluate(tree, values: dict):
    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return math.pi if node.id == "pi" else values[node.id]
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](ev(node.left), ev(node.right))
        return _UNARY[type(node.op)](ev(node.operand))
    return ev(tree)


class ParameterMap:
    """p(lambda): `base` with the free parameters set to lambda and the ties applied."""

    def __init__(self, model: Model, base: np.ndarray, free: list[str], ties=()):
        self.model = model
        self.base = np.array(base, float)
        for name in free:
            if name not in model.param_names:
                raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: "
                                    f"{', '.join(model.param_names)}")
        if len(set(free)) != len(free):
            raise AnalysisError("the free parameters must differ")
        self.free = list(free)
        self.index = [model.param_names.index(n) for n in free]
        self.ties = [t if isinstance(t, tuple) else parse_tie(t, model) for t in ties]
        for name, _ in self.ties:
            if name in self.free:
                raise AnalysisError(f"--tie {name}: a free parameter cannot be tied")
        self.tie_text = [str(t) for t in ties]

    def _apply(self, lam, dtype=float):
        p = self.base.astype(dtype)
        for k, v in zip(self.index, lam):
            p[k] = v
        if self.ties:
            values = dict(zip(self.model.param_names, p))
            for name, tree in self.ties:
                values[name] = _evaluate(tree, values)
                p[self.model.param_names.index(name)] = values[name]
        return p

    def __call__(self, lam) -> np.ndarray:
        p = self._apply(np.atleast_1d(np.asarray(lam, float)))
        if not np.all(np.isfinite(p)):
            raise AnalysisError(f"the ties give non-finite parameters at {dict(zip(self.free, np.atleast_1d(lam)))}")
        return p

    def direction(self, lam, j: int = 0) -> np.ndarray:
        """d p / d lambda_j (exact: complex step through the ties)."""
        lam = np.atleast_1d(np.asarray(lam, float)).astype(complex)
        lam[j] += 1j * STEP
        return np.imag(self._apply(lam, complex)) / STEP

    def values(self, lam) -> dict:
        return dict(zip(self.free, map(float, np.atleast_1d(lam))))
