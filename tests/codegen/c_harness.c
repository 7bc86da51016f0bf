/* Test harness for the emitted C library of one model (tests/codegen/test_c_target.py).
 *
 * Generic over the model: build with
 *     -DMODEL_HEADER='"<model>.h"' -DMODEL=<model> -DMODEL_UPPER=<MODEL>
 * together with <model>.c (under -fsanitize=address,undefined in the tests).
 *
 * Prints the model's metadata, then reads from stdin a count K followed by K records
 * "t y_0 .. y_{N-1} p_0 .. p_{P-1}" (any whitespace) and for each record prints one line:
 * rhs (N), jac (N x N), jac_p (N x P), mass (Nq x Nq), forcing (Nq), all row-major, %.17g.
 * Every input and output array is a heap block of exactly its size (so AddressSanitizer sees any
 * access past its end) and every output is filled with NaN before the call (so an entry the
 * function fails to write shows up).  -DHARNESS_SHORT_JAC makes the Jacobian block one entry short:
 * the tests' check that the sanitizers are really active.
 * Exit status: 0 on success, 2 on malformed input, 3 if out of memory.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include MODEL_HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define FN(suffix) CAT(MODEL, suffix)
#define CONST(suffix) CAT(MODEL_UPPER, suffix)

#define N CONST(_N_STATES)
#define P CONST(_N_PARAMS)
#define NQ CONST(_N_COORDINATES)

#ifdef HARNESS_SHORT_JAC
#define JAC_SIZE (N * N - 1)
#else
#define JAC_SIZE (N * N)
#endif

static double *block(size_t n)
{
    double *a = malloc(n * sizeof *a);
    size_t i;
    if (a == NULL) {
        exit(3);
    }
    for (i = 0; i < n; ++i) {
        a[i] = NAN;
    }
    return a;
}

static void print_row(const char *label, const double *a, size_t n)
{
    size_t i;
    printf("%s", label);
    for (i = 0; i < n; ++i) {
        printf(" %.17g", a[i]);
    }
    printf("\n");
}

static void print_values(const double *a, size_t n)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        printf(" %.17g", a[i]);
    }
}

static void print_names(const char *label, const char *const *names, size_t n)
{
    size_t i;
    printf("%s", label);
    for (i = 0; i < n; ++i) {
        printf(" %s", names[i]);
    }
    printf("\n");
}

int main(void)
{
    double *y = block(N), *p = block(P);
    double *rhs = block(N), *jac = block(JAC_SIZE), *jac_p = block(N * P);
    double *mass = block(NQ * NQ), *forcing = block(NQ);
    double t;
    long k, count;
    int i;

    printf("hash %s\n", CONST(_SOURCE_HASH));
    printf("sizes %d %d %d\n", N, P, NQ);
    print_names("states", FN(_state_names), N);
    print_names("params", FN(_param_names), P);
    print_row("defaults", FN(_defaults), P);
#if CONST(_HAS_START)
    print_row("start", FN(_start), N);
    print_row("start_parameters", FN(_start_parameters), P);
#endif

    if (scanf("%ld", &count) != 1 || count < 0) {
        return 2;
    }
    for (k = 0; k < count; ++k) {
        if (scanf("%lf", &t) != 1) {
            return 2;
        }
        for (i = 0; i < N; ++i) {
            if (scanf("%lf", &y[i]) != 1) {
                return 2;
            }
        }
        for (i = 0; i < P; ++i) {
            if (scanf("%lf", &p[i]) != 1) {
                return 2;
            }
        }
        FN(_rhs)(t, y, p, rhs);
        FN(_jac)(t, y, p, jac);
        FN(_jac_p)(t, y, p, jac_p);
        FN(_mass)(t, y, p, mass);
        FN(_forcing)(t, y, p, forcing);
        printf("out");
        print_values(rhs, N);
        print_values(jac, N * N);
        print_values(jac_p, N * P);
        print_values(mass, NQ * NQ);
        print_values(forcing, NQ);
        printf("\n");
    }
    free(forcing);
    free(mass);
    free(jac_p);
    free(jac);
    free(rhs);
    free(p);
    free(y);
    return 0;
}
