/* The pinned libm of the compiled engines: force-included (gcc -include) before the model's generated C
 * and the driver, so every elementary function they call gives the same bits on every x86-64 machine.
 *
 * Why: glibc's libm picks an implementation of sin, cos, exp, log, pow, atan, ... per processor at load
 * time (ifunc: FMA/AVX2 variants where the CPU has them, SSE2 ones elsewhere), and the variants differ in
 * the last bit for some arguments.  A loose-tolerance or chaotic run amplifies one such bit into a
 * different t_dec or end state, so a document computed on two machines differed (issue 23; shown by
 * GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA, which selects the SSE2 variants on this machine).
 * SLEEF's "cinz" scalar functions (consistent, no FMA: pure C, the same operations in the same order
 * everywhere, error <= 1.0 ulp) take their place; with -ffp-contract=off the compiler fuses no
 * multiply-add of the model's own code either.  sqrt and fabs are exact IEEE operations already.
 *
 * The Debian package libsleef-dev provides it (pkg-config sleef); compiled.py reports where it is missing.
 */
#ifndef ADB_FIXED_LIBM_H
#define ADB_FIXED_LIBM_H

#include <math.h> /* first, so its declarations are not touched by the macros below */

double Sleef_cinz_sind1_u10purec(double);
double Sleef_cinz_cosd1_u10purec(double);
double Sleef_cinz_tand1_u10purec(double);
double Sleef_cinz_asind1_u10purec(double);
double Sleef_cinz_acosd1_u10purec(double);
double Sleef_cinz_atand1_u10purec(double);
double Sleef_cinz_atan2d1_u10purec(double, double);
double Sleef_cinz_expd1_u10purec(double);
double Sleef_cinz_expm1d1_u10purec(double);
double Sleef_cinz_logd1_u10purec(double);
double Sleef_cinz_log1pd1_u10purec(double);
double Sleef_cinz_powd1_u10purec(double, double);
double Sleef_cinz_sinhd1_u10purec(double);
double Sleef_cinz_coshd1_u10purec(double);
double Sleef_cinz_tanhd1_u10purec(double);
double Sleef_cinz_cbrtd1_u10purec(double);
double Sleef_cinz_hypotd1_u05purec(double, double);

/* x^2 as the one rounded product gcc makes of glibc's pow(x, 2.0) (the generated code squares this way) */
static inline double adb_fixed_pow(double x, double y) { return y == 2.0 ? x * x : Sleef_cinz_powd1_u10purec(x, y); }

#define sin(x) Sleef_cinz_sind1_u10purec(x)
#define cos(x) Sleef_cinz_cosd1_u10purec(x)
#define tan(x) Sleef_cinz_tand1_u10purec(x)
#define asin(x) Sleef_cinz_asind1_u10purec(x)
#define acos(x) Sleef_cinz_acosd1_u10purec(x)
#define atan(x) Sleef_cinz_atand1_u10purec(x)
#define atan2(y, x) Sleef_cinz_atan2d1_u10purec(y, x)
#define exp(x) Sleef_cinz_expd1_u10purec(x)
#define expm1(x) Sleef_cinz_expm1d1_u10purec(x)
#define log(x) Sleef_cinz_logd1_u10purec(x)
#define log1p(x) Sleef_cinz_log1pd1_u10purec(x)
#define pow(x, y) adb_fixed_pow(x, y)
#define sinh(x) Sleef_cinz_sinhd1_u10purec(x)
#define cosh(x) Sleef_cinz_coshd1_u10purec(x)
#define tanh(x) Sleef_cinz_tanhd1_u10purec(x)
#define cbrt(x) Sleef_cinz_cbrtd1_u10purec(x)
#define hypot(x, y) Sleef_cinz_hypotd1_u05purec(x, y)

#endif
