"""Checks of the lowering, run before anything is written: every program of the intermediate form
(rhs, jac, jac_p, mass_matrix, forcing) against an evaluation that does not go through the lowering,
the start point at rest in the rendered rhs, and every declaration of the self-description against
the rendered rhs (`check_description`).

The references (`Reference`) lambdify the model's whole mass matrix M and forcing f (after the speed
law) and solve M q'' = f densely with numpy: no Schur complement, no structure, valid for any core
size.  The Jacobians are compared with fourth-order central differences of that dense solve, at
random points away from equilibria (rates, time and angles all random: a residual row whose
acceleration terms carry the wrong sign is invisible at rest, where the accelerations vanish), so an
error in the lowering's derivative construction cannot hide behind a program that shares it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from ...core.first_order import FirstOrderSystem
from ...errors import AdbgenError
from ..ir.model import ModelIR
from ..plain_python import compile_program

LOWERING_TOLERANCE = 1e-12  # rhs, mass_matrix, forcing against the symbolic model (exact arithmetic but rounding)
# the extension's rhs gets sin, cos(omega t) from the state, the forced model computes them: at
# omega t up to 4e3 rad their rounding alone is ~1e-12 (measured up to 1.5e-12)
EXTENSION_TOLERANCE = 1e-10
DERIVATIVE_TOLERANCE = 1e-7  # jac, jac_p against fourth-order central differences (<= 2e-9 measured)
PROGRAMS = ("rhs", "mass", "forcing", "jac", "jac_p")


class CheckFailed(AdbgenError):
    pass


@dataclass(frozen=True)
class Reference:
    """The symbolic model evaluated without the lowering: M, f lambdified, accelerations by a dense solve."""

    mass: Callable
    forcing: Callable
    N: int
    defaults: np.ndarray

    @classmethod
    def of(cls, system: FirstOrderSystem) -> "Reference":
        eom = system.solve.eom
        law = dict(eom.driven_law)
        args = (eom.time, list(system.states), [p.symbol for p in system.parameters])
        mass = sp.lambdify(args, eom.mass_matrix().xreplace(law), modules="numpy")
        forcing = sp.lambdify(args, [sp.sympify(e).xreplace(law) for e in eom.forcing], modules="numpy")
        return cls(mass, forcing, eom.size, np.array([p.default for p in system.parameters], dtype=float))

    def M(self, t, y, p) -> np.ndarray:
        return np.array(self.mass(t, y, p), dtype=float)

    def f(self, t, y, p) -> np.ndarray:
        return np.array(self.forcing(t, y, p), dtype=float)

    def rhs(self, t, y, p) -> np.ndarray:
        return np.concatenate([y[self.N: 2 * self.N], np.linalg.solve(self.M(t, y, p), self.f(t, y, p))])

    def points(self, n_states: int, n_coordinates: int, samples: int, seed: int):
        """Random (t, y, p) away from equilibria: rates in [-1, 1], coordinates in [-0.1, 0.1] (angles
        too: the lowering is not periodic in them), parameters 0.5x to 1.5x the defaults."""
        rng = np.random.default_rng(seed)
        for _ in range(samples):
            y = rng.uniform(-1, 1, n_states)
            y[:n_coordinates] *= 0.1
            yield float(rng.uniform(0, 10)), y, self.defaults * rng.uniform(0.5, 1.5, self.defaults.size)


def central_difference(fn: Callable[[np.ndarray], np.ndarray], x: np.ndarray,
                       steps: tuple[float, ...] = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7)) -> np.ndarray:
    """d fn/dx (columns by x) by the fourth-order central stencil.

    Per column the relative step (times max(|x_j|, 1e-2)) is the one of `steps` whose estimate
    changes least to the next smaller step: a dimensional forcing sin(omega t) at omega = 400, t = 10
    needs 1e-6, a dimensionless model is best near 1e-3.
    """
    cols = []
    # a wrong program can overflow here: its NaN or inf then fails the comparison (`not err <= tol`) with
    # the one-line refusal, so numpy's warnings would only add lines to stderr
    with np.errstate(all="ignore"):
        for j in range(x.size):
            cols.append(_column(fn, x, j, steps))
    return np.array(cols).T


def _column(fn, x: np.ndarray, j: int, steps: tuple[float, ...]) -> np.ndarray:
    """Column j of `central_difference`: the estimate of the step that changes least to the next one."""
    def stencil(rel):
        h = rel * max(abs(x[j]), 1e-2)

        def at(s):
            z = x.copy()
            z[j] += s * h
            return fn(z)
        return (8 * (at(1) - at(-1)) - (at(2) - at(-2))) / (12 * h)
    estimates = [stencil(rel) for rel in steps]
    change = [float(np.max(np.abs(a - b))) for a, b in zip(estimates, estimates[1:])]
    return estimates[int(np.argmin(change)) + 1]


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(1e-300, float(np.max(np.abs(b)))))


def errors_of(functions: dict[str, Callable], ref: Reference, n_states: int, n_coordinates: int,
              samples: int = 12, seed: int = 0) -> dict[str, float]:
    """{name: largest norm-wise relative difference from the independent evaluation} for the given
    functions (t, y, p) -> array of 'rhs', 'mass', 'forcing', 'jac', 'jac_p' (any subset; flat or
    shaped, row-major) at random non-equilibrium points: rhs against the dense solve, mass and forcing
    against the symbolic M and f, jac (d rhs/dy) and jac_p (d rhs/dp) against central differences of
    the dense solve.  Used on the lowered programs here and on every target's code in the tests."""
    N, S, P = ref.N, n_states, ref.defaults.size
    errors = dict.fromkeys(functions, 0.0)
    for k, (t, y, p) in enumerate(ref.points(S, n_coordinates, samples, seed)):
        def worse(name, reference, shape):
            if name in functions:
                got = np.asarray(functions[name](t, y, p), dtype=float).reshape(shape)
                errors[name] = max(errors[name], _relative(got, reference() if callable(reference) else reference))
        worse("rhs", ref.rhs(t, y, p), (S,))
        worse("mass", ref.M(t, y, p), (N, N))
        worse("forcing", ref.f(t, y, p), (N,))
        if k < 3:  # the derivatives cost 24 (S + P) dense solves a point
            worse("jac", lambda: central_difference(lambda z: ref.rhs(t, z, p), y), (S, S))
            worse("jac_p", lambda: central_difference(lambda q: ref.rhs(t, y, q), p), (S, P))
    return errors


def program_errors(ir: ModelIR, system: FirstOrderSystem, samples: int = 12, seed: int = 0,
                   reference: Reference | None = None) -> dict[str, float]:
    """`errors_of` the intermediate form's five programs (run in Python, `plain_python`)."""
    ref = reference or Reference.of(system)
    return errors_of({name: compile_program(ir, name) for name in PROGRAMS}, ref, ir.n_states, ir.n_coordinates,
                     samples, seed)


def extension_errors(ext: ModelIR, system: FirstOrderSystem, samples: int = 4, seed: int = 1,
                     reference: Reference | None = None) -> dict[str, float]:
    """The oscillator extension (40): its rhs on the cycle (osc = sin, cos(w t)) against the dense solve
    of the forced model, and its jac, jac_p against central differences of its own rhs program."""
    ref = reference or Reference.of(system)
    rhs, jac, jac_p = (compile_program(ext, name) for name in ("rhs", "jac", "jac_p"))
    names = {p.name: p.symbol for p in system.parameters}
    w = sp.lambdify([[p.symbol for p in system.parameters]],
                    sp.sympify(ext.forcing_frequency, locals=names), modules="numpy")
    S, P, n = ext.n_states, len(ext.parameters), 2 * ref.N
    errors = {"rhs": 0.0, "jac": 0.0, "jac_p": 0.0}
    for t, y, p in ref.points(n, ext.n_coordinates, samples, seed):
        z = np.concatenate([y, [np.sin(w(p) * t), np.cos(w(p) * t)]])
        errors["rhs"] = max(errors["rhs"], _relative(rhs(0.0, z, p)[:n], ref.rhs(t, y, p)))
        errors["jac"] = max(errors["jac"], _relative(jac(0.0, z, p).reshape(S, S), central_difference(lambda u: rhs(0.0, u, p), z)))
        errors["jac_p"] = max(errors["jac_p"], _relative(jac_p(0.0, z, p).reshape(S, P), central_difference(lambda q: rhs(0.0, z, q), p)))
    return errors


def _refuse(name: str, errors: dict[str, float], against: dict[str, str], rhs_tolerance: float = LOWERING_TOLERANCE) -> None:
    for program, err in errors.items():
        tol = DERIVATIVE_TOLERANCE if program.startswith("jac") else rhs_tolerance
        if not err <= tol:
            raise CheckFailed(f"{name}: program {program} differs from {against[program]} by {err:.2e} "
                              f"(tolerance {tol:g})")


_AGAINST = {"rhs": "the dense solve of the symbolic model", "mass": "the symbolic M", "forcing": "the symbolic f",
            "jac": "central differences of the dense solve", "jac_p": "central differences of the dense solve"}
_AGAINST_EXT = {"rhs": "the forced model's dense solve on the oscillator's cycle",
                "jac": "central differences of its rhs", "jac_p": "central differences of its rhs"}


def check_programs(ir: ModelIR, system: FirstOrderSystem, reference: Reference | None = None) -> dict[str, float]:
    """Every program of `ir` (and of its oscillator extension) within tolerance of its independent
    evaluation, or CheckFailed naming the program; returns the errors (the extension's as 'ext:...')."""
    ref = reference or Reference.of(system)
    errors = program_errors(ir, system, reference=ref)
    _refuse(ir.name, errors, _AGAINST)
    if ir.autonomous_extension is not None:
        ext = extension_errors(ir.autonomous_extension, system, reference=ref)
        _refuse(f"{ir.name} (oscillator extension)", ext, _AGAINST_EXT, EXTENSION_TOLERANCE)
        errors |= {f"ext:{k}": v for k, v in ext.items()}
    return errors


def lowering_error(ir: ModelIR, system: FirstOrderSystem, samples: int = 20, seed: int = 0) -> float:
    """Largest relative difference between the rhs program and a dense solve at random points."""
    ref = Reference.of(system)
    program = compile_program(ir, "rhs")
    return max(_relative(program(t, y, p), ref.rhs(t, y, p)) for t, y, p in ref.points(ir.n_states, ir.n_coordinates, samples, seed))


def check_start(ir: ModelIR) -> None:
    """The start point is a steady state (an equilibrium; on an oscillator extension, a point of a
    periodic orbit at rest apart from the oscillator) of the rendered rhs, to rounding: 1e-12 of the
    rhs's size at the start with its ball angles (the leaves) turned by 0.1 rad."""
    f = compile_program(ir, "rhs")
    y, p = np.array(ir.start), np.array(ir.start_parameters)
    rows = slice(0, 2 * ir.n_coordinates)  # not the oscillator's rows, if any
    turned = y.copy()
    for k, name in enumerate(ir.state_names[: ir.n_coordinates]):
        if name in ir.leaves:
            turned[k] += 0.1
    scale = max(1.0, float(np.max(np.abs(f(0.0, turned, p)[rows]))))
    residual = float(np.max(np.abs(f(0.0, y, p)[rows])))
    if not residual <= 1e-12 * scale:
        raise CheckFailed(f"{ir.name}: the start point ({ir.start_label}) is not at rest: |rhs| = {residual:.2e} "
                          f"(scale {scale:.2e})")


# ------------------------------------------------------------------------------ self-description

DESCRIPTION_SAMPLES = 24  # random parameter points per steady-state label
PERIODIC_TOLERANCE = 1e-9  # rhs(y + 2 pi e_k) against rhs(y), relative: sin, cos of shifted angles round
SYMMETRY_TOLERANCE = 1e-10  # rhs(S y) against S rhs(y), relative
STEADY_TOLERANCE = 1e-10  # |rhs| at a closed-form steady state, relative to the rhs's size nearby


def _project(p: np.ndarray, images, signs) -> np.ndarray:
    """p made invariant under the signed permutation: p[k] = signs[k] p[images[k]] for every k (a cycle
    whose signs multiply to -1 can only be zero)."""
    p = p.copy()
    done = set()
    for start in range(len(p)):
        if start in done:
            continue
        cycle, k = [], start
        while k not in done:
            done.add(k)
            cycle.append(k)
            k = images[k]
        # p[k] = s_k p[image(k)] with s_k = +-1, so p[image(k)] = s_k p[k] along the cycle
        if np.prod([signs[k] for k in cycle]) < 0:
            p[cycle] = 0.0
            continue
        for k in cycle[:-1]:
            p[images[k]] = signs[k] * p[k]
    return p


def _apply(y: np.ndarray, images, signs) -> np.ndarray:
    return np.asarray(signs, dtype=float) * y[list(images)]


def _relative_to(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(1e-300, float(np.max(np.abs(b))), float(np.max(np.abs(a)))))


def _state_points(ir: ModelIR, samples: int, seed: int):
    """Random (t, y, p): angles on the whole circle, other coordinates in [-0.1, 0.1], rates in [-1, 1],
    parameters 0.5x to 1.5x the defaults."""
    rng = np.random.default_rng(seed)
    N, names = ir.n_coordinates, ir.state_names
    angles = [names.index(a) for a in ir.description.angles]
    defaults = np.array([p.default for p in ir.parameters], dtype=float)
    for _ in range(samples):
        y = rng.uniform(-1, 1, ir.n_states)
        y[:N] *= 0.1
        y[angles] = rng.uniform(-np.pi, np.pi, len(angles))
        yield float(rng.uniform(0, 10)), y, defaults * rng.uniform(0.5, 1.5, defaults.size)


def _check_roles(ir: ModelIR) -> None:
    d = ir.description
    coords = ir.state_names[: ir.n_coordinates]
    turning = {c for c, role in zip(coords, d.roles) if role in ("ball_angle", "spin_angle")}
    if turning != set(d.angles):
        raise CheckFailed(f"{ir.name}: the angles {sorted(d.angles)} are not the coordinates whose role is a ball "
                          f"or spin angle {sorted(turning)}")


def _check_angles(ir: ModelIR, rhs) -> float:
    """The rhs is 2 pi-periodic in every declared angle (and the check sees a shift of anything else)."""
    worst = 0.0
    for t, y, p in _state_points(ir, 2, 11):
        base = rhs(t, y, p)
        for name in ir.description.angles:
            shifted = y.copy()
            shifted[ir.state_names.index(name)] += 2 * np.pi
            err = _relative_to(rhs(t, shifted, p), base)
            if not err <= PERIODIC_TOLERANCE:
                raise CheckFailed(f"{ir.name}: the rhs is not 2 pi-periodic in the declared angle {name} "
                                  f"(relative change {err:.2e})")
            worst = max(worst, err)
    return worst


def magnitudes(expr: sp.Expr) -> sp.Expr:
    """A bound of the magnitudes a floating-point evaluation of `expr` combines, as an expression in the same
    symbols (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., ch. 3: evaluated in any order with n
    operations, |fl(e) - e| <= gamma_n * magnitudes(e), gamma_n = n eps / (1 - n eps), to first order): every sum's
    terms in absolute value, products of their factors' bounds, a power's relative error |exponent| times its base's,
    and sin(u), cos(u) bounded by 1 + the bound of u (their value's rounding, and u's own carried through a slope of
    at most 1: the spin angle of a time law, omega t up to thousands of radians, enters here)."""
    if expr.is_Add:
        return sp.Add(*[magnitudes(a) for a in expr.args])
    if expr.is_Mul:
        return sp.Mul(*[magnitudes(a) for a in expr.args])
    if expr.is_Pow:
        base, exp = expr.args
        if exp.is_Integer and exp > 0:
            return magnitudes(base) ** exp
        # b**e from b with relative error delta: relative error |e| delta, delta = magnitudes(b) / |b|
        return sp.Abs(expr) * sp.Max(1, sp.Abs(exp)) * magnitudes(base) / sp.Abs(base)
    if isinstance(expr, sp.Piecewise):
        return sp.Piecewise(*[(magnitudes(value), cond) for value, cond in expr.args])
    if isinstance(expr, (sp.sin, sp.cos)):
        return 1 + magnitudes(expr.args[0])
    return sp.Abs(expr)


def _has_time_law(expr: sp.Expr, time: sp.Symbol) -> bool:
    return time in sp.sympify(expr).free_symbols


def measure_errors(ir: ModelIR, system: FirstOrderSystem, samples: int = 8, seed: int = 12):
    """Per random point and measure: (name, got, want, |got - want|, bound), the rendered measure against its SymPy
    expression.  The bound is LOWERING_TOLERANCE |want| (rounding of exact arithmetic), and for a measure in which
    time enters (a model with a time law: the law is written into every measure) at least the rounding the
    evaluation of its terms may carry, 2 n eps magnitudes(expr) (n its operations, both evaluations rounding):
    such a measure sums terms of the law's size (omega^2, omega t in sin and cos) that cancel to a small value, so a
    fixed relative bound is marginal there (a schedule's stick force was refused at 1.2e-12 against 1e-12:
    docs/friction.md) and could be broken by another CPU's or libm's last bits."""
    from ..plain_python import compile_measures

    d = ir.description
    eom = system.solve.eom
    args = (eom.time, list(system.states), [p.symbol for p in system.parameters])
    reference = sp.lambdify(args, list(d.measure_exprs), modules="numpy")
    timed = [k for k, e in enumerate(d.measure_exprs) if _has_time_law(e, eom.time)]
    rounding = {k: (2 * max(1, sp.count_ops(d.measure_exprs[k])) * float(np.finfo(float).eps),
                    sp.lambdify(args, magnitudes(sp.sympify(d.measure_exprs[k])), modules="numpy")) for k in timed}
    measures = compile_measures(ir)
    out = []
    for t, y, p in _state_points(ir, samples, seed):
        z = y[: len(system.states)]
        got, want = measures(t, y, p), np.array(reference(t, z, p), dtype=float)
        for k, name in enumerate(d.measure_names):
            bound = LOWERING_TOLERANCE * abs(want[k])
            if k in rounding:
                factor, size = rounding[k]
                bound = max(bound, factor * float(size(t, z, p)))
            out.append((name, got[k], want[k], abs(got[k] - want[k]), bound))
    return out


def _check_measures(ir: ModelIR, system: FirstOrderSystem) -> float:
    """The largest relative error of a measure; CheckFailed where one exceeds its bound (measure_errors)."""
    worst = 0.0
    for name, got, want, err, bound in measure_errors(ir, system):
        if not err <= max(bound, 1e-300 * LOWERING_TOLERANCE):
            raise CheckFailed(f"{ir.name}: measure {name} = {got!r} where its expression gives {want!r} "
                              f"(difference {err:.2e}, bound {bound:.2e})")
        worst = max(worst, err / max(1e-300, abs(want)))
    return worst


def _check_forcing(ir: ModelIR, system: FirstOrderSystem) -> None:
    from ...core.description import forcing_frequency

    d = ir.description
    frequency = forcing_frequency(system.solve.eom)
    declared = {p.name: p.symbol for p in system.parameters}.get(d.forcing_frequency)
    if frequency is None and declared is not None:
        raise CheckFailed(f"{ir.name}: declares the forcing frequency {d.forcing_frequency} but is not periodically "
                          "forced at one frequency")
    if frequency is not None and (declared is None or sp.simplify(frequency - declared) != 0):
        raise CheckFailed(f"{ir.name}: periodically forced at {frequency}, but declares "
                          f"{d.forcing_frequency or 'no forcing frequency'}")


def _check_symmetries(ir: ModelIR, rhs) -> float:
    from ...core.description import IDENTICAL_BALLS

    worst = 0.0
    for s in ir.description.symmetries:
        images, signs = s["states"], s["signs"]
        for t, y, p in _state_points(ir, 4, 13):
            p = _project(p, s["params"], s["param_signs"])
            err = _relative_to(rhs(t, _apply(y, images, signs), p), _apply(rhs(t, y, p), images, signs))
            if not err <= SYMMETRY_TOLERANCE:
                raise CheckFailed(f"{ir.name}: symmetry {s['name']!r} does not hold on the rhs "
                                  f"(relative difference {err:.2e})")
            worst = max(worst, err)
            if s["kind"] == IDENTICAL_BALLS:  # exact at a state the exchange fixes: balls together stay together
                fixed = _project(y, images, signs)
                f = rhs(t, fixed, p)
                if not np.array_equal(f, _apply(f, images, signs)):
                    raise CheckFailed(f"{ir.name}: {s['name']!r} holds only to rounding where the exchanged balls "
                                      "coincide (identical balls must stay bitwise together)")
    return worst


def _parameter_points(ir: ModelIR, samples: int, seed: int):
    """Random parameters for the steady states: the defaults and the named sets, each parameter scaled by
    a factor log-uniform in [0.2, 5]; every other point projected onto the equalities the closed forms'
    guards ask for (so closed forms that apply only there are met)."""
    d = ir.description
    rng = np.random.default_rng(seed)
    names = ir.parameter_names
    defaults = np.array([p.default for p in ir.parameters], dtype=float)
    bases = [defaults]
    for _, values in d.parameter_sets:
        base = defaults.copy()
        for k, v in values:
            base[names.index(k)] = v
        bases.append(base)
    psym = [p.symbol for p in ir.parameters]
    equalities = [g for form in d.declared.closed_forms for c in form.candidates for g in c.guards
                  if isinstance(g, sp.Eq) and g.lhs in psym]
    setters = [(names.index(g.lhs.name), sp.lambdify([psym], g.rhs, modules="numpy")) for g in equalities
               if g.rhs.free_symbols <= set(psym)]
    for k in range(samples):
        p = bases[k % len(bases)] * np.exp(rng.uniform(np.log(0.2), np.log(5.0), defaults.size))
        if k % 2:
            for index, value in setters:
                p[index] = float(value(p))
        yield p


def _check_steady_states(ir: ModelIR, rhs) -> tuple[float, tuple[str, ...]]:
    from ..plain_python import compile_steady_states

    d = ir.description
    if not d.steady_states:
        return 0.0, ()
    solvers = compile_steady_states(ir)
    psym = [p.symbol for p in ir.parameters]
    exists = {st.label: sp.lambdify([psym], st.exists, modules="numpy") for st in d.declared.steady_states
              if st.exists is not None}
    leaves = [ir.state_names.index(leaf) for leaf in ir.leaves]
    rows = slice(0, 2 * ir.n_coordinates)
    found = dict.fromkeys(d.labels, 0)
    worst = 0.0
    for p in _parameter_points(ir, DESCRIPTION_SAMPLES, 14):
        for label in d.labels:
            try:
                y = solvers[label](p)
            except (ValueError, ZeroDivisionError, OverflowError) as exc:  # a guard missing: NaN in C and numba
                raise CheckFailed(f"{ir.name}: steady state {label} cannot be evaluated where its guards let it "
                                  f"({exc}) at {dict(zip(ir.parameter_names, p.round(6)))}") from None
            if label in exists and bool(exists[label](p)) != (y is not None):
                raise CheckFailed(f"{ir.name}: steady state {label} is {'given' if y is not None else 'not given'} at "
                                  f"{dict(zip(ir.parameter_names, p.round(6)))}, where the reference's criterion "
                                  f"says it {'does not exist' if y is not None else 'exists'}")
            if y is None:
                continue
            found[label] += 1
            # a forced model's equilibrium holds at every t; small t keep the forcing's phase (omega t) exact
            # enough that its rounding stays below the tolerance
            for t in ((0.0,) if ir.autonomous else (0.0, 0.013, 0.037)):
                turned = y.copy()
                turned[leaves] += 0.1
                scale = max(1.0, float(np.max(np.abs(rhs(t, turned, p)[rows]))))
                residual = float(np.max(np.abs(rhs(t, y, p)[rows])))
                if not residual <= STEADY_TOLERANCE * scale:
                    raise CheckFailed(f"{ir.name}: steady state {label} is not a zero of the rhs: |rhs| = "
                                      f"{residual:.2e} (scale {scale:.2e}) at {dict(zip(ir.parameter_names, p.round(6)))}")
                worst = max(worst, residual / scale)
    # a label given at none of the points is not shown wrong, only not shown right: said, not refused
    # (a scene's parameters may put a state out of reach; the default set's are all exercised: a test)
    return worst, tuple(label for label, count in found.items() if not count)


def _check_equilibria(ir: ModelIR) -> float:
    """The declared manifold of equilibria (thesis (3.6)) is one: at every closed-form steady state that lies
    on it (its zero states 0) at the random parameter points, the null space T of the emitted constraint
    gradients in the free states annihilates the jac (|J T| <= STEADY_TOLERANCE |J|): moving along the
    manifold keeps an equilibrium to first order.  Returns the largest |J T| / |J| seen."""
    from ..plain_python import compile_kernel, compile_steady_states

    d = ir.description
    if d.equilibria is None or not d.steady_states:
        return 0.0
    name, zero, count = d.equilibria
    gradient = compile_kernel(ir, d.equilibria_gradient, "equilibria", time=False)
    jac = compile_program(ir, "jac")
    solvers = compile_steady_states(ir)
    zero_index = [ir.state_names.index(z) for z in zero]
    free = [k for k in range(ir.n_states) if k not in zero_index]
    worst = 0.0
    for p in _parameter_points(ir, DESCRIPTION_SAMPLES, 15):
        for label in d.labels:
            y = solvers[label](p)
            if y is None or np.max(np.abs(y[zero_index])) > 1e-12:
                continue
            G = gradient(y, p, np.zeros((count, ir.n_states)))[:, free]
            _, sv, vt = np.linalg.svd(G)
            rank = int(np.sum(sv > 1e-12 * max(1e-300, sv[0])))
            T = np.zeros((ir.n_states, len(free) - rank))
            T[free, :] = vt[rank:].T
            J = jac(0.0, y, p).reshape(ir.n_states, ir.n_states)
            residual = float(np.max(np.abs(J @ T), initial=0.0)) / max(1e-300, float(np.max(np.abs(J))))
            if not residual <= STEADY_TOLERANCE:
                raise CheckFailed(f"{ir.name}: the manifold of equilibria {name!r} is not one at steady state {label}: "
                                  f"|J T| = {residual:.2e} |J| along its tangent, at {dict(zip(ir.parameter_names, p.round(6)))}")
            worst = max(worst, residual)
    return worst


def check_description(ir: ModelIR, system: FirstOrderSystem) -> dict[str, float]:
    """Every declaration of the self-description against the rendered code (run in Python, as the numba
    target prints it), or CheckFailed naming it: the angles are the ball and spin angles and the rhs is
    2 pi-periodic in each; every measure equals its SymPy expression at random states; the forcing
    frequency is the one the model is forced at; every symmetry holds on the rhs at random states and
    parameters (bitwise where identical balls coincide); every closed-form steady state is a zero of
    the rhs wherever it is given, and given exactly where the reference's criterion says it exists; the
    manifold of equilibria's tangent annihilates the jac at the steady states on it.  Returns the
    largest relative errors seen, and under "unexercised" the labels given at none of the
    random parameter points (so not shown to be zeros there)."""
    if ir.description is None:
        return {}
    rhs = compile_program(ir, "rhs")
    _check_roles(ir)
    _check_forcing(ir, system)
    steady, unexercised = _check_steady_states(ir, rhs)
    return {"angles": _check_angles(ir, rhs), "measures": _check_measures(ir, system),
            "symmetries": _check_symmetries(ir, rhs), "steady_states": steady, "unexercised": unexercised,
            "equilibria": _check_equilibria(ir)}
