/* The look error (brdffit_model_log_error()): against a direct computation
 * from the public accessors on a noisy regular grid, exactly 0 for the
 * model the data came from, by hand on a small scattered grid with
 * missing values, given weights and a sample beyond the cap, and every
 * bad input with its status. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846
#define ALL ((size_t)-1)

/* The figure from brdffit_grid_weights(), brdffit_model_eval_grid() and
 * the grid's values and angles. */
static double direct(const brdffit_model *m, const brdffit_grid *g, const double *p, double cap,
                     size_t channel)
{
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g), s, c;
    double *w = malloc(n * sizeof *w), *mv = malloc(n * nc * sizeof *mv), num = 0, den = 0;
    assert_non_null(w);
    assert_non_null(mv);
    assert_int_equal(brdffit_grid_weights(g, cap, BRDFFIT_WEIGHT_SOLID_ANGLE, w, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_grid(m, g, 0, n, p, mv, NULL, NULL), BRDFFIT_OK);
    for (c = 0; c < nc; c++) {
        const double *r;
        if (channel != ALL && c != channel) continue;
        brdffit_grid_values(g, c, &r);
        for (s = 0; s < n; s++) {
            double ti, d;
            if (w[s] == 0.0 || brdffit_grid_is_missing(g, s, c)) continue;
            brdffit_grid_sample_angles(g, s, &ti, NULL, NULL, NULL);
            d = log(1 + cos(ti) * mv[c * n + s]) - log(1 + cos(ti) * r[s]);
            num += w[s] * d * d;
            den += w[s];
        }
    }
    free(w);
    free(mv);
    return sqrt(num / den);
}

static double log_error(const brdffit_model *m, const brdffit_grid *g, const double *p, double cap,
                        size_t channel)
{
    double e = -1.0;
    brdffit_error err;
    brdffit_status st = brdffit_model_log_error(m, g, p, cap, channel, &e, &err);
    if (st != BRDFFIT_OK) print_error("%s: %s\n", brdffit_status_name(st), err.message);
    assert_int_equal(st, BRDFFIT_OK);
    return e;
}

static void test_against_direct_computation(void **state)
{
    const double truth[7] = {60, 0.2, 0.3, 0.1, 0.5, 0.4, 0.9};
    const double other[7] = {200, 0.1, 0.35, 0.2, 0.8, 0.3, 0.5};
    brdffit_model *m = NULL;
    brdffit_grid *g = fx_grid_from_named("ashikhmin-shirley", truth, 3, NULL, 0.1, 7);
    size_t c;
    (void)state;
    assert_non_null(g);
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    for (c = 0; c < 3; c++) {
        double e = log_error(m, g, other, BRDFFIT_DEFAULT_CAP, c);
        assert_true(e > 0.01);
        assert_close(e / direct(m, g, other, BRDFFIT_DEFAULT_CAP, c), 1.0, 1e-12);
    }
    assert_close(log_error(m, g, other, DEG(40.0), ALL) / direct(m, g, other, DEG(40.0), ALL), 1.0,
                 1e-12);
    /* the model the data came from, with their 10 % noise, scores better */
    assert_true(log_error(m, g, truth, BRDFFIT_DEFAULT_CAP, ALL) <
                log_error(m, g, other, BRDFFIT_DEFAULT_CAP, ALL));
    brdffit_grid_destroy(g);
    /* without noise it scores exactly 0 */
    g = fx_grid_from_named("ashikhmin-shirley", truth, 3, NULL, 0.0, 7);
    assert_true(log_error(m, g, truth, BRDFFIT_DEFAULT_CAP, ALL) == 0.0);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(m);
}

/* Three samples of a Lambertian model cd / pi with cd = 1: sample 0 at
 * theta_i = 60 deg (weight 1, value 0.5), sample 1 at theta_i = 0 (weight
 * 3, value missing in channel 0, 2 in channel 1), sample 2 beyond a 70
 * degree cap. */
static void test_by_hand(void **state)
{
    const double ti[3] = {DEG(60), 0.0, DEG(80)}, pi_[3] = {0, 0, 0}, to[3] = {0.1, 0.2, 0.3};
    const double po[3] = {1, 2, 3}, values[6] = {0.5, 0.5, 9, 2, 7, 7}, wgt[3] = {1, 3, 5};
    const unsigned char miss[6] = {0, 0, 1, 0, 0, 0};
    const double cd[2] = {1, 1}, m = 1 / PI;
    brdffit_model *lam = NULL;
    brdffit_grid *g = NULL;
    double d0 = log1p(0.5 * m) - log1p(0.5 * 0.5), d1 = log1p(m) - log1p(2.0), want;
    (void)state;
    assert_int_equal(brdffit_model_create(&lam, "lambert", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(
        brdffit_grid_create_scattered(&g, 3, ti, pi_, to, po, 2, values, miss, wgt, NULL, NULL),
        BRDFFIT_OK);
    /* channel 0: only sample 0 (weight 1 of 4 within the cap) */
    assert_close(log_error(lam, g, cd, DEG(70), 0), fabs(d0), 1e-14);
    /* channel 1: samples 0 and 1, weights 1/4 and 3/4 */
    want = sqrt((0.25 * d0 * d0 + 0.75 * d1 * d1) / 1.0);
    assert_close(log_error(lam, g, cd, DEG(70), 1), want, 1e-14);
    /* both: the present values' weights, 1/4 + 1/4 + 3/4 */
    want = sqrt((2 * 0.25 * d0 * d0 + 0.75 * d1 * d1) / 1.25);
    assert_close(log_error(lam, g, cd, DEG(70), ALL), want, 1e-14);
    brdffit_grid_destroy(g);
    brdffit_model_destroy(lam);
}

static brdffit_status negative_eval(const brdffit_batch *b, const double *p, size_t nc, double *v,
                                    double *j, void *user)
{
    size_t s;
    (void)j, (void)user;
    for (s = 0; s < b->n * nc; s++) v[s] = s == 5 ? -p[0] : p[0];
    return BRDFFIT_OK;
}

static void expect_status(const brdffit_model *m, const brdffit_grid *g, const double *p,
                          double cap, size_t channel, brdffit_status want, const char *fragment)
{
    brdffit_error err;
    double out = 42.0;
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_model_log_error(m, g, p, cap, channel, &out, &err), want);
    assert_int_equal(err.status, want);
    assert_true(out == 42.0);
    if (fragment != NULL && strstr(err.message, fragment) == NULL) {
        print_error("message '%s' lacks '%s'\n", err.message, fragment);
        fail();
    }
}

static void test_bad_input(void **state)
{
    static const brdffit_param_info info = {"k", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5};
    static const uint64_t foreign[16] = {0x1234567812345678u};
    const double cd[3] = {0.5, 0.5, 0.5}, bad[3] = {0.5, NAN, 0.5};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *lam = NULL, *neg = NULL;
    brdffit_grid *g = fx_grid_from_named("lambert", cd, 3, NULL, 0.0, 1);
    const brdffit_status inv = BRDFFIT_E_INVALID_ARGUMENT;
    double out;
    (void)state;
    def.name = "negative", def.n_params = 1, def.params = &info, def.eval = negative_eval;
    assert_int_equal(brdffit_model_create_custom(&neg, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_create(&lam, "lambert", NULL, NULL), BRDFFIT_OK);
    expect_status(NULL, g, cd, 1.0, ALL, inv, "NULL");
    expect_status(lam, NULL, cd, 1.0, ALL, inv, "NULL");
    expect_status(lam, g, NULL, 1.0, ALL, inv, "NULL");
    assert_int_equal(brdffit_model_log_error(lam, g, cd, 1.0, ALL, NULL, NULL), inv);
    expect_status((const brdffit_model *)(const void *)foreign, g, cd, 1.0, ALL,
                  BRDFFIT_E_BAD_HANDLE, NULL);
    expect_status(lam, (const brdffit_grid *)(const void *)foreign, cd, 1.0, ALL,
                  BRDFFIT_E_BAD_HANDLE, NULL);
    expect_status(lam, g, cd, 1.0, 3, inv, "channel 3");
    expect_status(lam, g, cd, 1.6, ALL, inv, "cap");
    expect_status(lam, g, cd, NAN, ALL, inv, "cap");
    /* a cap of 0 keeps the samples at the normal, whose cells have no area */
    expect_status(lam, g, cd, 0.0, ALL, BRDFFIT_E_NO_DATA, NULL);
    expect_status(lam, g, bad, 1.0, ALL, BRDFFIT_E_NONFINITE, "cd");
    expect_status(neg, g, cd, 1.0, 0, BRDFFIT_E_RANGE, "sample 5, channel 0");
    /* channel 1 alone does not use the negative value */
    assert_int_equal(brdffit_model_log_error(neg, g, cd, 1.0, 1, &out, NULL), BRDFFIT_OK);
    brdffit_model_destroy(lam);
    brdffit_model_destroy(neg);
    brdffit_grid_destroy(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_direct_computation),
        cmocka_unit_test(test_by_hand),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
