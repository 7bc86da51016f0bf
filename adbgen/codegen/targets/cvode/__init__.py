"""The SUNDIALS CVODE target: CVRhsFn and dense CVLsJacFn adaptors over the C library, and a driver.
It prints no functions of its own (it calls the C target's).  Templates: templates/cvode/; proof:
`prove` (the adaptor through `harness.c`, the driver on a short transient)."""

from .. import Target


class CvodeTarget(Target):
    """Its own class so that `Target.prove` finds its `prove` module beside it."""


TARGET = CvodeTarget(
    name="cvode",
    files=(("cvode/adaptor.h.j2", "{name}/{name}_cvode.h"), ("cvode/adaptor.c.j2", "{name}/{name}_cvode.c"),
           ("cvode/driver.c.j2", "{name}/{name}_cvode_main.c")),
    loops=True,
    description="SUNDIALS CVODE callbacks and a BDF driver over the C library",
)
