"""The numba target: one Python module per model, `@njit(cache=True)` functions over the programs
printed as plain Python (`printers.PythonPrinter`); importable as `generated.<model>`."""

from pathlib import Path

from .. import Target

TARGET = Target(
    name="numba",
    files=(("numba/module.py.j2", "{name}/__init__.py"),),
    language="py",
    templates=Path(__file__).parent / "templates",
    loops=True,
    description="numba module: rhs, jac, jac_p, mass_matrix, forcing and metadata",
)
