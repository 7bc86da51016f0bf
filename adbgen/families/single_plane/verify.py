"""Every reduction checked against the thesis: exact identities and numbers with stated tolerances.

Each check returns a `CheckResult`; none prints.  `adbgen verify` runs them all, the tests call them
one by one (and add negative controls showing each can fail).
"""

from __future__ import annotations

import math
from typing import Callable

import sympy as sp

from ...core import is_identity
from ...core.checks import CheckResult, timed as _timed
from ...core.structure import cramer
from ...references import thesis
from .scene import Scene
from . import steady_states as ss
from .jacobi import rotating_lagrangian, undamped
from .model import derive
from .reductions import first_order, nondimensionalise, rotating_frame
from .symbols import DimensionalSymbols, G, Omega, beta, delta, mu, t, zeta


def _compare(eom, reference: dict[str, sp.Expr], scale: Callable[[str], sp.Expr] = lambda name: 1):
    bad = [name for name, r in reference.items() if not is_identity(eom.residual(eom.index(name)), scale(name) * r)]
    return not bad, ("all rows identical" if not bad else f"rows differ: {', '.join(bad)}")


def general_scene(n: int, law: str = "torque") -> Scene:
    """Unequal balls, anisotropic support, gravity: the most general single-plane scene."""
    speed = {"law": "torque", "tau0": 0.5, "motor_slope": 1e-3} if law == "torque" else {"law": "constant", "omega": 300.0}
    return Scene.from_mapping({
        "n": n, "ball_mass": [0.01 * (i + 2) for i in range(n)], "ball_damping": [1e-4 * (i + 1) for i in range(n)],
        "stiffness": [1.0e4, 1.3e4], "damping": [2.0, 3.0], "gravity": True, "speed": speed})


def fixed_frame(n: int) -> CheckResult:
    def run():
        scene = general_scene(n)
        eom = derive(scene)
        s = DimensionalSymbols.for_scene(scene)
        psi = eom.coordinates[eom.index("psi")]
        return _compare(eom, thesis.fixed_frame(s, n, torque=s.tau0 - s.kappa * psi.qd))
    return _timed(f"fixed frame, n={n}", "thesis (2.10)-(2.13)", run)


def prescribed_speed(n: int) -> CheckResult:
    """Constant speed psi = omega t: the X, Y, phi rows of the torque model with psi substituted."""
    def run():
        scene = general_scene(n, law="constant")
        eom = derive(scene)
        s = DimensionalSymbols.for_scene(scene)
        return _compare(eom, thesis.fixed_frame(s, n, spin=(s.omega * t, s.omega, 0)))
    return _timed(f"prescribed speed, n={n}", "thesis (2.10), (2.11), (2.13) with (2.14)", run)


def nondimensional(n: int, gravity: bool = True) -> CheckResult:
    def run():
        eom = nondimensionalise(Scene(n=n, gravity=gravity))
        ok, detail = _compare(eom, thesis.nondimensional(n, mu, Omega, zeta, beta, delta, G if gravity else 0, t))
        if ok and gravity:
            printed_ok, _ = _compare(eom, thesis.nondimensional(n, mu, Omega, zeta, beta, delta, G, t, printed=True))
            if printed_ok:
                return False, "the misprinted (2.21) (-G(1+n mu)) also matched: check is blind to gravity"
            detail += "; printed (2.21) differs (erratum: -delta G (1 + n mu))"
        return ok, detail
    return _timed(f"non-dimensional, n={n}", "thesis (2.20)-(2.22), (2.21) corrected", run)


def rotating(n: int) -> CheckResult:
    def run():
        eom = rotating_frame(Scene(n=n))
        return _compare(eom, thesis.rotating_frame(n, mu, Omega, zeta, beta, delta))
    return _timed(f"rotating frame, n={n}", "thesis (2.25)-(2.27)", run)


def two_routes(n: int) -> CheckResult:
    """Transforming the equations and transforming the Lagrangian give the same rotating-frame system."""
    def run():
        scene = Scene(n=n)
        by_equations = rotating_frame(scene)
        by_lagrangian = rotating_lagrangian(scene).eom
        bad = [c.name for k, c in enumerate(by_equations.coordinates)
               if not is_identity(by_lagrangian.residual(k), (1 if k < 2 else mu) * by_equations.residual(k))]
        return not bad, "identical (ball rows up to the factor mu)" if not bad else f"rows differ: {bad}"
    return _timed(f"reductions commute with Lagrange, n={n}", "thesis (2.1), (2.15)-(2.24)", run)


def appendix_a(n: int, full_solve_up_to: int = 2) -> CheckResult:
    def run():
        fo = first_order(rotating_frame(Scene(n=n)))
        ref = thesis.appendix_a(n, mu, Omega, zeta, beta, delta)
        S, rhs = fo.solve.schur, fo.solve.rhs
        pairs = {"a (A.9)": (S[0, 0], ref["a"]), "b (A.10)": (S[0, 1], ref["b"]), "b' (A.10)": (S[1, 0], ref["b"]),
                 "c (A.11)": (S[1, 1], ref["c"]), "f (A.12)": (rhs[0], ref["f"]), "g (A.13)": (rhs[1], ref["g"])}
        for i, a in enumerate(fo.solve.leaf_accel):
            pairs[f"G_{3 + i} (A.6)"] = (a, ref[f"G_{3 + i}"])
        # (A.7)-(A.8): with S and its right-hand side identical to [[a, b], [b, c]] and (f, g), the
        # solve is the same function of them; prove that on abstract entries (cheap for any n) and,
        # for small n, on the full expressions too.
        a, b, c, f, g = sp.symbols("a b c f g")
        generic = cramer(sp.Matrix([[a, b], [b, c]]), sp.Matrix([f, g]))
        pairs["G_1 (A.7), generic"] = (generic[0], (b * g - c * f) / (b**2 - a * c))
        pairs["G_2 (A.8), generic"] = (generic[1], (b * f - a * g) / (b**2 - a * c))
        if n <= full_solve_up_to:
            core = fo.solve.core_accel()
            pairs["G_1 (A.7)"] = (core[0], ref["G_1"])
            pairs["G_2 (A.8)"] = (core[1], ref["G_2"])
        bad = [k for k, (mine, theirs) in pairs.items() if not is_identity(mine, theirs)]
        if bad:
            return False, f"differ: {', '.join(bad)}"
        printed = thesis.appendix_a(n, mu, Omega, zeta, beta, delta, printed=True)
        if is_identity(rhs[0], printed["f"]):
            return False, "the literal line-by-line reading of (A.12) matched too: check is blind"
        return True, "a, b, c, f, g, G_1, G_2, G_2+i identical; literal reading of (A.12)-(A.13) differs"
    return _timed(f"first-order form, n={n}", "thesis (A.1)-(A.14), (A.12)-(A.13) as corrected", run)


def steady_states(n: int) -> CheckResult:
    def run():
        eom = rotating_frame(Scene(n=n))
        states = {"2+": ss.coincident(n, 1), "2-": ss.coincident(n, -1)}
        for m in range(1, n):
            for sign in (1, -1):
                states[f"3({n}-{m}){'+' if sign > 0 else '-'}"] = ss.inline(n, m, sign)
        if n >= 2:
            states["1"] = ss.balanced(n)
        bad = [name for name, st in states.items() if not ss.is_steady_state(eom, st)]
        return not bad, (f"{len(states)} states are exact zeros" if not bad else f"not steady: {bad}")
    return _timed(f"steady states, n={n}", "thesis (3.6), (3.9), (3.10)", run)


def jacobi(n: int) -> CheckResult:
    def run():
        rl = rotating_lagrangian(Scene(n=n))
        first, rate = rl.jacobi_rate_identities()
        ok = all(is_identity(f) for f in first) and is_identity(rate) and is_identity(undamped(rate))
        return ok, "dh/dt = -q'.dF/dq' identically; conserved for zeta = beta = 0" if ok else "identity fails"
    return _timed(f"Jacobi integral, n={n}", "rotating frame (2.25)-(2.27), zeta = beta = 0", run)


# Numbers printed in the thesis: (expected, tolerance, computed by).
def thesis_numbers() -> list[CheckResult]:
    p = dict(mu=0.05, delta=0.01, zeta=0.01)
    rows = []

    def num(name, ref, expected, tol, compute):
        def run():
            got = compute()
            return abs(got - expected) <= tol, f"{got:.10g} vs printed {expected} (tol {tol:g})"
        rows.append(_timed(name, ref, run))

    c1, c2 = ss.critical_speeds(3, 3, p["mu"], p["zeta"], p["delta"])
    num("Omega_c1, 2+-, n=3", "thesis (3.16), Fig. 3.1", 0.8114, 5e-5, lambda: c1)
    num("Omega_c2, 2+-, n=3", "thesis (3.16), Fig. 3.1", 1.0717, 5e-5, lambda: c2)
    d1, d2 = ss.critical_speeds(3, 2, p["mu"], p["zeta"], p["delta"])
    num("Omega_c1, 3(3-2)+-", "thesis (3.18), Fig. 3.2", 0.8909, 5e-5, lambda: d1)
    num("Omega_c2, 3(3-2)+-", "thesis (3.18), Fig. 3.2", 0.9761, 5e-5, lambda: d2)
    num("wedge tip, n=2", "thesis (4.1)", 0.9950372, 5e-8, lambda: ss.wedge_tip(2, 2, 0.01)[1])
    num("wedge tip, n=3", "thesis (4.2)", 0.9950372, 5e-8, lambda: ss.wedge_tip(3, 3, 0.01)[1])
    num("wedge tip 3+-, n=3", "thesis (4.3)", 0.9853293, 5e-8, lambda: ss.wedge_tip(3, 2, 0.01)[1])
    num("wedge tip 3B+-, n=4", "thesis (4.4)", 0.9901, 5e-5, lambda: ss.wedge_tip(4, 3, 0.01)[1])
    vals = dict(mu=0.05, delta=0.01)
    num("balanced phi_1, n=2", "thesis (5.2) (sign corrected)", 1.67096374795646, 1e-13,
        lambda: ss.evaluate(ss.balanced(2, branch=-1), vals)["phi_1"])
    num("balanced phi_1, n=3, phi_3=0", "thesis ch. 5.1.2", 2.21429743558818, 1e-13,
        lambda: ss.evaluate(ss.balanced(3, [0], branch=-1), vals)["phi_1"])
    num("balanced phi_1, n=3, phi_3=pi", "thesis ch. 5.1.2", 1.15927948072741, 1e-13,
        lambda: ss.evaluate(ss.balanced(3, [sp.pi]), vals)["phi_1"])
    num("balanced phi_1, n=4, phi_3=phi_4=pi", "thesis ch. 5.1.2", 0.45102681179626, 1e-13,
        lambda: ss.evaluate(ss.balanced(4, [sp.pi, sp.pi]), vals)["phi_1"])

    def printed_5_2():
        printed = math.acos(0.01 / (2 * 0.05))  # arccos(delta / (2 mu)) as printed
        miss = abs(2 * math.cos(printed) + 0.01 / 0.05)  # (3.6): sum cos phi_i = -delta/mu
        return miss > 0.1, f"printed formula gives {printed:.6f}, off the balance (3.6) by {miss:.3f}"
    rows.append(_timed("(5.2) as printed is not balanced", "thesis (5.2) erratum", printed_5_2))
    return rows


def _balanced_coordinates(lin, n: int, mu_: float = 0.05, delta_: float = 0.01):
    """The thesis' state 1 (ch. 4): phi_3 = ... = phi_n = pi."""
    return lin.point(ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2), branch=-1), {"mu": mu_, "delta": delta_}))


def _critical(lin, q, parameter: str, grid, **fixed) -> list[float]:
    """Parameter values on a grid where the stability of equilibrium q changes, refined by brentq."""
    from ...core.linearisation import hopf_crossing

    stable = [lin.spectrum(q, lin.parameters(**fixed, **{parameter: v})).stable for v in grid]
    return [hopf_crossing(lin, lambda v: q, parameter, (grid[i], grid[i + 1]), fixed=fixed)
            for i in range(len(grid) - 1) if stable[i] != stable[i + 1]]


def chapter4_numbers() -> list[CheckResult]:
    """Stability results of thesis ch. 4, from the exact linearisation of the derived equations."""
    import numpy as np

    from ...core.linearisation import Linearisation, hopf_crossing

    rows = []
    lins = {n: Linearisation(rotating_frame(Scene(n=n))) for n in (2, 3, 4)}
    for n, lin in lins.items():
        def run(n=n, lin=lin):
            q = np.array([0.0, 0.0] + [math.pi] * n)  # at mu = mu_c the balanced and coincident states meet
            om = hopf_crossing(lin, lambda v: q, "Omega", (1.2, 1.5), fixed={"mu": 0.01 / n})
            return abs(om - 1.338096) <= 1e-6, f"Omega = {om:.7f} vs printed 1.338096 (tol 1e-6)"
        rows.append(_timed(f"pitchfork-Hopf point, n={n}", "thesis ch. 4.1-4.2, (mu_c, 1.338096)", run))

    def windows():
        grid = np.linspace(0.3, 5.0, 471)
        found = {n: _critical(lins[n], _balanced_coordinates(lins[n], n), "Omega", grid) for n in (2, 3)}
        ok = len(found[2]) == 3 and len(found[3]) == 1
        text = "; ".join(f"n={n}: stability changes at Omega = {', '.join(f'{v:.5f}' for v in vals)}"
                         for n, vals in found.items())
        return ok, text + " (n=2: a window near Omega = 1 and Omega > H1; n=3: only Omega > H1)"
    rows.append(_timed("balanced state 1 stability windows, mu=0.05", "thesis Fig. 4.2(a), 4.6(a)", windows))

    def zeta_limit():
        crit = _critical(lins[4], _balanced_coordinates(lins[4], 4), "zeta", np.linspace(0.001, 0.5, 101), Omega=3.0)
        return len(crit) == 1 and 0.09 <= crit[0] <= 0.1, f"n=4, Omega=3: stable for zeta < {crit[0]:.4f} (thesis: < 0.1)"
    rows.append(_timed("zeta limit of state 1, n=4", "thesis Fig. 4.13(b) text", zeta_limit))

    def beta_effect():
        grid = np.linspace(0.001, 0.5, 101)
        q4, q3 = _balanced_coordinates(lins[4], 4), _balanced_coordinates(lins[3], 3)
        all4 = not _critical(lins[4], q4, "zeta", grid, Omega=4.0, beta=0.05)
        z3 = [_critical(lins[3], q3, "zeta", grid, Omega=4.0, beta=b)[0] for b in (0.05, 0.1)]
        linear = abs(z3[1] / z3[0] - 2) < 0.1
        return all4 and linear, (f"n=4, beta=0.05: stable for all zeta < 0.5 ({all4}); n=3: zeta limit "
                                 f"{z3[0]:.4f} at beta=0.05, {z3[1]:.4f} at beta=0.1 (grows linearly)")
    rows.append(_timed("ball damping widens stability", "thesis Fig. 4.9(a), 4.14(a)", beta_effect))
    return rows


SYMBOLIC_CHECKS = (fixed_frame, prescribed_speed, nondimensional, rotating, two_routes, appendix_a,
                   steady_states, jacobi)


def run_all(ns=(1, 2, 3, 4, 6), progress: Callable[[CheckResult], None] | None = None) -> list[CheckResult]:
    results = []
    for n in ns:
        for check in SYMBOLIC_CHECKS:
            r = check(n)
            results.append(r)
            if progress:
                progress(r)
    for r in thesis_numbers() + chapter4_numbers():
        results.append(r)
        if progress:
            progress(r)
    return results
