"""Checks of the lowering, run before anything is written: every program of the intermediate form
(rhs, jac, jac_p, mass_matrix, forcing) against an evaluation that does not go through the lowering,
and the start point at rest in the rendered rhs.

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

from ..core.first_order import FirstOrderSystem
from ..errors import AdbgenError
from .interpret import compile_program
from .ir import ModelIR

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
    for j in range(x.size):
        def stencil(rel, j=j):
            h = rel * max(abs(x[j]), 1e-2)
            def at(s):
                z = x.copy()
                z[j] += s * h
                return fn(z)
            return (8 * (at(1) - at(-1)) - (at(2) - at(-2))) / (12 * h)
        estimates = [stencil(rel) for rel in steps]
        change = [float(np.max(np.abs(a - b))) for a, b in zip(estimates, estimates[1:])]
        cols.append(estimates[int(np.argmin(change)) + 1])
    return np.array(cols).T


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
    """`errors_of` the intermediate form's five programs (run in Python, `interpret`)."""
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


def check_programs(ir: ModelIR, system: FirstOrderSystem) -> dict[str, float]:
    """Every program of `ir` (and of its oscillator extension) within tolerance of its independent
    evaluation, or CheckFailed naming the program; returns the errors (the extension's as 'ext:...')."""
    ref = Reference.of(system)
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


def check_lowering(ir: ModelIR, system: FirstOrderSystem) -> float:
    """The rhs check alone (kept for callers that want one number); `check_programs` checks them all."""
    err = lowering_error(ir, system)
    _refuse(ir.name, {"rhs": err}, _AGAINST)
    return err


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
