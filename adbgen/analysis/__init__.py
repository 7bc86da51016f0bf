"""What users run on the generated models: simulation, steady states and stability, continuation.

This layer imports the generated modules (`generated.<model>` or a folder written by
`adbgen regenerate --out`), numpy, scipy, numba and the integration libraries, never SymPy: the
equations were derived, checked and emitted upstream; here they are only evaluated.

    loading     a generated model by name, folder or scene file; parameters and states by name
    engines     integration engines (one registry): compiled CyRK and SUNDIALS paths, SciPy
    simulate    one trajectory or many; r, r_max, t_dec, final state, counts (thesis ch. 5)
"""
