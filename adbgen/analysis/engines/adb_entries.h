/* The exported entry points of a driver with a single-trajectory stepper adb_run (adb_engine.h): included
 * by the driver after adb_run.  ADB_MANY_SETUP(): what must run once before the threads (optional).  (The
 * lane-group builds, rk_batch_driver.c and taylor_driver.c with TS_B > 1, export their own
 * adb_integrate_many with the same signature instead.) */
#ifndef ADB_ENTRIES_H
#define ADB_ENTRIES_H

#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#ifndef ADB_MANY_SETUP
#define ADB_MANY_SETUP()
#endif

/* One trajectory from t = 0 to s->t_end from y0 with parameters p; returns the status (also r->status).
 * With s->keep and traj, the accepted steps into *traj (free with adb_release). */
int adb_integrate(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj, double *y_end,
                  adb_result *r)
{
    adb_result_clear(r);
    if (traj) traj->t = traj->y = NULL, traj->k = 0;
    return r->status = adb_run(y0, p, s, s->keep ? traj : NULL, y_end, r);
}

void adb_release(adb_trajectory *traj)
{
    free(traj->t);
    free(traj->y);
    traj->t = traj->y = NULL;
    traj->k = 0;
}

/* Many trajectories on `threads` OpenMP threads (< 1: all): row k of Y0 (n x ADB_NY) with row k of Pm (n x
 * ADB_NP), outputs in row k of Y_end and res[k]; no steps kept, no samples.  A trajectory's result does not
 * depend on the thread that ran it. */
void adb_integrate_many(int n, const double *Y0, const double *Pm, const adb_settings *s, int threads,
                        double *Y_end, adb_result *res)
{
    adb_settings one = *s;
    one.keep = 0, one.n_samples = 0, one.sample_times = NULL, one.samples = NULL, one.message = NULL;
    ADB_MANY_SETUP();
#ifdef _OPENMP
    if (threads < 1) threads = omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#else
    (void)threads;
#endif
    for (int k = 0; k < n; ++k) {
        adb_result_clear(res + k);
        res[k].status = adb_run(Y0 + (size_t)k * ADB_NY, Pm + (size_t)k * ADB_NP, &one, NULL,
                                Y_end + (size_t)k * ADB_NY, res + k);
    }
}

#endif
