"""The C target: a C99 library per model (`<model>.h`, `<model>.c`), printed by `printer.CPrinter` in
`dialect.CDialect`; the CVODE and AUTO-07p targets build on the same printer.  Templates: templates/c/."""

from .. import Target, columns
from .dialect import CDialect
from .printer import CPrinter


class CTarget(Target):
    def dialect(self, which, kernel):
        return CDialect("y", "p", "dydt" if which == "rhs" else "out", columns(kernel))


TARGET = CTarget(
    name="c",
    files=(("c/model.h.j2", "{name}/{name}.h"), ("c/model.c.j2", "{name}/{name}.c")),
    printer=CPrinter,
    loops=True,
    describe=True,
    description="C99 library: <model>_rhs, _jac, _jac_p, _mass, _forcing, measures, steady states, names, defaults",
)
