"""Periodic orbits of the generated models: found, continued, classified (issue 21).

    flow            arcs and their variational equations in the compiled driver (engines/variational_driver.c)
    shooting        the (multiple) shooting system, its exact Jacobian, Newton
    orbit           PeriodicOrbit: found from a trajectory or refined from a guess; multipliers, windings, r range
    describe        what the orbit code reads of a module's self-description (angles, amplitude, forcing)
    parameters      the free parameters and the ones tied to them (--tie)
    continuer       a generic pseudo-arclength continuer with test functions (knows nothing of its curve)
    equilibrium     the equilibrium curve (the one-parameter scans of `analysis.equilibrium_scan` run it);
                    the steady-state follower; homotopies
    cycle           the limit-cycle curve (fold, period-doubling, torus detected)
    hopf            Hopf points, the start of their cycles, the Hopf curve
    boundary        two-parameter curves' shared defining system; the fold curve; followers
    torus, period_doubling, fold_cycle     the other two-parameter curves
    lyapunov, jets  the first Lyapunov coefficient from exact second and third derivatives
    branches        branches of cycles (from a Hopf point, from an orbit) and their JSON
    charts          stability charts: grid, seeds, curves, plot
    auto_cycles     AUTO-07p's collocation on the same orbits (the independent method)
    run_points      what the points of AUTO-07p's one-parameter run gain (first Lyapunov coefficient, margins)

No SymPy, and no family or model named: everything a model offers is read from its generated module.
"""
