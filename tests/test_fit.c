/* Fitting: recovery of known parameters by every pipeline and model, the
 * global optimum on mismatched data, options, results and errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define MAXV 64

typedef struct truth {
    const char *model;
    double v[6][8]; /* per declared parameter: value, or one per channel */
} truth;

#define CD {0.30, 0.20, 0.10}
#define CS {0.40, 0.35, 0.30}
#define CS2 {0.15, 0.25, 0.35}

static const truth TRUTHS[] = {
    {"lambert", {CD}},
    {"phong", {{40.0}, CD, CS}},
    {"blinn-phong", {{80.0}, CD, CS}},
    {"ashikhmin-shirley", {{120.0}, CD, CS}},
    {"ashikhmin-shirley-fresnel", {{120.0}, {0.3}, CD, CS}},
    {"cook-torrance", {{0.15}, {0.04}, CD, CS}},
    {"ggx", {{0.2}, {0.04}, CD, CS}},
    {"ward", {{0.15}, CD, CS}},
    {"ward-duer", {{0.15}, CD, CS}},
    {"lafortune", {{30.0}, {0.8}, CD, CS}},
    {"ashikhmin-shirley-2", {{20.0}, {800.0}, CD, CS, CS2}},
    {"cook-torrance-2", {{0.35}, {0.08}, {0.04}, CD, CS, CS2}},
    {"ggx-2", {{0.35}, {0.08}, {0.04}, CD, CS, CS2}},
};

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    brdffit_error err;
    assert_int_equal(brdffit_model_create(&model, name, NULL, &err), BRDFFIT_OK);
    return model;
}

static brdffit_fit *make_fit(const brdffit_grid *grid, const brdffit_model *model)
{
    brdffit_fit *fit = NULL;
    brdffit_error err;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, &err), BRDFFIT_OK);
    return fit;
}

/* A fit of the thesis's weighted squares (the default is the cube root). */
static brdffit_fit *make_squares_fit(const brdffit_grid *grid, const brdffit_model *model)
{
    brdffit_fit *fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                     BRDFFIT_OK);
    return fit;
}

static void run_ok(brdffit_fit *fit)
{
    brdffit_status st = brdffit_fit_run(fit);
    if (st != BRDFFIT_OK) print_error("fit failed: %s\n", brdffit_fit_message(fit));
    assert_int_equal(st, BRDFFIT_OK);
}

/* Two-lobe models are symmetric in their lobes: compare with the lobes in
 * the order the fit found them. */
static void swap_lobes_if_needed(const brdffit_model *model, size_t nc, const double *fitted,
                                 double *expect)
{
    size_t k1, k2, c1, c2, c;
    double t;
    const char *a = brdffit_model_param(model, 0)->name;
    if (strcmp(a, "ns1") != 0 && strcmp(a, "m1") != 0 && strcmp(a, "a1") != 0) return;
    k1 = 0;
    k2 = 1;
    if (fabs(log(fitted[k1] / expect[k1])) < fabs(log(fitted[k1] / expect[k2]))) return;
    t = expect[k1];
    expect[k1] = expect[k2];
    expect[k2] = t;
    assert_int_equal(brdffit_model_param_find(model, "cs1", &c1), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_find(model, "cs2", &c2), BRDFFIT_OK);
    for (c = 0; c < nc; c++) {
        size_t i = brdffit_model_vector_index(model, c1, c, nc);
        size_t j = brdffit_model_vector_index(model, c2, c, nc);
        t = expect[i];
        expect[i] = expect[j];
        expect[j] = t;
    }
}

static double worst_relative(const double *a, const double *b, size_t n)
{
    double worst = 0.0;
    size_t i;
    for (i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]) / fmax(fabs(b[i]), 1e-3);
        if (d > worst) worst = d;
    }
    return worst;
}

static void check_recovery(const truth *t, unsigned weighting, double tol)
{
    brdffit_model *model = make_model(t->model);
    double expect[MAXV], got[MAXV];
    size_t n = brdffit_model_vector_size(model, 3);
    brdffit_grid *grid;
    brdffit_fit *fit;
    double worst;
    assert_true(n <= MAXV);
    fx_vector(model, 3, t->v, expect);
    grid = fx_grid_from_model(model, expect, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, weighting), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    swap_lobes_if_needed(model, 3, got, expect);
    worst = worst_relative(got, expect, n);
    if (!(worst < tol)) {
        size_t i;
        for (i = 0; i < n; i++) print_error("  %zu: got %.12g expected %.12g\n", i, got[i], expect[i]);
        print_error("%s (weighting %u): worst relative error %g\n", t->model, weighting, worst);
    }
    assert_true(worst < tol);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* Every built-in model, auto pipeline, no start values: exact data give the
 * true parameters back, with both weightings and with none.
 * BRDFFIT_TEST_QUICK (the sanitizer and valgrind runs): every model with
 * one of the two, in turn, so that both are still run. */
static void test_auto_recovers_every_model(void **state)
{
    const int quick = getenv("BRDFFIT_TEST_QUICK") != NULL;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof TRUTHS / sizeof TRUTHS[0]; i++) {
        if (!quick || i % 2 == 0) check_recovery(&TRUTHS[i], BRDFFIT_WEIGHT_DEFAULT, 1e-6);
        if (!quick || i % 2 == 1) check_recovery(&TRUTHS[i], BRDFFIT_WEIGHT_NONE, 1e-6);
    }
}

/* Exponents across the range real paints span, and beyond. */
static void test_auto_recovers_exponents(void **state)
{
    static const double ns[] = {5.0, 30.0, 200.0, 2000.0, 20000.0, 100000.0};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        truth t = {"ashikhmin-shirley", {{ns[i]}, CD, CS}};
        check_recovery(&t, BRDFFIT_WEIGHT_DEFAULT, 1e-6);
        check_recovery(&t, BRDFFIT_WEIGHT_COSINE, 1e-6);
    }
}

/* 1 % multiplicative noise: parameters within a few per cent. */
static void test_auto_with_noise(void **state)
{
    static const char *names[] = {"ashikhmin-shirley", "cook-torrance", "ggx", "ward"};
    size_t i, n;
    (void)state;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        const truth *t = NULL;
        size_t j;
        brdffit_model *model = make_model(names[i]);
        double expect[MAXV], got[MAXV];
        brdffit_grid *grid;
        brdffit_fit *fit;
        for (j = 0; j < sizeof TRUTHS / sizeof TRUTHS[0]; j++)
            if (strcmp(TRUTHS[j].model, names[i]) == 0) t = &TRUTHS[j];
        assert_non_null(t);
        n = brdffit_model_vector_size(model, 3);
        fx_vector(model, 3, t->v, expect);
        grid = fx_grid_from_model(model, expect, 3, NULL, 0.01, 42);
        assert_non_null(grid);
        fit = make_fit(grid, model);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        assert_true(worst_relative(got, expect, n) < 0.03);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
        brdffit_model_destroy(model);
    }
}

/* ---- mismatched data: the global optimum ------------------------------------ */

/* P2 of the benchmarks: Lambert plus a Cook-Torrance lobe, 1 % noise. */
static brdffit_grid *mismatched_grid(void)
{
    static const double v[4][8] = {{0.15}, {0.04}, {0.25, 0.12, 0.05}, {0.6, 0.6, 0.6}};
    brdffit_model *ct = make_model("cook-torrance");
    double p[MAXV];
    brdffit_grid *grid;
    fx_vector(ct, 3, v, p);
    grid = fx_grid_from_model(ct, p, 3, NULL, 0.01, 7);
    assert_non_null(grid);
    brdffit_model_destroy(ct);
    return grid;
}

/* The test's own weighted cost of a parameter vector. */
static double direct_cost(const brdffit_grid *grid, const brdffit_model *model, const double *p,
                          const double *w, double *vals)
{
    size_t n = brdffit_grid_sample_count(grid), nc = brdffit_grid_channel_count(grid), s, c;
    double cost = 0.0;
    assert_int_equal(brdffit_model_eval_grid(model, grid, 0, n, p, vals, NULL, NULL), BRDFFIT_OK);
    for (c = 0; c < nc; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            double d = w[s] * (vals[c * n + s] - r[s]);
            cost += d * d;
        }
    }
    return cost;
}

/* Best non-negative (a, b) for min sum w^2 (a A + b B - R)^2, by trying
 * every active set. */
static void nnls2(double g11, double g12, double g22, double b1, double b2, double *a, double *b)
{
    double det = g11 * g22 - g12 * g12, best = HUGE_VAL, x, y, f;
#define TRY(X, Y)                                                              \
    do {                                                                       \
        x = (X);                                                               \
        y = (Y);                                                               \
        if (x >= 0 && y >= 0) {                                                \
            f = g11 * x * x + 2 * g12 * x * y + g22 * y * y - 2 * (b1 * x + b2 * y); \
            if (f < best) { best = f; *a = x; *b = y; }                        \
        }                                                                      \
    } while (0)
    TRY(0.0, 0.0);
    if (g11 > 0) TRY(b1 / g11, 0.0);
    if (g22 > 0) TRY(0.0, b2 / g22);
    if (det > 1e-30 * g11 * g22) TRY((b1 * g22 - b2 * g12) / det, (b2 * g11 - b1 * g12) / det);
#undef TRY
}

/* Brute force over the single shape parameter of a cd/cs model: a dense
 * log-spaced scan, colours solved exactly at each point. */
static double brute_force(const brdffit_grid *grid, const brdffit_model *model, const double *w,
                          size_t points, double *best_shape)
{
    size_t n = brdffit_grid_sample_count(grid), nc = 3, i, s, c, kd, ks;
    const brdffit_param_info *shape = brdffit_model_param(model, 0);
    double lo = log(shape->lower), hi = log(shape->upper), best = HUGE_VAL;
    double *vals = malloc(n * nc * sizeof *vals), *jac, p[MAXV];
    size_t np = brdffit_model_param_count(model);
    jac = malloc(np * n * nc * sizeof *jac);
    assert_non_null(vals);
    assert_non_null(jac);
    assert_int_equal(brdffit_model_param_find(model, "cd", &kd), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_find(model, "cs", &ks), BRDFFIT_OK);
    assert_int_equal(brdffit_model_default_params(model, nc, p), BRDFFIT_OK);
    for (i = 0; i < points; i++) {
        double cost;
        p[0] = exp(lo + (hi - lo) * (double)i / (double)(points - 1));
        assert_int_equal(brdffit_model_eval_grid(model, grid, 0, n, p, vals, jac, NULL), BRDFFIT_OK);
        for (c = 0; c < nc; c++) {
            const double *r, *A = jac + (kd * nc + c) * n, *B = jac + (ks * nc + c) * n;
            double g11 = 0, g12 = 0, g22 = 0, b1 = 0, b2 = 0;
            assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
            for (s = 0; s < n; s++) {
                double ww = w[s] * w[s];
                g11 += ww * A[s] * A[s];
                g12 += ww * A[s] * B[s];
                g22 += ww * B[s] * B[s];
                b1 += ww * A[s] * r[s];
                b2 += ww * B[s] * r[s];
            }
            nnls2(g11, g12, g22, b1, b2, &p[brdffit_model_vector_index(model, kd, c, nc)],
                  &p[brdffit_model_vector_index(model, ks, c, nc)]);
        }
        cost = direct_cost(grid, model, p, w, vals);
        if (cost < best) {
            best = cost;
            *best_shape = p[0];
        }
    }
    free(vals);
    free(jac);
    return best;
}

/* On data from another model the auto pipeline finds the global optimum of
 * the weighted squares: no dense scan (of the squares, as the test's
 * brute_force() solves them) finds a lower cost. Every objective's optimum
 * is checked against a brute force in test_fit_brute_force.c. */
static void test_auto_global_optimum_on_mismatched_data(void **state)
{
    static const char *names[] = {"ashikhmin-shirley", "phong", "blinn-phong", "ward",
                                  "ward-duer", "ggx"};
    brdffit_grid *grid = mismatched_grid();
    size_t n = brdffit_grid_sample_count(grid), i;
    /* BRDFFIT_TEST_QUICK (the valgrind runs): the first model only */
    size_t n_models = getenv("BRDFFIT_TEST_QUICK") ? 1 : sizeof names / sizeof names[0];
    double *w = malloc(n * sizeof *w);
    (void)state;
    assert_non_null(w);
    assert_int_equal(brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_DEFAULT, w,
                                          NULL),
                     BRDFFIT_OK);
    for (i = 0; i < n_models; i++) {
        brdffit_model *model = make_model(names[i]);
        brdffit_fit *fit = make_squares_fit(grid, model);
        double cost, brute, shape = 0.0, got[MAXV], *vals = malloc(3 * n * sizeof *vals);
        assert_non_null(vals);
        run_ok(fit);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        /* the reported cost is the cost of the reported parameters */
        assert_close(direct_cost(grid, model, got, w, vals), cost, 1e-9);
        brute = brute_force(grid, model, w, 1500, &shape);
        if (!(cost <= brute * (1.0 + 1e-9)))
            print_error("%s: fit cost %.12g (shape %g), brute force %.12g (shape %g)\n", names[i],
                        cost, got[0], brute, shape);
        assert_true(cost <= brute * (1.0 + 1e-9));
        /* and the scan lands next to the fit's shape: same basin */
        assert_true(fabs(log(shape / got[0])) < 0.05);
        free(vals);
        brdffit_fit_destroy(fit);
        brdffit_model_destroy(model);
    }
    free(w);
    brdffit_grid_destroy(grid);
}

/* The thesis's two-stage pipeline (its cost, the weighted squares) from
 * start exponents 25 and 250 on the same mismatched data, next to auto;
 * auto does not depend on the start. */
static void test_two_stage_and_auto_from_different_starts(void **state)
{
    static const double starts[] = {25.0, 250.0};
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    double auto_params[2][MAXV], auto_cost = 0.0;
    size_t n = brdffit_model_vector_size(model, 3), i;
    (void)state;
    for (i = 0; i < 2; i++) {
        brdffit_fit *fit = make_squares_fit(grid, model);
        double start[MAXV], got[MAXV], cost;
        const double v[3][8] = {{starts[i]}, {0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}};
        fx_vector(model, 3, v, start);
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_damping(fit, brdffit_damping_thesis()), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_TWO_STAGE),
                         BRDFFIT_OK);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                         BRDFFIT_OK);
        printf("two-stage from ns=%g: ns=%.6g cd=(%.4g %.4g %.4g) cs=(%.4g %.4g %.4g) cost=%.6g "
               "stop=%s\n",
               starts[i], got[0], got[1], got[2], got[3], got[4], got[5], got[6], cost,
               brdffit_stop_reason_string(brdffit_fit_stop_reason(fit)));
        assert_true(got[0] >= 1e-3 && got[0] <= 1e6);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_AUTO),
                         BRDFFIT_OK);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, auto_params[i]), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS,
                                           &auto_cost),
                         BRDFFIT_OK);
        printf("auto (start ns=%g ignored): ns=%.6g cost=%.6g\n", starts[i], auto_params[i][0],
               auto_cost);
        /* two-stage optimises the channel mean first, so it can only be worse */
        assert_true(auto_cost <= cost * (1.0 + 1e-9));
        brdffit_fit_destroy(fit);
    }
    assert_memory_equal(auto_params[0], auto_params[1], n * sizeof(double));
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* The joint pipeline from the thesis's starts reaches the auto optimum on
 * data from the model. */
static void test_joint_from_thesis_start(void **state)
{
    const double v[3][8] = {{25.0}, {0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}};
    brdffit_model *model = make_model("ashikhmin-shirley");
    double truth_p[MAXV], start[MAXV], got[MAXV];
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    fx_vector(model, 3, TRUTHS[3].v, truth_p);
    fx_vector(model, 3, v, start);
    grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    assert_true(worst_relative(got, truth_p, 7) < 1e-6);
    assert_true(brdffit_fit_iterations(fit) > 0);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* Clear-coat compensation: base data with the coat's Fresnel removed as in
 * eq. 4.20 fit back to the model's parameters. */
static void test_clearcoat(void **state)
{
    const double r0 = 0.05;
    brdffit_model *model = make_model("ashikhmin-shirley");
    double p[MAXV], got[MAXV];
    brdffit_grid *grid, *coated;
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n, s, c, i;
    double *values;
    brdffit_fit *fit;
    (void)state;
    fx_vector(model, 3, TRUTHS[3].v, p);
    grid = fx_grid_from_model(model, p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    n = brdffit_grid_sample_count(grid);
    values = malloc(3 * n * sizeof *values);
    assert_non_null(values);
    for (c = 0; c < 3; c++) {
        const double *v;
        assert_int_equal(brdffit_grid_values(grid, c, &v), BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            double ti = axes->theta_i[s / (axes->n_theta_o * axes->n_phi_o)];
            double ci = fmax(cos(ti), 1e-4), f = r0 + (1 - r0) * pow(1 - ci, 5);
            values[s * 3 + c] = v[s] * (1.0 - f);
        }
    }
    assert_int_equal(brdffit_grid_create_regular(&coated, axes, 3, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    fit = make_fit(coated, model);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, r0), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    for (i = 0; i < 7; i++) assert_close(got[i], p[i], 1e-6);
    /* without compensation the same data fit to something else */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, 0.0), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    assert_true(worst_relative(got, p, 7) > 1e-3);
    brdffit_fit_destroy(fit);
    free(values);
    brdffit_grid_destroy(coated);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* One thread or several: the same result up to rounding. */
static void test_threads_agree(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    double one[MAXV], two[MAXV], c1, c2;
    size_t i;
    (void)state;
    for (i = 0; i < 2; i++) {
        brdffit_fit *fit = make_fit(grid, model);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, i == 0 ? 1 : 3), BRDFFIT_OK);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, i == 0 ? one : two), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS,
                                           i == 0 ? &c1 : &c2),
                         BRDFFIT_OK);
        brdffit_fit_destroy(fit);
    }
    for (i = 0; i < 7; i++) assert_close(two[i], one[i], 1e-9);
    assert_close(c2, c1, 1e-9);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* ---- a user model, defined here, fitted through the same pipelines ------- */

/* value = cd / pi + cs * exp(-k (1 - n.h)): a Gaussian-like lobe. */
static brdffit_status gauss_eval(const brdffit_batch *b, const double *p, size_t nc,
                                 double *values, double *jac, void *user)
{
    size_t s, c, n = b->n;
    double k = p[0];
    (void)user;
    for (s = 0; s < n; s++) {
        double e = exp(-k * (1.0 - b->nh[s]));
        for (c = 0; c < nc; c++) {
            double cd = p[1 + c], cs = p[1 + nc + c];
            values[c * n + s] = cd / 3.14159265358979323846 + cs * e;
            if (jac != NULL) {
                jac[(0 * nc + c) * n + s] = -cs * (1.0 - b->nh[s]) * e;
                jac[(1 * nc + c) * n + s] = 1.0 / 3.14159265358979323846;
                jac[(2 * nc + c) * n + s] = e;
            }
        }
    }
    return BRDFFIT_OK;
}

static void test_user_model_fit(void **state)
{
    static const brdffit_param_info params[] = {
        {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-2, 1e5, 10.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
        {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    const double v[3][8] = {{350.0}, CD, CS};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    double truth_p[MAXV], got[MAXV];
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    def.name = "gauss";
    def.n_params = 3;
    def.params = params;
    def.eval = gauss_eval;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    fx_vector(model, 3, v, truth_p);
    grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_fit(grid, model);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    assert_true(worst_relative(got, truth_p, 7) < 1e-6);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* The same lobe with a domain error: k above 3000 is refused with
 * BRDFFIT_E_RANGE (as model.h suggests for a domain error). The auto scan
 * skips those points, as the joint and two-stage pipelines reject such
 * trial steps: every pipeline finds the optimum. */
static brdffit_status gauss_domain_eval(const brdffit_batch *b, const double *p, size_t nc,
                                        double *values, double *jac, void *user)
{
    if (p[0] > 3000.0) return BRDFFIT_E_RANGE;
    return gauss_eval(b, p, nc, values, jac, user);
}

static void test_user_model_domain_error(void **state)
{
    static const brdffit_param_info params[] = {
        {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-2, 1e5, 10.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
        {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    const double v[3][8] = {{350.0}, CD, CS};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    double truth_p[MAXV], got[MAXV];
    brdffit_grid *grid;
    int pl;
    (void)state;
    def.name = "gauss-domain";
    def.n_params = 3;
    def.params = params;
    def.eval = gauss_domain_eval;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    fx_vector(model, 3, v, truth_p);
    grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    for (pl = 0; pl < 3; pl++) {
        brdffit_fit *fit = make_fit(grid, model);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pl), BRDFFIT_OK);
        run_ok(fit);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        if (!(worst_relative(got, truth_p, 7) < 1e-6))
            print_error("pipeline %d: k %g\n", pl, got[0]);
        assert_true(worst_relative(got, truth_p, 7) < 1e-6);
        brdffit_fit_destroy(fit);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* Six scanned shape parameters (the lobe's exponent split into six
 * factors' sum): the auto scan's grid shrinks to fit its budget however
 * many dimensions it has (five or more used to loop for ever) and the fit
 * reaches the exact data's zero cost. */
static brdffit_status gauss6_eval(const brdffit_batch *b, const double *p, size_t nc,
                                  double *values, double *jac, void *user)
{
    size_t s, c, j, n = b->n;
    double k = p[0] + p[1] + p[2] + p[3] + p[4] + p[5];
    (void)user;
    for (s = 0; s < n; s++) {
        double e = exp(-k * (1.0 - b->nh[s]));
        for (c = 0; c < nc; c++) {
            double cd = p[6 + c], cs = p[6 + nc + c];
            values[c * n + s] = cd / 3.14159265358979323846 + cs * e;
            if (jac == NULL) continue;
            for (j = 0; j < 6; j++) jac[(j * nc + c) * n + s] = -cs * (1.0 - b->nh[s]) * e;
            jac[(6 * nc + c) * n + s] = 1.0 / 3.14159265358979323846;
            jac[(7 * nc + c) * n + s] = e;
        }
    }
    return BRDFFIT_OK;
}

static void test_many_scan_dimensions(void **state)
{
    static const brdffit_param_info params[] = {
        {"k1", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"k2", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"k3", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"k4", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"k5", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"k6", BRDFFIT_PARAM_LOG_SCALE, 1.0, 1e3, 10.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
        {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    const double v[8][8] = {{60.0}, {60.0}, {60.0}, {60.0}, {60.0}, {60.0}, CD, CS};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    double truth_p[MAXV], cost = 1.0;
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    def.name = "gauss6";
    def.n_params = 8;
    def.params = params;
    def.eval = gauss6_eval;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    fx_vector(model, 3, v, truth_p);
    grid = fx_grid_from_model(model, truth_p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_squares_fit(grid, model); /* the subject: the scan's dimensions */
    run_ok(fit);
    assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                     BRDFFIT_OK);
    assert_true(cost < 1e-14);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* ---- results ------------------------------------------------------------------ */

/* A fit's error figures against the test's own sums (docs/definitions.md,
 * Cost and error figures): e and E whatever the objective, and the cost
 * of the fit's objective, squares (sum (w (M - R))^2, w the residual
 * weight) or cube-root (sum (a (cbrt(c M) - cbrt(c R)))^2, a the
 * solid-angle weight alone, c = cos theta_i; docs/fitting.md, Objectives). */
static void check_error_figures_of(brdffit_fit *fit, const brdffit_grid *grid,
                                   const brdffit_model *model, int cube_root,
                                   const unsigned char *missing)
{
    size_t n = brdffit_grid_sample_count(grid), s, c;
    double *w = malloc(n * sizeof *w), *a = malloc(n * sizeof *a), *vals = malloc(3 * n * 8);
    double p[MAXV], e2[4] = {0}, ng_num[4] = {0}, ng_den[4] = {0}, cost[4] = {0}, got;
    const brdffit_axes *axes = brdffit_axes_default();
    assert_non_null(w);
    assert_non_null(a);
    assert_non_null(vals);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_DEFAULT, w,
                                          NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_SOLID_ANGLE,
                                          a, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_grid(model, grid, 0, n, p, vals, NULL, NULL), BRDFFIT_OK);
    for (c = 0; c < 3; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            double ti = axes->theta_i[s / (axes->n_theta_o * axes->n_phi_o)];
            double to = axes->theta_o[(s / axes->n_phi_o) % axes->n_theta_o];
            double m = vals[c * n + s], d = m - r[s], ci = cos(ti);
            double t = a[s] * (cbrt(ci * m) - cbrt(ci * r[s]));
            if (ti > BRDFFIT_DEFAULT_CAP + 1e-9 || to > BRDFFIT_DEFAULT_CAP + 1e-9) continue;
            if (missing != NULL && missing[3 * s + c]) continue;
            e2[c] += d * d;
            ng_num[c] += a[s] * ci * ci * d * d;
            ng_den[c] += a[s];
            cost[c] += cube_root ? t * t : w[s] * w[s] * d * d;
        }
        e2[3] += e2[c];
        ng_num[3] += ng_num[c];
        ng_den[3] += ng_den[c];
        cost[3] += cost[c];
    }
    for (c = 0; c < 4; c++) {
        size_t ch = c == 3 ? BRDFFIT_ALL_CHANNELS : c;
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, ch, &got), BRDFFIT_OK);
        assert_close(got, sqrt(e2[c]), 1e-9);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, ch, &got), BRDFFIT_OK);
        assert_close(got, sqrt(ng_num[c] / ng_den[c]), 1e-9);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, ch, &got), BRDFFIT_OK);
        assert_close(got / cost[c], 1.0, 1e-9);
    }
    free(w);
    free(a);
    free(vals);
}

static void check_error_figures(brdffit_fit *fit, const brdffit_grid *grid,
                                const brdffit_model *model, int cube_root)
{
    check_error_figures_of(fit, grid, model, cube_root, NULL);
}

/* The default objective is the cube root: the fit says so, and its cost is
 * the cube-root sum; with the squares set, the squares sum. */
static void test_error_figures(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit = make_fit(grid, model);
    double v = -1.0;
    (void)state;
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_OBJECTIVE, &v), BRDFFIT_OK);
    assert_true(v == (double)BRDFFIT_OBJECTIVE_CUBE_ROOT);
    run_ok(fit);
    check_error_figures(fit, grid, model, 1);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                     BRDFFIT_OK);
    run_ok(fit);
    check_error_figures(fit, grid, model, 0);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* The error figures where values are missing: the sums leave them out
 * (the pass then weighs each row by its presence; on a grid without
 * missing values it reads the values in place, test_error_figures). */
static void test_error_figures_missing(void **state)
{
    brdffit_grid *full = mismatched_grid(), *grid = NULL;
    brdffit_model *model = make_model("ashikhmin-shirley");
    size_t n = brdffit_grid_sample_count(full), s, c;
    double *values = malloc(3 * n * sizeof *values);
    unsigned char *missing = malloc(3 * n);
    brdffit_fit *fit;
    (void)state;
    assert_non_null(values);
    assert_non_null(missing);
    for (c = 0; c < 3; c++) {
        const double *r;
        assert_int_equal(brdffit_grid_values(full, c, &r), BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            values[3 * s + c] = r[s];
            missing[3 * s + c] = (unsigned char)((3 * s + c) % 11 == 4);
        }
    }
    assert_int_equal(brdffit_grid_create_regular(&grid, brdffit_axes_default(), 3, values, missing,
                                                 NULL, NULL),
                     BRDFFIT_OK);
    fit = make_fit(grid, model);
    run_ok(fit);
    check_error_figures_of(fit, grid, model, 1, missing);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                     BRDFFIT_OK);
    run_ok(fit);
    check_error_figures_of(fit, grid, model, 0, missing);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    brdffit_grid_destroy(full);
    free(values);
    free(missing);
}

/* The renderer form (docs/definitions.md), the history and the standard errors. */
static void test_shader_history_std_errors(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit = make_fit(grid, model);
    double p[MAXV], se[MAXV], rs, cd[3], cs[3], hist[512], lam[512];
    size_t c, n;
    (void)state;
    assert_int_equal(brdffit_fit_shader(fit, &rs, cd, cs), BRDFFIT_E_NOT_READY);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_shader(fit, &rs, cd, cs), BRDFFIT_OK);
    assert_close(rs, fmax(p[4], fmax(p[5], p[6])), 1e-15);
    for (c = 0; c < 3; c++) {
        assert_close(cs[c], p[4 + c] / rs, 1e-15);
        assert_close(cd[c], p[1 + c] / (1.0 - rs), 1e-15);
    }
    n = brdffit_fit_history(fit, NULL, NULL);
    assert_true(n >= 1 && n <= 512);
    assert_int_equal(brdffit_fit_history(fit, hist, lam), n);
    for (c = 1; c < n; c++) assert_true(hist[c] <= hist[c - 1]);
    assert_int_equal(brdffit_fit_std_errors(fit, se), BRDFFIT_OK);
    for (c = 0; c < 7; c++) {
        assert_true(isfinite(se[c]) && se[c] >= 0.0);
        assert_true(se[c] < 0.1 * fabs(p[c]) + 1e-12); /* a well-determined fit */
    }
    assert_true(brdffit_fit_stop_reason(fit) != BRDFFIT_STOP_NONE);
    assert_true(brdffit_fit_passes(fit) > 0);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* The Fresnel model converges in auto mode, with Rs in [0, 1], under the
 * default objective and the squares. Under the squares, the cost the
 * bound below was set on, it ends no worse than 1.5 times the simplified
 * model on the same real-looking data (Rs = 1 gives the simplified
 * model's lobe without its diffuse term, Rs = 0 its diffuse term of
 * another shape). Under the default (cube-root), whose cost weighs the
 * dim diffuse region where the two diffuse shapes differ, auto's optimum
 * of the Fresnel model is checked against a brute force in
 * test_fit_brute_force.c. */
static void test_fresnel_converges_on_mismatched_data(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *simple = make_model("ashikhmin-shirley");
    brdffit_model *fresnel = make_model("ashikhmin-shirley-fresnel");
    brdffit_fit *a = make_squares_fit(grid, simple), *b = make_squares_fit(grid, fresnel);
    brdffit_fit *d = make_fit(grid, fresnel);
    double ca, cb, p[MAXV];
    (void)state;
    run_ok(a);
    run_ok(b);
    run_ok(d);
    assert_int_equal(brdffit_fit_error(a, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &ca),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_error(b, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cb),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_params(b, p), BRDFFIT_OK);
    printf("fresnel: ns=%.6g Rs=%.6g cost=%.6g; simplified cost=%.6g\n", p[0], p[1], cb, ca);
    assert_true(p[1] >= 0.0 && p[1] <= 1.0);
    assert_true(brdffit_fit_converged(b));
    assert_true(cb <= ca * 1.5);
    assert_int_equal(brdffit_fit_params(d, p), BRDFFIT_OK);
    printf("fresnel, default objective: ns=%.6g Rs=%.6g\n", p[0], p[1]);
    assert_true(p[1] >= 0.0 && p[1] <= 1.0);
    assert_true(brdffit_fit_converged(d));
    brdffit_fit_destroy(a);
    brdffit_fit_destroy(b);
    brdffit_fit_destroy(d);
    brdffit_model_destroy(simple);
    brdffit_model_destroy(fresnel);
    brdffit_grid_destroy(grid);
}

/* ---- bad input --------------------------------------------------------------- */

static void test_errors(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit = NULL;
    brdffit_error err;
    double p[MAXV], v;
    (void)state;
    assert_int_equal(brdffit_fit_create(NULL, grid, model, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_create(&fit, NULL, model, NULL, &err), BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(fit);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_E_NOT_READY);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, 2.0), BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(brdffit_fit_message(fit), "out of range"));
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, NAN), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, 0), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, 1.5), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, 1.0), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, 3), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_set(fit, (brdffit_fit_setting)99, 1), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_get(fit, BRDFFIT_FIT_CAP, &v), BRDFFIT_OK);
    assert_close(v, BRDFFIT_DEFAULT_CAP, 1e-15);
    assert_int_equal(brdffit_fit_set_fixed(fit, 3, 1), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_default_params(model, 3, p), BRDFFIT_OK);
    p[0] = -1.0;
    assert_int_equal(brdffit_fit_set_start(fit, p), BRDFFIT_E_RANGE);
    p[0] = NAN;
    assert_int_equal(brdffit_fit_set_start(fit, p), BRDFFIT_E_INVALID_ARGUMENT);
    /* a cap of 0 leaves cells without solid angle: no data */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, 0.0), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_NO_DATA);
    assert_string_not_equal(brdffit_fit_message(fit), "");
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_E_NOT_READY);
    brdffit_fit_destroy(fit);
    brdffit_fit_destroy(NULL);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* Every value missing: a clear error, not a NaN. */
static void test_all_missing(void **state)
{
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    double *values = calloc(n, sizeof *values);
    unsigned char *missing = malloc(n);
    brdffit_grid *grid = NULL;
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit;
    (void)state;
    assert_non_null(values);
    assert_non_null(missing);
    memset(missing, 1, n);
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, 1, values, missing, NULL, NULL),
                     BRDFFIT_OK);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_NO_DATA);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    free(values);
    free(missing);
}

/* Every value missing, every pipeline: found before any pass over the
 * samples and worded (auto said "auto fit: " and joint "no measured value
 * inside the cap: " with nothing after the colon). */
static void test_all_missing_message(void **state)
{
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    double *values = calloc(n, sizeof *values);
    unsigned char *missing = malloc(n);
    brdffit_grid *grid = NULL;
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit;
    int pipeline;
    (void)state;
    assert_non_null(values);
    assert_non_null(missing);
    memset(missing, 1, n);
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, 1, values, missing, NULL, NULL),
                     BRDFFIT_OK);
    fit = make_fit(grid, model);
    for (pipeline = 0; pipeline < 3; pipeline++) {
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pipeline), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_NO_DATA);
        assert_string_equal(brdffit_fit_message(fit),
                            "no measured value inside the cap: every value with a non-zero "
                            "weight there is missing");
        assert_int_equal(brdffit_fit_passes(fit), 0);
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    free(values);
    free(missing);
}

/* Two-stage with one channel wholly missing: the other channels have data,
 * so stage 1 runs, and the channel's stage 2 names the channel (it said
 * "no measured value inside the cap: "). */
static void test_one_channel_missing_message(void **state)
{
    const brdffit_axes *axes = brdffit_axes_default();
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    double *values = calloc(3 * n, sizeof *values);
    unsigned char *missing = calloc(3 * n, 1);
    brdffit_grid *grid = NULL;
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit;
    size_t s;
    (void)state;
    assert_non_null(values);
    assert_non_null(missing);
    for (s = 0; s < n; s++) {
        values[3 * s] = values[3 * s + 2] = 0.1;
        missing[3 * s + 1] = 1;
    }
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, 3, values, missing, NULL, NULL),
                     BRDFFIT_OK);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_TWO_STAGE),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_NO_DATA);
    assert_string_equal(brdffit_fit_message(fit), "channel 1 has no measured value inside the cap");
    assert_true(brdffit_fit_passes(fit) > 0); /* stage 1 ran */
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    free(values);
    free(missing);
}

/* A user model with 17 linear parameters: value = sum_q p_q (n.h)^q. */
#define LIN17 17
static brdffit_status lin17_eval(const brdffit_batch *b, const double *p, size_t nc,
                                 double *values, double *jac, void *user)
{
    size_t s, c, q, n = b->n;
    (void)user;
    for (s = 0; s < n; s++)
        for (c = 0; c < nc; c++) {
            double term = 1.0, v = 0.0;
            for (q = 0; q < LIN17; q++) {
                v += p[q * nc + c] * term;
                if (jac != NULL) jac[(q * nc + c) * n + s] = term;
                term *= b->nh[s];
            }
            values[c * n + s] = v;
        }
    return BRDFFIT_OK;
}

/* The auto pipeline solves at most 16 linear parameters exactly: a model
 * with 17 is refused up front with a message naming the limit (it used to
 * run and return BRDFFIT_OK, the 17th left at its start value during the
 * scan), while joint fits it. */
static void test_auto_refuses_17_linear_parameters(void **state)
{
    brdffit_param_info params[LIN17];
    char names[LIN17][8];
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    double truth_p[LIN17], got[LIN17];
    brdffit_grid *grid;
    brdffit_fit *fit;
    size_t q;
    (void)state;
    for (q = 0; q < LIN17; q++) {
        snprintf(names[q], sizeof names[q], "c%zu", q);
        params[q].name = names[q];
        params[q].flags = BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR;
        params[q].lower = 0.0;
        params[q].upper = HUGE_VAL;
        params[q].start = 0.1;
        truth_p[q] = q == 0 ? 0.2 : (q == LIN17 - 1 ? 0.5 : 0.0);
    }
    def.name = "lin17";
    def.n_params = LIN17;
    def.params = params;
    def.eval = lin17_eval;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    grid = fx_grid_from_model(model, truth_p, 1, NULL, 0.0, 1);
    assert_non_null(grid);
    fit = make_fit(grid, model);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_E_UNSUPPORTED);
    assert_string_equal(brdffit_fit_message(fit),
                        "the auto pipeline solves at most 16 linear parameters exactly; "
                        "model 'lin17' has 17 (use the joint or two-stage pipeline)");
    assert_int_equal(brdffit_fit_passes(fit), 0);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_E_NOT_READY);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    for (q = 0; q < LIN17; q++) assert_true(got[q] >= 0.0 && isfinite(got[q]));
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* Fail the Nth allocation of create + run for every N until both succeed:
 * each failure is BRDFFIT_E_OUT_OF_MEMORY and leaks nothing. */
static void test_allocation_failures(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    size_t n;
    (void)state;
    for (n = 1;; n++) {
        counting_alloc ca;
        brdffit_fit *fit = NULL;
        brdffit_status st;
        counting_alloc_init(&ca, n);
        st = brdffit_fit_create(&fit, grid, model, &ca.hook, NULL);
        if (st == BRDFFIT_OK) st = brdffit_fit_run(fit);
        brdffit_fit_destroy(fit);
        assert_int_equal(ca.live, 0);
        if (st == BRDFFIT_OK) break;
        assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
        assert_true(n < 1000);
    }
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* A cancel request stops the fit within one iteration; the callback can stop it. */
static int cancel_on_second(const brdffit_iteration *it, void *user)
{
    if (it->iteration == 2) brdffit_fit_cancel((brdffit_fit *)user);
    return 0;
}

static int stop_at_once(const brdffit_iteration *it, void *user)
{
    (void)it;
    (*(int *)user)++;
    return 1;
}

static void test_cancel_and_callback(void **state)
{
    brdffit_grid *grid = mismatched_grid();
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_fit *fit = make_fit(grid, model);
    int calls = 0;
    (void)state;
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_callback(fit, cancel_on_second, fit), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
    assert_true(brdffit_fit_iterations(fit) <= 3);
    assert_int_equal(brdffit_fit_set_callback(fit, stop_at_once, &calls), BRDFFIT_OK);
    run_ok(fit);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CALLBACK);
    assert_int_equal(calls, 1);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_auto_recovers_every_model),
        cmocka_unit_test(test_auto_recovers_exponents),
        cmocka_unit_test(test_auto_with_noise),
        cmocka_unit_test(test_auto_global_optimum_on_mismatched_data),
        cmocka_unit_test(test_two_stage_and_auto_from_different_starts),
        cmocka_unit_test(test_joint_from_thesis_start),
        cmocka_unit_test(test_clearcoat),
        cmocka_unit_test(test_threads_agree),
        cmocka_unit_test(test_user_model_fit),
        cmocka_unit_test(test_user_model_domain_error),
        cmocka_unit_test(test_many_scan_dimensions),
        cmocka_unit_test(test_error_figures),
        cmocka_unit_test(test_error_figures_missing),
        cmocka_unit_test(test_shader_history_std_errors),
        cmocka_unit_test(test_fresnel_converges_on_mismatched_data),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_all_missing),
        cmocka_unit_test(test_all_missing_message),
        cmocka_unit_test(test_one_channel_missing_message),
        cmocka_unit_test(test_auto_refuses_17_linear_parameters),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_cancel_and_callback),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
