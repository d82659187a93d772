/* Fit objectives (brdffit_objective): recovery of known parameters by every
 * pipeline under every objective, the Jacobian of the transformed residuals
 * against finite differences of the test's own objective cost, auto against
 * joint fits from many starts, and the bad values. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_internal.h"
#include "fit/stage.h"
#include "fit_fixtures.h"
#include "test_support.h"

#define MAXV 64
#define NOBJ 4
#define PI 3.14159265358979323846

static const char *const OBJ_NAMES[NOBJ] = {"squares", "log", "cube-root", "relative"};

typedef struct truth {
    const char *model;
    double v[4][8];
} truth;

static const truth TRUTHS[] = {
    {"ashikhmin-shirley", {{120.0}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}}},
    {"ggx", {{0.2}, {0.04}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}}},
};

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

static brdffit_fit *make_fit(const brdffit_grid *grid, const brdffit_model *model, int objective,
                             brdffit_pipeline pipeline)
{
    brdffit_fit *fit = NULL;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, objective), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pipeline), BRDFFIT_OK);
    return fit;
}

static void run_ok(brdffit_fit *fit)
{
    brdffit_status st = brdffit_fit_run(fit);
    if (st != BRDFFIT_OK) print_error("fit failed: %s\n", brdffit_fit_message(fit));
    assert_int_equal(st, BRDFFIT_OK);
}

/* ---- the test's own objective cost (fit.h, brdffit_objective) ---------- */

typedef struct data {
    const brdffit_grid *grid;
    size_t n, nc;
    double *w, *cz, *vals; /* weight of the objective, max(cos theta_i, 0), model values */
    double delta;
} data;

static void data_init(data *d, const brdffit_grid *grid, int objective)
{
    unsigned weighting =
        objective == 1 || objective == 2 ? BRDFFIT_WEIGHT_SOLID_ANGLE : BRDFFIT_WEIGHT_DEFAULT;
    double sum = 0.0, count = 0.0;
    size_t s, c;
    d->grid = grid;
    d->n = brdffit_grid_sample_count(grid);
    d->nc = brdffit_grid_channel_count(grid);
    d->w = malloc(d->n * sizeof *d->w);
    d->cz = malloc(d->n * sizeof *d->cz);
    d->vals = malloc(d->n * d->nc * sizeof *d->vals);
    assert_true(d->w && d->cz && d->vals);
    assert_int_equal(brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, weighting, d->w, NULL),
                     BRDFFIT_OK);
    for (s = 0; s < d->n; s++) {
        double ti;
        assert_int_equal(brdffit_grid_sample_angles(grid, s, &ti, NULL, NULL, NULL), BRDFFIT_OK);
        d->cz[s] = fmax(cos(ti), 0.0);
    }
    for (c = 0; c < d->nc; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < d->n; s++)
            if (d->w[s] != 0.0 && r[s] != 0.0) {
                sum += log(fabs(r[s]));
                count += 1.0;
            }
    }
    d->delta = 1e-3 * exp(sum / count); /* of the geometric mean of the non-zero |R| */
}

static void data_free(data *d)
{
    free(d->w);
    free(d->cz);
    free(d->vals);
}

static double residual(const data *d, int objective, double m, double r, double c)
{
    switch (objective) {
    case 1: return log(1.0 + c * m) - log(1.0 + c * r);
    case 2: return cbrt(c * m) - cbrt(c * r);
    case 3: return (m - r) / (fabs(r) + d->delta);
    }
    return m - r;
}

static double objective_cost(data *d, const brdffit_model *model, int objective, const double *p)
{
    size_t s, c, n = d->n;
    double cost = 0.0;
    assert_int_equal(brdffit_model_eval_grid(model, d->grid, 0, n, p, d->vals, NULL, NULL),
                     BRDFFIT_OK);
    for (c = 0; c < d->nc; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(d->grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            double e;
            if (d->w[s] == 0.0) continue;
            e = d->w[s] * residual(d, objective, d->vals[c * n + s], r[s], d->cz[s]);
            cost += e * e;
        }
    }
    return cost;
}

/* ---- recovery ------------------------------------------------------------ */

static double worst_relative(const double *a, const double *b, size_t n)
{
    double worst = 0.0;
    size_t i;
    for (i = 0; i < n; i++) worst = fmax(worst, fabs(a[i] - b[i]) / fmax(fabs(b[i]), 1e-3));
    return worst;
}

/* Exact data: every pipeline under every objective returns the truth to
 * 1e-4 relative. Joint and two-stage start 1.5x off in the shape and at
 * colours 0.2 (the cube root also from colours 0: the floored slope). */
static void check_recovery(const truth *t, int objective, brdffit_pipeline pipeline,
                           double colour_start)
{
    brdffit_model *model = make_model(t->model);
    size_t n = brdffit_model_vector_size(model, 3), i;
    double expect[MAXV], got[MAXV], start[MAXV], worst;
    brdffit_grid *grid;
    brdffit_fit *fit;
    fx_vector(model, 3, t->v, expect);
    grid = fx_grid_from_model(model, expect, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_fit(grid, model, objective, pipeline);
    memcpy(start, expect, n * sizeof *start);
    start[0] *= 1.5;
    for (i = brdffit_model_param_count(model) == 4 ? 2 : 1; i < n; i++) start[i] = colour_start;
    assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    worst = worst_relative(got, expect, n);
    printf("%-18s %-9s pipeline %d: worst relative error %.3g\n", t->model, OBJ_NAMES[objective],
           (int)pipeline, worst);
    if (!(worst < 1e-4))
        for (i = 0; i < n; i++)
            print_error("  %zu: got %.12g expected %.12g\n", i, got[i], expect[i]);
    assert_true(worst < 1e-4);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_recovery(void **state)
{
    static const brdffit_pipeline pipes[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT,
                                             BRDFFIT_PIPELINE_TWO_STAGE};
    size_t t, o, p;
    (void)state;
    for (t = 0; t < sizeof TRUTHS / sizeof TRUTHS[0]; t++)
        for (o = 0; o < NOBJ; o++)
            for (p = 0; p < 3; p++) check_recovery(&TRUTHS[t], (int)o, pipes[p], 0.2);
    check_recovery(&TRUTHS[0], 2, BRDFFIT_PIPELINE_JOINT, 0.0);
}

/* ---- the Jacobian ---------------------------------------------------------- */

/* A NORMAL pass of the fit's problem at natural point p: the cost into
 * acc[0], J^T r into acc[1..n]. */
static void normal_pass(brdffit_fit *fit, double delta, const double *p, double *out, size_t n)
{
    bf_run run;
    bf_result result;
    bf_stage st;
    memset(&run, 0, sizeof run);
    memset(&result, 0, sizeof result);
    run.fit = fit;
    run.result = &result;
    run.delta = delta;
    assert_int_equal(
        bf_weight_plan_init(&run.plan, fit->grid, fit->cap, fit->weighting, &fit->alloc, NULL),
        BRDFFIT_OK);
    assert_int_equal(bf_weight_plan_init(&run.plan_sa, fit->grid, fit->cap,
                                         BRDFFIT_WEIGHT_SOLID_ANGLE, &fit->alloc, NULL),
                     BRDFFIT_OK);
    assert_int_equal(bf_stage_init(&st, &run, fit->nc, BF_SOURCE_CHANNELS, 0, 0), BRDFFIT_OK);
    assert_int_equal(st.n, n);
    memcpy(st.p, p, n * sizeof *p);
    assert_int_equal(bf_stage_pass(&st, BF_PASS_NORMAL), BRDFFIT_OK);
    memcpy(out, st.acc, (1 + n) * sizeof *out);
    bf_stage_free(&st);
    bf_weight_plan_free(&run.plan, &fit->alloc);
    bf_weight_plan_free(&run.plan_sa, &fit->alloc);
}

/* The pass's cost is the test's objective cost and its J^T r is half the
 * central difference of that cost, for every objective, at a point away
 * from the optimum of noisy data (every |M| above delta). */
static void check_gradient(const truth *t, int objective)
{
    brdffit_model *model = make_model(t->model);
    size_t n = brdffit_model_vector_size(model, 3), i;
    double truth_p[MAXV], p[MAXV], acc[1 + MAXV];
    brdffit_grid *grid;
    brdffit_fit *fit;
    data d;
    fx_vector(model, 3, t->v, truth_p);
    grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.05, 3);
    assert_non_null(grid);
    fit = make_fit(grid, model, objective, BRDFFIT_PIPELINE_JOINT);
    data_init(&d, grid, objective);
    for (i = 0; i < n; i++) p[i] = truth_p[i] * (i % 2 ? 0.7 : 1.3);
    normal_pass(fit, d.delta, p, acc, n);
    /* the squares' passes take the fused loop, whose inputs are single
     * precision (lib/fit/pass_fused.c): 1e-7, not rounding */
    assert_close(acc[0] / objective_cost(&d, model, objective, p), 1.0,
                 objective == BRDFFIT_OBJECTIVE_SQUARES ? 1e-7 : 1e-10);
    for (i = 0; i < n; i++) {
        double q[MAXV], h = 1e-6 * fabs(p[i]), num;
        memcpy(q, p, n * sizeof *q);
        q[i] = p[i] + h;
        num = objective_cost(&d, model, objective, q);
        q[i] = p[i] - h;
        num = 0.5 * (num - objective_cost(&d, model, objective, q)) / (2.0 * h);
        if (!(fabs(acc[1 + i] - num) <= 1e-5 * fabs(num) + 1e-12 * acc[0]))
            print_error("%s %s: entry %zu J^T r %.12g numeric %.12g\n", t->model,
                        OBJ_NAMES[objective], i, acc[1 + i], num);
        assert_true(fabs(acc[1 + i] - num) <= 1e-5 * fabs(num) + 1e-12 * acc[0]);
    }
    data_free(&d);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_gradient(void **state)
{
    size_t t, o;
    (void)state;
    for (t = 0; t < sizeof TRUTHS / sizeof TRUTHS[0]; t++)
        for (o = 0; o < NOBJ; o++) check_gradient(&TRUTHS[t], (int)o);
}

/* The cube root's slope at M = 0 is floored: with every colour 0 the pass
 * stays finite and its gradient in the colours is the floored one,
 * sum over rows of w^2 (0 - cbrt(c R)) cbrt(c) / (3 delta^(2/3)) B, B the
 * model's value at colour 1. */
static void test_cube_root_at_zero(void **state)
{
    brdffit_model *model = make_model("lambert");
    double truth_p[3] = {0.3, 0.2, 0.1}, p[3] = {0.0, 0.0, 0.0}, acc[4];
    brdffit_grid *grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1);
    brdffit_fit *fit;
    data d;
    size_t c, s;
    (void)state;
    assert_non_null(grid);
    fit = make_fit(grid, model, 2, BRDFFIT_PIPELINE_JOINT);
    data_init(&d, grid, 2);
    normal_pass(fit, d.delta, p, acc, 3);
    {
        double one[3] = {1.0, 1.0, 1.0}; /* the basis column B of every channel */
        assert_int_equal(brdffit_model_eval_grid(model, grid, 0, d.n, one, d.vals, NULL, NULL),
                         BRDFFIT_OK);
    }
    for (c = 0; c < 3; c++) {
        const double *r;
        double want = 0.0, t = cbrt(d.delta);
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < d.n; s++)
            want += d.w[s] * d.w[s] * (-cbrt(d.cz[s] * r[s])) * cbrt(d.cz[s]) / (3.0 * t * t) *
                    d.vals[c * d.n + s];
        assert_true(isfinite(acc[1 + c]));
        assert_close(acc[1 + c] / want, 1.0, 1e-9);
    }
    data_free(&d);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* ---- auto against joint from many starts ------------------------------------ */

static double fit_cost(brdffit_fit *fit)
{
    double cost;
    run_ok(fit);
    assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                     BRDFFIT_OK);
    return cost;
}

/* Noisy Cook-Torrance data fitted by ashikhmin-shirley: under every
 * objective auto's cost is the test's own cost of its parameters and no
 * higher than the best of a brute force, a dense log scan of ns over its
 * whole range each followed by a joint polish from colours 0.1. */
static void test_auto_against_brute_force(void **state)
{
    static const double v[4][8] = {{0.15}, {0.04}, {0.25, 0.12, 0.05}, {0.6, 0.6, 0.6}};
    size_t points = getenv("BRDFFIT_TEST_QUICK") ? 6 : 24, o, i, k;
    brdffit_model *ct = make_model("cook-torrance"), *model = make_model("ashikhmin-shirley");
    const brdffit_param_info *ns = brdffit_model_param(model, 0);
    double p[MAXV];
    brdffit_grid *grid;
    (void)state;
    fx_vector(ct, 3, v, p);
    grid = fx_grid_from_model(ct, p, 3, NULL, 0.05, 7);
    assert_non_null(grid);
    for (o = 0; o < NOBJ; o++) {
        brdffit_fit *fit = make_fit(grid, model, (int)o, BRDFFIT_PIPELINE_AUTO);
        double cost = fit_cost(fit), brute = HUGE_VAL, got[MAXV], best_ns = 0.0;
        data d;
        data_init(&d, grid, (int)o);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        assert_close(objective_cost(&d, model, (int)o, got) / cost, 1.0, 1e-9);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                         BRDFFIT_OK);
        for (i = 0; i < points; i++) {
            double start[7], c;
            start[0] =
                exp(log(ns->lower) + log(ns->upper / ns->lower) * (double)i / (double)(points - 1));
            for (k = 1; k < 7; k++) start[k] = 0.1;
            assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
            c = fit_cost(fit);
            if (c < brute) {
                brute = c;
                assert_int_equal(brdffit_fit_params(fit, start), BRDFFIT_OK);
                best_ns = start[0];
            }
        }
        printf("%-9s auto cost %.10g (ns %.6g), brute force %.10g (ns %.6g), ratio %.9f\n",
               OBJ_NAMES[o], cost, got[0], brute, best_ns, cost / brute);
        assert_true(cost <= brute * (1.0 + 1e-6));
        data_free(&d);
        brdffit_fit_destroy(fit);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    brdffit_model_destroy(ct);
}

/* ---- grazing samples at cap 90 --------------------------------------------- */

/* Exact Ashikhmin-Shirley data on axes that reach 90 degrees, fitted at
 * cap 90: the sample at theta_i = theta_o = 90 with light and view
 * opposite has a value of ~1.6e8 (its clamped dot products), and the
 * theta_i = 90 rows lie on the horizon. Every objective's auto fit must
 * recover the parameters and converge within a few iterations with no
 * warning: the floor delta is not pulled up by the spike, and the
 * horizon rows weigh nothing under the log and cube-root objectives. */
static void test_grazing_spike(void **state)
{
    static const double v[3][8] = {{200.0}, {0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}};
    double ti[10], to[19], po[18], truth_p[MAXV], got[MAXV];
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_axes axes;
    brdffit_grid *grid;
    size_t i, o, n = brdffit_model_vector_size(model, 3);
    const double *r;
    double largest = 0.0;
    (void)state;
    for (i = 0; i < 10; i++) ti[i] = (double)(10 * i) * PI / 180.0;
    for (i = 0; i < 19; i++) to[i] = (double)(5 * i) * PI / 180.0;
    for (i = 0; i < 18; i++) po[i] = (double)i * PI / 17.0;
    axes.theta_i = ti;
    axes.n_theta_i = 10;
    axes.theta_o = to;
    axes.n_theta_o = 19;
    axes.phi_o = po;
    axes.n_phi_o = 18;
    fx_vector(model, 3, v, truth_p);
    grid = fx_grid_from_model(model, truth_p, 3, &axes, 0.0, 1);
    assert_non_null(grid);
    assert_int_equal(brdffit_grid_values(grid, 0, &r), BRDFFIT_OK);
    for (i = 0; i < brdffit_grid_sample_count(grid); i++) largest = fmax(largest, r[i]);
    assert_true(largest > 1e7); /* the spike the test is about */
    for (o = 1; o < NOBJ; o++) {
        brdffit_fit *fit = make_fit(grid, model, (int)o, BRDFFIT_PIPELINE_AUTO);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, PI / 2.0), BRDFFIT_OK);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        printf("%-9s cap 90: ns %.12g, %zu iterations, warnings %#x\n", OBJ_NAMES[o], got[0],
               brdffit_fit_iterations(fit), brdffit_fit_warnings(fit));
        for (i = 0; i < n; i++) assert_close(got[i] / truth_p[i], 1.0, 1e-7);
        assert_true(brdffit_fit_converged(fit));
        assert_true(brdffit_fit_iterations(fit) <= 20);
        assert_int_equal(brdffit_fit_warnings(fit), 0);
        brdffit_fit_destroy(fit);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* ---- bad values -------------------------------------------------------------- */

static void test_bad_values(void **state)
{
    static const double bad[] = {-1.0, 4.0, 0.5, 1e9};
    brdffit_model *model = make_model("lambert");
    double truth_p[3] = {0.3, 0.2, 0.1}, value, *vals;
    brdffit_grid *grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1), *neg = NULL;
    size_t n = brdffit_grid_sample_count(grid), c, s, i;
    brdffit_fit *fit;
    (void)state;
    fit = make_fit(grid, model, 0, BRDFFIT_PIPELINE_JOINT);
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_OBJECTIVE, &value), BRDFFIT_OK);
    assert_true(value == 0.0);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, bad[i]),
                         BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_RELATIVE),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_OBJECTIVE, &value), BRDFFIT_OK);
    assert_true(value == 3.0);
    brdffit_fit_destroy(fit);
    /* one value far below zero at normal light: 1 + cos(theta_i) R <= 0 */
    vals = malloc(3 * n * sizeof *vals);
    assert_non_null(vals);
    for (c = 0; c < 3; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        memcpy(vals + c * n, r, n * sizeof *r);
    }
    for (s = 0; s < n; s++) {
        double ti;
        assert_int_equal(brdffit_grid_sample_angles(grid, s, &ti, NULL, NULL, NULL), BRDFFIT_OK);
        if (ti < 0.5) break;
    }
    assert_true(s < n);
    vals[n + s] = -5.0;
    assert_int_equal(
        brdffit_grid_create_regular(&neg, brdffit_axes_default(), 3, vals, NULL, NULL, NULL),
        BRDFFIT_OK);
    for (i = 0; i < NOBJ; i++) {
        brdffit_status want = i == 1 ? BRDFFIT_E_RANGE : BRDFFIT_OK;
        fit = make_fit(neg, model, (int)i, BRDFFIT_PIPELINE_JOINT);
        assert_int_equal(brdffit_fit_run(fit), want);
        if (want != BRDFFIT_OK) assert_non_null(strstr(brdffit_fit_message(fit), "1 + cos"));
        brdffit_fit_destroy(fit);
    }
    free(vals);
    brdffit_grid_destroy(neg);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_recovery),          cmocka_unit_test(test_gradient),
        cmocka_unit_test(test_cube_root_at_zero), cmocka_unit_test(test_auto_against_brute_force),
        cmocka_unit_test(test_grazing_spike),     cmocka_unit_test(test_bad_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
