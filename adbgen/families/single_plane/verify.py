"""Every reduction checked against the thesis: exact identities and numbers with stated tolerances.

Each check returns a `CheckResult`; none prints.  `adbgen verify` runs them all, the tests call them
one by one (and add negative controls showing each can fail).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

import sympy as sp

from ...core import is_identity
from ...core import speed_schedule as _schedule
from ...core.checks import (DERIVED, FORMULA, CheckResult, Registered, flip_term,
                             moved, printed_tolerance, timed as _timed)
from ...core.structure import cramer
from ...references import thesis
from .scene import Scene
from . import steady_states as ss
from .jacobi import rotating_lagrangian, undamped
from .model import derive
from .reductions import first_order, nondimensionalise, rotating_frame, rotating_frame_dimensional
from .symbols import DimensionalSymbols, G, Omega, beta, delta, mu, t, zeta


def _compare(eom, reference: dict[str, sp.Expr], scale: Callable[[str], sp.Expr] = lambda name: 1, wrong: bool = False):
    """Every row of `reference` identical to the derived residual; `wrong`: the first row with a flipped term."""
    if wrong:
        first = next(iter(reference))
        reference = {**reference, first: flip_term(reference[first])}
    bad = [name for name, r in reference.items() if not is_identity(eom.residual(eom.index(name)), scale(name) * r)]
    return not bad, ("all rows identical" if not bad else f"rows differ: {', '.join(bad)}")


def general_scene(n: int, law: str = "torque") -> Scene:
    """Unequal balls, anisotropic support, gravity: the most general single-plane scene."""
    speed = {"law": "torque", "tau0": 0.5, "motor_slope": 1e-3} if law == "torque" else {"law": "constant", "omega": 300.0}
    return Scene.from_mapping({
        "n": n, "ball_mass": [0.01 * (i + 2) for i in range(n)], "ball_damping": [1e-4 * (i + 1) for i in range(n)],
        "stiffness": [1.0e4, 1.3e4], "damping": [2.0, 3.0], "gravity": True, "speed": speed})


def fixed_frame(n: int, wrong: bool = False) -> CheckResult:
    def run():
        scene = general_scene(n)
        eom = derive(scene)
        s = DimensionalSymbols.for_scene(scene)
        psi = eom.coordinates[eom.index("psi")]
        return _compare(eom, thesis.fixed_frame(s, n, torque=s.tau0 - s.kappa * psi.qd), wrong=wrong)
    return _timed(f"fixed frame, n={n}", "thesis (2.10)-(2.13)", run)


def prescribed_speed(n: int, wrong: bool = False) -> CheckResult:
    """Constant speed psi = omega t: the X, Y, phi rows of the torque model with psi substituted."""
    def run():
        scene = general_scene(n, law="constant")
        eom = derive(scene)
        s = DimensionalSymbols.for_scene(scene)
        return _compare(eom, thesis.fixed_frame(s, n, spin=(s.omega * t, s.omega, 0)), wrong=wrong)
    return _timed(f"prescribed speed, n={n}", "thesis (2.10), (2.11), (2.13) with (2.14)", run)


def nondimensional(n: int, gravity: bool = True, wrong: bool = False) -> CheckResult:
    """wrong: the misprinted (2.21) taken as the reference."""
    def run():
        eom = nondimensionalise(Scene(n=n, gravity=gravity))
        ok, detail = _compare(eom, thesis.nondimensional(n, mu, Omega, zeta, beta, delta, G if gravity else 0, t,
                                                         printed=wrong))
        if ok and gravity:
            printed_ok, _ = _compare(eom, thesis.nondimensional(n, mu, Omega, zeta, beta, delta, G, t, printed=True))
            if printed_ok:
                return False, "the misprinted (2.21) (-G(1+n mu)) also matched: check is blind to gravity"
            detail += "; printed (2.21) differs (erratum: -delta G (1 + n mu))"
        return ok, detail
    return _timed(f"non-dimensional, n={n}", "thesis (2.20)-(2.22), (2.21) corrected", run)


def rotating(n: int, wrong: bool = False) -> CheckResult:
    def run():
        eom = rotating_frame(Scene(n=n))
        return _compare(eom, thesis.rotating_frame(n, mu, Omega, zeta, beta, delta), wrong=wrong)
    return _timed(f"rotating frame, n={n}", "thesis (2.25)-(2.27)", run)


def friction_scene(n: int, law: str = "torque") -> Scene:
    """`general_scene` with ball-race friction, a rolling resistance of its own for each ball."""
    return replace(general_scene(n, law), rolling_resistance=tuple(0.01 * (i + 1) for i in range(n)))


def friction_zero_limit(n: int, wrong: bool = False) -> CheckResult:
    """With friction (issue 37), mu_r_i = 0 gives today's equations exactly: the fixed frame under a torque
    and at constant speed, and the rotating frame (isotropic, no gravity), row by row and entry by entry
    of M and f.  wrong: the frictionless model's first residual with a flipped term."""
    def run():
        pairs = []
        for law in ("torque", "constant"):
            pairs.append((derive(friction_scene(n, law)), derive(general_scene(n, law))))
        plain = Scene(n=n, ball_mass=tuple(0.01 * (i + 2) for i in range(n)))
        pairs.append((rotating_frame_dimensional(replace(plain, rolling_resistance=(0.02,) * n)),
                      rotating_frame_dimensional(plain)))
        # the hybrid model (static_friction given), every ball slipping (stuck_i = 0), any slip_dir_i
        sticky = replace(friction_scene(n, "torque"), static_friction=tuple(0.05 * (i + 1) for i in range(n)))
        pairs.append((derive(sticky), derive(general_scene(n, "torque"))))
        bad = []
        for k, (rough, smooth) in enumerate(pairs):
            zero = {p.symbol: 0 for p in rough.parameters if p.name.startswith(("mu_r", "mu_s", "stuck_"))}
            zero |= {p.symbol: 1 for p in rough.parameters if p.name.startswith("slip_dir_")}
            if not zero:
                return False, "the friction model has no rolling-resistance parameter"
            if all(sp.expand(rough.residual(r) - smooth.residual(r)) == 0 for r in range(smooth.size)):
                return False, "the friction model equals the frictionless one at mu_r > 0: no friction derived"
            limit = rough.map(lambda e: sp.expand(e.xreplace(zero)))
            for row, c in enumerate(smooth.coordinates):
                ref = smooth.residual(row)
                if wrong and k == 0 and row == 0:
                    ref = flip_term(ref)
                if limit.coordinates[row].name != c.name or sp.expand(limit.residual(row) - ref) != 0:
                    bad.append(f"{('torque', 'constant speed', 'rotating frame', 'hybrid')[k]}: {c.name}")
        return not bad, ("mu_r = 0: every row identical (torque, constant speed, rotating frame; the hybrid model "
                         "with every ball slipping)" if not bad
                         else f"rows differ: {', '.join(bad)}")
    return _timed(f"friction, zero limit, n={n}", "thesis (2.10)-(2.13), (2.25) at mu_r = 0 (issue 37)", run)


def normal_force(n: int, wrong: bool = False) -> CheckResult:
    """The race's normal force on each ball (`model.normal_forces`, Lagrange's equation of the radial
    coordinate) against Newton's second law along the radius, N_i = -m_i a_i . e_r - m_i g sin(psi + phi_i)
    with a_i the position (2.4) differentiated twice (the most general scene: torque, gravity, unequal
    balls, anisotropy), and against the closed form of a ball in a race spinning at constant speed, rotor
    fixed (X = Y = 0): N_i = m_i R (omega + phi_i')^2 - m_i g sin(omega t + phi_i).  wrong: a normal force
    without the Coriolis-like cross term 2 m R psi' phi_i' (the rotor's speed alone)."""
    def run():
        from ...core import Coordinate, time_derivative
        from .model import lagrangian, normal_forces

        scene = general_scene(n)
        lag = lagrangian(scene)
        s = lag.symbols
        derived = list(normal_forces(lag))
        X, Y, psi = (Coordinate.make(name) for name in ("X", "Y", "psi"))
        if wrong:
            derived = [N - 2 * s.m[i] * s.R * psi.qd * Coordinate.make(f"phi_{i + 1}").qd for i, N in enumerate(derived)]
        bad = []
        for i in range(n):
            phi = Coordinate.make(f"phi_{i + 1}")
            theta = psi.q + phi.q
            ax, ay = (time_derivative(time_derivative(e, lag.all_coordinates, t), lag.all_coordinates, t)
                      for e in lag.positions[f"ball_{i + 1}"])
            newton = -s.m[i] * (ax * sp.cos(theta) + ay * sp.sin(theta)) - s.m[i] * s.g * sp.sin(theta)
            if not is_identity(derived[i], newton):
                bad.append(f"N_{i + 1} (Newton)")
            fixed = {X.q: 0, Y.q: 0, X.qd: 0, Y.qd: 0, X.qdd: 0, Y.qdd: 0, psi.q: s.omega * t, psi.qd: s.omega,
                     psi.qdd: 0}
            closed = s.m[i] * s.R * (s.omega + phi.qd) ** 2 - s.m[i] * s.g * sp.sin(s.omega * t + phi.q)
            if not is_identity(derived[i].xreplace(fixed), closed):
                bad.append(f"N_{i + 1} (rotor fixed)")
        return not bad, ("N_i = Newton's radial law and m R (omega + phi')^2 - m g sin(omega t + phi) with the rotor "
                         "fixed" if not bad else f"differ: {', '.join(bad)}")
    return _timed(f"normal force, n={n}", "Lagrange multiplier of the race (issue 37); thesis (2.4)", run)


ENERGY_RTOL = 1e-11  # the run's tolerance; the balance is asked to 1e-7 of E(0) (measured 1.5e-13 to 2.2e-13, n = 1..3)
ENERGY_MAX_N = 2  # the closed-form rhs it integrates grows as n^2: n = 3 took 5 minutes


def friction_energy(n: int, wrong: bool = False) -> CheckResult:
    """Energy balance over a run with friction: a free rotor (torque law with tau0 = motor_slope = 0),
    gravity, anisotropic support, each ball slipping; along the run (SciPy DOP853 on the derived
    first-order system) E(t) + W(t) = E(0) with E = T + V from the energies (2.7)-(2.8) and W the work of
    the support and ball damping (2F) and of friction, R mu_r_i N_i |phi_i'|, N_i the derived normal force
    at the solution's accelerations.  Every ball keeps slipping (the run ends before any phi_i' = 0, checked):
    the stick phase (the hybrid engine) is not in this check.  wrong: the friction's work counted twice."""
    def run():
        import numpy as np
        from scipy.integrate import solve_ivp

        from .model import lagrangian, normal_forces
        from .reductions import first_order as _first_order

        scene = Scene.from_mapping({
            "n": n, "ball_mass": [0.04 + 0.01 * i for i in range(n)], "stiffness": [1.0e4, 1.3e4],
            "damping": [2.0, 3.0], "gravity": True, "rolling_resistance": [0.02 + 0.01 * i for i in range(n)],
            "speed": {"law": "torque", "tau0": 0.0, "motor_slope": 0.0}})
        lag = lagrangian(scene)
        system = _first_order(derive(scene))
        values = {p.symbol: p.default for p in system.parameters}
        states = list(system.states)
        coords = system.coordinates
        accel = [c.qdd for c in coords]
        energy = sum((term.T + term.V for term in lag.terms), sp.S.Zero)
        power = 2 * lag.rayleigh()  # F is quadratic in the rates: q' . dF/dq' = 2F
        for i, N in enumerate(normal_forces(lag)):
            rate = coords[[c.name for c in coords].index(f"phi_{i + 1}")].qd
            power += (2 if wrong else 1) * lag.symbols.R * lag.symbols.mu_r[i] * N * sp.Abs(rate)
        f_rhs = sp.lambdify(states, [e.xreplace(values) for e in system.rhs()], "numpy", cse=True)
        f_energy = sp.lambdify(states, energy.xreplace(values), "numpy")
        f_power = sp.lambdify(states + accel, power.xreplace(values), "numpy")
        size = len(states)

        def rhs(_t, y):
            dy = np.array(f_rhs(*y[:size]), dtype=float)
            return np.append(dy, f_power(*y[:size], *dy[size // 2:]))
        y0 = np.zeros(size + 1)
        names = [str(v) for v in states]
        y0[names.index("psi_dot")] = 100.0
        for i in range(n):
            y0[names.index(f"phi_{i + 1}")] = 1.3 * i + 0.2
            y0[names.index(f"phi_{i + 1}_dot")] = (40.0 + 10 * i) * (-1) ** i
        sol = solve_ivp(rhs, (0.0, 0.02), y0, method="DOP853", rtol=ENERGY_RTOL, atol=1e-13, dense_output=False,
                        t_eval=np.linspace(0.0, 0.02, 41))
        if not sol.success:
            return False, f"the run failed: {sol.message}"
        rates = sol.y[[names.index(f"phi_{i + 1}_dot") for i in range(n)]]
        if not np.all(np.sign(rates) == np.sign(rates[:, :1])):
            return False, "a ball stopped slipping during the run (the check needs slip throughout)"
        E = np.array([f_energy(*y[:size]) for y in sol.y.T])
        lost = E[0] - E
        error = float(np.max(np.abs(lost - sol.y[size])) / abs(E[0]))
        ok = error <= 1e-7 and float(sol.y[size, -1]) > 1e-3 * abs(E[0])
        return ok, (f"E(0) - E(t) = work of damping and friction to {error:.1e} of E(0) over 0.02 s "
                    f"(friction and damping took {sol.y[size, -1] / abs(E[0]):.1%} of E(0); tol 1e-7)")
    return _timed(f"friction, energy balance, n={n}", "(2.7)-(2.9) with friction in slip (issue 37)", run)


def speed_schedule(wrong: bool = False) -> CheckResult:
    """The speed schedule (`core.speed_schedule.law`, issue 37 item 4): on each phase the angle's derivative is
    the speed and the speed's derivative the acceleration, angle and speed continuous at every phase end,
    the speed omega t / t_ramp on the ramp, omega (1 - depth) on the plateau and omega at the end, all
    exact in the symbols.  wrong: the ramp's angle omega t^2 / t_ramp (the factor 1/2 dropped)."""
    return _timed("speed schedule", "ramp, hold, temporary reduction (issue 37 item 4)",
                  lambda: _schedule.check(t, wrong=wrong))


def two_routes(n: int, wrong: bool = False) -> CheckResult:
    """Transforming the equations and transforming the Lagrangian give the same rotating-frame system
    (wrong: the ball rows' factor mu dropped)."""
    def run():
        scene = Scene(n=n)
        by_equations = rotating_frame(scene)
        by_lagrangian = rotating_lagrangian(scene).eom
        bad = [c.name for k, c in enumerate(by_equations.coordinates)
               if not is_identity(by_lagrangian.residual(k), (1 if k < 2 or wrong else mu) * by_equations.residual(k))]
        return not bad, "identical (ball rows up to the factor mu)" if not bad else f"rows differ: {bad}"
    return _timed(f"reductions commute with Lagrange, n={n}", "thesis (2.1), (2.15)-(2.24)", run)


def appendix_a(n: int, full_solve_up_to: int = 2, wrong: bool = False) -> CheckResult:
    """wrong: the line-by-line reading of (A.12)-(A.13) in the text extraction (its line breaks misplace two
    terms of f onto g's line; Appendix A itself is correct) taken as the reference."""
    def run():
        fo = first_order(rotating_frame(Scene(n=n)))
        ref = thesis.appendix_a(n, mu, Omega, zeta, beta, delta, printed=wrong)
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
        return True, ("a, b, c, f, g, G_1, G_2, G_2+i identical; the extracted text's line-by-line reading of "
                      "(A.12)-(A.13) differs (an extraction artefact, not an erratum)")
    return _timed(f"first-order form, n={n}", "thesis (A.1)-(A.14) (Appendix A is correct: the misplaced terms of "
                  "(A.12)-(A.13) are line breaks of the text extraction, not an erratum)", run)


def steady_states(n: int, wrong: bool = False) -> CheckResult:
    """wrong: every state with its first angle turned by 1/10 rad."""
    def run():
        eom = rotating_frame(Scene(n=n))
        states = {"2+": ss.coincident(n, 1), "2-": ss.coincident(n, -1)}
        for m in range(1, n):
            for sign in (1, -1):
                states[f"3({n}-{m}){'+' if sign > 0 else '-'}"] = ss.inline(n, m, sign)
        if n >= 2:
            states["1"] = ss.balanced(n)
        if wrong:
            states = {k_: {**st, next(iter(st)): st[next(iter(st))] + sp.Rational(1, 10)} for k_, st in states.items()}
        bad = [name for name, st in states.items() if not ss.is_steady_state(eom, st)]
        return not bad, (f"{len(states)} states are exact zeros" if not bad else f"not steady: {bad}")
    return _timed(f"steady states, n={n}", "thesis (3.6), (3.9), (3.10)", run)


# Above this n regenerate runs the proportionate form of the slow checks (`steady_states_numeric`);
# the test suite and `regenerate --full-checks` run the exact ones.
FULL_CHECKS_MAX_N = 6
RESIDUAL_DIGITS = 50  # working precision of the numeric steady-state residuals


def steady_states_numeric(n: int, wrong: bool = False, values: dict | None = None) -> CheckResult:
    """The states of `steady_states` (2+-, 3(n-m)+-, balanced 1) checked numerically instead of
    symbolically: the forcing at rest evaluated in 50-digit arithmetic (mpmath) at parameter values
    (thesis (5.1) by default; complex where a state does not exist there) must vanish to 1e-35 of the
    rows' size with the first angle turned by 0.1 rad.  Linear in n per state where the exact check
    simplifies O(n)-term sums symbolically.  wrong: every state's first angle turned by 1/10 rad."""
    import mpmath

    def run():
        eom = rotating_frame(Scene(n=n))
        vals = {"mu": 0.05, "Omega": 4.0, "zeta": 0.01, "beta": 0.01, "delta": 0.01, **(values or {})}
        rest = {c.qd: sp.S.Zero for c in eom.coordinates}
        coords = [c.q for c in eom.coordinates]
        params = [s_ for s_ in (mu, Omega, zeta, beta, delta)]
        rows = sp.lambdify([coords, params], [f.xreplace(rest) for f in eom.forcing], modules="mpmath")
        states = {"2+": ss.coincident(n, 1), "2-": ss.coincident(n, -1)}
        for m in range(1, n):
            for sign in (1, -1):
                states[f"3({n}-{m}){'+' if sign > 0 else '-'}"] = ss.inline(n, m, sign)
        if n >= 2:
            states["1"] = ss.balanced(n, [sp.pi if k % 2 == 0 else sp.S.Zero for k in range(n - 2)])
        subs = {s_: sp.Float(vals[s_.name], RESIDUAL_DIGITS) for s_ in params}

        memo: dict = {}

        def number(expr):
            expr = sp.sympify(expr)
            if expr not in memo:
                memo[expr] = _number(expr)
            return memo[expr]

        def _number(expr):
            re_, im_ = sp.N(sp.sympify(expr).xreplace(subs), RESIDUAL_DIGITS).as_real_imag()
            return mpmath.mpc(str(sp.N(re_, RESIDUAL_DIGITS)), str(sp.N(im_, RESIDUAL_DIGITS)))
        pv = [mpmath.mpf(vals[s_.name]) for s_ in params]
        bad = []
        with mpmath.workdps(RESIDUAL_DIGITS):
            for name, st in states.items():
                q = [number(st.get(c, sp.S.Zero)) for c in coords]
                if wrong:
                    q[coords.index(next(iter(st)))] += mpmath.mpf(1) / 10
                k = coords.index(next(c for c in coords if c.name == "phi_1"))
                turned = list(q)
                turned[k] += mpmath.mpf(1) / 10
                scale = max(1, max(abs(v) for v in rows(turned, pv)))
                residual = max(abs(v) for v in rows(q, pv))
                if not residual <= mpmath.mpf(10) ** -35 * scale:
                    bad.append(name)
        return not bad, (f"{len(states)} states: residuals below 1e-35 in {RESIDUAL_DIGITS}-digit arithmetic"
                         if not bad else f"not steady: {bad}")
    return _timed(f"steady states (numeric, {RESIDUAL_DIGITS} digits), n={n}", "thesis (3.6), (3.9), (3.10)", run)


def jacobi(n: int, wrong: bool = False) -> CheckResult:
    """wrong: the Rayleigh power dropped from the rate (h claimed conserved with damping)."""
    def run():
        rl = rotating_lagrangian(Scene(n=n))
        first, rate = rl.jacobi_rate_identities()
        if wrong:
            rate = sp.expand(rate - sum((c.qd * sp.diff(rl.F, c.qd) for c in rl.eom.coordinates), sp.S.Zero))
        ok = all(is_identity(f) for f in first) and is_identity(rate) and is_identity(undamped(rate))
        return ok, "dh/dt = -q'.dF/dq' identically; conserved for zeta = beta = 0" if ok else "identity fails"
    return _timed(f"Jacobi integral, n={n}", "rotating frame (2.25)-(2.27), zeta = beta = 0", run)


# Numbers printed in the thesis, compared at their printed precision (half a unit in the last digit).
def thesis_numbers(wrong: bool = False) -> list[CheckResult]:
    """wrong: every printed value moved by 3 units of its last digit."""
    p = dict(mu=0.05, delta=0.01, zeta=0.01)
    rows = []

    def num(name, ref, printed, compute, kind=DERIVED):
        printed = moved(printed) if wrong else printed
        expected, tol = float(printed), printed_tolerance(printed)

        def run():
            got = compute()
            return abs(got - expected) <= tol, f"{got:.15g} vs printed {printed} (tol {tol:g}, half a unit)"
        rows.append(_timed(name, ref, run, kind))

    # (3.16), (3.18): the thesis' closed forms for the critical speeds, re-evaluated
    c1, c2 = ss.critical_speeds(3, 3, p["mu"], p["zeta"], p["delta"])
    num("Omega_c1, 2+-, n=3", "thesis (3.16), Fig. 3.1", "0.8114", lambda: c1, FORMULA)
    num("Omega_c2, 2+-, n=3", "thesis (3.16), Fig. 3.1", "1.0717", lambda: c2, FORMULA)
    d1, d2 = ss.critical_speeds(3, 2, p["mu"], p["zeta"], p["delta"])
    num("Omega_c1, 3(3-2)+-", "thesis (3.18), Fig. 3.2", "0.8909", lambda: d1, FORMULA)
    num("Omega_c2, 3(3-2)+-", "thesis (3.18), Fig. 3.2", "0.9761", lambda: d2, FORMULA)
    # the thesis' own formula 1/sqrt(1 + n mu_c) re-evaluated (FORMULA): the SN2+- wedge tip, not where H2- ends
    num("wedge tip, n=2 (formula re-evaluated)", "thesis (4.1)", "0.9950372", lambda: ss.wedge_tip(2, 2, 0.01)[1], FORMULA)
    num("wedge tip, n=3 (formula re-evaluated)", "thesis (4.2)", "0.9950372", lambda: ss.wedge_tip(3, 3, 0.01)[1], FORMULA)
    num("wedge tip 3+-, n=3", "thesis (4.3)", "0.9853293", lambda: ss.wedge_tip(3, 2, 0.01)[1], FORMULA)
    num("wedge tip 3B+-, n=4", "thesis (4.4)", "0.9901", lambda: ss.wedge_tip(4, 3, 0.01)[1], FORMULA)
    # the balanced states (3.6), proven exact zeros of the derived equations (`steady_states`)
    vals = dict(mu=0.05, delta=0.01)
    num("balanced phi_1, n=2", "thesis (5.2) (sign corrected)", "1.67096374795646",
        lambda: ss.evaluate(ss.balanced(2, branch=-1), vals)["phi_1"])
    num("balanced phi_1, n=3, phi_3=0", "thesis ch. 5.1.2", "2.21429743558818",
        lambda: ss.evaluate(ss.balanced(3, [0], branch=-1), vals)["phi_1"])
    num("balanced phi_1, n=3, phi_3=pi", "thesis ch. 5.1.2", "1.15927948072741",
        lambda: ss.evaluate(ss.balanced(3, [sp.pi]), vals)["phi_1"])
    num("balanced phi_1, n=4, phi_3=phi_4=pi", "thesis ch. 5.1.2", "0.45102681179626",
        lambda: ss.evaluate(ss.balanced(4, [sp.pi, sp.pi]), vals)["phi_1"])

    def printed_5_2():
        # wrong: the corrected sign, which is balanced, claimed to be the misprint
        printed = math.acos((-0.01 if wrong else 0.01) / (2 * 0.05))  # arccos(delta / (2 mu)) as printed
        miss = abs(2 * math.cos(printed) + 0.01 / 0.05)  # (3.6): sum cos phi_i = -delta/mu
        return miss > 0.1, f"printed formula gives {printed:.6f}, off the balance (3.6) by {miss:.3f}"
    rows.append(_timed("(5.2) as printed is not balanced", "thesis (5.2) erratum", printed_5_2, FORMULA))
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


# Hopf points of the balanced state at mu = 0.05 located by a second route: AUTO-07p's HB labels on the
# generated files (README "Stability" table; tests/codegen/test_auto.py re-locates n = 2's).
AUTO_HOPF = {2: (1.0296942, 1.0936343, 1.8822394), 3: (1.8753675,)}
H2_MINUS_END = 1.0079598  # where H2- meets the pitchfork line mu = mu_c (the same for n = 2, 3, 4; the audits' 1.0079598)


def chapter4_numbers(wrong: bool = False) -> list[CheckResult]:
    """Stability results of thesis ch. 4, from the exact linearisation of the derived equations.

    wrong: the printed values moved by 3 units of their last digit, AUTO's Hopf points by 1e-3, the
    zeta limit asked in [0.1, 0.11], the zeta limit's growth in beta claimed quadratic, the end of H2- claimed
    at (4.1)'s 0.9950372, section 5.2.1's "no stable equilibria" claimed at Omega = 0.16."""
    import numpy as np

    from ...core.linearisation import Linearisation, hopf_crossing

    rows = []
    lins = {n: Linearisation(rotating_frame(Scene(n=n))) for n in (2, 3, 4)}
    for n, lin in lins.items():
        def run(n=n, lin=lin):
            q = np.array([0.0, 0.0] + [math.pi] * n)  # at mu = mu_c the balanced and coincident states meet
            om = hopf_crossing(lin, lambda v: q, "Omega", (1.2, 1.5), fixed={"mu": 0.01 / n})
            printed = moved("1.338096") if wrong else "1.338096"
            tol = printed_tolerance(printed)
            return abs(om - float(printed)) <= tol, f"Omega = {om:.8f} vs printed {printed} (tol {tol:g}, half a unit)"
        rows.append(_timed(f"pitchfork-Hopf point, n={n}", "thesis ch. 4.1-4.2, (mu_c, 1.338096)", run))

    def windows():
        grid = np.linspace(0.3, 5.0, 471)
        found = {n: _critical(lins[n], _balanced_coordinates(lins[n], n), "Omega", grid) for n in (2, 3)}
        shift = 1e-3 if wrong else 0.0
        ok = all(len(found[n]) == len(AUTO_HOPF[n]) and
                 all(abs(a - b - shift) <= 1e-6 for a, b in zip(sorted(found[n]), AUTO_HOPF[n])) for n in (2, 3))
        text = "; ".join(f"n={n}: stability changes at Omega = {', '.join(f'{v:.7f}' for v in vals)}"
                         for n, vals in found.items())
        return ok, text + (" = AUTO-07p's HB labels to 1e-6 (n=2: a window near Omega = 1 and Omega > H1; "
                           "n=3: only Omega > H1)")
    rows.append(_timed("balanced state 1 stability windows, mu=0.05", "thesis Fig. 4.2(a), 4.6(a); AUTO-07p", windows))

    def zeta_limit():
        crit = _critical(lins[4], _balanced_coordinates(lins[4], 4), "zeta", np.linspace(0.001, 0.5, 101), Omega=3.0)
        lo, hi = (0.1, 0.11) if wrong else (0.09, 0.1)
        return len(crit) == 1 and lo <= crit[0] <= hi, f"n=4, Omega=3: stable for zeta < {crit[0]:.4f} (thesis: < 0.1)"
    rows.append(_timed("zeta limit of state 1, n=4", "thesis Fig. 4.13(b) text", zeta_limit))

    def beta_effect():
        grid = np.linspace(0.001, 0.5, 101)
        q4, q3 = _balanced_coordinates(lins[4], 4), _balanced_coordinates(lins[3], 3)
        all4 = not _critical(lins[4], q4, "zeta", grid, Omega=4.0, beta=0.05)
        z3 = [_critical(lins[3], q3, "zeta", grid, Omega=4.0, beta=b)[0] for b in (0.05, 0.1)]
        linear = abs(z3[1] / z3[0] - (4 if wrong else 2)) < 0.1  # wrong: claimed quadratic
        return all4 and linear, (f"n=4, beta=0.05: stable for all zeta < 0.5 ({all4}); n=3: zeta limit "
                                 f"{z3[0]:.4f} at beta=0.05, {z3[1]:.4f} at beta=0.1 (grows linearly)")
    rows.append(_timed("ball damping widens stability", "thesis Fig. 4.9(a), 4.14(a)", beta_effect))

    for n, lin in lins.items():
        def h2_end(n=n, lin=lin):
            # erratum (4.1): "given precisely by (mu_c, 1/sqrt(1 + n mu_c)) = (mu_c, 0.9950372)".  At mu = mu_c
            # the coincident state 2- (every ball at pi) is the balanced state; H2- meets that line where its
            # complex pair crosses, computed, not the formula re-evaluated (which gives 0.9950372 by construction)
            q = np.array([0.0, 0.0] + [math.pi] * n)
            om = hopf_crossing(lin, lambda v: q, "Omega", (1.0, 1.2), fixed={"mu": 0.01 / n})
            claim = 0.9950372 if wrong else H2_MINUS_END
            ok = abs(om - claim) <= 1e-6 and abs(om - 0.9950372) > 1e-3
            return ok, (f"H2- meets the pitchfork line at Omega = {om:.8f}, not at the printed 0.9950372 (the wedge "
                        f"tip, a double-zero point): (4.1)'s \"given precisely by\" is an identification (erratum)")
        rows.append(_timed(f"end of H2-, n={n}", "thesis (4.1)-(4.2) erratum", h2_end))

    def omega_016():
        # erratum, section 5.2.1: "Panels (b) depict the case for Omega = 0.16 ... finds no stable equilibria";
        # the captions of Figs. 5.12-5.14 give (Omega, mu) = (1.6, 0.05).  At 0.16 the coincident state 2- is a
        # stable equilibrium for n = 2, 3, 4; at 1.6 none of the closed-form states is stable (the text's claim)
        text = []
        ok = True
        for n, lin in lins.items():
            vals = dict(mu=0.05, zeta=0.01, delta=0.01)
            stable = {}
            for Om in (0.16, 1.6):
                states = [ss.coincident(n, 1), ss.coincident(n, -1)] + ([ss.balanced(n, [sp.pi] * (n - 2), branch=-1)])
                stable[Om] = [lin.spectrum(lin.point(ss.evaluate(st, {**vals, "Omega": Om})),
                                           lin.parameters(Omega=Om)).stable for st in states]
            claim = (not any(stable[0.16])) if wrong else (stable[0.16][1] and not any(stable[1.6]))
            ok &= claim
            text.append(f"n={n}: 2- stable at 0.16 {stable[0.16][1]}, any of 2+, 2-, 1 stable at 1.6 {any(stable[1.6])}")
        return ok, "; ".join(text) + ": the text's Omega = 0.16 is the captions' 1.6 (erratum)"
    rows.append(_timed("section 5.2.1's Omega = 0.16", "thesis section 5.2.1 erratum, Figs. 5.12-5.14 (b)", omega_016))
    return rows


def _per_n(fn, ns):
    return lambda wrong: [fn(n, wrong=wrong) for n in ns]


def registered(ns=(1, 2, 3, 4, 6)) -> list[Registered]:
    """Every check of the family with what it compares and its deliberately wrong variant."""
    ns = tuple(ns)
    return [
        Registered("fixed frame", DERIVED, _per_n(fixed_frame, ns), "first row of (2.10)-(2.13) with a flipped term"),
        Registered("prescribed speed", DERIVED, _per_n(prescribed_speed, ns), "first row with a flipped term"),
        Registered("non-dimensional", DERIVED, _per_n(nondimensional, ns), "the misprinted (2.21)"),
        Registered("rotating frame", DERIVED, _per_n(rotating, ns), "first row of (2.25)-(2.27) with a flipped term"),
        Registered("friction, zero limit", DERIVED, _per_n(friction_zero_limit, ns),
                   "the frictionless first row with a flipped term"),
        Registered("normal force", DERIVED, _per_n(normal_force, ns), "the cross term 2 m R psi' phi' dropped"),
        Registered("friction, energy balance", DERIVED, _per_n(friction_energy, tuple(k for k in ns if k <= ENERGY_MAX_N)),
                   "the friction's work counted twice"),
        Registered("two routes", DERIVED, _per_n(two_routes, ns), "the ball rows' factor mu dropped"),
        Registered("first-order form", DERIVED, _per_n(appendix_a, ns),
                   "the extracted text's line-by-line reading of (A.12)-(A.13)"),
        Registered("steady states", DERIVED, _per_n(steady_states, ns), "each state's first coordinate moved by 1/10"),
        Registered("Jacobi integral", DERIVED, _per_n(jacobi, ns), "the Rayleigh power dropped"),
        Registered("speed schedule", DERIVED, lambda wrong: [speed_schedule(wrong=wrong)],
                   "the ramp's angle without its factor 1/2"),
        Registered("thesis numbers", FORMULA, thesis_numbers, "printed values moved by 3 units of the last digit"),
        Registered("chapter 4 stability", DERIVED, chapter4_numbers,
                   "printed values moved, AUTO's Hopf points moved by 1e-3, zeta window [0.1, 0.11], the beta effect claimed quadratic, "
                   "H2-'s end claimed at (4.1)'s 0.9950372, no stable state claimed at Omega = 0.16"),
    ]

