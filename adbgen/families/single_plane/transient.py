"""The thesis' transients (ch. 5): simulate, measure r_max and the decay time t_dec.

Figure 5.4 (n = 2, parameters (5.1), all initial rates and x, y zero): the thesis reports
r_max = 0.0483, 0.2878, 0.0478 and t_dec = 462.42, 745.02, 549.93 (r < 1e-3) for the initial
ball positions (pi/2, -pi/2), (3pi/4, -3pi/4), (0, pi).  Those runs used Matlab's ode45 at its
default tolerances, so agreement to a few tenths of a percent is what to expect.

Downstream of code generation: the right-hand side is the generated numba module
`generated.thesis_rotating_n<n>` (no SymPy at run time).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ...errors import AdbgenError

FIGURE_5_4 = {  # initial (phi_1, phi_2): (r_max, t_dec) as printed
    "a": ((np.pi / 2, -np.pi / 2), (0.0483, 462.42)),
    "c": ((3 * np.pi / 4, -3 * np.pi / 4), (0.2878, 745.02)),
    "d": ((0.0, np.pi), (0.0478, 549.93)),
}


@dataclass(frozen=True)
class Transient:
    t: np.ndarray
    y: np.ndarray  # states on the rows, as `state_names`
    state_names: tuple[str, ...]
    r_max: float
    t_dec: float  # last time r >= threshold (first sample after it)


def thesis_model(n: int):
    """The generated numba module of the thesis' rotating-frame model with n balls."""
    name = f"generated.thesis_rotating_n{n}"
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError:
        raise AdbgenError(f"{name} is not generated (generated/ holds n = 2, 3, 4; "
                          f"`adbgen regenerate --n {n} --out DIR` makes others)") from None


def simulate(n: int, phi0, t_end: float = 1000.0, params: dict[str, float] | None = None,
             threshold: float = 1e-3, samples: int = 200_001, rtol: float = 1e-10) -> Transient:
    """Rotating-frame transient from rest (x = y = 0, all rates 0) with balls at phi0."""
    model = thesis_model(n)
    p = model.params(**(params or {}))
    y0 = np.zeros(model.N_STATES)
    y0[[model.state_index(f"phi_{i + 1}") for i in range(n)]] = phi0
    sol = solve_ivp(model.rhs, (0.0, t_end), y0, args=(p,), method="DOP853", rtol=rtol, atol=rtol * 1e-2,
                    dense_output=True)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    tt = np.linspace(0.0, t_end, samples)
    Y = sol.sol(tt)
    r = np.hypot(Y[model.state_index("x")], Y[model.state_index("y")])
    above = np.nonzero(r >= threshold)[0]
    t_dec = float(tt[min(above[-1] + 1, len(tt) - 1)]) if len(above) else 0.0
    return Transient(tt, Y, model.STATE_NAMES, float(r.max()), t_dec)
