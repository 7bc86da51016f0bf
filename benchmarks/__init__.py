"""Benchmarks (never timed tests): each module below measures one question and writes its results to a
committed file beside it in `benchmarks/` (`adbgen bench WHAT`; every benchmark declares its name, options
and run function as ``BENCHMARK`` and is listed once in `registry.REGISTRY`).  They live in the source
checkout only, not in the installed package, which never imports them (issue 33; docs/layout.md);
`adbgen bench` loads them from the checkout it runs from.

The benchmarks:
derive      derivation time and expression size, and the regenerate stages, against n
codegen     emitted operations, source sizes, compile times, ns per call; loop form against unrolled
simulate    problem A on every engine and the peers, the floor, exchange symmetry, threads
sweep       the 100 x 100 basin map with and without the shortcuts
failures    where methods fail (fixed_step, jacobi, pairs hold its parts)
smallest    one scene as the smallest exact model against the bigger ones
precision   work-precision of problems A, B, C on every pathway; the loosest reliable tolerance
            (precision_curves, precision_sweep, precision_charts; percall: ns per rhs/jac call)
mutation    one-line mistakes in code generation: how many are refused or caught (the mutation tool)
orbits      periodic orbits: a Newton step of shooting, a branch against AUTO-07p, the paper's charts
auto        engine_table.py: the auto engine's table (adbgen/analysis/engines/auto_table.json, written here)
rk          the DOP853 drivers against their floor (time / rhs evaluations x ns per rhs)
ensemble    trajectories per CPU-s on the basin map, labels against a converged map, heyoka beside
reproduce   `adbgen reproduce`'s wall time and its document against the committed one

What they share, once:
registry    the registry and the options several benchmarks take
report      the results file, charts, the machine and versions, targets
timing      calls in a numba or C loop (c/rhs_timer.c), Python calls, CPU clocks
problems    the initial-value problems (problem A) and the exchange-symmetry records
pathways    a way of integrating a problem, timed best-of-N round-robin; errors, time at equal error
floor       wall time against rhs evaluations x ns per call
threads     many trajectories on 1 and 2 threads, with an OpenMP control (c/omp_control.c)
peers       JiTCODE and heyoka fed the generated statements
symbolic    the SymPy side: model kinds, the closed form lambdified
baseline    the hand-written numba rhs of thesis Appendix A (the expert baseline)
c/          the benchmarks' C programs (rhs_timer.c, omp_control.c, midpoint.c, flop_timer.c)
"""
