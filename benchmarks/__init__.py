"""Benchmarks (never timed tests): each module below measures one question and writes its results to a
committed file under `benchmarks/` (`adbgen bench WHAT`; every benchmark declares its name, options and
run function as ``BENCHMARK`` and is listed once in `registry.REGISTRY`).

The benchmarks:
derive      derivation time and expression size, and the regenerate stages, against n
codegen     emitted operations, source sizes, compile times, ns per call; loop form against unrolled
simulate    problem A on every engine and the peers, the floor, exchange symmetry, threads
sweep       the 100 x 100 basin map with and without the shortcuts
failures    where methods fail (fixed_step, jacobi, pairs hold its parts)
smallest    one scene as the smallest exact model against the bigger ones
precision   work-precision of problems A, B, C on every pathway; the loosest reliable tolerance
            (precision_curves, precision_sweep, precision_charts; percall: ns per rhs/jac call)

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
