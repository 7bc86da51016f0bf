"""Checks of the lowering, run before anything is written: the structured rhs program against a dense
solve of the whole system, and the start point at rest in the rendered rhs."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..core.first_order import FirstOrderSystem
from ..errors import AdbgenError
from .interpret import compile_program
from .ir import ModelIR

LOWERING_TOLERANCE = 1e-12


class CheckFailed(AdbgenError):
    pass


def lowering_error(ir: ModelIR, system: FirstOrderSystem, samples: int = 20, seed: int = 0) -> float:
    """Largest relative difference between the rhs program and a dense solve at random points.

    The reference lambdifies the whole mass matrix and forcing and solves M q'' = f with numpy:
    independent of the structured lowering (no Schur complement), and valid for any core size.
    """
    rng = np.random.default_rng(seed)
    eom = system.solve.eom
    law = dict(eom.driven_law)
    args = (eom.time, list(system.states), [p.symbol for p in system.parameters])
    mass = sp.lambdify(args, eom.mass_matrix().xreplace(law), modules="numpy")
    forcing = sp.lambdify(args, [sp.sympify(e).xreplace(law) for e in eom.forcing], modules="numpy")
    program = compile_program(ir, "rhs")
    N = eom.size
    worst = 0.0
    defaults = np.array([p.default for p in system.parameters])
    for _ in range(samples):
        y = rng.uniform(-1, 1, ir.n_states)
        y[: ir.n_coordinates] *= 0.1
        p = defaults * rng.uniform(0.5, 1.5, defaults.size)
        time = float(rng.uniform(0, 10))
        acc = np.linalg.solve(np.array(mass(time, y, p), dtype=float), np.array(forcing(time, y, p), dtype=float))
        a, b = np.array(program(time, y, p)), np.concatenate([y[N:], acc])
        worst = max(worst, float(np.max(np.abs(a - b)) / max(1e-300, float(np.max(np.abs(b))))))
    return worst


def check_lowering(ir: ModelIR, system: FirstOrderSystem) -> float:
    err = lowering_error(ir, system)
    if not err <= LOWERING_TOLERANCE:
        raise CheckFailed(f"{ir.name}: the structured rhs differs from the closed form by {err:.2e} "
                          f"(tolerance {LOWERING_TOLERANCE:g})")
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
