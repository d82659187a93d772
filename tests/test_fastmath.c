/* The vectorisable elementary functions of lib/core/fastmath.h against
 * libm: bf_exp, bf_cbrt, bf_rcbrt, bf_log and bf_log1p within a few units in the
 * last place over wide ranges of arguments, and their edge values (0,
 * signs, subnormals, the ends of the double range, NaN). */
#include <float.h>
#include <math.h>
#include <stdint.h>

#include "core/fastmath.h"
#include "test_support.h"

/* Distance of a from the reference b in units of b's last place. */
static double ulps(double a, double b)
{
    if (a == b) return 0.0;
    return fabs(a - b) / (nextafter(fabs(b), INFINITY) - fabs(b));
}

/* A fixed xorshift generator: uniform in [0, 1). */
static double uniform(uint64_t *state)
{
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    return (double)(*state >> 11) * 0x1.0p-53;
}

static void test_cbrt_matches_libm(void **state)
{
    uint64_t st = 88172645463325252ULL;
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 200000; i++) {
        double x = pow(10.0, 600.0 * uniform(&st) - 300.0) * (i % 2 ? -1.0 : 1.0);
        worst = fmax(worst, ulps(bf_cbrt(x), cbrt(x)));
    }
    assert_true(worst <= 4.0);
    assert_true(bf_cbrt(0.0) == 0.0);
    assert_true(bf_cbrt(-27.0) == -3.0);
    assert_true(bf_cbrt(8.0) == 2.0);
    assert_true(ulps(bf_cbrt(5e-324), cbrt(5e-324)) <= 4.0); /* subnormal */
    assert_true(ulps(bf_cbrt(DBL_MAX), cbrt(DBL_MAX)) <= 4.0);
    assert_true(ulps(bf_cbrt(-1e-310), cbrt(-1e-310)) <= 4.0);
    assert_true(isnan(bf_cbrt(NAN)));
    assert_true(isnan(bf_cbrt(INFINITY)));
}

/* bf_rcbrt(x) against 1 / cbrt(x) in long double, and x y^2 (the cube
 * root the cube-root objective's rows take from it) against cbrt(x),
 * over the whole positive range, subnormals included. */
static void test_rcbrt_matches_libm(void **state)
{
    uint64_t st = 1181783497276652981ULL;
    double worst = 0.0, worst_root = 0.0;
    const double edges[] = {5e-324, 1e-310, 0x1p-1022, 0x1p-1000, 1.0, 0x1p1000, DBL_MAX};
    size_t i;
    (void)state;
    for (i = 0; i < 200000 + sizeof edges / sizeof *edges; i++) {
        double x = i < 200000 ? pow(2.0, 2098.0 * uniform(&st) - 1074.0) : edges[i - 200000];
        double y = bf_rcbrt(x);
        worst = fmax(worst, ulps(y, (double)(1.0L / cbrtl((long double)x))));
        worst_root = fmax(worst_root, ulps(x * (y * y), cbrt(x)));
    }
    assert_true(worst <= 2.0);
    assert_true(worst_root <= 6.0);
    /* 0 is taken as 2^-1000: a finite y, so 0 * y * y is 0 */
    assert_true(isfinite(bf_rcbrt(0.0)) && bf_rcbrt(0.0) > 0.0);
    assert_true(0.0 * (bf_rcbrt(0.0) * bf_rcbrt(0.0)) == 0.0);
    assert_true(bf_rcbrt(8.0) == 0.5);
    assert_true(isnan(bf_rcbrt(NAN)));
    assert_true(isnan(bf_rcbrt(INFINITY)));
}

static void test_log_matches_libm(void **state)
{
    uint64_t st = 2463534242ULL;
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 200000; i++) {
        double x = pow(10.0, 616.0 * uniform(&st) - 308.0);
        if (fabs(x - 1.0) < 1e-3) continue; /* ln x ~ 0: the ulp of the result is tiny */
        worst = fmax(worst, ulps(bf_log(x), log(x)));
    }
    assert_true(worst <= 2.0);
    assert_true(bf_log(1.0) == 0.0);
    assert_true(bf_log(0.0) == -HUGE_VAL);
    assert_true(isnan(bf_log(-1.0)));
    assert_true(isnan(bf_log(NAN)));
    assert_true(ulps(bf_log(5e-324), log(5e-324)) <= 2.0);
    assert_true(ulps(bf_log(DBL_MAX), log(DBL_MAX)) <= 2.0);
}

static void test_log1p_matches_libm(void **state)
{
    uint64_t st = 123456789ULL;
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 200000; i++) {
        double u = 2.0 * uniform(&st) - 1.0; /* (-1, 1), dense near 0 */
        double x = u * fabs(u) * fabs(u) * fabs(u) * fabs(u), big = pow(10.0, 10.0 * uniform(&st));
        if (x == 0.0) continue;
        worst = fmax(worst, ulps(bf_log1p(x), log1p(x)));
        worst = fmax(worst, ulps(bf_log1p(big), log1p(big)));
    }
    assert_true(worst <= 3.0);
    assert_true(bf_log1p(1e-300) == 1e-300);
    assert_true(bf_log1p(-1.0) == -HUGE_VAL);
    assert_true(isnan(bf_log1p(-2.0)));
}

static void test_exp_matches_libm(void **state)
{
    uint64_t st = 362436069ULL;
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 200000; i++) {
        double x = 1400.0 * uniform(&st) - 700.0;
        worst = fmax(worst, ulps(bf_exp(x), exp(x)));
    }
    assert_true(worst <= 2.0);
    assert_true(bf_exp(0.0) == 1.0);
    assert_true(bf_exp(-800.0) == 0.0); /* flushed below e^-708 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cbrt_matches_libm),
        cmocka_unit_test(test_rcbrt_matches_libm),
        cmocka_unit_test(test_log_matches_libm),
        cmocka_unit_test(test_log1p_matches_libm),
        cmocka_unit_test(test_exp_matches_libm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
