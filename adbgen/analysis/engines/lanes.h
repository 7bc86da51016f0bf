/* The lane type of the ensemble engine (rk_batch_driver.c) and the math the lanes target's rhs calls on
 * it (generated/<model>/<model>_lanes.h: adb_sin, adb_cos, adb_pow, ...).
 *
 * adb_lanes is a GCC vector of ADB_LANES doubles: 8 (AVX-512), 4 (AVX2) or 1 (the scalar fallback),
 * chosen by adbgen.analysis.engines.rk from the CPU's flags when the library is built.  sin and cos are
 * glibc's libmvec (_ZGVeN8v_sin: 8 lanes in one call, _ZGVdN4v_sin: 4; within 4 ulp of the correctly
 * rounded value, glibc's scalar sin/cos within 1): libmvec because it ships with glibc (nothing to
 * install, the vector ABI GCC itself emits for `#pragma omp declare simd`); SLEEF would add a
 * dependency for the same job.  ADB_EXACT_MATH=1 calls glibc's scalar functions lane by lane instead:
 * the ensemble then reproduces the scalar engine (rk_driver.c) bit for bit when both are built with
 * sin and cos never merged into sincos (engines/rk.py SEPARATE_SINCOS; tested).  Every other function is
 * computed lane by lane with libm (sqrt vectorises anyway).
 */
#ifndef ADB_LANES_H
#define ADB_LANES_H

#include <math.h>
#include <string.h>

#ifndef ADB_LANES
#define ADB_LANES 8
#endif
#ifndef ADB_EXACT_MATH
#define ADB_EXACT_MATH 0
#endif

typedef double adb_lanes __attribute__((vector_size(ADB_LANES * sizeof(double))));

/* a scalar or a vector as adb_lanes (x - 0 is exact for every x, -0 included) */
#define adb_splat(x) ((x) - (adb_lanes){0})

#define ADB_LANEWISE(name, fn)                                  \
    static inline adb_lanes name(adb_lanes x)                   \
    {                                                           \
        adb_lanes r;                                            \
        for (int b = 0; b < ADB_LANES; ++b) r[b] = fn(x[b]);    \
        return r;                                               \
    }

#if ADB_EXACT_MATH == 0 && ADB_LANES == 8 && defined(__AVX512F__)
adb_lanes _ZGVeN8v_sin(adb_lanes);
adb_lanes _ZGVeN8v_cos(adb_lanes);
#define adb_sin(x) _ZGVeN8v_sin(adb_splat(x))
#define adb_cos(x) _ZGVeN8v_cos(adb_splat(x))
#define ADB_VECTOR_MATH "libmvec AVX-512 (_ZGVeN8v_sin/cos)"
#elif ADB_EXACT_MATH == 0 && ADB_LANES == 4 && defined(__AVX2__)
adb_lanes _ZGVdN4v_sin(adb_lanes);
adb_lanes _ZGVdN4v_cos(adb_lanes);
#define adb_sin(x) _ZGVdN4v_sin(adb_splat(x))
#define adb_cos(x) _ZGVdN4v_cos(adb_splat(x))
#define ADB_VECTOR_MATH "libmvec AVX2 (_ZGVdN4v_sin/cos)"
#else
ADB_LANEWISE(adb_sin_, sin)
ADB_LANEWISE(adb_cos_, cos)
#define adb_sin(x) adb_sin_(adb_splat(x))
#define adb_cos(x) adb_cos_(adb_splat(x))
#define ADB_VECTOR_MATH "glibc libm lane by lane"
#endif

ADB_LANEWISE(adb_tan_, tan)
ADB_LANEWISE(adb_exp_, exp)
ADB_LANEWISE(adb_log_, log)
ADB_LANEWISE(adb_sqrt_, sqrt)
ADB_LANEWISE(adb_atan_, atan)
ADB_LANEWISE(adb_fabs_, fabs)
ADB_LANEWISE(adb_tanh_, tanh)
ADB_LANEWISE(adb_cbrt_, cbrt)
#define adb_tan(x) adb_tan_(adb_splat(x))
#define adb_exp(x) adb_exp_(adb_splat(x))
#define adb_log(x) adb_log_(adb_splat(x))
#define adb_sqrt(x) adb_sqrt_(adb_splat(x))
#define adb_atan(x) adb_atan_(adb_splat(x))
#define adb_fabs(x) adb_fabs_(adb_splat(x))
#define adb_tanh(x) adb_tanh_(adb_splat(x))
#define adb_cbrt(x) adb_cbrt_(adb_splat(x))

static inline adb_lanes adb_pow_(adb_lanes a, adb_lanes e)
{
    adb_lanes r;
    for (int b = 0; b < ADB_LANES; ++b) r[b] = pow(a[b], e[b]);
    return r;
}
#define adb_pow(a, e) adb_pow_(adb_splat(a), adb_splat(e))

static inline adb_lanes adb_lanes_abs(adb_lanes x)
{
    adb_lanes r;
    for (int b = 0; b < ADB_LANES; ++b) r[b] = fabs(x[b]);
    return r;
}

static inline adb_lanes adb_lanes_max(adb_lanes a, adb_lanes c)
{
    adb_lanes r;
    for (int b = 0; b < ADB_LANES; ++b) r[b] = fmax(a[b], c[b]);
    return r;
}

#endif
