"""The C target: a C99 library per model (`<model>.h`, `<model>.c`), programs printed by
`printers.CPrinter`; the CVODE and AUTO-07p targets build on the same printer."""

from pathlib import Path

from .. import Target

TARGET = Target(
    name="c",
    files=(("c/model.h.j2", "{name}/{name}.h"), ("c/model.c.j2", "{name}/{name}.c")),
    language="c",
    templates=Path(__file__).parent / "templates",
    loops=True,
    description="C99 library: <model>_rhs, _jac, _jac_p, _mass, _forcing, names, defaults",
)
