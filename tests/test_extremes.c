/* Numerical extremes of fitting: degenerate data (all zeros, one non-zero
 * sample, values near the ends of the double range, denormals), caps that
 * select nothing, everything or only grazing samples, one and 64 channels,
 * and true parameters at both ends of their ranges.
 *
 * The rule every case checks (check_outcome): a fit either ends with
 * BRDFFIT_OK and finite parameters inside the model's bounds, finite
 * non-negative standard errors, error figures and history, and a stop
 * reason; or with a clear error status and a message. Never a NaN. Each
 * case then states what it must give beyond that. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "grid_fixtures.h"
#include "test_support.h"

#define MAXV 160
#define HIST 4096

static const int PIPELINES[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT,
                                BRDFFIT_PIPELINE_TWO_STAGE};

/* 6 x 16 x 10 = 960 samples, theta up to 75 degrees. */
static const double TI_DEG[] = {0, 15, 30, 45, 60, 75};
static const double TO_DEG[] = {0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 55, 60, 65, 70, 75};
static const double PO_DEG[] = {0, 20, 40, 60, 80, 100, 120, 140, 160, 180};

static fx_axes small;

static const brdffit_axes *small_axes(void)
{
    fx_axes_set(&small, TI_DEG, 6, TO_DEG, 16, PO_DEG, 10);
    return &small.axes;
}

static size_t axes_samples(const brdffit_axes *a)
{
    return a->n_theta_i * a->n_theta_o * a->n_phi_o;
}

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

/* A regular grid on `axes` with nc channels, every value `v`. */
static brdffit_grid *constant_grid(const brdffit_axes *axes, size_t nc, double v)
{
    size_t n = axes_samples(axes) * nc, i;
    double *values = malloc(n * sizeof *values);
    brdffit_grid *grid = NULL;
    assert_non_null(values);
    for (i = 0; i < n; i++) values[i] = v;
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, nc, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    free(values);
    return grid;
}

/* A grid holding the values of another grid times `scale`. */
static brdffit_grid *scaled_grid(const brdffit_grid *src, const brdffit_axes *axes, double scale)
{
    size_t n = brdffit_grid_sample_count(src), nc = brdffit_grid_channel_count(src), s, c;
    double *values = malloc(n * nc * sizeof *values);
    brdffit_grid *grid = NULL;
    assert_non_null(values);
    for (c = 0; c < nc; c++) {
        const double *v;
        assert_int_equal(brdffit_grid_values(src, c, &v), BRDFFIT_OK);
        for (s = 0; s < n; s++) values[s * nc + c] = v[s] * scale;
    }
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, nc, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    free(values);
    return grid;
}

/* ---- one fit and the universal check ------------------------------------- */

typedef struct outcome {
    brdffit_status status;
    char message[512];
    size_t n, nc, n_history;
    double params[MAXV], se[MAXV];
    double rms, ngan, cost;
    double history[2 * HIST];
    brdffit_stop_reason stop;
} outcome;

typedef struct options {
    int pipeline;
    double cap;       /* < 0: default */
    int weighting;    /* < 0: default */
    const double *start;
    const brdffit_objective *objective; /* NULL: the library's default */
} options;

static const brdffit_objective SQUARES = BRDFFIT_OBJECTIVE_SQUARES;

static void fit_once(const brdffit_grid *grid, const brdffit_model *model, const options *o,
                     outcome *out)
{
    brdffit_fit *fit = NULL;
    memset(out, 0, sizeof *out);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, o->pipeline), BRDFFIT_OK);
    /* the cost's optimum over the model's own bounds: data scaled far
     * beyond any albedo must still be fitted exactly */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), BRDFFIT_OK);
    if (o->cap >= 0.0) assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, o->cap), BRDFFIT_OK);
    if (o->weighting >= 0)
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, o->weighting), BRDFFIT_OK);
    if (o->start != NULL) assert_int_equal(brdffit_fit_set_start(fit, o->start), BRDFFIT_OK);
    if (o->objective != NULL)
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, *o->objective), BRDFFIT_OK);
    out->status = brdffit_fit_run(fit);
    snprintf(out->message, sizeof out->message, "%s", brdffit_fit_message(fit));
    out->n = brdffit_fit_param_count(fit);
    out->nc = brdffit_grid_channel_count(grid);
    assert_true(out->n <= MAXV);
    if (out->status == BRDFFIT_OK) {
        assert_int_equal(brdffit_fit_params(fit, out->params), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_std_errors(fit, out->se), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS, &out->rms),
                         BRDFFIT_OK);
        assert_int_equal(
            brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, BRDFFIT_ALL_CHANNELS, &out->ngan),
            BRDFFIT_OK);
        assert_int_equal(
            brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &out->cost),
            BRDFFIT_OK);
        out->n_history = brdffit_fit_history(fit, NULL, NULL);
        assert_true(out->n_history <= HIST);
        brdffit_fit_history(fit, out->history, out->history + out->n_history);
        out->stop = brdffit_fit_stop_reason(fit);
    } else {
        assert_int_equal(brdffit_fit_params(fit, out->params), BRDFFIT_E_NOT_READY);
        assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_NONE);
    }
    brdffit_fit_destroy(fit);
}

static int finite_nonneg(double x)
{
    return isfinite(x) && x >= 0.0;
}

/* A standard error: finite and >= 0, or HUGE_VAL for a parameter the data
 * do not determine (never NaN). */
static int valid_se(double x)
{
    return finite_nonneg(x) || x == HUGE_VAL;
}

/* The universal rule; `what` names the case in failure messages. */
static void check_outcome(const outcome *o, const brdffit_model *model, const char *what)
{
    size_t k, c, i, np = brdffit_model_param_count(model);
    if (o->status != BRDFFIT_OK) {
        if (o->message[0] == '\0') print_error("%s: %s without a message\n", what,
                                               brdffit_status_name(o->status));
        assert_true(o->message[0] != '\0');
        return;
    }
    for (k = 0; k < np; k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < o->nc; c++) {
            size_t at = brdffit_model_vector_index(model, k, c, o->nc);
            double v = o->params[at];
            if (!(isfinite(v) && v >= info->lower && v <= info->upper && valid_se(o->se[at])))
                print_error("%s: %s[%zu] = %g (se %g) outside [%g, %g] or not finite\n", what,
                            info->name, c, v, o->se[at], info->lower, info->upper);
            assert_true(isfinite(v) && v >= info->lower && v <= info->upper);
            assert_true(valid_se(o->se[at]));
        }
    }
    if (!(finite_nonneg(o->rms) && finite_nonneg(o->ngan) && finite_nonneg(o->cost)))
        print_error("%s: error figures rms %g ngan %g cost %g\n", what, o->rms, o->ngan, o->cost);
    assert_true(finite_nonneg(o->rms) && finite_nonneg(o->ngan) && finite_nonneg(o->cost));
    for (i = 0; i < 2 * o->n_history; i++) assert_true(finite_nonneg(o->history[i]));
    /* the cost of the final run never rises */
    for (i = 1; i < o->n_history; i++) assert_true(o->history[i] <= o->history[i - 1]);
    assert_int_not_equal(o->stop, BRDFFIT_STOP_NONE);
}

static void describe(const char *what, const outcome *o)
{
    fflush(stderr);
    printf("%-44s %-22s", what, brdffit_status_name(o->status));
    if (o->status == BRDFFIT_OK)
        printf(" stop=%d rms=%.3g cost=%.3g p0=%.6g", (int)o->stop, o->rms, o->cost, o->params[0]);
    else
        printf(" \"%s\"", o->message);
    printf("\n");
    fflush(stdout);
}

/* The largest colour (linear parameter) of a result. */
static double max_colour(const outcome *o, const brdffit_model *model)
{
    size_t k, c, np = brdffit_model_param_count(model);
    double m = 0.0;
    for (k = 0; k < np; k++)
        if (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_LINEAR)
            for (c = 0; c < o->nc; c++)
                m = fmax(m, o->params[brdffit_model_vector_index(model, k, c, o->nc)]);
    return m;
}

static int has_linear(const brdffit_model *model)
{
    size_t k;
    for (k = 0; k < brdffit_model_param_count(model); k++)
        if (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_LINEAR) return 1;
    return 0;
}

static double named(const outcome *o, const brdffit_model *model, const char *name, size_t c)
{
    size_t k = 0;
    assert_int_equal(brdffit_model_param_find(model, name, &k), BRDFFIT_OK);
    return o->params[brdffit_model_vector_index(model, k, c, o->nc)];
}

/* gltf cannot be black: its dielectric always reflects F0 = 0.04 and its
 * metal the grazing Fresnel term. Its darkest form is a black metal
 * (baseColor 0, metallic 1: value S (1 - h.v)^5); on all-zero data every
 * pipeline must end there. */
static void expect_darkest(const outcome *o, const brdffit_model *model, const char *what)
{
    size_t c;
    double top = 0.0;
    for (c = 0; c < o->nc; c++) top = fmax(top, named(o, model, "baseColor", c));
    print_message("%s: metallic %g, roughness %g, largest baseColor %g, cost %g\n", what,
                  named(o, model, "metallic", 0), named(o, model, "roughness", 0), top, o->cost);
    assert_int_equal(o->status, BRDFFIT_OK);
    assert_true(top <= 1e-6);
    assert_true(named(o, model, "metallic", 0) >= 1.0 - 1e-6);
}

/* The OpenPBR models cannot be black either: the dielectric reflects at
 * least the Fresnel term of specular_ior 1.1 and the metal the grazing
 * Schlick term; under the coat (IOR 1.6, coat_weight >= 0.01) more so. On
 * all-zero data every pipeline must end with a black base_color, and
 * openpbr at the darkest dielectric (specular_ior 1.1, base_metalness 0),
 * openpbr-coat with its coat at the lowest weight. */
static void expect_openpbr_dark(const outcome *o, const brdffit_model *model, const char *what)
{
    const int coated = strcmp(brdffit_model_name(model), "openpbr-coat") == 0;
    size_t c;
    double top = 0.0;
    for (c = 0; c < o->nc; c++) top = fmax(top, named(o, model, "base_color", c));
    print_message("%s: metalness %g, ior %g, largest base_color %g, rms %g\n", what,
                  named(o, model, "base_metalness", 0), named(o, model, "specular_ior", 0), top,
                  o->rms);
    assert_int_equal(o->status, BRDFFIT_OK);
    assert_true(top <= 1e-6);
    if (coated) {
        assert_true(named(o, model, "coat_weight", 0) <= 0.01 + 1e-9);
    } else {
        assert_true(named(o, model, "specular_ior", 0) <= 1.1 + 1e-6);
        assert_true(named(o, model, "base_metalness", 0) <= 1e-6);
    }
}

/* Run every built-in model in every pipeline on `grid` under `objective`
 * (NULL: the default); `expect` is called with each outcome. */
typedef void (*expect_fn)(const outcome *o, const brdffit_model *model, int pipeline,
                          const char *what, void *user);

static void every_model(const brdffit_grid *grid, const char *label,
                        const brdffit_objective *objective, expect_fn expect, void *user)
{
    size_t m, p;
    for (m = 0; m < brdffit_model_builtin_count(); m++) {
        const char *name = brdffit_model_builtin_name(m);
        brdffit_model *model = make_model(name);
        for (p = 0; p < 3; p++) {
            options o = {PIPELINES[p], -1.0, -1, NULL, objective};
            outcome out;
            char what[128];
            snprintf(what, sizeof what, "%s %s pipeline %d", label, name, PIPELINES[p]);
            fit_once(grid, model, &o, &out);
            describe(what, &out);
            check_outcome(&out, model, what);
            if (expect != NULL) expect(&out, model, PIPELINES[p], what, user);
        }
        brdffit_model_destroy(model);
    }
}

/* ---- degenerate data ------------------------------------------------------- */

/* All zeros: the zero model fits exactly. Every model in every pipeline
 * gives BRDFFIT_OK. The auto pipeline solves the colours exactly: every
 * colour and every error figure is 0. The Levenberg-Marquardt pipelines
 * approach the bound 0 from their start values and stop on a small step
 * (relative to the whole parameter vector, shape parameters included):
 * colours below 1e-9 and the root-mean-square error below 1e-7, i.e.
 * black to any renderer. The models that cannot be black (gltf, openpbr)
 * end with a black base colour; which of their other forms is the darkest
 * depends on the objective: under the squares, the cost the reasoning of
 * expect_darkest() and expect_openpbr_dark() is about, they end there
 * (`user` non-NULL); under the default objective the base colour alone is
 * checked. */
static void expect_black_base(const outcome *o, const brdffit_model *model, const char *what)
{
    const char *name =
        strncmp(brdffit_model_name(model), "openpbr", 7) == 0 ? "base_color" : "baseColor";
    size_t c;
    double top = 0.0;
    for (c = 0; c < o->nc; c++) top = fmax(top, named(o, model, name, c));
    if (!(top <= 1e-6)) print_error("%s: largest %s %g\n", what, name, top);
    assert_int_equal(o->status, BRDFFIT_OK);
    assert_true(top <= 1e-6);
}

static void expect_zero_fit(const outcome *o, const brdffit_model *model, int pipeline,
                            const char *what, void *user)
{
    int exact = pipeline == BRDFFIT_PIPELINE_AUTO;
    double tol = exact ? 0.0 : 1e-9, rms_tol = exact ? 0.0 : 1e-7;
    if (!has_linear(model) && user == NULL) {
        expect_black_base(o, model, what);
        return;
    }
    if (strncmp(brdffit_model_name(model), "openpbr", 7) == 0) {
        expect_openpbr_dark(o, model, what);
        return;
    }
    if (!has_linear(model)) {
        expect_darkest(o, model, what);
        return;
    }
    if (!(max_colour(o, model) <= tol && o->rms <= rms_tol && o->ngan <= rms_tol &&
          o->cost <= rms_tol * rms_tol))
        print_error("%s: largest colour %g, rms %g, ngan %g, cost %g\n", what,
                    max_colour(o, model), o->rms, o->ngan, o->cost);
    assert_int_equal(o->status, BRDFFIT_OK);
    assert_true(max_colour(o, model) <= tol);
    assert_true(o->rms <= rms_tol && o->ngan <= rms_tol && o->cost <= rms_tol * rms_tol);
}

static void test_all_zeros(void **state)
{
    brdffit_grid *grid = constant_grid(small_axes(), 3, 0.0);
    int squares = 1;
    (void)state;
    every_model(grid, "zeros", &SQUARES, expect_zero_fit, &squares);
    every_model(grid, "zeros, default objective", NULL, expect_zero_fit, NULL);
    brdffit_grid_destroy(grid);
}

/* One non-zero value (channel 1 of the mirror sample at theta 30 degrees):
 * BRDFFIT_OK in every model and pipeline, and no fit of a model that
 * contains the zero model (all but gltf and openpbr) is worse than it,
 * whose cost is (w 0.5)^2 under the squares, w that sample's weight, and
 * (a cbrt(cos 30deg 0.5))^2 under the default cube-root objective, a its
 * solid-angle weight alone (docs/fitting.md, Objectives). */
static void expect_not_worse_than_zero(const outcome *o, const brdffit_model *model,
                                       int pipeline, const char *what, void *user)
{
    double zero_cost = *(const double *)user;
    (void)pipeline;
    assert_int_equal(o->status, BRDFFIT_OK);
    assert_true(isfinite(o->cost));
    if (!has_linear(model)) return; /* gltf has no zero model (expect_darkest) */
    if (!(o->cost <= zero_cost * (1.0 + 1e-9)))
        print_error("%s: cost %.17g above the zero model's %.17g\n", what, o->cost, zero_cost);
    assert_true(o->cost <= zero_cost * (1.0 + 1e-9));
}

static void test_one_nonzero_sample(void **state)
{
    const brdffit_axes *axes = small_axes();
    size_t n = axes_samples(axes), s = (2 * 16 + 6) * 10; /* theta_i 30, theta_o 30, phi_o 0 */
    double *values = calloc(3 * n, sizeof *values), *w = malloc(n * sizeof *w), zero_cost;
    double *a = malloc(n * sizeof *a);
    brdffit_grid *grid = NULL;
    (void)state;
    assert_non_null(values);
    assert_non_null(w);
    assert_non_null(a);
    values[3 * s + 1] = 0.5;
    assert_int_equal(brdffit_grid_create_regular(&grid, axes, 3, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_DEFAULT, w,
                                          NULL),
                     BRDFFIT_OK);
    zero_cost = (w[s] * 0.5) * (w[s] * 0.5);
    assert_true(zero_cost > 0.0);
    every_model(grid, "one value", &SQUARES, expect_not_worse_than_zero, &zero_cost);
    assert_int_equal(
        brdffit_grid_weights(grid, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_SOLID_ANGLE, a, NULL),
        BRDFFIT_OK);
    zero_cost = pow(a[s] * cbrt(cos(DEG(30.0)) * 0.5), 2.0);
    assert_true(zero_cost > 0.0);
    every_model(grid, "one value, default objective", NULL, expect_not_worse_than_zero, &zero_cost);
    brdffit_grid_destroy(grid);
    free(values);
    free(w);
    free(a);
}

/* Data of the Ashikhmin-Shirley model (ns 120) scaled by `scale`. */
static const double AS_TRUTH[3][8] = {{120.0}, {0.1, 0.2, 0.3}, {0.4, 0.35, 0.3}};

static brdffit_grid *as_grid(double scale)
{
    brdffit_model *model = make_model("ashikhmin-shirley");
    double p[7];
    brdffit_grid *base, *grid;
    fx_vector(model, 3, AS_TRUTH, p);
    base = fx_grid_from_model(model, p, 3, small_axes(), 0.0, 1);
    assert_non_null(base);
    grid = scaled_grid(base, small_axes(), scale);
    brdffit_grid_destroy(base);
    brdffit_model_destroy(model);
    return grid;
}

/* The data's own model fitted to the scaled data: either the true shape
 * and the true colours times `scale` (within `tol`), as on unscaled data,
 * or a clear refusal (an error status with a message). Returns whether the
 * demand held, printing what went wrong. */
static int scaled_fit_ok(double scale, int pipeline, double tol)
{
    brdffit_grid *grid = as_grid(scale);
    brdffit_model *model = make_model("ashikhmin-shirley");
    options o = {pipeline, -1.0, -1, NULL, NULL};
    double truth[7];
    outcome out;
    size_t i;
    int ok = 1;
    fx_vector(model, 3, AS_TRUTH, truth);
    fit_once(grid, model, &o, &out);
    check_outcome(&out, model, "scaled data");
    if (out.status == BRDFFIT_OK)
        for (i = 0; i < 7; i++) {
            double want = i == 0 ? truth[0] : truth[i] * scale;
            if (!(fabs(out.params[i] - want) <= tol * want)) {
                print_error("data scaled by %g, pipeline %d: parameter %zu = %g, expected %g\n",
                            scale, pipeline, i, out.params[i], want);
                ok = 0;
            }
        }
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
    return ok;
}

/* The units of the data do not matter within 1e-6 .. 1e6: the auto
 * pipeline gives the true shape and the colours scaled, within 1e-6 as on
 * unscaled data. */
static void test_scale_invariance(void **state)
{
    (void)state;
    assert_true(scaled_fit_ok(1.0, BRDFFIT_PIPELINE_AUTO, 1e-6));
    assert_true(scaled_fit_ok(1e-6, BRDFFIT_PIPELINE_AUTO, 1e-6));
    assert_true(scaled_fit_ok(1e6, BRDFFIT_PIPELINE_AUTO, 1e-6));
}

/* Values of 1e-300 and denormals (1e-310): every model in every pipeline
 * passes the universal rule. A fit of the data's own model must then give
 * the scaled truth or refuse the data with an error; returning
 * BRDFFIT_OK with a wrong shape or wrong colours is a defect: squared,
 * such values underflow to 0, so a fit that does not guard against it
 * takes every cost as zero and returns the first scan point (auto) or
 * colours 1e287 times too large (joint). */
static void check_tiny(double scale, const char *label)
{
    brdffit_grid *grid = as_grid(scale);
    size_t p;
    int ok = 1;
    every_model(grid, label, NULL, NULL, NULL);
    brdffit_grid_destroy(grid);
    for (p = 0; p < 3; p++) ok &= scaled_fit_ok(scale, PIPELINES[p], 1e-3);
    assert_true(ok);
}

static void test_tiny_values(void **state)
{
    (void)state;
    check_tiny(1e-300, "1e-300");
}

static void test_denormal_values(void **state)
{
    (void)state;
    check_tiny(1e-310, "denormal");
}

/* Values of 1e300: their squares overflow. Every model in every pipeline
 * passes the universal rule; the data's own model gives the scaled truth
 * or a clear error (the library says BRDFFIT_E_NONFINITE: the cost is not
 * finite). */
static void test_huge_values(void **state)
{
    brdffit_grid *grid = as_grid(1e300);
    size_t p;
    (void)state;
    every_model(grid, "1e300", NULL, NULL, NULL);
    for (p = 0; p < 3; p++) assert_true(scaled_fit_ok(1e300, PIPELINES[p], 1e-3));
    brdffit_grid_destroy(grid);
}

/* ---- caps ---------------------------------------------------------------------- */

/* Every model and pipeline: BRDFFIT_E_NO_DATA with a message. */
static void expect_no_data(const outcome *o, const brdffit_model *model, int pipeline,
                           const char *what, void *user)
{
    (void)model;
    (void)pipeline;
    (void)user;
    if (o->status != BRDFFIT_E_NO_DATA) print_error("%s: %s\n", what, o->message);
    assert_int_equal(o->status, BRDFFIT_E_NO_DATA);
}

/* Axes that start above the default cap of 75 degrees (light, then view):
 * nothing to fit. */
static void test_all_samples_beyond_cap(void **state)
{
    static const double high[] = {80, 85, 90}, low[] = {0, 30, 60}, po[] = {0, 90, 180};
    fx_axes a;
    brdffit_grid *grid;
    double ti[4] = {DEG(80), DEG(10), DEG(88), DEG(76)}, to[4] = {DEG(10), DEG(80), DEG(88), DEG(76)};
    double pi_[4] = {0, 1, 2, 3}, po_[4] = {0, 0.5, 1, 1.5}, v[4] = {0.1, 0.2, 0.3, 0.4};
    (void)state;
    fx_axes_set(&a, high, 3, low, 3, po, 3);
    grid = constant_grid(&a.axes, 3, 0.2);
    every_model(grid, "light beyond cap", NULL, expect_no_data, NULL);
    brdffit_grid_destroy(grid);
    fx_axes_set(&a, low, 3, high, 3, po, 3);
    grid = constant_grid(&a.axes, 1, 0.2);
    every_model(grid, "view beyond cap", NULL, expect_no_data, NULL);
    brdffit_grid_destroy(grid);
    assert_int_equal(brdffit_grid_create_scattered(&grid, 4, ti, pi_, to, po_, 1, v, NULL, NULL,
                                                   NULL, NULL),
                     BRDFFIT_OK);
    every_model(grid, "scattered beyond cap", NULL, expect_no_data, NULL);
    brdffit_grid_destroy(grid);
}

/* A cap of 0 keeps only samples with theta_i = theta_o = 0, whose view
 * cells have no solid angle: BRDFFIT_E_NO_DATA with a message in every
 * pipeline when the weights use the solid angle; without it those samples
 * are fitted (the Ngan figure then weighs them alike). */
static void test_cap_zero(void **state)
{
    brdffit_grid *grid = as_grid(1.0);
    brdffit_model *model = make_model("ashikhmin-shirley");
    size_t p, w;
    (void)state;
    for (w = 0; w < 4; w++)
        for (p = 0; p < 3; p++) {
            options o = {PIPELINES[p], 0.0, (int)w, NULL, NULL};
            outcome out;
            char what[64];
            snprintf(what, sizeof what, "cap 0 weighting %zu pipeline %d", w, PIPELINES[p]);
            fit_once(grid, model, &o, &out);
            describe(what, &out);
            check_outcome(&out, model, what);
            if (!(w & BRDFFIT_WEIGHT_SOLID_ANGLE)) {
                /* only the samples at theta_i = theta_o = 0: fitted */
                assert_int_equal(out.status, BRDFFIT_OK);
                continue;
            }
            assert_int_equal(out.status, BRDFFIT_E_NO_DATA);
            assert_non_null(strstr(out.message, "solid angle"));
        }
    brdffit_model_destroy(model);
    brdffit_grid_destroy(grid);
}

/* Grids with one value on a view axis (in-plane data: one phi_o; or a
 * single theta_o) have cells without solid angle. With the solid-angle
 * weighting off they are fitted (the error figure E then weights the
 * samples alike) and exact data are recovered by the auto pipeline; with
 * it on the fit says the cells have no solid angle. */
static void in_plane_case(const brdffit_axes *axes, const char *name)
{
    brdffit_model *model = make_model("ashikhmin-shirley");
    double truth[7];
    brdffit_grid *grid;
    size_t p, w, i;
    fx_vector(model, 3, AS_TRUTH, truth);
    grid = fx_grid_from_model(model, truth, 3, axes, 0.0, 1);
    assert_non_null(grid);
    for (w = 0; w < 4; w++)
        for (p = 0; p < 3; p++) {
            options o = {PIPELINES[p], -1.0, (int)w, NULL, NULL};
            outcome out;
            char what[96];
            snprintf(what, sizeof what, "%s, weighting %zu, pipeline %d", name, w, PIPELINES[p]);
            fit_once(grid, model, &o, &out);
            describe(what, &out);
            check_outcome(&out, model, what);
            if (w & BRDFFIT_WEIGHT_SOLID_ANGLE) {
                assert_int_equal(out.status, BRDFFIT_E_NO_DATA);
                assert_non_null(strstr(out.message, "solid angle"));
                continue;
            }
            if (out.status != BRDFFIT_OK) print_error("%s: %s\n", what, out.message);
            assert_int_equal(out.status, BRDFFIT_OK);
            assert_true(isfinite(out.ngan) && out.ngan >= 0.0);
            if (PIPELINES[p] != BRDFFIT_PIPELINE_AUTO) continue;
            for (i = 0; i < 7; i++)
                assert_true(fabs(out.params[i] - truth[i]) <= 1e-4 * truth[i]);
            assert_true(out.ngan < 1e-6);
        }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_in_plane_and_single_theta_o(void **state)
{
    static const double one_phi[] = {0}, one_to[] = {40};
    fx_axes a;
    (void)state;
    fx_axes_set(&a, TI_DEG, 6, TO_DEG, 16, one_phi, 1);
    in_plane_case(&a.axes, "one phi_o");
    fx_axes_set(&a, TI_DEG, 6, one_to, 1, PO_DEG, 10);
    in_plane_case(&a.axes, "one theta_o");
}

/* A cap of 90 degrees takes in the grazing samples, where the clamped dot
 * products make some models very large: every pipeline recovers exact data
 * of the full default grid (shape and colours within 1e-6). brdffit_fit_set
 * accepts a cap up to pi/2 + 1e-12 (a cap computed from degrees); such a
 * cap must then fit exactly as pi/2 does. */
static void test_cap_90(void **state)
{
    const double half_pi = 1.5707963267948966;
    brdffit_model *model = make_model("ashikhmin-shirley");
    double p[7];
    outcome out, edge;
    brdffit_grid *grid;
    brdffit_fit *fit = NULL;
    size_t i, pl;
    (void)state;
    fx_vector(model, 3, AS_TRUTH, p);
    grid = fx_grid_from_model(model, p, 3, NULL, 0.0, 1);
    assert_non_null(grid);
    assert_true(DEG(90.0) == half_pi);
    for (pl = 0; pl < 3; pl++) {
        options o = {PIPELINES[pl], half_pi, -1, NULL, NULL};
        char what[64];
        snprintf(what, sizeof what, "cap 90 pipeline %d", PIPELINES[pl]);
        fit_once(grid, model, &o, &out);
        describe(what, &out);
        check_outcome(&out, model, what);
        assert_int_equal(out.status, BRDFFIT_OK);
        for (i = 0; i < 7; i++) assert_close(out.params[i], p[i], 1e-6);
    }
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, half_pi + 1e-12), BRDFFIT_OK);
    brdffit_fit_destroy(fit);
    {
        options o = {BRDFFIT_PIPELINE_AUTO, half_pi, -1, NULL, NULL};
        options e = {BRDFFIT_PIPELINE_AUTO, half_pi + 1e-12, -1, NULL, NULL};
        fit_once(grid, model, &o, &out);
        fit_once(grid, model, &e, &edge);
        describe("cap pi/2 + 1e-12", &edge);
        check_outcome(&edge, model, "cap pi/2 + 1e-12");
        assert_int_equal(edge.status, BRDFFIT_OK);
        assert_memory_equal(edge.params, out.params, 7 * sizeof(double));
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* ---- parameters at the ends of their ranges ------------------------------------ */

/* Root of the sum of squared values of a grid. */
static double grid_norm(const brdffit_grid *grid)
{
    size_t n = brdffit_grid_sample_count(grid), nc = brdffit_grid_channel_count(grid), s, c;
    double sum = 0.0;
    for (c = 0; c < nc; c++) {
        const double *v;
        assert_int_equal(brdffit_grid_values(grid, c, &v), BRDFFIT_OK);
        for (s = 0; s < n; s++) sum += v[s] * v[s];
    }
    return sqrt(sum);
}

/* True shape parameters at the ends of their ranges (exponents 1e-3 and
 * 1e6, roughness 1e-4 and 1). Every pipeline passes the universal rule (the
 * joint and two-stage pipelines start from the model's defaults and may
 * stop in a local minimum far from such a truth). The auto pipeline, which
 * does not depend on start values, reproduces the data: its RMS error is
 * below 1e-6 of the data's norm. (At an exponent of 1e6 the lobe is a spike
 * that only the mirror samples see, so the exponent itself is not
 * determined; the data are.) */
static void test_parameter_extremes(void **state)
{
    static const struct { const char *model; double shape; } cases[] = {
        {"ashikhmin-shirley", 1e-3}, {"ashikhmin-shirley", 1e6}, {"phong", 1e-3},
        {"phong", 1e6}, {"blinn-phong", 1e-3}, {"blinn-phong", 1e6}, {"ggx", 1e-4},
        {"ggx", 1.0}, {"cook-torrance", 1e-4}, {"cook-torrance", 1.0}, {"ward", 1e-4},
        {"ward", 1.0}, {"ward-duer", 1e-4}, {"ward-duer", 1.0}, {"lafortune", 1e-3},
        {"lafortune", 1e6},
    };
    size_t i, pl;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        brdffit_model *model = make_model(cases[i].model);
        double v[4][8] = {{cases[i].shape}, {0.04}, {0.1, 0.2, 0.3}, {0.4, 0.35, 0.3}}, p[16];
        double norm;
        brdffit_grid *grid;
        if (brdffit_model_param_count(model) == 3) {
            memcpy(v[1], v[2], sizeof v[1]);
            memcpy(v[2], v[3], sizeof v[2]);
        } else if (strcmp(cases[i].model, "lafortune") == 0) {
            v[1][0] = 0.8;
        }
        fx_vector(model, 3, (const double(*)[8])v, p);
        grid = fx_grid_from_model(model, p, 3, small_axes(), 0.0, 1);
        assert_non_null(grid);
        norm = grid_norm(grid);
        assert_true(norm > 0.0 && isfinite(norm));
        for (pl = 0; pl < 3; pl++) {
            options o = {PIPELINES[pl], -1.0, -1, NULL, NULL};
            outcome out;
            char what[96];
            snprintf(what, sizeof what, "%s shape %g pipeline %d", cases[i].model, cases[i].shape,
                     PIPELINES[pl]);
            fit_once(grid, model, &o, &out);
            describe(what, &out);
            check_outcome(&out, model, what);
            assert_int_equal(out.status, BRDFFIT_OK);
            if (PIPELINES[pl] == BRDFFIT_PIPELINE_AUTO) {
                if (!(out.rms <= 1e-6 * norm))
                    print_error("%s: rms %g, data norm %g\n", what, out.rms, norm);
                assert_true(out.rms <= 1e-6 * norm);
            }
        }
        brdffit_grid_destroy(grid);
        brdffit_model_destroy(model);
    }
}

/* ---- a fit stopped at the end of a range ------------------------------------ */

/* cd / pi + cs (n.h)^(k / 1e4 + m) with k in [1e-2, 1e5] and m in [0, 1]:
 * the exponent is 10 at the top of k with m = 0, which the test grid
 * resolves. The model cancels its own fit the first time it is evaluated at
 * the top of k. */
typedef struct edge_user {
    brdffit_fit *fit;
    int cancelled;
} edge_user;

static const brdffit_param_info EDGE_PARAMS[] = {
    {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-2, 1e5, 10.0},
    {"m", 0, 0.0, 1.0, 0.5},
    {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.2},
    {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.2},
};

static brdffit_status edge_eval(const brdffit_batch *b, const double *p, size_t nc,
                                double *values, double *jac, void *user)
{
    edge_user *u = user;
    size_t s, c, n = b->n;
    if (u->fit != NULL && !u->cancelled && p[0] >= 1e5 * (1.0 - 1e-9)) {
        brdffit_fit_cancel(u->fit);
        u->cancelled = 1;
    }
    for (c = 0; c < nc; c++)
        for (s = 0; s < n; s++) {
            double lobe = exp((1e-4 * p[0] + p[1]) * b->log_nh[s]);
            values[c * n + s] = p[2 + c] / 3.14159265358979323846 + p[2 + nc + c] * lobe;
            if (jac == NULL) continue;
            jac[c * n + s] = p[2 + nc + c] * lobe * 1e-4 * b->log_nh[s];
            jac[(nc + c) * n + s] = p[2 + nc + c] * lobe * b->log_nh[s];
            jac[(2 * nc + c) * n + s] = 1.0 / 3.14159265358979323846;
            jac[(3 * nc + c) * n + s] = lobe;
        }
    return BRDFFIT_OK;
}

/* Data best fitted at the top of a log-scale range, the fit cancelled while
 * the global scan evaluates that end (k varies fastest, so the scan goes on
 * to the next m and sees the cancel there): the result is the scan's best
 * point, the top, and it lies inside the bounds (the scan's top coordinate,
 * log(upper) up to rounding, mapped back with exp can overshoot the bound). */
static void test_cancel_at_range_end(void **state)
{
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    edge_user user = {NULL, 0};
    brdffit_model *model = NULL;
    brdffit_grid *grid;
    brdffit_fit *fit = NULL;
    double truth[4] = {1e5, 0.0, 0.1, 0.5}, p[4];
    (void)state;
    def.name = "edge";
    def.n_params = 4;
    def.params = EDGE_PARAMS;
    def.eval = edge_eval;
    def.user = &user;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    grid = fx_grid_from_model(model, truth, 1, small_axes(), 0.0, 1);
    assert_non_null(grid);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    user.fit = fit;
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_true(user.cancelled);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_CANCELLED);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    if (!(p[0] <= 1e5)) print_error("k = %.17g above its bound 1e5\n", p[0]);
    assert_true(p[0] <= 1e5 && p[0] >= 1e5 * (1.0 - 1e-9));
    assert_true(p[1] == 0.0);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* ---- channel counts ------------------------------------------------------------- */

/* One channel and 64 channels (colours different in every channel), exact
 * data of the full default grid: every pipeline recovers every parameter
 * within 1e-6 (two-stage fits the shape to the channel mean, which exact
 * data of one shape does not disturb). */
static void check_channels(const char *name, double shape, size_t nc)
{
    brdffit_model *model = make_model(name);
    size_t n = brdffit_model_vector_size(model, nc), np = brdffit_model_param_count(model);
    size_t k, c, pl, i;
    double *truth = malloc(n * sizeof *truth);
    brdffit_grid *grid;
    assert_non_null(truth);
    assert_true(n <= MAXV);
    for (k = 0; k < np; k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < nc; c++) {
            size_t at = brdffit_model_vector_index(model, k, c, nc);
            if (!(info->flags & BRDFFIT_PARAM_LINEAR))
                truth[at] = k == 0 ? shape : info->start;
            else if (strcmp(info->name, "cd") == 0)
                truth[at] = 0.02 + 0.004 * (double)c;
            else
                truth[at] = 0.5 - 0.005 * (double)c;
        }
    }
    grid = fx_grid_from_model(model, truth, nc, NULL, 0.0, 1);
    assert_non_null(grid);
    for (pl = 0; pl < 3; pl++) {
        /* 64 channels under the squares: the channel count is the subject,
         * and the default objective's colour steps make them several times
         * slower; one channel keeps the default */
        options o = {PIPELINES[pl], -1.0, -1, NULL, nc > 1 ? &SQUARES : NULL};
        outcome out;
        char what[96];
        snprintf(what, sizeof what, "%s, %zu channels, pipeline %d", name, nc, PIPELINES[pl]);
        fit_once(grid, model, &o, &out);
        describe(what, &out);
        check_outcome(&out, model, what);
        assert_int_equal(out.status, BRDFFIT_OK);
        assert_int_equal(out.n, n);
        for (i = 0; i < n; i++) assert_close(out.params[i], truth[i], 1e-6);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    free(truth);
}

static void test_one_channel(void **state)
{
    (void)state;
    check_channels("ashikhmin-shirley", 120.0, 1);
    check_channels("ggx", 0.2, 1);
}

static void test_64_channels(void **state)
{
    (void)state;
    check_channels("ashikhmin-shirley", 120.0, 64);
    check_channels("ggx", 0.2, 64);
}

/* ---- channel limits ------------------------------------------------------------ */

/* An allocator that refuses any request above 64 MB and records the
 * largest one. */
typedef struct capped_alloc {
    size_t largest;
} capped_alloc;

static void *capped_alloc_fn(size_t size, void *ctx)
{
    capped_alloc *ca = ctx;
    if (size > ca->largest) ca->largest = size;
    return size > ((size_t)64 << 20) ? NULL : malloc(size);
}

static void capped_free_fn(void *ptr, void *ctx)
{
    (void)ctx;
    free(ptr);
}

static int capped_run(const brdffit_grid *grid, const brdffit_model *model, int pipeline,
                      capped_alloc *ca, char *message, size_t size)
{
    brdffit_allocator a = {capped_alloc_fn, capped_free_fn, NULL};
    brdffit_fit *fit = NULL;
    brdffit_status st;
    a.ctx = ca;
    ca->largest = 0;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, &a, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pipeline), BRDFFIT_OK);
    st = brdffit_fit_run(fit);
    snprintf(message, size, "%s", brdffit_fit_message(fit));
    brdffit_fit_destroy(fit);
    return (int)st;
}

/* The joint and auto pipelines fit every channel's parameters at once and
 * refuse more than BRDFFIT_FIT_MAX_PARAMS of them with BRDFFIT_E_TOO_LARGE,
 * naming the limit, before allocating anything of that size (2048 and
 * 300000 channels of Ashikhmin-Shirley: 4097 and 600001 parameters); the
 * two-stage pipeline fits each channel alone and fits them all. */
static void test_channel_limit(void **state)
{
    static const double two[] = {0, 30}, po[] = {0, 90};
    brdffit_model *model = make_model("ashikhmin-shirley");
    const size_t counts[] = {2048, 300000};
    capped_alloc ca;
    fx_axes a;
    size_t i;
    (void)state;
    fx_axes_set(&a, two, 2, two, 2, po, 2);
    for (i = 0; i < 2; i++) {
        brdffit_grid *grid = constant_grid(&a.axes, counts[i], 0.1);
        char message[512];
        int p;
        for (p = 0; p < 2; p++) {
            int st = capped_run(grid, model, PIPELINES[p], &ca, message, sizeof message);
            if (st != BRDFFIT_E_TOO_LARGE) print_error("%zu channels: %s\n", counts[i], message);
            assert_int_equal(st, BRDFFIT_E_TOO_LARGE);
            assert_non_null(strstr(message, "4096"));
            assert_non_null(strstr(message, "two-stage"));
            assert_true(ca.largest <= ((size_t)64 << 20)); /* none refused */
        }
        if (i == 0) {
            int st = capped_run(grid, model, BRDFFIT_PIPELINE_TWO_STAGE, &ca, message,
                                sizeof message);
            if (st != BRDFFIT_OK) print_error("two-stage: %s\n", message);
            assert_int_equal(st, BRDFFIT_OK);
        }
        brdffit_grid_destroy(grid);
    }
    brdffit_model_destroy(model);
}

/* Two-stage with more parameters than one stage takes (2048 channels of
 * Ashikhmin-Shirley): the error figures come channel by channel, each e
 * from that channel's own values, which differ from channel to channel
 * (against the test's own sums over the 8 samples, all inside the cap). */
static void test_channel_by_channel_figures(void **state)
{
    static const double two[] = {0, 30}, po[] = {0, 90};
    const size_t nc = 2048;
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = NULL;
    brdffit_fit *fit = NULL;
    double *values, *p, *vals, got;
    size_t n, nv, s, c;
    fx_axes a;
    (void)state;
    fx_axes_set(&a, two, 2, two, 2, po, 2);
    n = axes_samples(&a.axes);
    nv = brdffit_model_vector_size(model, nc);
    values = malloc(n * nc * sizeof *values);
    p = malloc(nv * sizeof *p);
    vals = malloc(n * nc * sizeof *vals);
    assert_non_null(values);
    assert_non_null(p);
    assert_non_null(vals);
    for (s = 0; s < n; s++)
        for (c = 0; c < nc; c++)
            values[s * nc + c] = (0.05 + 0.01 * (double)(c % 13)) * (1.0 + 0.3 * (double)s);
    assert_int_equal(brdffit_grid_create_regular(&grid, &a.axes, nc, values, NULL, NULL, NULL),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_TWO_STAGE),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_grid(model, grid, 0, n, p, vals, NULL, NULL), BRDFFIT_OK);
    for (c = 0; c < nc; c += 97) {
        const double *r;
        double e2 = 0.0;
        assert_int_equal(brdffit_grid_values(grid, c, &r), BRDFFIT_OK);
        for (s = 0; s < n; s++) e2 += (vals[c * n + s] - r[s]) * (vals[c * n + s] - r[s]);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, c, &got), BRDFFIT_OK);
        assert_true(e2 > 0.0);
        assert_true(fabs(got - sqrt(e2)) <= 1e-9 * sqrt(e2));
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    free(values);
    free(p);
    free(vals);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_zeros),
        cmocka_unit_test(test_one_nonzero_sample),
        cmocka_unit_test(test_scale_invariance),
        cmocka_unit_test(test_tiny_values),
        cmocka_unit_test(test_denormal_values),
        cmocka_unit_test(test_huge_values),
        cmocka_unit_test(test_all_samples_beyond_cap),
        cmocka_unit_test(test_cap_zero),
        cmocka_unit_test(test_in_plane_and_single_theta_o),
        cmocka_unit_test(test_cap_90),
        cmocka_unit_test(test_parameter_extremes),
        cmocka_unit_test(test_cancel_at_range_end),
        cmocka_unit_test(test_one_channel),
        cmocka_unit_test(test_64_channels),
        cmocka_unit_test(test_channel_limit),
        cmocka_unit_test(test_channel_by_channel_figures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
