"""What users run on the generated models: simulation, steady states and stability, continuation.

This layer imports the generated modules (`generated.<model>` or a folder written by
`adbgen regenerate --out`), numpy, scipy, numba and the integration libraries, never SymPy: the
equations were derived, checked and emitted upstream; here they are only evaluated.

    loading     a generated model by name, folder or scene file; parameters and states by name
    engines     integration engines (one registry): compiled CyRK and SUNDIALS paths, SciPy
    simulate    one trajectory or many; r, r_max, t_dec, final state, counts (thesis ch. 5)
    steady      steady states by Newton, eigenvalues, the n >= 3 family's neutral directions removed (ch. 3)
    starts      the states stability and continuation start from (START, the module's closed forms)
    continuation  a steady state along a parameter: Hopf points, folds, stable intervals (ch. 4)
    auto        AUTO-07p on the emitted files: one- and two-parameter runs, fort.7/fort.8 readers
    orbits      periodic orbits: shooting on the variational equations, continuation, bifurcations, charts
    attractors  where a trajectory ends: steady states named, stop regions (basin_regions), the classifier
    approach    r's rate of approach over a run's tail (exponential, algebraic, band, drift): decides a run
    grid, sweep, sweep_figures   grids of trajectories or steady states on Dask, into Zarr, drawn
    results     what a simulation returns
    reproduction  the reproduction document (the families' science packages give its sections)

It knows no family: what it needs of a model it reads from the generated module's self-description
(roles of the states, angles, amplitude, measures, symmetries, closed-form steady states and their
names).
"""
