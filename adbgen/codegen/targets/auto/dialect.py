"""How the AUTO-07p target's func writes its statements: C with AUTO's types, arrays and PAR indices."""

from __future__ import annotations

from dataclasses import dataclass

from ..c.dialect import CDialect


def par_index(k: int) -> int:
    """0-based index into AUTO's PAR of model parameter k: PAR(11)-PAR(14) are AUTO's own."""
    return k if k < 10 else k + 4


def apar(index: str) -> str:
    """AUTO's PAR index of model parameter `index` (a number, or an index expression: APAR(.))."""
    return str(par_index(int(index))) if index.isdigit() else f"APAR({index})"


@dataclass(frozen=True)
class AutoDialect(CDialect):
    """u[k], par[APAR(k)]; f[r], ARRAY2D(dfdu, r, c) (column-major), ARRAY2D(dfdp, r, APAR(c)).

    ``columns_are_parameters``: the output's columns are model parameters (dfdp)."""

    ctype: str = "doublereal"
    time: bool = False
    columns_are_parameters: bool = False

    def param(self, index: str) -> str:
        return f"{self.params}[{apar(index)}]"

    def entry(self, row: str, col: str | None) -> str:
        if col is None:
            return f"{self.out}[{row}]"
        return f"ARRAY2D({self.out}, {row}, {apar(col) if self.columns_are_parameters else col})"

    def zero(self, shape: tuple[int, ...]) -> list[tuple[int, str]]:
        if not self.columns_are_parameters:
            return super().zero(shape)
        return [(0, f"for (int j = 0; j < {shape[1]}; ++j) {{"),
                (1, f"memset(&ARRAY2D({self.out}, 0, APAR(j)), 0, sizeof(doublereal) * {shape[0]});"), (0, "}")]
