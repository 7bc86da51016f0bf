"""adbgen: equations of motion of automatic dynamic balancers, derived, checked, emitted.

Data flows one way: scene -> symbolic model -> Lagrange -> reductions (checked) -> intermediate form
-> targets -> generated files -> analysis -> figures and documents.  The packages, each importing only
those before it (import-linter's contracts in pyproject.toml, run by the tests): `core` (what every
family shares), `families` (the machines, one registry; their derivations), `codegen` (the intermediate
form, its lowering and the targets, one registry), `analysis` (what runs the generated code), the
families' `science` packages and `bench` (published results, reproductions, benchmarks), `cli` (the
command line assembled from the registries).
"""

__version__ = "0.1.0"

from .errors import AdbgenError, ReductionError, SceneError  # noqa: E402

__all__ = ["AdbgenError", "ReductionError", "SceneError", "__version__"]
