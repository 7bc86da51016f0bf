"""How the C target's functions (C99) write their statements; the CVODE and AUTO-07p targets build on it."""

from __future__ import annotations

from dataclasses import dataclass

from ...emit import Dialect, paren


@dataclass(frozen=True)
class CDialect(Dialect):
    """y[k], p[k], out[r] / out[r * ncol + c] (row-major); ``for (int i = 0; i < n; ++i) {``."""

    ctype: str = "double"

    def entry(self, row: str, col: str | None) -> str:
        if col is None:
            return f"{self.out}[{row}]"
        if row.isdigit() and col.isdigit():
            return f"{self.out}[{int(row) * self.ncol + int(col)}]"
        return f"{self.out}[{paren(row)} * {self.ncol} + {col}]"

    def let(self, name: str, value: str, mutable: bool = False) -> str:
        return f"{'' if mutable else 'const '}{self.ctype} {name} = {value};"

    def stmt(self, text: str) -> str:
        return text + ";"

    def loop(self, var: str, count: int) -> str:
        return f"for (int {var} = 0; {var} < {count}; ++{var}) {{"

    def end(self) -> str:
        return "}"

    def array(self, name: str, size: int) -> str:
        return f"{self.ctype} {name}[{size}];"

    def zero(self, shape: tuple[int, ...]) -> list[tuple[int, str]]:
        size = 1
        for s in shape:
            size *= s
        return [(0, f"memset({self.out}, 0, sizeof({self.ctype}) * {size});")]

    def unused(self, time: bool, states: bool, params: bool) -> list[str]:
        return (([] if time else ["(void)t;"]) + ([] if states else [f"(void){self.states};"])
                + ([] if params else [f"(void){self.params};"]))

    def guard(self, condition: str) -> list[tuple[int, str]]:
        return [(0, f"if (!({condition})) {{"), (1, "return 0;"), (0, "}")]
