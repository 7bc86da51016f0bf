/* The one C interface of the compiled engines (issue 33 item 1): what Python hands a driver (adb_settings),
 * what a run returns (adb_result) and the steps it keeps (adb_trajectory).  engines/c_interface.py holds
 * the one typed ctypes mirror of these structs and checks it at load against adb_abi_layout below.
 *
 * A driver defines its stepper as
 *     static int adb_run(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj,
 *                        double *y_end, adb_result *r);
 * (traj NULL or s->keep == 0: no steps kept) and includes adb_entries.h after it for the exported entry
 * points (adb_integrate, adb_integrate_many, adb_release).  Included by driver_common.h. */
#ifndef ADB_ENGINE_H
#define ADB_ENGINE_H

#include <stddef.h>

/* One run's settings, shared by every trajectory of a batch.  Fields a driver does not use are ignored
 * (method by the single-method drivers, step_factor but by Taylor's, the samples but by SUNDIALS'). */
typedef struct {
    double t_end, rtol, atol;
    int method;              /* the driver's method number (CyRK's, sundials_driver.c's table) */
    double step_factor;      /* taylor_driver.c: the step-size factor (the engine table's) */
    long max_steps;          /* <= 0: no limit */
    int amp[4];              /* ix, iy, ixd, iyd: the rotor's coordinates and rates (r = |(x, y)|) */
    double threshold;        /* t_dec = sup{t : r(t) >= threshold} */
    double check_dt;         /* > 0: segments of check_dt, early stop in a target region at their ends */
    int n_targets;           /* target regions (driver_common.h adb_in_target) */
    const double *centres, *weights, *cubics, *levels;
    const unsigned char *periodic;
    int keep;                /* 1: every accepted step into the trajectory (a single run) */
    int measures;            /* 0: r_max and t_dec not asked for (NaN) */
    int n_samples;           /* sundials_driver.c: states at sample_times (n_samples) into samples */
    const double *sample_times;
    double *samples;
    char *message;           /* 256 bytes for the solver's last message, or NULL */
} adb_settings;

/* A run's report; stats NaN where not computed (t_fail NaN unless the run failed) */
typedef struct {
    int status;              /* ADB_SUCCESS ... (driver_common.h) */
    int target;              /* the target region it stopped in, or -1 */
    double r_max, t_dec, t_last, t_fail;
    long n_rhs, n_steps;     /* rhs evaluations (Taylor: order passes, steps x order), accepted steps */
} adb_result;

/* The accepted steps of a run (t: k times, y: k x ADB_NY), malloc'd; adb_release frees them */
typedef struct {
    double *t, *y;
    long k;
} adb_trajectory;

/* The layout the Python mirror compares with its own (c_interface.LAYOUT, the same order): sizes and
 * field offsets in bytes.  Returns the number of entries; writes at most n of them into out. */
long adb_abi_layout(long *out, long n)
{
#define ADB_OFF(T, f) (long)offsetof(T, f)
    const long layout[] = {
        (long)sizeof(adb_settings), ADB_OFF(adb_settings, t_end), ADB_OFF(adb_settings, rtol),
        ADB_OFF(adb_settings, atol), ADB_OFF(adb_settings, method), ADB_OFF(adb_settings, step_factor),
        ADB_OFF(adb_settings, max_steps), ADB_OFF(adb_settings, amp), ADB_OFF(adb_settings, threshold),
        ADB_OFF(adb_settings, check_dt), ADB_OFF(adb_settings, n_targets), ADB_OFF(adb_settings, centres),
        ADB_OFF(adb_settings, weights), ADB_OFF(adb_settings, cubics), ADB_OFF(adb_settings, levels),
        ADB_OFF(adb_settings, periodic), ADB_OFF(adb_settings, keep), ADB_OFF(adb_settings, measures),
        ADB_OFF(adb_settings, n_samples), ADB_OFF(adb_settings, sample_times), ADB_OFF(adb_settings, samples),
        ADB_OFF(adb_settings, message),
        (long)sizeof(adb_result), ADB_OFF(adb_result, status), ADB_OFF(adb_result, target),
        ADB_OFF(adb_result, r_max), ADB_OFF(adb_result, t_dec), ADB_OFF(adb_result, t_last),
        ADB_OFF(adb_result, t_fail), ADB_OFF(adb_result, n_rhs), ADB_OFF(adb_result, n_steps),
        (long)sizeof(adb_trajectory), ADB_OFF(adb_trajectory, t), ADB_OFF(adb_trajectory, y),
        ADB_OFF(adb_trajectory, k),
    };
#undef ADB_OFF
    const long count = (long)(sizeof layout / sizeof layout[0]);
    for (long i = 0; i < count && i < n; ++i) out[i] = layout[i];
    return count;
}

/* a result before its run: nothing computed yet */
static inline void adb_result_clear(adb_result *r)
{
    r->status = 0;
    r->target = -1;
    r->r_max = r->t_dec = r->t_last = r->t_fail = __builtin_nan("");
    r->n_rhs = r->n_steps = 0;
}

#endif
