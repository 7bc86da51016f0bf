"""How the numba target's functions (plain Python that numba compiles) write their statements."""

from __future__ import annotations

from dataclasses import dataclass

from ...emit import Dialect

# targets/numba's module template defines _scratch: the loops' per-ball work arrays on the stack
NUMBA_SCRATCH = "_scratch({size})"


@dataclass(frozen=True)
class PythonDialect(Dialect):
    """y[k], p[k], out[r] / out[r, c]; ``for i in range(n):``.

    ``scratch``: a per-ball work array of `size` doubles; the numba module puts it on the stack
    (`NUMBA_SCRATCH`: np.empty would cost a heap allocation, ~100 ns, per call); plain Python (the
    checks' interpreter, `codegen.plain_python`) takes np.empty."""

    scratch: str = "np.empty({size})"

    def entry(self, row: str, col: str | None) -> str:
        return f"{self.out}[{row}]" if col is None else f"{self.out}[{row}, {col}]"

    def let(self, name: str, value: str, mutable: bool = False) -> str:
        return f"{name} = {value}"

    def loop(self, var: str, count: int) -> str:
        return f"for {var} in range({count}):"

    def array(self, name: str, size: int) -> str:
        return f"{name} = {self.scratch.format(size=size)}"

    def zero(self, shape: tuple[int, ...]) -> list[tuple[int, str]]:
        return [(0, f"{self.out}[{', '.join([':'] * len(shape))}] = 0.0")]

    def guard(self, condition: str) -> list[tuple[int, str]]:
        return [(0, f"if not ({condition}):"), (1, "return False")]
