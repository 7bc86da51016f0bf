"""The largest Lyapunov exponent of a trajectory from the variational equations (Benettin et al. 1980):
the thesis calls the motion at Omega = 1.6 of Figs. 5.12-5.14 (b) "chaotic" by its look; the exponent
decides it.

The state y and one tangent vector v are integrated together, y' = f(t, y), v' = J(t, y) v, J the generated
Jacobian (the exact derivative of the generated rhs), by scipy's DOP853 on a numba-compiled right-hand side;
every `renorm` time units v is rescaled to length 1 and log |v| summed.  After a transient the running mean
converges to the largest exponent: positive for chaos, 0 for a limit cycle or a torus (the flow direction),
negative at a stable equilibrium.  The two halves of the averaging window are reported beside the whole,
so a non-converged estimate shows.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp


@lru_cache(maxsize=None)
def _augmented(module):
    from numba import njit

    rhs_inplace, jac_inplace = module.rhs_inplace, module.jac_inplace
    n = len(module.STATE_NAMES)

    @njit(cache=False)
    def f(t, z, p):
        out = np.empty(2 * n)
        rhs_inplace(t, z[:n], p, out[:n])
        J = np.empty((n, n))
        jac_inplace(t, z[:n], p, J)
        for i in range(n):  # a loop, not J @ v: numba's @ calls OpenBLAS, whose kernel follows the processor
            acc = 0.0
            for j in range(n):
                acc += J[i, j] * z[n + j]
            out[n + i] = acc
        return out

    return f


def largest_exponent(model, p, y0, t_transient: float = 1000.0, t_average: float = 4000.0, renorm: float = 1.0,
                     rtol: float = 1e-10, atol: float = 1e-12, seed: int = 1) -> dict:
    """{"exponent", "first_half", "second_half", "r_window"}: the largest Lyapunov exponent averaged over
    t_average after t_transient (the tangent vector starts random, fixed seed), and the largest rotor amplitude
    at the solver's steps over that window."""
    f = _augmented(model.module)
    n = model.n_states
    p = np.asarray(p, float)
    y = solve_ivp(lambda t, z: f(t, np.concatenate([z, np.zeros(n)]), p)[:n], (0.0, t_transient),
                  np.asarray(y0, float), method="DOP853", rtol=rtol, atol=atol).y[:, -1]
    v = np.random.default_rng(seed).standard_normal(n)
    v /= np.linalg.norm(v)
    logs = []
    ix, iy = model.amplitude_indices[:2]
    r_window = 0.0
    t = t_transient
    fun = lambda s, z: f(s, z, p)  # noqa: E731
    for _ in range(int(round(t_average / renorm))):
        sol = solve_ivp(fun, (t, t + renorm), np.concatenate([y, v]), method="DOP853", rtol=rtol, atol=atol)
        z = sol.y[:, -1]
        y, v = z[:n], z[n:]
        g = np.linalg.norm(v)
        logs.append(np.log(g))
        r_window = max(r_window, float(np.max(np.hypot(sol.y[ix], sol.y[iy]))))
        v = v / g
        t += renorm
    logs = np.asarray(logs)
    half = len(logs) // 2
    return {"exponent": float(logs.sum() / t_average), "first_half": float(logs[:half].sum() / (half * renorm)),
            "second_half": float(logs[half:].sum() / ((len(logs) - half) * renorm)), "t_transient": t_transient,
            "t_average": t_average, "r_window": r_window}
