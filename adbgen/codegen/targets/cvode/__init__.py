"""The SUNDIALS CVODE target: CVRhsFn and dense CVLsJacFn adaptors over the C library, and a driver."""

from pathlib import Path

from .. import Target

TARGET = Target(
    name="cvode",
    files=(("cvode/adaptor.h.j2", "{name}/{name}_cvode.h"), ("cvode/adaptor.c.j2", "{name}/{name}_cvode.c"),
           ("cvode/driver.c.j2", "{name}/{name}_cvode_main.c")),
    language="c",
    templates=Path(__file__).parent / "templates",
    loops=True,
    description="SUNDIALS CVODE callbacks and a BDF driver over the C library",
)
