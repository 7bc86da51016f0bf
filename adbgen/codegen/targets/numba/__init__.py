"""The numba target: one Python module per model, `@njit(cache=True)` functions over the kernels printed
as plain Python (`printer.PythonPrinter`, `dialect.PythonDialect`); importable as `generated.<model>`;
beside it program.json, its rhs as expression trees (`codegen.program_tree`).  Templates: templates/numba/."""

from .. import Target, columns
from .dialect import NUMBA_SCRATCH, PythonDialect
from .printer import PythonPrinter


class NumbaTarget(Target):
    def dialect(self, which, kernel):
        return PythonDialect("y", "p", "out", columns(kernel), scratch=NUMBA_SCRATCH)

    def context(self, ir) -> dict:
        from ...program_tree import program_json
        from ...render import source_hash

        return {"program_json": program_json(ir, source_hash(ir))}


TARGET = NumbaTarget(
    name="numba",
    # program.json: the rhs as data (`codegen.program_tree`), for the benchmarks' peers
    files=(("numba/module.py.j2", "{name}/__init__.py"), ("numba/program.json.j2", "{name}/program.json")),
    printer=PythonPrinter,
    loops=True,
    describe=True,
    description="numba module: rhs, jac, jac_p, mass_matrix, forcing, measures, steady states and metadata",
)
