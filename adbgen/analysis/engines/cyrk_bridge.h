/* CyRK's solver reached from C: the function pointers of its numba bridge (CyRK.nb.numba_c_api), bound once
 * per library by the driver's init, and CyRK's status codes in ours.  Included by the drivers that run CyRK
 * (cyrk_driver.c, variational_driver.c) after driver_common.h. */
#ifndef ADB_CYRK_BRIDGE_H
#define ADB_CYRK_BRIDGE_H

#include <stdbool.h>
#include <stddef.h>

typedef void (*PreEvalFn)(char *, double, double *, char *);
typedef void (*DiffeqFn)(double *, double, double *, char *, PreEvalFn);
typedef void *(*SolveFn)(DiffeqFn, double, double, double *, size_t, int, size_t, size_t, char *, size_t, size_t,
                         size_t, bool, double *, size_t, PreEvalFn, void *, size_t, double *, size_t, double *, size_t,
                         double, double, bool);
typedef bool (*BoolFn)(void *);
typedef int (*IntFn)(void *);
typedef size_t (*SizeFn)(void *);
typedef double *(*PtrFn)(void *);
typedef int (*CallFn)(void *, double, double *);
typedef void (*FreeFn)(void *);

static struct {
    SolveFn solve;
    BoolFn success;
    IntFn status;
    SizeFn size;
    PtrFn t;
    PtrFn y;
    SizeFn steps;
    CallFn call;
    FreeFn free;
} cy;

/* ptrs: solve, success, status, size, t, y, steps_taken, call, free (CyRK.nb.numba_c_api). */
static void adb_cyrk_bind(void *const *ptrs)
{
    cy.solve = (SolveFn)ptrs[0];
    cy.success = (BoolFn)ptrs[1];
    cy.status = (IntFn)ptrs[2];
    cy.size = (SizeFn)ptrs[3];
    cy.t = (PtrFn)ptrs[4];
    cy.y = (PtrFn)ptrs[5];
    cy.steps = (SizeFn)ptrs[6];
    cy.call = (CallFn)ptrs[7];
    cy.free = (FreeFn)ptrs[8];
}

/* CyRK status -> ours (CyrkErrorCodes: -51..-53 step limits, -54/-55/-80 step size) */
static int adb_cyrk_decode(int code)
{
    if (code == -51 || code == -52 || code == -53) return ADB_MAX_STEPS;
    if (code == -54 || code == -55 || code == -80) return ADB_STEP_UNDERFLOW;
    return ADB_SOLVER_FAILURE;
}

#endif
