"""The thesis' closed-form steady states (ch. 3), evaluated with numpy for `--state LABEL`.

The symbolic forms live in `adbgen.families.single_plane.steady_states` (SymPy, shown there to be exact
zeros of the derived equations); this layer never imports SymPy, so the same formulas are written
here once more in numpy and the tests show both agree and are zeros of the generated `rhs`.

Labels (thesis models `thesis_rotating_n*`, parameters Omega, beta, delta, mu, zeta):

    1         balanced state (3.6), phi_3.. = pi (thesis ch. 4's choice), 0 where pi leaves no solution
    2+, 2-    coincident states (3.9)
    3(k)+, 3(k)-   in-line states (3.10) with k = n - m balls opposite the m coincident ones
              (1 <= k <= n - 1; the thesis' 3 (n = 2), 3+- (n = 3), 3A = 3(2)+, 3B+- = 3(1)+- (n = 4))
"""

from __future__ import annotations

import math

import numpy as np

from .loading import AnalysisError, Model

THESIS_PARAMETERS = ("Omega", "beta", "delta", "mu", "zeta")


def is_thesis_model(model: Model) -> bool:
    """The dimensionless rotating-frame model (2.25)-(2.27) of identical balls."""
    return (model.autonomous and set(THESIS_PARAMETERS) == set(model.param_names)
            and tuple(model.module.CORE) == ("x", "y"))


def labels(model: Model) -> list[str]:
    """The closed-form states this model has labels for (empty unless a thesis model)."""
    if not is_thesis_model(model):
        return []
    n = len(model.leaves)
    out = (["1"] if n >= 2 else []) + ["2+", "2-"]
    for k in range(1, n):
        out += [f"3({k})+", f"3({k})-"]
    return out


def _values(model: Model, p: np.ndarray) -> dict[str, float]:
    return dict(zip(model.param_names, (float(v) for v in p)))


def balanced(n: int, mu: float, delta: float) -> np.ndarray | None:
    """Angles of the balanced state (3.6) with phi_3.. = pi (or pi, 0, pi, ... where that has no solution)."""
    if n < 2:
        return None
    for free in ([math.pi] * (n - 2), [math.pi if k % 2 == 0 else 0.0 for k in range(n - 2)]):
        A = -delta / mu - sum(math.cos(a) for a in free)
        B = -sum(math.sin(a) for a in free)
        r = math.hypot(A, B) / 2
        if r <= 1:
            alpha, gamma = math.atan2(B, A), math.acos(r)
            return np.array([alpha + gamma, alpha - gamma, *free])
    return None


def inline(n: int, m: int, sign: int, Omega: float, delta: float, mu: float, zeta: float) -> np.ndarray | None:
    """(x, y, phi_1..phi_n) of the in-line state (3.10) (m = n: the coincident state (3.9)); None if absent."""
    p = 2 * m - n
    K = 1 - Omega**2 * (1 + n * mu)
    den = K**2 + (2 * Omega * zeta) ** 2
    arg = -2 * p * mu * zeta * Omega / math.sqrt((2 * Omega * zeta * delta) ** 2 + (K * delta) ** 2)
    if abs(arg) > 1 or zeta <= 0:
        return None
    phi1 = sign * math.acos(arg) - math.atan(-K / (2 * Omega * zeta))
    x = (K * Omega**2 * (p * mu * math.cos(phi1) + delta) + 2 * p * mu * Omega**3 * zeta * math.sin(phi1)) / den
    y = (p * K * mu * Omega**2 * math.sin(phi1) - 2 * Omega * zeta * (delta * Omega**2 + p * mu * Omega**2 * math.cos(phi1))) / den
    return np.array([x, y] + [phi1 if i < m else phi1 + math.pi for i in range(n)])


def state(model: Model, label: str, p: np.ndarray) -> np.ndarray:
    """The full state (rates zero) of closed-form state `label` at parameters p."""
    known = labels(model)
    if label not in known:
        hint = f"labels: start, {', '.join(known)}" if known else "this model has only: start"
        raise AnalysisError(f"unknown state label {label!r}; {hint}")
    v = _values(model, p)
    n = len(model.leaves)
    if label == "1":
        angles = balanced(n, v["mu"], v["delta"])
        if angles is None:
            raise AnalysisError(f"no balanced state (3.6) at mu = {v['mu']:g}, delta = {v['delta']:g} "
                                f"(needs mu >= delta/n, (3.14))")
        coords = np.r_[0.0, 0.0, angles]
    else:
        sign = 1 if label.endswith("+") else -1
        m = n if label.startswith("2") else n - int(label[2:label.index(")")])
        coords = inline(n, m, sign, v["Omega"], v["delta"], v["mu"], v["zeta"])
        if coords is None:
            raise AnalysisError(f"state {label} does not exist at these parameters ((3.16)/(3.18), zeta > 0)")
    y = np.zeros(model.n_states)
    order = ("x", "y", *model.leaves)
    for name, value in zip(order, coords):
        y[model.index(name)] = value
    return y
