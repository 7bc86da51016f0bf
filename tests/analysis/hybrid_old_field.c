/* Planted (the negative control of tests/analysis/test_hybrid_stall.py): the hybrid driver run on the field
 * the stick/slip models had before the stall was fixed, a slipping ball's friction along the sign of its
 * rate at every stage (sign(phi') as a Piecewise, the mode's slip_dir only at phi' = 0) in place of its
 * mode.  The model's rhs is wrapped: the mode's slip_dir is replaced by the rate's sign before each call.
 *
 *     -DADB_MODEL_SOURCE=... -DMODEL_RHS=<model>_rhs -DADB_RHS=old_field_rhs -DADB_MEASURE=... -DADB_NY
 *     -DADB_NP -DPLANT_NB=<balls> -DPLANT_RATE={states} -DPLANT_DIR={parameters} -DPLANT_STUCK={parameters}
 */
#include <string.h>

#include ADB_MODEL_SOURCE
#define ADB_MODEL_INCLUDED

static const int plant_rate[PLANT_NB] = PLANT_RATE, plant_dir[PLANT_NB] = PLANT_DIR,
                 plant_stuck[PLANT_NB] = PLANT_STUCK;

static void old_field_rhs(double t, const double *y, const double *p, double *f)
{
    double q[ADB_NP];
    memcpy(q, p, sizeof q);
    for (int b = 0; b < PLANT_NB; ++b) {
        double rate = y[plant_rate[b]];
        if (q[plant_stuck[b]] < 0.5 && rate != 0.0) q[plant_dir[b]] = rate > 0.0 ? 1.0 : -1.0;
    }
    MODEL_RHS(t, y, q, f);
}

#include "hybrid_driver.c"
