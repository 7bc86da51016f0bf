/* ns per call of a generated model's C rhs and jac, each call in a loop (`adbgen.bench.timing`).
 *
 * Compiled with the model's C source and these macros (-D):
 *   ADB_MODEL_HEADER  the model's header, e.g. "thesis_rotating_n3.h"
 *   ADB_RHS, ADB_JAC  its functions, e.g. thesis_rotating_n3_rhs
 *   ADB_NY, ADB_NP    numbers of states and parameters
 *   ADB_Y0, ADB_P     the state and the parameters, comma-separated literals
 * Arguments: target seconds per repeat, repeats, 1 to time the jac too.
 * Prints "<label> calls N", then "<label> ns X" per repeat and "<label> sink S". */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include ADB_MODEL_HEADER

#define NS ADB_NY
static const double Y0[NS] = { ADB_Y0 };
static const double P[ADB_NP] = { ADB_P };
static double jac_out[NS * NS];

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* y[0] follows the previous output (by 1e-300: no effect on the values), so calls cannot be hoisted */
static double run_rhs(long calls)
{
    double y[NS], out[NS];
    long i;
    int k;
    for (k = 0; k < NS; ++k) y[k] = Y0[k];
    for (i = 0; i < calls; ++i) {
        ADB_RHS(0.0, y, P, out);
        y[0] = Y0[0] + 1e-300 * out[NS - 1];
    }
    return out[NS - 1];
}

static double run_jac(long calls)
{
    double y[NS];
    long i;
    int k;
    for (k = 0; k < NS; ++k) y[k] = Y0[k];
    for (i = 0; i < calls; ++i) {
        ADB_JAC(0.0, y, P, jac_out);
        y[0] = Y0[0] + 1e-300 * jac_out[NS * NS - 1];
    }
    return jac_out[NS * NS - 1];
}

static void bench(const char *label, double (*run)(long), double target, int repeats)
{
    long calls = 64;
    double t0, t1, sink = 0.0;
    int r;
    for (;;) { /* calibrate: calls so that one repeat takes about `target` seconds */
        t0 = now();
        sink += run(calls);
        t1 = now();
        if (t1 - t0 > 0.2 * target || calls > (1L << 40)) break;
        calls *= 4;
    }
    calls = (long)((double)calls * target / (t1 - t0)) + 1;
    printf("%s calls %ld\n", label, calls);
    for (r = 0; r < repeats; ++r) {
        t0 = now();
        sink += run(calls);
        t1 = now();
        printf("%s ns %.6f\n", label, 1e9 * (t1 - t0) / (double)calls);
    }
    printf("%s sink %g\n", label, sink);
}

int main(int argc, char **argv)
{
    double target = argc > 1 ? atof(argv[1]) : 0.1;
    int repeats = argc > 2 ? atoi(argv[2]) : 5;
    int jac = argc > 3 ? atoi(argv[3]) : 1;
    bench("rhs", run_rhs, target, repeats);
    if (jac) bench("jac", run_jac, target, repeats);
    return 0;
}
