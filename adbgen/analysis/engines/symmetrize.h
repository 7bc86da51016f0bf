/* The right-hand side made exactly equivariant under one declared symmetry S of the model (force-included
 * by the symmetrized engines, adbgen/analysis/engines/symmetrized.py):
 *
 *     f_S(y) = (f(y) + S f(S y)) / 2,    (S y)_i = s_i y_{pi(i)},  S an involution with s_i s_{pi(i)} = 1.
 *
 * Then f_S(S y)_i = (f(S y)_i + s_i f(y)_{pi(i)})/2 and (S f_S(y))_i = (s_i f(y)_{pi(i)} + f(S y)_i)/2: the same
 * two numbers added (addition commutes, sign changes and halving are exact), so f_S(S y) = S f_S(y) bit for
 * bit.  Where the parameters are S-symmetric f_S = f in exact arithmetic; in floating point it differs from f
 * by rounding only.  A Runge-Kutta step updates every component by the same element-wise operations, so a
 * state with S y = y keeps S y = y exactly (the tilt of a race-symmetric run of a model with a race swap stays 0, not 1e-17
 * growing to 1e-4).  Defines expected: ADB_NY, ADB_MODEL_RHS, ADB_SYM_STATES, ADB_SYM_SIGNS.
 */
#ifndef ADB_SYMMETRIZE_H
#define ADB_SYMMETRIZE_H

void ADB_MODEL_RHS(double t, const double *y, const double *p, double *dydt);

static const int adb_sym_states[ADB_NY] = {ADB_SYM_STATES};
static const double adb_sym_signs[ADB_NY] = {ADB_SYM_SIGNS};

static void adb_symmetrized_rhs(double t, const double *y, const double *p, double *out)
{
    double sy[ADB_NY], f[ADB_NY], g[ADB_NY];
    for (int i = 0; i < ADB_NY; ++i) sy[i] = adb_sym_signs[i] * y[adb_sym_states[i]];
    ADB_MODEL_RHS(t, y, p, f);
    ADB_MODEL_RHS(t, sy, p, g);
    for (int i = 0; i < ADB_NY; ++i) out[i] = 0.5 * (f[i] + adb_sym_signs[i] * g[adb_sym_states[i]]);
}

#endif
