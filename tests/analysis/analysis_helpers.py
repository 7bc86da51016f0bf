"""Helpers of the analysis tests (a module name of its own: tests/codegen puts its folder on sys.path too)."""

from __future__ import annotations

from adbgen.analysis import auto07p

# tests/codegen/toolchain.py (conftest.py puts its folder on sys.path): a missing tool fails under CI
from toolchain import require_tool

# thesis ch. 4: mu = 0.05, zeta = beta = delta = 0.01 (Fig. 4.1, 4.5, 4.10)
CH4 = {"mu": 0.05, "zeta": 0.01, "beta": 0.01, "delta": 0.01}


def require_auto() -> None:
    """Fail (CI=true) or skip (elsewhere) when AUTO-07p or its toolchain is missing."""
    missing = auto07p.missing_tools()
    require_tool(not missing, ", ".join(missing) + " (Debian packages auto-07p gfortran gcc make)")



def thesis_n2_state(omega: float):
    """(model, p, y): thesis_rotating_n2 at START_PARAMETERS with Omega = omega and its balanced state 1 there,
    refined by Newton."""
    import numpy as np

    from adbgen.analysis import steady
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.starts import labelled_state

    model = load_model("thesis_rotating_n2")
    p = np.array(model.module.START_PARAMETERS, float)
    p[model.param_names.index("Omega")] = omega
    return model, p, steady.newton(model, p, labelled_state(model, "1", p))[0]


def thesis_n2_hopf(low: float = 1.02, high: float = 1.04) -> tuple[float, object]:
    """(Omega, follower): thesis_rotating_n2's Hopf point of the balanced state 1 in [low, high] (the lowest, near
    1.0297, thesis Fig. 4.2) as the root of its leading real part (`steady.margin_at`), and a function
    (q, guess) -> the steady state at q by Newton."""
    import scipy.optimize

    from adbgen.analysis import steady

    model = thesis_n2_state(low)[0]
    hopf = scipy.optimize.brentq(lambda w: steady.margin_at(*thesis_n2_state(w)).value, low, high, xtol=1e-15)
    return hopf, lambda q, guess: steady.newton(model, q, guess)[0]
