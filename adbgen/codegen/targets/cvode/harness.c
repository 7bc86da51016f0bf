/* Proof harness of a model's SUNDIALS CVODE adaptor (adbgen/codegen/targets/cvode/prove.py).
 *
 * Built with -DMODEL=<model> -DMODEL_UPPER=<MODEL> -DMODEL_CVODE_HEADER='"<model>_cvode.h"' into a
 * shared library with the adaptor: with the model's C library (the values, the Jacobian's layout), or
 * with -DPROOF_STUB and no library, in which case <model>_rhs and <model>_jac copy what the caller put
 * in proof_stub_rhs / proof_stub_jac (a non-finite value at any one position, to see the adaptor
 * return CVODE's recoverable error for each).  The adaptor sees N_Vectors over the caller's arrays,
 * so cells after ydot are the caller's: an adaptor that reads past the end reads them.
 */
#include <math.h>
#include <string.h>

#include MODEL_CVODE_HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define FN(suffix) CAT(MODEL, suffix)
#define N CAT(MODEL_UPPER, _N_STATES)

#ifdef PROOF_STUB
double proof_stub_rhs[N];
double proof_stub_jac[N * N];

void FN(_rhs)(double t, const double *y, const double *p, double *dydt)
{
    (void)t;
    (void)y;
    (void)p;
    memcpy(dydt, proof_stub_rhs, sizeof proof_stub_rhs);
}

void FN(_jac)(double t, const double *y, const double *p, double *out)
{
    (void)t;
    (void)y;
    (void)p;
    memcpy(out, proof_stub_jac, sizeof proof_stub_jac);
}
#endif

static SUNContext ctx = NULL;

static int context(void)
{
    if (ctx != NULL) {
        return 0;
    }
#if SUNDIALS_VERSION_MAJOR >= 7
    return SUNContext_Create(SUN_COMM_NULL, &ctx);
#else
    return SUNContext_Create(NULL, &ctx);
#endif
}

/* the adaptor's CVRhsFn on y (N values) into ydot; its return value, or -100 if SUNDIALS failed */
int proof_rhs(double t, double *y, const double *p, double *ydot)
{
    N_Vector yv, fv;
    int flag;

    if (context() != 0) {
        return -100;
    }
    yv = N_VMake_Serial(N, y, ctx);
    fv = N_VMake_Serial(N, ydot, ctx);
    if (yv == NULL || fv == NULL) {
        return -100;
    }
    flag = FN(_cvode_rhs)(t, yv, fv, (void *)p);
    N_VDestroy(fv);
    N_VDestroy(yv);
    return flag;
}

/* the adaptor's CVLsJacFn into a rows x cols dense matrix (NAN before the call), read back row-major
 * into out with SM_ELEMENT_D; its return value, or -100 if SUNDIALS failed */
int proof_jac(double t, double *y, const double *p, long rows, long cols, double *out)
{
    N_Vector yv, fv, t1, t2, t3;
    SUNMatrix J;
    long i, j;
    int flag;

    if (context() != 0) {
        return -100;
    }
    yv = N_VMake_Serial(N, y, ctx);
    fv = N_VNew_Serial(N, ctx);
    t1 = N_VNew_Serial(N, ctx);
    t2 = N_VNew_Serial(N, ctx);
    t3 = N_VNew_Serial(N, ctx);
    J = SUNDenseMatrix(rows, cols, ctx);
    if (yv == NULL || fv == NULL || t1 == NULL || t2 == NULL || t3 == NULL || J == NULL) {
        return -100;
    }
    for (j = 0; j < cols; ++j) {
        for (i = 0; i < rows; ++i) {
            SM_ELEMENT_D(J, i, j) = NAN;
        }
    }
    flag = FN(_cvode_jac)(t, yv, fv, J, (void *)p, t1, t2, t3);
    for (i = 0; i < rows; ++i) {
        for (j = 0; j < cols; ++j) {
            out[i * cols + j] = SM_ELEMENT_D(J, i, j);
        }
    }
    SUNMatDestroy(J);
    N_VDestroy(t3);
    N_VDestroy(t2);
    N_VDestroy(t1);
    N_VDestroy(fv);
    N_VDestroy(yv);
    return flag;
}
