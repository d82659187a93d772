/* The OpenPBR models recover their own parameters: exact data made with
 * them at several materials (dielectrics of different IOR, a metal, a
 * blend, coated ones) fitted by the auto pipeline without start values;
 * and with 1 % noise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

/* Exact data: every parameter within 1e-6 (worst_error()). */
#define RECOVERY_TOLERANCE 1e-6
/* 1 % multiplicative noise: every parameter within 2 % (fractions within
 * 0.02, colours within 2 % or 0.01: the dark channels of a mostly
 * metallic base are barely seen). */
#define NOISY_TOLERANCE 2e-2
#define NC 3
#define NV (5 + NC) /* largest vector: openpbr-coat's */

typedef struct material {
    const char *model, *what;
    double v[6][8]; /* per declared parameter: value, or one per channel */
} material;

/* openpbr: specular_roughness, base_metalness, specular_ior, base_color;
 * openpbr-coat: the same three, coat_weight, coat_roughness, base_color
 * (specular_ior held at its default 1.5). */
static const material MATERIALS[] = {
    {"openpbr", "glossy plastic (ior 1.5)", {{0.3}, {0.0}, {1.5}, {0.6, 0.2, 0.1}}},
    {"openpbr", "rough dense dielectric (ior 2.2)", {{0.7}, {0.0}, {2.2}, {0.3, 0.5, 0.7}}},
    {"openpbr", "glossy low-ior dielectric (1.33)", {{0.12}, {0.0}, {1.33}, {0.05, 0.1, 0.2}}},
    {"openpbr", "half metal", {{0.45}, {0.5}, {1.8}, {0.5, 0.4, 0.3}}},
    {"openpbr", "glossy metal (gold)", {{0.2}, {1.0}, {1.5}, {0.95, 0.766, 0.336}}},
    {"openpbr-coat", "car paint (coat 0.9)", {{0.5}, {0.5}, {1.5}, {0.9}, {0.1}, {0.6, 0.1, 0.08}}},
    {"openpbr-coat", "coated rough plastic", {{0.8}, {0.0}, {1.5}, {0.8}, {0.1}, {0.2, 0.4, 0.6}}},
    {"openpbr-coat", "half-coated metal", {{0.4}, {1.0}, {1.5}, {0.5}, {0.15}, {0.9, 0.7, 0.3}}},
};

/* Relative errors of roughnesses, IOR and colours (absolute below 1e-3,
 * or below `colour_floor` for the colours),
 * absolute errors of the fractions base_metalness and coat_weight. A pure
 * metal (base_metalness 1) has no dielectric part, so its specular_ior
 * has no effect and is not compared. */
static double worst_error(const brdffit_model *model, const double *a, const double *b,
                          double colour_floor)
{
    size_t k, c, im;
    double worst = 0.0;
    assert_int_equal(brdffit_model_param_find(model, "base_metalness", &im), BRDFFIT_OK);
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *p = brdffit_model_param(model, k);
        const int fraction = k == im || strcmp(p->name, "coat_weight") == 0;
        const double floor = (p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? colour_floor : 1e-3;
        if (strcmp(p->name, "specular_ior") == 0 && b[im] == 1.0) continue;
        for (c = 0; c < ((p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? NC : 1); c++) {
            const size_t i = brdffit_model_vector_index(model, k, c, NC);
            worst = fmax(worst, fabs(a[i] - b[i]) / (fraction ? 1.0 : fmax(fabs(b[i]), floor)));
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

/* Fit data made from `mat` (with multiplicative `noise`) by `pipeline`
 * (auto: no start values; joint: from the model's defaults) under
 * `objective`;
 * returns the worst error of the parameters and the cost in *cost. */
static double recover(const material *mat, double noise, int pipeline, int objective,
                      double *cost)
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
    grid = fx_grid_from_model(model, truth, NC, NULL, noise, 7);
    assert_non_null(grid);
    assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, objective), BRDFFIT_OK);
    if (brdffit_fit_run(fit) != BRDFFIT_OK) fail_msg("%s: %s", mat->what, brdffit_fit_message(fit));
    assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
    assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, cost),
                     BRDFFIT_OK);
    worst = worst_error(model, got, truth, noise > 0.0 ? 0.5 : 1e-3);
    print_message("%-13s %-34s %-5s noise %.2f: worst error %.2e, cost %.3g\n", mat->model,
                  mat->what, pipeline == BRDFFIT_PIPELINE_AUTO ? "auto" : "joint", noise, worst,
                  *cost);
    print_vector("fitted", got, n);
    if (!(worst < (noise > 0.0 ? NOISY_TOLERANCE : RECOVERY_TOLERANCE)))
        print_vector("truth ", truth, n);
    brdffit_fit_destroy(fit);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
    return worst;
}

static size_t material_count(void)
{
    /* BRDFFIT_TEST_QUICK (the valgrind runs): the first 2 materials only */
    return getenv("BRDFFIT_TEST_QUICK") ? 2 : sizeof MATERIALS / sizeof MATERIALS[0];
}

/* The auto pipeline, no start values, exact data: every material under
 * the squares objective, the first also under cube-root (whose profile
 * takes Gauss-Newton colour steps at every scan point: about 20 s for one
 * of these materials on a loaded machine, so the valgrind runs leave it
 * out). */
static void test_openpbr_auto_recovers_itself(void **state)
{
    size_t i;
    double cost;
    (void)state;
    for (i = 0; i < material_count(); i++) {
        assert_true(recover(&MATERIALS[i], 0.0, BRDFFIT_PIPELINE_AUTO, BRDFFIT_OBJECTIVE_SQUARES,
                            &cost) < RECOVERY_TOLERANCE);
        assert_true(cost < 1e-20);
    }
    if (getenv("BRDFFIT_TEST_QUICK")) return;
    assert_true(recover(&MATERIALS[0], 0.0, BRDFFIT_PIPELINE_AUTO,
                        BRDFFIT_OBJECTIVE_CUBE_ROOT, &cost) < RECOVERY_TOLERANCE);
    assert_true(cost < 1e-20);
}

/* With 1 % noise every parameter stays within NOISY_TOLERANCE. */
static void test_openpbr_auto_with_noise(void **state)
{
    size_t i;
    double cost;
    (void)state;
    for (i = 0; i < material_count(); i++)
        assert_true(recover(&MATERIALS[i], 0.01, BRDFFIT_PIPELINE_AUTO, BRDFFIT_OBJECTIVE_SQUARES,
                            &cost) < NOISY_TOLERANCE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_openpbr_auto_recovers_itself),
        cmocka_unit_test(test_openpbr_auto_with_noise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
