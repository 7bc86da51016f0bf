/* Proof harness of a model's AUTO-07p user file (adbgen/codegen/targets/auto/prove.py).
 *
 * Built with -DUSER_FILE='"<model>.c"' (and AUTO's auto_f2c.h on the include path) into a shared
 * library: the user file is included here as AUTO's own build compiles it, and its functions are
 * called the way AUTO calls them, through the table `user` (auto_f2c.h) of AUTO's function types.
 */
#include USER_FILE

int proof_func(long ndim, const double *u, const double *par, long ijac, double *f, double *dfdu, double *dfdp)
{
    const integer icp[3] = { 1, 2, 3 };

    return user.func((integer)ndim, u, icp, par, (integer)ijac, f, dfdu, dfdp);
}

int proof_stpnt(long ndim, double t, double *u, double *par)
{
    return user.stpnt((integer)ndim, t, u, par);
}

int proof_pvls(long ndim, const double *u, double *par)
{
    return user.pvls((integer)ndim, u, par);
}
