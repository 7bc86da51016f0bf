/* The machine's time per floating-point operation for the Taylor series' kind of work (`adbgen bench auto`):
 * the convolutions sum_j a_j b_{K-j}, K = 1..P, of series kept in L1, in four partial sums of fused
 * multiply-adds, over LANES lanes (1: scalar; 4: a vector of four balls), every K's sum unrolled.
 * Compiled with the Taylor engine's flags and -DP=<order> -DLANES=<lanes>.
 * Argument: CPU seconds to run.  Prints "flops F seconds S ns_per_flop X" (a multiply and an add: 2 flops). */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define NSER 16 /* series pairs: enough independent work to fill the pipelines, all in L1 */
static double A[NSER][P + 1][LANES], B[NSER][P + 1][LANES], OUT[NSER][P + 1][LANES];

static double now(void) /* CPU time of the process: time-sharing on a loaded machine does not count */
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline __attribute__((always_inline)) void conv(int q, const int K)
{
    for (int l = 0; l < LANES; ++l) {
        double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
        int j = 0;
        for (; j + 3 <= K; j += 4) {
            s0 = fma(A[q][j][l], B[q][K - j][l], s0);
            s1 = fma(A[q][j + 1][l], B[q][K - j - 1][l], s1);
            s2 = fma(A[q][j + 2][l], B[q][K - j - 2][l], s2);
            s3 = fma(A[q][j + 3][l], B[q][K - j - 3][l], s3);
        }
        for (; j <= K; ++j) s0 = fma(A[q][j][l], B[q][K - j][l], s0);
        OUT[q][K][l] = (s0 + s1) + (s2 + s3);
    }
}

#define ORDER_FN(K) static __attribute__((noinline)) void order_##K(void) { for (int q = 0; q < NSER; ++q) conv(q, K); }
ORDER_FN(1) ORDER_FN(2) ORDER_FN(3) ORDER_FN(4) ORDER_FN(5) ORDER_FN(6) ORDER_FN(7) ORDER_FN(8) ORDER_FN(9)
ORDER_FN(10) ORDER_FN(11) ORDER_FN(12) ORDER_FN(13) ORDER_FN(14) ORDER_FN(15) ORDER_FN(16) ORDER_FN(17)
ORDER_FN(18) ORDER_FN(19) ORDER_FN(20) ORDER_FN(21) ORDER_FN(22) ORDER_FN(23) ORDER_FN(24)
static void (*const orders[25])(void) = {NULL, order_1, order_2, order_3, order_4, order_5, order_6, order_7,
    order_8, order_9, order_10, order_11, order_12, order_13, order_14, order_15, order_16, order_17, order_18,
    order_19, order_20, order_21, order_22, order_23, order_24};

int main(int argc, char **argv)
{
    double seconds = argc > 1 ? atof(argv[1]) : 0.5;
    for (int q = 0; q < NSER; ++q)
        for (int k = 0; k <= P; ++k)
            for (int l = 0; l < LANES; ++l) {
                A[q][k][l] = 1.0 / (1.0 + q + k + l);
                B[q][k][l] = 1.0 / (2.0 + q + k * l);
            }
    double flops_per_pass = 0.0;
    for (int K = 1; K <= P && K < 25; ++K) flops_per_pass += 2.0 * (K + 1) * LANES * NSER;
    long passes = 0;
    double start = now(), elapsed = 0.0;
    while (elapsed < seconds) {
        for (int r = 0; r < 100; ++r) {
            for (int K = 1; K <= P && K < 25; ++K) orders[K]();
            A[r % NSER][0][0] = OUT[(r + 1) % NSER][P][0] * 1e-300 + 1.0; /* a dependence: nothing is hoisted */
        }
        passes += 100;
        elapsed = now() - start;
    }
    double flops = flops_per_pass * (double)passes;
    printf("flops %.0f seconds %.6f ns_per_flop %.6f sink %g\n", flops, elapsed, 1e9 * elapsed / flops, OUT[0][P][0]);
    return 0;
}
