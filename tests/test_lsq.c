/* The quick bounded least squares of a batch's scan (fit/lsq.h):
 * bf_bounded_lsq_quick() finds the minimum bf_bounded_lsq() finds, to
 * rounding, on random well-conditioned problems of 1 to 4 variables whose
 * unconstrained minimiser lies inside the box, on its boundary's edges or
 * at a corner (colours >= 0 with and without upper bounds); and the
 * closed form of two variables keeps every bound. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fit/lsq.h"
#include "fit_fixtures.h"
#include "test_support.h"

/* A random positive definite G = A^T A + I / 10 and right-hand side. */
static void random_problem(size_t K, uint64_t *seed, double *G, double *b)
{
    double A[4 * 4];
    size_t i, j, k;
    for (i = 0; i < K * K; i++) A[i] = 2.0 * fx_uniform(seed) - 1.0;
    for (i = 0; i < K; i++) {
        for (j = 0; j < K; j++) {
            double s = i == j ? 0.1 : 0.0;
            for (k = 0; k < K; k++) s += A[k * K + i] * A[k * K + j];
            G[i * K + j] = s;
        }
        b[i] = 2.0 * fx_uniform(seed) - 1.0;
    }
}

static double objective(size_t K, const double *G, const double *b, const double *c)
{
    double f = 0.0;
    size_t i, j;
    for (i = 0; i < K; i++) {
        double gi = 0.0;
        for (j = 0; j < K; j++) gi += G[i * K + j] * c[j];
        f += c[i] * gi - 2.0 * b[i] * c[i];
    }
    return f;
}

static void test_quick_equals_full(void **state)
{
    uint64_t seed = 11;
    size_t K, trial, i, interior = 0, boundary = 0;
    (void)state;
    for (K = 1; K <= 4; K++)
        for (trial = 0; trial < 400; trial++) {
            double G[16], b[4], lo[4], hi[4], c1[4], c2[4], f1, f2, scale = 0.0;
            int inside = 1;
            random_problem(K, &seed, G, b);
            for (i = 0; i < K; i++) {
                lo[i] = 0.0;
                hi[i] = trial % 3 == 0 ? HUGE_VAL : 0.2 + fx_uniform(&seed);
            }
            f1 = bf_bounded_lsq(K, G, b, lo, hi, c1);
            f2 = bf_bounded_lsq_quick(K, G, b, lo, hi, c2);
            for (i = 0; i < K; i++) {
                scale += fabs(b[i]) * fabs(c1[i]) + G[i * K + i] * c1[i] * c1[i];
                /* inside the box to rounding (the scaling's d (hi / d)) */
                assert_true(c2[i] >= lo[i] && c2[i] <= hi[i] * (1.0 + 1e-15));
                assert_true(fabs(c2[i] - c1[i]) <= 1e-8 * (1.0 + fabs(c1[i])));
                inside = inside && c1[i] > lo[i] && c1[i] < hi[i];
            }
            assert_true(fabs(f2 - f1) <= 1e-12 * (scale + 1e-300));
            assert_true(fabs(f2 - objective(K, G, b, c2)) <= 1e-12 * (scale + 1e-300));
            interior += inside;
            boundary += !inside;
        }
    /* both kinds of solution were met */
    assert_true(interior > 100);
    assert_true(boundary > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quick_equals_full),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
