"""What every family shares: Lagrange's equations, structured mass-matrix solves, identities, first-order
systems, rotating frames, the oscillator extension, Jacobi integrals, linearisation, numeric evaluation,
check results.  Imports nothing of a family or of code generation."""

from .identities import assert_identity, canonical_trig, is_identity, reduce_pythagorean
from .lagrange import Coordinate, EnergyTerm, EquationsOfMotion, Parameter, ParameterTable, lagrange_equations, time_derivative
from .structure import StructuredSolve, schur_solve

__all__ = [
    "Coordinate", "EnergyTerm", "EquationsOfMotion", "Parameter", "ParameterTable", "StructuredSolve",
    "assert_identity", "canonical_trig", "is_identity", "reduce_pythagorean", "lagrange_equations", "schur_solve",
    "time_derivative",
]
