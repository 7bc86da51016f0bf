"""Parameter symbols of the flexible-rotor model: the reduced matrices' entries, the balancer node's mode
shapes, the balls, the unbalance and the speed.

An entry the scene gives as exactly 0 gets no symbol (a structural zero: modal truncation leaves M_q, K_q
diagonal, and the emitted code should not carry k^2 zero products); every other entry is a parameter with
the scene's value as its default, so a generated model runs any rotor of the same sparsity.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ...core import Parameter, ParameterTable, speed_schedule
from ...core.symbols import nonnegative, positive, t  # noqa: F401  (t: the family's time)
from .scene import FlexibleScene


@dataclass(frozen=True)
class FlexibleSymbols:
    """Symbolic k x k matrices (entries a symbol or 0), the 2 x k node shape, and the scalars."""

    M: sp.Matrix
    K: sp.Matrix
    C: sp.Matrix
    G: sp.Matrix
    Phi: sp.Matrix  # 2 x k
    w: sp.Matrix  # k x 1 gravity load
    U: sp.Expr  # m_u eps
    R: sp.Symbol
    m: tuple[sp.Symbol, ...]
    D: tuple[sp.Symbol, ...]
    g: sp.Expr
    omega: sp.Symbol
    parameters: tuple[Parameter, ...]
    shapes: tuple[sp.Matrix, ...] = ()  # each node's 2 x k shapes: (Phi,) or (Phi, Phi_2)
    radii: tuple[sp.Expr, ...] = ()  # each node's race radius: (R,) or (R, R_2)
    ball_node: tuple[int, ...] = ()  # the node of each ball
    omega_start: sp.Expr = sp.S.Zero  # a schedule's start speed (its symbol when the scene gives one)

    @classmethod
    def for_scene(cls, scene: FlexibleScene) -> "FlexibleSymbols":
        params = ParameterTable()
        add = params.add
        modal, k = scene.modal, scene.k

        def matrix(name, values, what, unit, sign):  # sign 1 symmetric, -1 skew: one symbol per pair
            out = sp.zeros(k, k)
            for i in range(k):
                for j in range(i if sign > 0 else i + 1, k):
                    if values[i][j] != 0.0:
                        s = add(sp.Symbol(f"{name}_{i + 1}_{j + 1}", real=True), f"{what} [{i + 1}, {j + 1}]", unit,
                                values[i][j])
                        out[i, j], out[j, i] = s, sign * s
            return out

        M = matrix("M_q", modal.mass, "reduced mass matrix Phi^T M Phi", "kg", 1)
        K = matrix("K_q", modal.stiffness, "reduced stiffness matrix Phi^T K Phi", "N/m", 1)
        C = matrix("C_q", modal.damping, "reduced damping matrix Phi^T C Phi", "N s/m", 1)
        G = matrix("G_q", modal.gyroscopic, "reduced gyroscopic matrix Phi^T G Phi (times the speed)", "kg", -1)
        # with a second node, an entry zero at one node but not at the other gets a symbol at both: the loop
        # form indexes each ball's node shape as one of its own parameters (`models.ball_slots`)
        other = scene.node_2.node_shape if scene.node_2 is not None else modal.node_shape
        union = [[modal.node_shape[a][j] != 0.0 or other[a][j] != 0.0 for j in range(k)] for a in range(2)]

        def shape(values, prefix, which):
            out = sp.zeros(2, k)
            for a, axis in enumerate("xy"):
                for j in range(k):
                    if union[a][j]:
                        out[a, j] = add(sp.Symbol(f"{prefix}_{axis}_{j + 1}", real=True),
                                        f"{which}'s {axis} translation in mode {j + 1}", "dimensionless", values[a][j])
            return out

        Phi = shape(modal.node_shape, "Phi", "balancer node")
        w = sp.zeros(k, 1)
        if scene.gravity:
            for j in range(k):
                if modal.gravity_load[j] != 0.0:
                    w[j] = add(sp.Symbol(f"w_{j + 1}", real=True), f"gravity load of mode {j + 1} (Phi^T M e_y)",
                               "kg", modal.gravity_load[j])
        U = add(positive("m_u"), "mass of the unbalanced body (disk) at the balancer node", "kg",
                scene.unbalance_mass) * add(nonnegative("eps"), "eccentricity of its centre of mass", "m",
                                            scene.eccentricity)
        R = add(positive("R"), "race radius", "m", scene.race_radius)
        masses, drags = scene.masses(), scene.ball_dampings()
        shapes, radii = (Phi,), (R,)
        if scene.node_2 is not None:  # its balls numbered after the first node's, each with its own m_i, D_i
            shapes += (shape(scene.node_2.node_shape, "Phi2", "second balancer node"),)
            radii += (add(positive("R_2"), "race radius at the second node", "m", scene.node_2.race_radius),)
            masses, drags = masses + scene.node_2.masses(), drags + scene.node_2.ball_dampings()
        if scene.equal_balls:
            m = (add(positive("m"), "ball mass", "kg", masses[0]),) * scene.n
            D = (add(nonnegative("D"), "viscous drag on each ball", "N m s/rad", drags[0]),) * scene.n
        else:
            m = tuple(add(positive(f"m_{i + 1}"), f"mass of ball {i + 1}", "kg", masses[i])
                      for i in range(scene.balls))
            D = tuple(add(nonnegative(f"D_{i + 1}"), f"viscous drag on ball {i + 1}", "N m s/rad", drags[i])
                      for i in range(scene.balls))
        g = add(positive("g"), "gravitational acceleration (-y)", "m/s^2", scene.g) if scene.gravity else sp.S.Zero
        start = sp.S.Zero
        if scene.speed.law == "schedule":  # omega is the schedule's final speed (`core.speed_schedule`)
            speed_schedule.add_parameters(params, scene.speed.schedule)
            omega = speed_schedule.symbols()["omega"]
            if scene.speed.omega_start is not None:
                start = add(nonnegative("omega_start"), "spin speed the schedule's ramp starts from at t = 0", "rad/s",
                            scene.speed.omega_start)
        else:
            omega = add(positive("omega"), "spin speed", "rad/s", scene.omega)
        return cls(M, K, C, G, Phi, w, U, R, m, D, g, omega, params.sorted(), shapes, radii, scene.ball_node(),
                   start)
