/* The verdict on a fit (brdffit_fit_warnings()): each warning raised by a
 * fit made to show it, none on a sound fit, the sentences and the names. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define PI 3.14159265358979323846
#define MAXV 64

#define CD {0.30, 0.20, 0.10}
#define CS {0.40, 0.35, 0.30}

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

/* The user models of these tests: value = c f(k, n.v) per channel, one
 * shape parameter k and one colour c, with f and its derivative in k given
 * through the model's user pointer. */
typedef struct shape_fn {
    double (*f)(double k, double x);
    double (*dk)(double k, double x);
} shape_fn;

static brdffit_status shape_eval(const brdffit_batch *b, const double *p, size_t nc,
                                 double *values, double *jac, void *user)
{
    const shape_fn *fn = user;
    size_t s, c, n = b->n;
    for (s = 0; s < n; s++)
        for (c = 0; c < nc; c++) {
            double f = fn->f(p[0], b->nv[s]);
            values[c * n + s] = p[1 + c] * f;
            if (jac != NULL) {
                jac[c * n + s] = p[1 + c] * fn->dk(p[0], b->nv[s]);
                jac[(nc + c) * n + s] = f;
            }
        }
    return BRDFFIT_OK;
}

/* x^k: data made with k = 5 push a k bounded to [0.5, 2] onto 2. */
static double power_f(double k, double x) { return pow(x, k); }
static double power_dk(double k, double x) { return pow(x, k) * log(x); }
static const shape_fn POWER = {power_f, power_dk};

/* (1 - F0) x: every point with c (1 - F0) = 2 is optimal. */
static double valley_f(double k, double x) { return (1.0 - k) * x; }
static double valley_dk(double k, double x) { (void)k; return -x; }
static const shape_fn VALLEY = {valley_f, valley_dk};

/* x, whatever k: the data cannot tell k, the run stalls. */
static double idle_f(double k, double x) { (void)k; return x; }
static double idle_dk(double k, double x) { (void)k; (void)x; return 0.0; }
static const shape_fn IDLE = {idle_f, idle_dk};

/* A user model of shape `fn` with parameters k and a per-channel colour. */
static brdffit_model *custom(const char *name, const brdffit_param_info *params,
                             const shape_fn *fn)
{
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *model = NULL;
    def.name = name;
    def.n_params = 2;
    def.params = params;
    def.eval = shape_eval;
    def.user = (void *)fn;
    assert_int_equal(brdffit_model_create_custom(&model, &def, NULL, NULL), BRDFFIT_OK);
    return model;
}

static brdffit_grid *grid_of(const brdffit_model *model, const double values[][8],
                             const brdffit_axes *axes)
{
    double p[MAXV];
    brdffit_grid *grid;
    fx_vector(model, 3, values, p);
    grid = fx_grid_from_model(model, p, 3, axes, 0.0, 1);
    assert_non_null(grid);
    return grid;
}

/* Fit `model` to `grid` with `pipeline` and return its warnings. */
static unsigned warnings_of(brdffit_fit **out, const brdffit_grid *grid,
                            const brdffit_model *model, brdffit_pipeline pipeline)
{
    brdffit_fit *fit = NULL;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pipeline), BRDFFIT_OK);
    /* the verdict on the cost's own optimum: plausibility would hide an albedo above 1 */
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    *out = fit;
    return brdffit_fit_warnings(fit);
}

/* The sentence of `warning` must name `word`. */
static void assert_text(const brdffit_fit *fit, unsigned warning, const char *word)
{
    char text[256];
    assert_int_equal(brdffit_fit_warning_text(fit, warning, text, sizeof text), BRDFFIT_OK);
    if (strstr(text, word) == NULL) print_error("'%s' lacks '%s'\n", text, word);
    assert_non_null(strstr(text, word));
}

static void test_sound_fit_has_no_warning(void **state)
{
    const double v[3][8] = {{120.0}, CD, CS};
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit;
    char text[64];
    (void)state;
    assert_int_equal(warnings_of(&fit, grid, model, BRDFFIT_PIPELINE_AUTO), 0u);
    assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_AT_BOUND, text, sizeof text),
                     BRDFFIT_E_NOT_FOUND);
    assert_string_equal(text, "");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* An ashikhmin-shirley auto fit to its own data with values v must give
 * exactly the warnings `want`, the text of `bit` naming `word`. */
static void expect_own_fit(const double v[][8], unsigned want, unsigned bit, const char *word)
{
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit;
    assert_int_equal(warnings_of(&fit, grid, model, BRDFFIT_PIPELINE_AUTO), want);
    assert_text(fit, bit, word);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_no_diffuse(void **state)
{
    const double v[3][8] = {{120.0}, {0.0, 0.0, 0.0}, CS};
    (void)state;
    expect_own_fit(v, BRDFFIT_WARN_NO_DIFFUSE, BRDFFIT_WARN_NO_DIFFUSE, "cd");
}

static void test_albedo_above_one(void **state)
{
    const double v[3][8] = {{120.0}, {0.3, 1.6, 0.2}, CS};
    (void)state;
    expect_own_fit(v, BRDFFIT_WARN_ALBEDO, BRDFFIT_WARN_ALBEDO, "channel 1");
}

static brdffit_model *power_model(double lower, double upper)
{
    brdffit_param_info params[] = {
        {"k", 0, lower, upper, 1.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    return custom("power", params, &POWER);
}

static void test_shape_at_bound(void **state)
{
    const double v[2][8] = {{5.0}, CD};
    brdffit_model *wide = power_model(0.1, 10.0), *narrow = power_model(0.5, 2.0);
    brdffit_grid *grid = grid_of(wide, v, NULL);
    brdffit_fit *fit;
    brdffit_pipeline pipelines[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT};
    size_t i;
    (void)state;
    assert_int_equal(warnings_of(&fit, grid, wide, BRDFFIT_PIPELINE_AUTO), 0u);
    brdffit_fit_destroy(fit);
    for (i = 0; i < 2; i++) {
        assert_int_equal(warnings_of(&fit, grid, narrow, pipelines[i]), BRDFFIT_WARN_AT_BOUND);
        assert_text(fit, BRDFFIT_WARN_AT_BOUND, "k = 2 ");
        brdffit_fit_destroy(fit);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(wide);
    brdffit_model_destroy(narrow);
}

/* A held parameter on its bound is the caller's choice, not a warning. */
static void test_held_parameter_on_bound_is_no_warning(void **state)
{
    const double v[2][8] = {{2.0}, CD};
    brdffit_model *model = power_model(0.5, 2.0);
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit = NULL;
    double start[4] = {2.0, 0.1, 0.1, 0.1};
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_fixed(fit, 0, 1), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_warnings(fit), 0u);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_iteration_limit(void **state)
{
    const double v[3][8] = {{120.0}, CD, CS};
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit = NULL;
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, 1), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_MAX_ITERATIONS);
    assert_true(brdffit_fit_warnings(fit) & BRDFFIT_WARN_ITERATION_LIMIT);
    assert_text(fit, BRDFFIT_WARN_ITERATION_LIMIT, "iteration limit");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static int stop_at_once(const brdffit_iteration *info, void *user)
{
    (void)info;
    (void)user;
    return 1;
}

static void test_stopped_early(void **state)
{
    const double v[3][8] = {{120.0}, CD, CS};
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit = NULL;
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_callback(fit, stop_at_once, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_true(brdffit_fit_warnings(fit) & BRDFFIT_WARN_STOPPED_EARLY);
    assert_text(fit, BRDFFIT_WARN_STOPPED_EARLY, "callback");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* One lobe's data fitted with two lobes: the second lobe has nothing to do. */
static void test_lobes_merged(void **state)
{
    const double one[3][8] = {{120.0}, CD, CS};
    const double two[5][8] = {{20.0}, {800.0}, CD, CS, {0.15, 0.25, 0.35}};
    brdffit_model *single = make_model("ashikhmin-shirley");
    brdffit_model *dual = make_model("ashikhmin-shirley-2");
    brdffit_grid *grid = grid_of(single, one, NULL), *grid2 = grid_of(dual, two, NULL);
    brdffit_fit *fit;
    (void)state;
    assert_true(warnings_of(&fit, grid, dual, BRDFFIT_PIPELINE_AUTO) &
                BRDFFIT_WARN_LOBES_MERGED);
    brdffit_fit_destroy(fit);
    assert_int_equal(warnings_of(&fit, grid2, dual, BRDFFIT_PIPELINE_AUTO), 0u);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_grid_destroy(grid2);
    brdffit_model_destroy(single);
    brdffit_model_destroy(dual);
}

static void test_fresnel_valley(void **state)
{
    const brdffit_param_info params[] = {
        {"F0", 0, 0.0, 1.0, 0.995},
        {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 400.0},
    };
    const double v[2][8] = {{0.995}, {400.0, 400.0, 400.0}};
    brdffit_model *model = custom("valley", params, &VALLEY);
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    grid = grid_of(model, v, NULL);
    assert_true(warnings_of(&fit, grid, model, BRDFFIT_PIPELINE_JOINT) &
                BRDFFIT_WARN_FRESNEL_VALLEY);
    assert_text(fit, BRDFFIT_WARN_FRESNEL_VALLEY, "F0 = 0.995");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_stalled(void **state)
{
    const brdffit_param_info params[] = {
        {"k", 0, 0.0, 10.0, 1.0},
        {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.1},
    };
    const double v[2][8] = {{1.0}, CD};
    brdffit_model *model = custom("idle", params, &IDLE);
    brdffit_grid *grid;
    brdffit_fit *fit;
    (void)state;
    grid = grid_of(model, v, NULL);
    assert_true(warnings_of(&fit, grid, model, BRDFFIT_PIPELINE_JOINT) & BRDFFIT_WARN_STALLED);
    assert_int_equal(brdffit_fit_stop_reason(fit), BRDFFIT_STOP_STALLED);
    assert_text(fit, BRDFFIT_WARN_STALLED, "stalled");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* The default axes in degrees, read as if they were radians' worth of
 * degrees: 0 .. 90 becomes 0 .. 1.5708 degrees. */
static void test_radians_given_as_degrees(void **state)
{
    const brdffit_axes *d = brdffit_axes_default();
    double ti[64], to[64], po[64];
    brdffit_axes axes;
    const double v[3][8] = {{120.0}, CD, CS};
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid;
    brdffit_fit *fit;
    size_t i;
    (void)state;
    for (i = 0; i < d->n_theta_i; i++) ti[i] = d->theta_i[i] * PI / 180.0;
    for (i = 0; i < d->n_theta_o; i++) to[i] = d->theta_o[i] * PI / 180.0;
    for (i = 0; i < d->n_phi_o; i++) po[i] = d->phi_o[i] * PI / 180.0;
    axes = *d;
    axes.theta_i = ti;
    axes.theta_o = to;
    axes.phi_o = po;
    grid = grid_of(model, v, &axes);
    assert_true(warnings_of(&fit, grid, model, BRDFFIT_PIPELINE_AUTO) &
                BRDFFIT_WARN_DEGREES_AS_RADIANS);
    assert_text(fit, BRDFFIT_WARN_DEGREES_AS_RADIANS, "1.571 degrees");
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_bad_calls(void **state)
{
    const double v[3][8] = {{120.0}, CD, CS};
    brdffit_model *model = make_model("ashikhmin-shirley");
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit = NULL;
    char text[32] = "x";
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_warnings(fit), 0u);
    assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_ALBEDO, text, sizeof text),
                     BRDFFIT_E_NOT_READY);
    assert_string_equal(text, "");
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_warning_text(fit, 0, text, sizeof text),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_ALBEDO | BRDFFIT_WARN_AT_BOUND,
                                              text, sizeof text),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warning_text(fit, 1024, text, sizeof text),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_ALBEDO, NULL, 8),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_ALBEDO, text, 0),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warning_text(NULL, BRDFFIT_WARN_ALBEDO, text, sizeof text),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_fit_warnings(NULL), 0u);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* The no-better-than-mean text of a held, far too dark fit on one thread
 * and on three: equal. */
static int same_baseline(const brdffit_grid *grid, const brdffit_model *model,
                         const double *start, brdffit_objective objective)
{
    char text[2][512];
    size_t k;
    for (k = 0; k < 2; k++) {
        brdffit_fit *fit = NULL;
        assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, k == 0 ? 1 : 3), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, objective), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_fixed(fit, 0, 1), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_warning_text(fit, BRDFFIT_WARN_NO_BETTER_THAN_MEAN,
                                                  text[k], sizeof text[k]),
                         BRDFFIT_OK);
        brdffit_fit_destroy(fit);
    }
    return strcmp(text[0], text[1]) == 0;
}

/* A Lambertian fit whose colour is held far below the data explains less
 * than each channel's mean: the warning, with its text; the data's own
 * model has none. */
static void test_no_better_than_mean(void **state)
{
    static const double v[4][8] = {{60.0}, CD, CS};
    brdffit_model *as = make_model("ashikhmin-shirley"), *model = make_model("lambert");
    brdffit_grid *grid = grid_of(as, v, NULL);
    brdffit_fit *fit = NULL;
    double start[3] = {1e-4, 1e-4, 1e-4};
    char text[256];
    (void)state;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_fixed(fit, 0, 1), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_true(brdffit_fit_warnings(fit) & BRDFFIT_WARN_NO_BETTER_THAN_MEAN);
    assert_int_equal(
        brdffit_fit_warning_text(fit, BRDFFIT_WARN_NO_BETTER_THAN_MEAN, text, sizeof text),
        BRDFFIT_OK);
    assert_non_null(strstr(text, "best constant"));
    brdffit_fit_destroy(fit);
    /* the baseline is the same sum on one thread and on three (the text
     * gives the fit's and the baseline's figures), for the squares cost
     * and for the error measures the other objectives are judged by */
    assert_true(same_baseline(grid, model, start, BRDFFIT_OBJECTIVE_SQUARES));
    assert_true(same_baseline(grid, model, start, BRDFFIT_OBJECTIVE_CUBE_ROOT));
    /* the data's own model explains them */
    assert_int_equal(brdffit_fit_create(&fit, grid, as, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_warnings(fit) & BRDFFIT_WARN_NO_BETTER_THAN_MEAN, 0);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    brdffit_model_destroy(as);
}

/* Two-lobe results come sharper lobe first, whichever order the data's
 * parameters or the start values have: ggx-2 data with the broad lobe
 * first give a1 < a2 with each lobe's colour (cook-torrance-2 m1 < m2);
 * ashikhmin-shirley-2 gives ns1 > ns2. */
static void check_order(const char *name, const double v[][8], size_t pipeline, int larger)
{
    brdffit_model *model = make_model(name);
    brdffit_grid *grid = grid_of(model, v, NULL);
    brdffit_fit *fit = NULL;
    size_t n = brdffit_model_param_count(model), cs1 = n - 2, c;
    double p[MAXV];
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)pipeline), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), BRDFFIT_OK);
    if (pipeline == BRDFFIT_PIPELINE_JOINT) { /* start at the data's own order */
        fx_vector(model, 3, v, p);
        assert_int_equal(brdffit_fit_set_start(fit, p), BRDFFIT_OK);
    }
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_params(fit, p), BRDFFIT_OK);
    printf("%s pipeline %zu: x1 %g x2 %g\n", name, pipeline, p[0], p[1]);
    assert_close(p[0] / v[1][0], 1.0, 1e-4); /* lobe 2 of the data is the sharper */
    assert_close(p[1] / v[0][0], 1.0, 1e-4);
    assert_true(larger ? p[0] > p[1] : p[0] < p[1]);
    for (c = 0; c < 3; c++) {
        assert_close(p[brdffit_model_vector_index(model, cs1, c, 3)] / v[cs1 + 1][c], 1.0, 1e-4);
        assert_close(p[brdffit_model_vector_index(model, cs1 + 1, c, 3)] / v[cs1][c], 1.0, 1e-4);
    }
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

static void test_lobe_order(void **state)
{
    static const double ggx[6][8] = {{0.4}, {0.08}, {0.04}, CD, {0.5, 0.4, 0.3}, {2.0, 1.5, 1.0}};
    static const double as[5][8] = {{20.0}, {400.0}, CD, {0.3, 0.2, 0.1}, {0.5, 0.4, 0.3}};
    (void)state;
    check_order("ggx-2", ggx, BRDFFIT_PIPELINE_AUTO, 0);
    check_order("ggx-2", ggx, BRDFFIT_PIPELINE_JOINT, 0);
    check_order("ashikhmin-shirley-2", as, BRDFFIT_PIPELINE_AUTO, 1);
    check_order("ashikhmin-shirley-2", as, BRDFFIT_PIPELINE_JOINT, 1);
    check_order("cook-torrance-2", ggx, BRDFFIT_PIPELINE_AUTO, 0); /* same layout as ggx-2 */
}

static void test_names(void **state)
{
    unsigned w;
    size_t i = 0;
    const char *seen[10];
    (void)state;
    for (w = 1; w <= BRDFFIT_WARN_NO_BETTER_THAN_MEAN; w <<= 1) {
        size_t j;
        const char *name = brdffit_warning_name(w);
        assert_non_null(name);
        for (j = 0; j < i; j++) assert_string_not_equal(seen[j], name);
        seen[i++] = name;
    }
    assert_int_equal(i, 10);
    assert_null(brdffit_warning_name(0));
    assert_null(brdffit_warning_name(3));
    assert_null(brdffit_warning_name(1024));
    assert_string_equal(brdffit_warning_name(BRDFFIT_WARN_NO_BETTER_THAN_MEAN),
                        "no-better-than-mean");
    assert_string_equal(brdffit_warning_name(BRDFFIT_WARN_ALBEDO), "albedo-above-1");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sound_fit_has_no_warning),
        cmocka_unit_test(test_no_diffuse),
        cmocka_unit_test(test_albedo_above_one),
        cmocka_unit_test(test_shape_at_bound),
        cmocka_unit_test(test_held_parameter_on_bound_is_no_warning),
        cmocka_unit_test(test_iteration_limit),
        cmocka_unit_test(test_stopped_early),
        cmocka_unit_test(test_lobes_merged),
        cmocka_unit_test(test_fresnel_valley),
        cmocka_unit_test(test_radians_given_as_degrees),
        cmocka_unit_test(test_stalled),
        cmocka_unit_test(test_bad_calls),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_no_better_than_mean),
        cmocka_unit_test(test_lobe_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
