"""The numba target: one Python module per model, `@njit(cache=True)` functions over the kernels printed
as plain Python (`printer.PythonPrinter`, `dialect.PythonDialect`); importable as `generated.<model>`.
Templates: templates/numba/."""

from .. import Target, columns
from .dialect import NUMBA_SCRATCH, PythonDialect
from .printer import PythonPrinter


class NumbaTarget(Target):
    def dialect(self, which, kernel):
        return PythonDialect("y", "p", "out", columns(kernel), scratch=NUMBA_SCRATCH)

    def prove(self, proof):
        from .prove import prove

        prove(self, proof)


TARGET = NumbaTarget(
    name="numba",
    files=(("numba/module.py.j2", "{name}/__init__.py"),),
    printer=PythonPrinter,
    loops=True,
    describe=True,
    description="numba module: rhs, jac, jac_p, mass_matrix, forcing, measures, steady states and metadata",
)
