"""What users run on the generated models: simulation, steady states and stability, continuation.

This layer imports the generated modules (`generated.<model>` or a folder written by
`adbgen regenerate --out`), numpy, scipy, numba and the integration libraries, never SymPy: the
equations were derived, checked and emitted upstream; here they are only evaluated.

    loading     a generated model by name, folder or scene file; parameters and states by name
    engines     integration engines (one registry): compiled CyRK and SUNDIALS paths, SciPy
    simulate    one trajectory or many; r, r_max, t_dec, final state, counts (thesis ch. 5)
    steady      steady states by Newton, eigenvalues, the n >= 3 family's neutral directions removed (ch. 3)
    closed_forms  the thesis' closed-form states (3.6), (3.9), (3.10) in numpy
    continuation  a steady state along a parameter: Hopf points, folds, stable intervals (ch. 4)
    auto        AUTO-07p on the emitted files: one- and two-parameter runs, fort.7/fort.8 readers
    orbits      periodic orbits: shooting on the variational equations, continuation, bifurcations, charts
"""
