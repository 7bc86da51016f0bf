/* A control for the thread speed-up (`adbgen.bench.threads`): independent busy loops (no memory
 * traffic, no shared state) on OpenMP threads, built with the engines' flags.  Its speed-up is what
 * the machine gives two threads at that moment; on a shared machine whose other core is busy it is
 * near 1, whatever the engine does.  Arguments: threads, tasks, work per task.  Prints the wall
 * seconds and a sink. */
#include <stdio.h>
#include <stdlib.h>
#include <omp.h>
int main(int argc, char **argv)
{
    int threads = atoi(argv[1]), tasks = atoi(argv[2]);
    long work = atol(argv[3]);
    double sum = 0.0, t0 = omp_get_wtime();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+:sum)
    for (int i = 0; i < tasks; ++i) {
        double x = i;
        for (long k = 0; k < work; ++k) x = x * 1.0000001 + 1e-9;
        sum += x;
    }
    printf("%.9f %g\n", omp_get_wtime() - t0, sum);
    return 0;
}
