"""Small model folders for the orbit tests: systems whose periodic orbits and bifurcations are known exactly.

`write_toy` renders a toy's rhs, Jacobian and parameter Jacobian from SymPy expressions into a folder
that `load_model(folder)` reads like one written by `adbgen regenerate --out` (a C file with
<name>_rhs, <name>_jac, <name>_jac_p for the compiled variational driver; an __init__.py with the
self-description the orbit code reads and the same functions in Python).

* `pd_toy`: a cycle (the Hopf normal form's unit circle, period 2 pi) with a Moebius-twisted pair (u, v):
  in coordinates turning by half a revolution per period the pair is diag(mu + d, mu - d), so its
  multipliers are -exp(2 pi (mu +- d)): a period-doubling at mu = -d and at mu = d, exactly.
* `torus_toy`: the same cycle with a pair (u, v) of eigenvalues mu +- i w2: multipliers exp(2 pi (mu +- i w2)),
  a torus (Neimark-Sacker) point at mu = 0 with angle 2 pi w2, exactly.  `saddle=True`: eigenvalues
  mu + 1, mu - 1 instead, whose multipliers' product passes 1 at mu = 0 without a complex pair (a neutral
  saddle: the torus test function changes sign there, and it is not a torus point).
* `duffing_toy`: x'' + c x' - x + x^3 = g cos(w t), periodically forced (FORCING_FREQUENCY "w").
* `hopf_toy`: the Hopf normal form z' = (a + i) z + l |z|^2 z in Cartesian form: first Lyapunov
  coefficient l (Kuznetsov's normalisation), the cycle's radius sqrt(-a / l) for a l < 0.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import sympy as sp


def write_toy(folder: Path, name: str, states, params: dict, rhs, *, angles=(), amplitude=None,
              forcing: str = "", autonomous: bool = True) -> Path:
    ys = sp.symbols(states)
    ps = sp.symbols(list(params))
    F = sp.Matrix(rhs)
    J = F.jacobian(ys)
    Jp = F.jacobian(ps)
    n, m = len(ys), len(ps)
    folder = Path(folder) / name
    folder.mkdir(parents=True, exist_ok=True)
    sub = {**{s: sp.Symbol(f"y[{i}]") for i, s in enumerate(ys)}, **{s: sp.Symbol(f"p[{i}]") for i, s in enumerate(ps)}}

    def c(e):
        return sp.ccode(sp.sympify(e).xreplace(sub))

    def py(e):
        return sp.pycode(sp.sympify(e).xreplace(sub)).replace("math.", "math.")
    body = ["#include <math.h>",
            f"void {name}_rhs(double t, const double *y, const double *p, double *dydt) {{",
            "    (void)t; (void)p;"]
    body += [f"    dydt[{i}] = {c(e)};" for i, e in enumerate(F)] + ["}"]
    for fn, M, cols in (("jac", J, n), ("jac_p", Jp, m)):
        body += [f"void {name}_{fn}(double t, const double *y, const double *p, double *out) {{",
                 "    (void)t; (void)y; (void)p;"]
        body += [f"    out[{i * cols + j}] = {c(M[i, j])};" for i in range(n) for j in range(cols)] + ["}"]
    (folder / f"{name}.c").write_text("\n".join(body) + "\n")

    def block(M, cols, target):
        return "\n".join(f"    {target}[{i}, {j}] = {py(M[i, j])}" for i in range(M.shape[0]) for j in range(cols))
    src = f'''
        """Toy model {name} (tests/analysis/orbit_toys.py)."""
        import math
        import numpy as np

        NAME = {name!r}
        SOURCE_HASH = "toy"
        AUTONOMOUS = {autonomous!r}
        STATE_NAMES = {tuple(states)!r}
        PARAM_NAMES = {tuple(params)!r}
        DEFAULTS = np.array({[float(v) for v in params.values()]!r})
        CORE = ()
        LEAVES = ()
        ANGLES = {tuple(angles)!r}
        AMPLITUDE = {tuple(amplitude or states[:2])!r}
        FORCING_FREQUENCY = {forcing!r}
        MEASURES = ()  # no compiled measures (the orbit code reads MEASURES, it does not guess)
        START = None
        START_PARAMETERS = None


        def rhs(t, y, p):
            return np.array([{", ".join(py(e) for e in F)}])


        def jac_inplace(t, y, p, out):
            out[:, :] = 0.0
{textwrap.indent(block(J, n, "out"), "        ")}


        def jac(t, y, p):
            out = np.zeros(({n}, {n}))
            jac_inplace(t, y, p, out)
            return out


        def jac_p(t, y, p):
            out = np.zeros(({n}, {m}))
{textwrap.indent(block(Jp, m, "out"), "        ")}
            return out
        '''
    (folder / "__init__.py").write_text(textwrap.dedent(src))
    return folder


def _cycle(x1, y1):
    r2 = x1**2 + y1**2
    return [x1 - y1 - x1 * r2, x1 + y1 - y1 * r2]


def pd_toy(folder: Path, d: float = 0.1) -> Path:
    x1, y1, u, v, mu, dd = sp.symbols("x1 y1 u v mu d")
    rhs = _cycle(x1, y1) + [mu * u - v / 2 + dd * (x1 * u + y1 * v), mu * v + u / 2 + dd * (y1 * u - x1 * v)]
    return write_toy(folder, "toy_pd", ["x1", "y1", "u", "v"], {"mu": -0.3, "d": d}, rhs)


def torus_toy(folder: Path, w2: float = 0.3, saddle: bool = False) -> Path:
    x1, y1, u, v, mu, w = sp.symbols("x1 y1 u v mu w")
    pair = [(mu + 1) * u, (mu - 1) * v] if saddle else [mu * u - w * v, w * u + mu * v]
    return write_toy(folder, "toy_saddle" if saddle else "toy_torus", ["x1", "y1", "u", "v"], {"mu": -0.2, "w": w2},
                     _cycle(x1, y1) + pair)


def duffing_toy(folder: Path) -> Path:
    x, xd, c, g, w, t = sp.symbols("x x_dot c g w t")
    return write_toy(folder, "toy_duffing", ["x", "x_dot"], {"c": 0.3, "g": 0.2, "w": 1.2},
                     [xd, -c * xd + x - x**3 + g * sp.cos(w * t)], amplitude=("x", "x_dot"), forcing="w",
                     autonomous=False)


def hopf_toy(folder: Path, l: float = -0.5) -> Path:
    x, y, a, ll = sp.symbols("x y a l")
    r2 = x**2 + y**2
    return write_toy(folder, "toy_hopf", ["x", "y"], {"a": 0.0, "l": l},
                     [a * x - y + ll * r2 * x, x + a * y + ll * r2 * y])
