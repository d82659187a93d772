/* The run's data summary (lib/fit/summary.c): the largest value inside the
 * cap, the row counts of both weight plans and the error of each channel's
 * best constant value, against sums taken here sample by sample (two-pass
 * means in long double) from the plans' weights (brdffit_grid_weights()),
 * the grid's values and cos(theta_i); on one thread and on three, with
 * and without missing values and a clear coat, on 3 channels and on 9
 * (two sweeps), and on a scattered grid with a sample of weight 0 whose
 * compensated value overflows (it must add nothing). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/run.h"
#include "fit/stage.h"
#include "grid/grid_internal.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define CAP (70.0 * DEG2RAD)

/* The default axes with fx_values() on nc channels; every 5th value
 * missing with `missing`, and channel 1 scaled by 40 (its largest value
 * is the grid's). */
static brdffit_grid *make_grid(size_t nc, int missing)
{
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o, i;
    double *v = fx_values(axes, nc);
    unsigned char *m = calloc(n * nc, 1);
    brdffit_grid *g = NULL;
    assert_non_null(v);
    assert_non_null(m);
    for (i = 0; i < n * nc; i++) {
        if (i % nc == 1) v[i] *= 40.0;
        if (missing && i % 5 == 2) m[i] = 1;
    }
    assert_int_equal(brdffit_grid_create_regular(&g, axes, nc, v, missing ? m : NULL, NULL, NULL),
                     BRDFFIT_OK);
    free(v);
    free(m);
    return g;
}

/* The squared deviation of r about its a-weighted mean over the samples
 * where a > 0; 0 when there is none. */
static long double deviation(const double *a, const double *r, size_t n)
{
    long double w = 0.0L, s1 = 0.0L, m2 = 0.0L, mean;
    size_t s;
    for (s = 0; s < n; s++) {
        w += a[s];
        s1 += (long double)a[s] * r[s];
    }
    if (!(w > 0.0L)) return 0.0L;
    mean = s1 / w;
    for (s = 0; s < n; s++) m2 += a[s] * (r[s] - mean) * (r[s] - mean);
    return m2;
}

/* The summary of a fit of grid g on `threads` threads against the sums
 * taken here; the largest value inside the cap is at least top_min. */
static void check(brdffit_grid *g, double coat, size_t threads, double top_min)
{
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    bf_result result;
    bf_run run;
    const bf_geometry *geo = bf_grid_geometry(g);
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g), c, s;
    double *w = calloc(n, sizeof *w), *wsa = calloc(n, sizeof *wsa);
    double *a[3], *r[2], top = 0.0;
    long double want[3] = {0.0L, 0.0L, 0.0L};
    size_t on[2] = {0, 0}, rows[2] = {0, 0}, k;
    bf_problem pb;
    assert_non_null(w);
    assert_non_null(wsa);
    for (k = 0; k < 3; k++) assert_non_null(a[k] = calloc(n, sizeof(double)));
    for (k = 0; k < 2; k++) assert_non_null(r[k] = calloc(n, sizeof(double)));
    assert_int_equal(brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, g, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, CAP), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, coat), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, (double)threads), BRDFFIT_OK);
    memset(&run, 0, sizeof run);
    memset(&result, 0, sizeof result);
    run.fit = fit;
    run.result = &result;
    assert_int_equal(bf_run_plans(fit, &run.plan, &run.plan_sa, NULL), BRDFFIT_OK);
    bf_pool_start(&run.pool, threads - 1);
    bf_summary_make(&run);

    assert_int_equal(brdffit_grid_weights(g, CAP, BRDFFIT_WEIGHT_DEFAULT, w, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(g, CAP, BRDFFIT_WEIGHT_SOLID_ANGLE, wsa, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < n; s++) {
        on[0] += w[s] != 0.0;
        on[1] += wsa[s] != 0.0;
    }
    for (c = 0; c < nc; c++) {
        double meas[1], pres[1];
        for (s = 0; s < n; s++) {
            double cz = geo->lz[s] > 0.0 ? geo->lz[s] : 0.0, x;
            bf_grid_load_channel(g, c, s, 1, meas, pres);
            x = meas[0];
            if (wsa[s] != 0.0 || w[s] != 0.0) top = fmax(top, x);
            if (coat > 0.0) x /= bf_grid_coat_divisor(coat, geo->lz[s]);
            a[0][s] = pres[0] != 0.0 && wsa[s] != 0.0 ? wsa[s] * cz * cz : 0.0;
            a[1][s] = pres[0] != 0.0 && wsa[s] != 0.0 ? 1.0 : 0.0;
            a[2][s] = pres[0] != 0.0 && w[s] != 0.0 ? w[s] * w[s] : 0.0;
            r[0][s] = r[1][s] = wsa[s] != 0.0 || w[s] != 0.0 ? x : 0.0;
            rows[0] += a[2][s] != 0.0;
            rows[1] += a[1][s] != 0.0;
        }
        want[0] += deviation(a[0], r[0], n);
        want[1] += deviation(a[1], r[0], n);
        want[2] += deviation(a[2], r[1], n);
    }
    top = fmax(top, top_min);
    assert_true(top > 0.0);
    assert_true(run.summary.top == top);
    assert_int_equal(run.summary.on[0], on[0]);
    assert_int_equal(run.summary.on[1], on[1]);
    assert_int_equal(run.summary.rows[0], rows[0]);
    assert_int_equal(run.summary.rows[1], rows[1]);
    assert_true(want[0] > 0.0L && want[1] > 0.0L && want[2] > 0.0L);
    assert_true(fabsl(run.summary.mean_error - want[0]) <= 1e-12L * want[0]);
    assert_true(fabsl(run.summary.mean_plain - want[1]) <= 1e-12L * want[1]);
    assert_true(fabsl(run.summary.mean_cost - want[2]) <= 1e-12L * want[2]);

    /* a stage's rows: the summary's, or counted where it does not hold
     * them (one channel or the mean with missing values) */
    for (k = 0; k < 3; k++) {
        size_t counted;
        memset(&pb, 0, sizeof pb);
        pb.grid = g;
        pb.plan = k == 1 ? &run.plan_sa : &run.plan;
        pb.source = k == 0 ? BF_SOURCE_CHANNELS : k == 1 ? BF_SOURCE_ONE_CHANNEL : BF_SOURCE_MEAN;
        pb.source_channel = nc - 1;
        pb.nc = k == 0 ? nc : 1;
        assert_int_equal(bf_count_rows(&pb, &counted, NULL), BRDFFIT_OK);
        assert_true(counted > 0);
        assert_int_equal(bf_summary_rows(&run, &pb), counted);
    }

    bf_pool_stop(&run.pool);
    bf_weight_plan_free(&run.plan, &fit->alloc);
    bf_weight_plan_free(&run.plan_sa, &fit->alloc);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    for (k = 0; k < 3; k++) free(a[k]);
    for (k = 0; k < 2; k++) free(r[k]);
    free(w);
    free(wsa);
}

static void test_three_channels(void **state)
{
    size_t missing, t;
    (void)state;
    for (missing = 0; missing < 2; missing++) {
        brdffit_grid *g = make_grid(3, (int)missing);
        for (t = 1; t <= 3; t += 2) {
            check(g, 0.0, t, 0.0);
            check(g, 0.04, t, 0.0);
        }
        brdffit_grid_destroy(g);
    }
}

static void test_nine_channels(void **state)
{
    size_t missing;
    (void)state;
    for (missing = 0; missing < 2; missing++) {
        brdffit_grid *g = make_grid(9, (int)missing);
        check(g, 0.0, 1, 0.0);
        check(g, 0.04, 3, 0.0);
        brdffit_grid_destroy(g);
    }
}

/* A scattered grid whose sample ZERO (inside the cap) has the weight 0
 * and the value HUGE in every channel: with the clear coat of R0 0.5 its
 * compensated value overflows (the divisors are below 0.5), yet the sums
 * are those of the other samples; it is still the largest value inside
 * the cap. */
static void test_weight_zero_overflow(void **state)
{
    enum { N = 300, ZERO = 17 };
    const double huge = DBL_MAX / 1.5;
    double ti[N], pi[N], to[N], po[N], values[N * 3], weights[N];
    brdffit_grid *g = NULL;
    size_t s, c, t;
    (void)state;
    for (s = 0; s < N; s++) {
        ti[s] = (double)(s * 7 % 60) * DEG2RAD;
        pi[s] = 0.0;
        to[s] = (double)(s * 11 % 65) * DEG2RAD;
        po[s] = (double)(s * 13 % 360) * DEG2RAD;
        weights[s] = s == ZERO ? 0.0 : 0.5 + (double)(s % 5) / 4.0;
        for (c = 0; c < 3; c++)
            values[s * 3 + c] = s == ZERO ? huge : fx_value(ti[s], to[s], po[s], c);
    }
    assert_int_equal(
        brdffit_grid_create_scattered(&g, N, ti, pi, to, po, 3, values, NULL, weights, NULL, NULL),
        BRDFFIT_OK);
    for (s = 0; s < N; s++)
        assert_true(isinf(huge / bf_grid_coat_divisor(0.5, bf_grid_geometry(g)->lz[s])));
    for (t = 1; t <= 3; t += 2) {
        check(g, 0.5, t, huge);
        check(g, 0.0, t, huge);
    }
    brdffit_grid_destroy(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_three_channels),
        cmocka_unit_test(test_nine_channels),
        cmocka_unit_test(test_weight_zero_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
