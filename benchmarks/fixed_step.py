"""Fixed-step explicit Runge-Kutta near its stability limit (issue 14, item 3): step against error,
the blow-up step, and the Jacobian's spectral radius along the trajectory.

Neither CyRK nor SciPy's ``solve_ivp`` has a fixed-step mode (both adapt the step; SUNDIALS ARKODE's
``ERKStepSetFixedStep`` has one, but its N_Vector layer costs about a microsecond per stage here and
its 6.4 tables have no classical RK4), so the fixed-step loop is written here, in numba, over the
generated ``rhs_inplace``: a dozen lines that take any explicit Butcher tableau.  The tableaus are the
classical RK4 (Kutta 1901) and the ones SciPy's adaptive solvers propagate (``RK45``: Dormand-Prince
5(4), ``DOP853``: Hairer's 12-stage order 8), read from SciPy so that no coefficient is copied.

The stability region of an explicit tableau is where |R(z)| <= 1, R(z) = 1 + z b^T (I - z A)^-1 1;
along a ray arg z = theta it ends at r_b(theta) (RK4: 2.785 on the negative real axis, 2.828 on the
imaginary one).  A step h is linearly stable at a state when h |lambda| <= r_b(arg lambda) for every
eigenvalue lambda of the Jacobian there with Re lambda < 0; the predicted blow-up step is the
smallest r_b(arg lambda) / |lambda| along the trajectory.
"""

from __future__ import annotations

import math

import numpy as np

RK4 = (np.array([[0.0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1.0, 0]]),
       np.array([1 / 6, 1 / 3, 1 / 3, 1 / 6]), np.array([0.0, 0.5, 0.5, 1.0]))


def tableaus() -> dict:
    """name -> (A, b, c): classical RK4 and the tableaus SciPy's RK45 and DOP853 propagate."""
    from scipy.integrate._ivp import rk

    dop = rk.DOP853
    s = dop.n_stages
    return {"rk4": RK4,
            "rk45": (_square(rk.RK45.A), np.array(rk.RK45.B, float), np.array(rk.RK45.C, float)),
            "dop853": (np.array(dop.A[:s, :s], float), np.array(dop.B, float), np.array(dop.C[:s], float))}


def _square(A) -> np.ndarray:
    A = np.array(A, float)
    out = np.zeros((A.shape[0], A.shape[0]))
    out[:, :A.shape[1]] = A
    return out


def stability_polynomial(tableau) -> np.ndarray:
    """Coefficients (highest power first) of R(z) = 1 + sum_k z^k b^T A^(k-1) 1, the stability
    function of an explicit tableau (A strictly lower triangular, so the sum ends at k = stages)."""
    A, b, _ = tableau
    coeffs = [1.0]
    v = np.ones(len(b))
    for _ in range(len(b)):
        coeffs.append(float(b @ v))
        v = A @ v
    return np.array(coeffs[::-1])


def stability_function(tableau, z):
    """R(z) = 1 + z b^T (I - z A)^-1 1 (complex z or array)."""
    return np.polyval(stability_polynomial(tableau), z)


def stability_boundary(tableau, theta: float, r_max: float = 20.0) -> float:
    """r_b(theta): the first r > 0 with |R(r e^{i theta})| > 1 (scan, then bisection to 1e-10)."""
    direction = complex(math.cos(theta), math.sin(theta))
    # |R| = 1 - O(r^(p+1)) near 0 on the imaginary axis: start the scan just off 0 and demand a clear excess
    grid = np.linspace(1e-3, r_max, 20001)
    vals = np.abs(stability_function(tableau, grid * direction))
    bad = np.nonzero(vals > 1 + 1e-12)[0]
    if len(bad) == 0:
        return math.inf
    k = bad[0]
    lo, hi = (grid[k - 1] if k else 0.0), grid[k]
    while hi - lo > 1e-10:
        mid = 0.5 * (lo + hi)
        if abs(stability_function(tableau, mid * direction)) > 1 + 1e-12:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


_KERNELS: dict = {}


def fixed_rk(rhs_inplace):
    """A jitted fixed-step explicit RK over `rhs_inplace(t, y, p, out)` (compiled once per rhs).

    run(y0, p, t_end, n_steps, A, b, c, blow) -> (y_end, steps_done, ok): ok is False when the state
    stopped being finite or exceeded `blow` in absolute value (the step is then recorded)."""
    key = id(rhs_inplace)
    if key in _KERNELS:
        return _KERNELS[key]
    from numba import njit

    f = rhs_inplace

    @njit(cache=False)
    def run(y0, p, t_end, n_steps, A, b, c, blow):
        n = y0.shape[0]
        s = b.shape[0]
        h = t_end / n_steps
        y = y0.copy()
        k = np.empty((s, n))
        yi = np.empty(n)
        for step in range(n_steps):
            t = step * h
            for i in range(s):
                for m in range(n):
                    acc = y[m]
                    for j in range(i):
                        acc += h * A[i, j] * k[j, m]
                    yi[m] = acc
                f(t + c[i] * h, yi, p, k[i])
            worst = 0.0
            for m in range(n):
                acc = 0.0
                for i in range(s):
                    acc += b[i] * k[i, m]
                y[m] += h * acc
                v = abs(y[m])
                if not (v <= blow):  # also catches NaN
                    return y, step + 1, False
                worst = max(worst, v)
        return y, n_steps, True

    _KERNELS[key] = run
    return run


def run_fixed(model, p, y0, t_end: float, n_steps: int, tableau, blow: float = 1e3) -> dict:
    import time

    A, b, c = tableau
    run = fixed_rk(model.module.rhs_inplace)
    start = time.perf_counter()
    y, done, ok = run(np.asarray(y0, float), np.asarray(p, float), float(t_end), int(n_steps), A, b, c, float(blow))
    wall = time.perf_counter() - start
    return {"h": t_end / n_steps, "n_steps": int(n_steps), "steps_done": int(done), "ok": bool(ok),
            "t_fail": None if ok else float(done * t_end / n_steps), "y_end": y, "wall_s": wall,
            "n_rhs": int(done) * len(b)}


def blow_up_step(model, p, y0, t_end: float, tableau, h_grid, blow: float = 1e3, rel: float = 1e-4) -> dict:
    """The smallest step on `h_grid` that blows up, then bisection (in the number of steps) against the
    largest stable grid step below it, to a relative width `rel`.  Also records every grid run."""
    runs = []
    for h in sorted(h_grid):
        n = max(1, int(round(t_end / h)))
        r = run_fixed(model, p, y0, t_end, n, tableau, blow)
        runs.append({"h": r["h"], "ok": r["ok"], "t_fail": r["t_fail"]})
    bad = [r["h"] for r in runs if not r["ok"]]
    if not bad:
        return {"grid": runs, "h_blow": None, "h_stable": max(r["h"] for r in runs)}
    h_bad = min(bad)
    good = [r["h"] for r in runs if r["ok"] and r["h"] < h_bad]
    if not good:
        return {"grid": runs, "h_blow": h_bad, "h_stable": None}
    n_good, n_bad = int(round(t_end / max(good))), int(round(t_end / h_bad))
    while n_good - n_bad > 1 and (t_end / n_bad - t_end / n_good) > rel * t_end / n_good:
        mid = (n_good + n_bad) // 2
        if run_fixed(model, p, y0, t_end, mid, tableau, blow)["ok"]:
            n_good = mid
        else:
            n_bad = mid
    return {"grid": runs, "h_blow": t_end / n_bad, "h_stable": t_end / n_good}


def spectrum_along(model, p, t, Y, tableau_boundaries: dict) -> dict:
    """Eigenvalues of the generated Jacobian at the states Y[:, k]: the largest |lambda| (and its
    argument), and per tableau the predicted stability limit min r_b(arg lambda) / |lambda| over the
    decaying eigenvalues (Re lambda < 0) of every state.  `tableau_boundaries`: name -> callable
    theta -> r_b(theta)."""
    jac = model.module.jac
    rho, arg_at_rho, t_rho = 0.0, 0.0, 0.0
    limits = {name: (math.inf, None, None) for name in tableau_boundaries}
    cache: dict = {}
    for k in range(Y.shape[1]):
        lam = np.linalg.eigvals(np.asarray(jac(float(t[k]), Y[:, k], p)))
        a = np.abs(lam)
        i = int(np.argmax(a))
        if a[i] > rho:
            rho, arg_at_rho, t_rho = float(a[i]), float(np.angle(lam[i])), float(t[k])
        for lm in lam:
            if lm.real >= 0 or abs(lm) == 0:
                continue
            theta = round(float(np.angle(lm)), 3)  # r_b is smooth in theta: a table at 1e-3 rad
            for name, boundary in tableau_boundaries.items():
                rb = cache.get((name, theta))
                if rb is None:
                    rb = cache[(name, theta)] = boundary(theta)
                h = rb / abs(lm)
                if h < limits[name][0]:
                    limits[name] = (float(h), float(t[k]), complex(lm))
    return {"rho_max": rho, "arg_at_rho_max": arg_at_rho, "t_at_rho_max": t_rho, "samples": int(Y.shape[1]),
            "predicted_h_limit": {name: {"h": h, "t": tt, "lambda": None if lm is None else [lm.real, lm.imag]}
                                  for name, (h, tt, lm) in limits.items()}}


__all__ = ["RK4", "blow_up_step", "fixed_rk", "run_fixed", "spectrum_along", "stability_boundary",
           "stability_function", "stability_polynomial", "tableaus"]
