/* Arcs of a generated model with their variational equations, integrated in C by CyRK's DOP853 (or any of
 * its explicit Runge-Kutta methods): the flow map x -> phi(t0 + h; t0, x), its derivative
 * Phi = d phi / d x and, optionally, w = d phi / d p along dp, with no Python per step or per evaluation.
 *
 *     y'   = f(t, y, p)
 *     Phi' = J(t, y, p) Phi,          Phi(t0) = I        (J the generated analytic Jacobian)
 *     w'   = J(t, y, p) w + f_p dp,    w(t0) = 0         (f_p the generated d f / d p, dp a direction in
 *                                                        parameter space: one parameter, or several tied)
 *
 * integrated as one system, so the monodromy matrix of a periodic orbit is Phi over one period (a product
 * of the arcs' Phi in multiple shooting) and the shooting Newton has its exact Jacobian.  The error control
 * covers Phi and w too (their accuracy is what the Floquet multipliers and Newton's convergence need).
 *
 * One translation unit per model: it #includes the model's generated C source, compiled by
 * adbgen.analysis.orbits.flow through engines.compiled.build with
 *     -DADB_MODEL_SOURCE='"<model>.c"' -DADB_RHS=<model>_rhs -DADB_JAC=<model>_jac -DADB_JAC_P=<model>_jac_p
 *     -DADB_NY=<states> -DADB_NP=<parameters>
 * CyRK's solver is reached through the C function pointers of its numba bridge (CyRK.nb.numba_c_api),
 * handed over once by adb_var_init, as in cyrk_driver.c.  Each arc keeps only its end point (CyRK's
 * t_eval at the arc's end), so memory does not grow with the number of steps.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"
#include "cyrk_bridge.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* CyRK's function pointers, once per library (cyrk_bridge.h) */
int adb_var_init(void *const *ptrs)
{
    adb_cyrk_bind(ptrs);
    return ADB_NY;
}

#define NN (ADB_NY * ADB_NY)

/* CyRK copies the argument bytes; the counter pointer survives the copy */
typedef struct {
    double p[ADB_NP];
    long *count;
    int phi;            /* integrate Phi */
    int w;              /* integrate w along dp */
    double dp[ADB_NP];  /* the parameter direction of w */
} Args;

static void diffeq(double *dz, double t, double *z, char *args, PreEvalFn pre)
{
    (void)pre;
    Args *a = (Args *)args;
    ADB_RHS(t, z, a->p, dz);
    ++*a->count;
    if (!a->phi) return;
    double J[NN];
    ADB_JAC(t, z, a->p, J);
    const double *Phi = z + ADB_NY;
    double *dPhi = dz + ADB_NY;
    /* dPhi = J Phi (row-major): row i of J times each column of Phi; i-k-j order for contiguous rows */
    for (int i = 0; i < ADB_NY; ++i) {
        double *row = dPhi + i * ADB_NY;
        for (int j = 0; j < ADB_NY; ++j) row[j] = 0.0;
        for (int k = 0; k < ADB_NY; ++k) {
            double c = J[i * ADB_NY + k];
            if (c == 0.0) continue; /* the Jacobians are sparse (rates, the balls' own columns) */
            const double *src = Phi + k * ADB_NY;
            for (int j = 0; j < ADB_NY; ++j) row[j] += c * src[j];
        }
    }
    if (!a->w) return;
    double Fp[ADB_NY * ADB_NP];
    ADB_JAC_P(t, z, a->p, Fp);
    const double *w = z + ADB_NY + NN;
    double *dw = dz + ADB_NY + NN;
    for (int i = 0; i < ADB_NY; ++i) {
        double s = 0.0;
        for (int k = 0; k < ADB_NP; ++k) s += Fp[i * ADB_NP + k] * a->dp[k];
        for (int k = 0; k < ADB_NY; ++k) s += J[i * ADB_NY + k] * w[k];
        dw[i] = s;
    }
}

/* One arc from (t0, x0) over h > 0 (or h < 0: backwards).  out_x: the end state; out_phi (NULL: not
 * integrated): Phi at the end, row-major; out_w (NULL, or dp NULL: not integrated): w at the end.
 * counts: [rhs evaluations, steps].  Returns a status code of driver_common.h. */
static int arc(const double *x0, double t0, double h, const double *p, const double *dp, double rtol, double atol,
               int method, long max_steps, double *out_x, double *out_phi, double *out_w, long *counts)
{
    int with_phi = out_phi != NULL, with_w = with_phi && out_w != NULL && dp != NULL;
    size_t n = ADB_NY + (with_phi ? NN : 0) + (with_w ? ADB_NY : 0);
    double *z = calloc(n, sizeof(double));
    if (!z) return ADB_SOLVER_FAILURE;
    memcpy(z, x0, sizeof(double) * ADB_NY);
    if (with_phi)
        for (int i = 0; i < ADB_NY; ++i) z[ADB_NY + i * ADB_NY + i] = 1.0;
    long count = 0;
    Args args;
    memcpy(args.p, p, sizeof args.p);
    args.count = &count;
    args.phi = with_phi;
    args.w = with_w;
    if (with_w) memcpy(args.dp, dp, sizeof args.dp);
    double t1 = t0 + h;
    double t_eval[1] = {t1};
    void *res = cy.solve(diffeq, t0, t1, z, n, method, 4, 0, (char *)&args, sizeof(Args),
                         max_steps > 0 ? (size_t)max_steps : 0, 2000, false, t_eval, 1, NULL, NULL, 0, &rtol, 1, &atol, 1,
                         INFINITY, 0.0, true);
    int status = ADB_SUCCESS;
    if (!res) {
        free(z);
        return ADB_SOLVER_FAILURE;
    }
    if (!cy.success(res)) status = adb_cyrk_decode(cy.status(res));
    else {
        size_t m = cy.size(res);
        const double *ry = cy.y(res);
        const double *end = ry + (m - 1) * n;
        if (m < 1 || !adb_all_finite(end, (int)n)) status = ADB_NONFINITE;
        else {
            memcpy(out_x, end, sizeof(double) * ADB_NY);
            if (with_phi) memcpy(out_phi, end + ADB_NY, sizeof(double) * NN);
            if (with_w) memcpy(out_w, end + ADB_NY + NN, sizeof(double) * ADB_NY);
        }
    }
    counts[0] += count;
    counts[1] += (long)cy.steps(res);
    cy.free(res);
    free(z);
    return status;
}

/* m arcs, arc i from (T0[i], X0 + i ADB_NY) over H[i], on `threads` OpenMP threads (< 1: all).
 * with_phi: 0 state only, 1 with Phi; dp (not NULL, with Phi) adds w = d x / d p along dp.  Outputs by arc
 * (rows of Xend, blocks of Phi and W); status per arc; counts: [rhs evaluations, steps] summed over the arcs. */
void adb_var_arcs(int m, const double *X0, const double *T0, const double *H, const double *p, const double *dp,
                  int with_phi,
                  double rtol, double atol, int method, long max_steps, int threads, double *Xend, double *Phi,
                  double *W, int *status, long *counts)
{
    long c0 = 0, c1 = 0;
#ifdef _OPENMP
    if (threads < 1) threads = omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : c0, c1) if (m > 1)
#endif
    for (int i = 0; i < m; ++i) {
        long c[2] = {0, 0};
        status[i] = arc(X0 + (size_t)i * ADB_NY, T0[i], H[i], p, dp, rtol, atol, method, max_steps,
                        Xend + (size_t)i * ADB_NY, with_phi ? Phi + (size_t)i * NN : NULL,
                        with_phi && dp ? W + (size_t)i * ADB_NY : NULL, c);
        c0 += c[0];
        c1 += c[1];
    }
    counts[0] = c0;
    counts[1] = c1;
}

/* The state only, from (t0, y0), at `times` (n, monotone from t0, not including it) into out (n x ADB_NY):
 * CyRK's t_eval (its dense output between steps).  Returns a status code. */
int adb_var_sample(const double *y0, double t0, const double *p, int n, const double *times, double rtol, double atol,
                   int method, long max_steps, double *out)
{
    long count = 0;
    Args args;
    memcpy(args.p, p, sizeof args.p);
    args.count = &count;
    args.phi = 0;
    args.w = 0;
    double z[ADB_NY];
    memcpy(z, y0, sizeof z);
    void *res = cy.solve(diffeq, t0, times[n - 1], z, ADB_NY, method, (size_t)n + 1, 0, (char *)&args, sizeof(Args),
                         max_steps > 0 ? (size_t)max_steps : 0, 2000, false, (double *)times, (size_t)n, NULL, NULL, 0,
                         &rtol, 1, &atol, 1, INFINITY, 0.0, true);
    if (!res) return ADB_SOLVER_FAILURE;
    int status = ADB_SUCCESS;
    if (!cy.success(res)) status = adb_cyrk_decode(cy.status(res));
    else if ((int)cy.size(res) != n) status = ADB_SOLVER_FAILURE;
    else memcpy(out, cy.y(res), sizeof(double) * (size_t)n * ADB_NY);
    cy.free(res);
    return status;
}
