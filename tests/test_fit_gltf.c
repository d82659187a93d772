/* The glTF models recover their own parameters: exact data made with them
 * at several materials (dielectric and metal, rough and glossy, a blend,
 * and coated ones) fitted by the auto pipeline without start values and by
 * the joint pipeline from the model's defaults; and all with 1 % noise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

/* Exact data: every parameter within 1e-6 of the truth (worst_error(): as
 * for the other built-in models in test_fit.c, metallic and clearcoat
 * absolute). */
#define RECOVERY_TOLERANCE 1e-6
/* 1 % multiplicative noise: every parameter within 2 % (metallic within
 * 0.02). */
#define NOISY_TOLERANCE 2e-2
#define NC 3
#define NV (4 + NC) /* largest vector: gltf-clearcoat's */

typedef struct material {
    const char *model, *what;
    double v[5][8]; /* per declared parameter: value, or one per channel */
} material;

/* gltf: roughness, metallic, baseColor; gltf-clearcoat: roughness,
 * metallic, clearcoat, clearcoatRoughness, baseColor. */
static const material MATERIALS[] = {
    {"gltf", "glossy dielectric (red plastic)", {{0.3}, {0.0}, {0.6, 0.2, 0.1}}},
    {"gltf", "rough dielectric", {{0.8}, {0.0}, {0.3, 0.5, 0.7}}},
    {"gltf", "very glossy dielectric", {{0.08}, {0.0}, {0.05, 0.05, 0.05}}},
    {"gltf", "glossy metal (gold)", {{0.2}, {1.0}, {0.95, 0.766, 0.336}}},
    {"gltf", "rough metal", {{0.6}, {1.0}, {0.9, 0.9, 0.9}}},
    {"gltf", "half metal", {{0.45}, {0.5}, {0.5, 0.4, 0.3}}},
    {"gltf-clearcoat", "car paint", {{0.6}, {0.5}, {1.0}, {0.2}, {0.6, 0.1, 0.08}}},
    {"gltf-clearcoat", "coated rough plastic", {{0.8}, {0.0}, {0.8}, {0.1}, {0.2, 0.4, 0.6}}},
    {"gltf-clearcoat", "half-coated metal", {{0.4}, {1.0}, {0.5}, {0.15}, {0.9, 0.7, 0.3}}},
};

/* Relative errors of the roughnesses and the colours (absolute below
 * 1e-3) and absolute errors of metallic and clearcoat (fractions in
 * [0, 1]). */
static double worst_error(const brdffit_model *model, const double *a, const double *b)
{
    double worst = 0.0;
    size_t k, c;
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *p = brdffit_model_param(model, k);
        const int fraction = strcmp(p->name, "metallic") == 0 || strcmp(p->name, "clearcoat") == 0;
        for (c = 0; c < ((p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? NC : 1); c++) {
            const size_t i = brdffit_model_vector_index(model, k, c, NC);
            worst = fmax(worst, fabs(a[i] - b[i]) / (fraction ? 1.0 : fmax(fabs(b[i]), 1e-3)));
        }
    }
    return worst;
}

static void print_vector(const char *label, const double *x, size_t n)
{
    char line[256];
    size_t i, len = 0;
    for (i = 0; i < n && len < sizeof line - 24; i++)
        len += (size_t)snprintf(line + len, sizeof line - len, " %.9g", x[i]);
    print_message("    %s%s\n", label, line);
}

/* Fit exact data made from `mat` with `pipeline` (defaults otherwise);
 * returns the worst error of the parameters (worst_error()). */
static double recover(const material *mat, int pipeline)
{
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    brdffit_grid *grid;
    double truth[NV], got[NV], worst;
    size_t n;
    assert_int_equal(brdffit_model_create(&model, mat->model, NULL, NULL), BRDFFIT_OK);
    n = brdffit_model_vector_size(model, NC);
    assert_true(n <= NV);
    fx_vector(model, NC, mat->v, truth);
    grid = fx_grid_from_model(model, truth, NC, NULL, 0.0, 1);
    assert_non_null(grid);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, pipeline), BRDFFIT_OK);
    /* the joint pipeline is a local method from the model's defaults: the
     * thesis's, with its cost, the squares; under the default cube-root it
     * ends the very glossy dielectric (roughness 0.08) in the broad lobe's
     * local minimum (roughness 0.90), which auto's scan avoids */
    if (pipeline == BRDFFIT_PIPELINE_JOINT)
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                         BRDFFIT_OK);
    if (brdffit_fit_run(fit) != BRDFFIT_OK) fail_msg("%s: %s", mat->what, brdffit_fit_message(fit));
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    worst = worst_error(model, got, truth);
    print_message("%-14s %-32s %-5s worst error %.2e\n", mat->model, mat->what,
                  pipeline == BRDFFIT_PIPELINE_AUTO ? "auto" : "joint", worst);
    print_vector("fitted", got, n);
    if (!(worst < RECOVERY_TOLERANCE)) print_vector("truth ", truth, n);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    return worst;
}

static void check_all(int pipeline)
{
    /* BRDFFIT_TEST_QUICK (the valgrind runs): the first 2 materials only */
    size_t i, n = getenv("BRDFFIT_TEST_QUICK") ? 2 : sizeof MATERIALS / sizeof MATERIALS[0];
    for (i = 0; i < n; i++) assert_true(recover(&MATERIALS[i], pipeline) < RECOVERY_TOLERANCE);
}

/* The auto pipeline, no start values: scan of the shared parameters
 * (roughness and metallic, and the coat's two), LM polish of everything. */
static void test_gltf_auto_recovers_itself(void **state)
{
    (void)state;
    check_all(BRDFFIT_PIPELINE_AUTO);
}

/* The joint pipeline from the model's default start. */
static void test_gltf_joint_recovers_itself(void **state)
{
    (void)state;
    check_all(BRDFFIT_PIPELINE_JOINT);
}

/* Cost of a joint fit of `grid` started at `start`. */
static double cost_from(const brdffit_model *model, const brdffit_grid *grid, const double *start)
{
    brdffit_fit *fit = NULL;
    double cost;
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                     BRDFFIT_OK);
    brdffit_fit_destroy(fit);
    return cost;
}

/* With 1 % noise the auto pipeline (no starts), under the squares (every
 * objective's optimum is test_fit_brute_force's), reaches a cost no higher
 * than LM started at the truth, for every material; the parameters stay
 * within NOISY_TOLERANCE for every material but the very glossy dark
 * dielectric, where noise leaves metallic undetermined: metallic 0.157
 * with baseColor 0.037 keeps F0 = 0.04 (1 - m) + m b at 0.040 and fits
 * those data better (cost 8.9e-5) than the truth's neighbourhood does
 * (1.8e-4). */
static void test_gltf_auto_with_noise(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < sizeof MATERIALS / sizeof MATERIALS[0]; i++) {
        const material *mat = &MATERIALS[i];
        double truth[NV], got[NV], cost, best, worst;
        brdffit_model *model = NULL;
        brdffit_fit *fit = NULL;
        brdffit_grid *grid;
        assert_int_equal(brdffit_model_create(&model, mat->model, NULL, NULL), BRDFFIT_OK);
        fx_vector(model, NC, mat->v, truth);
        grid = fx_grid_from_model(model, truth, NC, NULL, 0.01, 7);
        assert_non_null(grid);
        assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, BRDFFIT_OBJECTIVE_SQUARES),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                         BRDFFIT_OK);
        best = cost_from(model, grid, truth);
        worst = worst_error(model, got, truth);
        print_message("%-14s %-32s auto noise 0.01: worst error %.2e, cost %.4g (LM from the "
                      "truth %.4g)\n",
                      mat->model, mat->what, worst, cost, best);
        print_vector("fitted", got, brdffit_model_vector_size(model, NC));
        assert_true(cost <= best * (1.0 + 1e-6));
        if (strcmp(mat->what, "very glossy dielectric") != 0) assert_true(worst < NOISY_TOLERANCE);
        brdffit_fit_destroy(fit);
        brdffit_grid_destroy(grid);
        brdffit_model_destroy(model);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_auto_recovers_itself),
        cmocka_unit_test(test_gltf_joint_recovers_itself),
        cmocka_unit_test(test_gltf_auto_with_noise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
