/* Implicit midpoint rule (one-stage Gauss-Legendre) at a fixed step, by SUNDIALS ARKStep with a
 * user Butcher table; Newton with a dense solver and the generated analytic Jacobian
 * (`adbgen.bench.jacobi`).  Compiled with these macros (-D): ADB_MODEL_SOURCE, the model's generated C
 * file (included: one translation unit); ADB_RHS, ADB_JAC, its functions; ADB_NY, its number of states. */
#include <math.h>
#include <string.h>
#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include ADB_MODEL_SOURCE

static int rhs_fn(realtype t, N_Vector y, N_Vector yd, void *p)
{
    double *out = N_VGetArrayPointer(yd);
    ADB_RHS(t, N_VGetArrayPointer(y), (const double *)p, out);
    for (int i = 0; i < ADB_NY; ++i)
        if (!isfinite(out[i])) return -1;
    return 0;
}

static int jac_fn(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *p, N_Vector a, N_Vector b, N_Vector c)
{
    (void)fy; (void)a; (void)b; (void)c;
    double buf[ADB_NY * ADB_NY];
    ADB_JAC(t, N_VGetArrayPointer(y), (const double *)p, buf);
    for (int i = 0; i < ADB_NY; ++i)
        for (int j = 0; j < ADB_NY; ++j) SM_ELEMENT_D(J, i, j) = buf[i * ADB_NY + j];
    return 0;
}

/* returns 0 on success; out[k * ny] = y(times[k]); counts = steps, rhs evaluations, Newton iterations,
 * Jacobian evaluations, samples reached */
int adb_midpoint(const double *y0, const double *p, double h, double rtol, double atol, int n_out,
                 const double *times, double *out, long *counts)
{
    SUNContext ctx;
    if (SUNContext_Create(NULL, &ctx)) return -1;
    N_Vector y = N_VNew_Serial(ADB_NY, ctx);
    memcpy(N_VGetArrayPointer(y), y0, sizeof(double) * ADB_NY);
    void *mem = ARKStepCreate(NULL, rhs_fn, 0.0, y, ctx);
    double A[1] = {0.5}, b[1] = {1.0}, c[1] = {0.5};
    ARKodeButcherTable B = ARKodeButcherTable_Create(1, 2, 0, c, A, b, NULL);
    SUNMatrix M = SUNDenseMatrix(ADB_NY, ADB_NY, ctx);
    SUNLinearSolver LS = SUNLinSol_Dense(y, M, ctx);
    int flag = ARKStepSetTables(mem, 2, 0, B, NULL);
    flag |= ARKStepSetUserData(mem, (void *)p);
    flag |= ARKStepSStolerances(mem, rtol, atol); /* the Newton iteration's stopping test */
    flag |= ARKStepSetFixedStep(mem, h);
    flag |= ARKStepSetMaxNonlinIters(mem, 10); /* a fixed step cannot shrink: let Newton converge instead */
    flag |= ARKStepSetMaxNumSteps(mem, -1);
    flag |= ARKStepSetLinearSolver(mem, LS, M);
    flag |= ARKStepSetJacFn(mem, jac_fn);
    int k = 0;
    double t = 0.0;
    if (!flag) {
        for (; k < n_out; ++k) {
            if (ARKStepEvolve(mem, times[k], y, &t, ARK_NORMAL) < 0) break;
            memcpy(out + (long)k * ADB_NY, N_VGetArrayPointer(y), sizeof(double) * ADB_NY);
        }
    }
    long st = 0, fe = 0, fi = 0, nni = 0, nje = 0;
    ARKStepGetNumSteps(mem, &st);
    ARKStepGetNumRhsEvals(mem, &fe, &fi);
    ARKStepGetNumNonlinSolvIters(mem, &nni);
    ARKStepGetNumJacEvals(mem, &nje);
    counts[0] = st; counts[1] = fi; counts[2] = nni; counts[3] = nje; counts[4] = k;
    ARKodeButcherTable_Free(B);
    ARKStepFree(&mem);
    SUNLinSolFree(LS);
    SUNMatDestroy(M);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return flag ? -2 : (k == n_out ? 0 : -3);
}
