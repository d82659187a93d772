/* Parameters held fixed (brdffit_fit_set_fixed()): every pipeline (auto,
 * joint, two-stage) holds every kind of parameter (a shape exponent, a
 * per-channel colour, a Fresnel term) at exactly its start value, reports
 * the standard error documented for held parameters (0), and recovers the
 * free parameters from noisy data generated with known parameters. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define MAXV 32
#define NC 3

static const brdffit_pipeline PIPELINES[] = {BRDFFIT_PIPELINE_AUTO, BRDFFIT_PIPELINE_JOINT,
                                             BRDFFIT_PIPELINE_TWO_STAGE};
static const char *const PIPELINE_NAMES[] = {"auto", "joint", "two-stage"};

/* Truths: Ashikhmin-Shirley with a free Fresnel term (ns shape, Rs
 * Fresnel, cd and cs colours), and GGX with its Fresnel term F0 at a value
 * other than the default (held by default). */
static const double ASF[4][8] = {{120.0}, {0.3}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}};
static const double AS[3][8] = {{120.0}, {0.30, 0.20, 0.10}, {0.40, 0.35, 0.30}};
static const double GGX[4][8] = {{0.2}, {0.1}, {0.30, 0.20, 0.10}, {0.50, 0.45, 0.40}};

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

static size_t param_index(const brdffit_model *model, const char *name)
{
    size_t k = 0;
    assert_int_equal(brdffit_model_param_find(model, name, &k), BRDFFIT_OK);
    return k;
}

static int is_held(const brdffit_model *model, size_t k, const char *const *held)
{
    size_t i;
    for (i = 0; held[i] != NULL; i++)
        if (k == param_index(model, held[i])) return 1;
    return 0;
}

/* Start values: the truth for held parameters, the truth moved by a third
 * (colours halved) for the free ones, inside the bounds. */
static void make_start(const brdffit_model *model, const double *truth, const char *const *held,
                       double *start)
{
    size_t k, c;
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < NC; c++) {
            size_t e = brdffit_model_vector_index(model, k, c, NC);
            double v = truth[e];
            if (!is_held(model, k, held))
                v = (info->flags & BRDFFIT_PARAM_LINEAR) ? 0.5 * v : fmin(1.3 * v, info->upper);
            start[e] = v;
        }
    }
}

/* Fit data made from `truth` with 1 % multiplicative noise, holding the
 * parameters named in `held` (NULL-terminated; every other one free, F0
 * included) at their true values: the held entries come back bitwise, with
 * standard error 0; the free ones within `tol` relative of the truth, with
 * positive finite standard errors. */
static void check_held(const char *name, const double values[][8], const char *const *held,
                       double tol)
{
    brdffit_model *model = make_model(name);
    size_t n = brdffit_model_vector_size(model, NC), np = brdffit_model_param_count(model);
    double truth[MAXV], start[MAXV], got[MAXV], se[MAXV];
    brdffit_grid *grid;
    size_t p, k, c;
    assert_true(n <= MAXV);
    fx_vector(model, NC, values, truth);
    grid = fx_grid_from_model(model, truth, NC, NULL, 0.01, 7);
    assert_non_null(grid);
    make_start(model, truth, held, start);
    for (p = 0; p < sizeof PIPELINES / sizeof PIPELINES[0]; p++) {
        brdffit_fit *fit = NULL;
        assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, PIPELINES[p]), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        for (k = 0; k < np; k++)
            assert_int_equal(brdffit_fit_set_fixed(fit, k, is_held(model, k, held)), BRDFFIT_OK);
        if (brdffit_fit_run(fit) != BRDFFIT_OK)
            print_error("%s %s: %s\n", name, PIPELINE_NAMES[p], brdffit_fit_message(fit));
        assert_int_equal(brdffit_fit_params(fit, got), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_std_errors(fit, se), BRDFFIT_OK);
        for (k = 0; k < np; k++)
            for (c = 0; c < NC; c++) {
                size_t e = brdffit_model_vector_index(model, k, c, NC);
                double rel = fabs(got[e] - truth[e]) / fmax(fabs(truth[e]), 1e-3);
                int h = is_held(model, k, held);
                if ((h && (got[e] != truth[e] || se[e] != 0.0)) || (!h && !(rel < tol)))
                    print_error("%s %s, %s held: %s[%zu] = %.17g (truth %.17g), se %g\n", name,
                                PIPELINE_NAMES[p], held[0], brdffit_model_param(model, k)->name, c,
                                got[e], truth[e], se[e]);
                if (h) {
                    assert_true(got[e] == truth[e]);
                    assert_true(se[e] == 0.0);
                } else {
                    assert_true(rel < tol);
                    assert_true(se[e] > 0.0 && isfinite(se[e]));
                }
            }
        brdffit_fit_destroy(fit);
    }
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

/* A shape parameter (the exponent). */
static void test_held_shape(void **state)
{
    static const char *const held[] = {"ns", NULL};
    (void)state;
    check_held("ashikhmin-shirley-fresnel", ASF, held, 2e-2);
}

/* A linear colour, with a different value in every channel: auto solves the
 * colours for every shape and must keep the held ones; two-stage's second
 * stage must hold each channel's own value, not the channels' mean. */
static void test_held_colour(void **state)
{
    static const char *const held[] = {"cs", NULL};
    (void)state;
    check_held("ashikhmin-shirley-fresnel", ASF, held, 2e-2);
}

/* Every colour held: the profile has no colour left to solve. */
static void test_held_every_colour(void **state)
{
    static const char *const held[] = {"cd", "cs", NULL};
    (void)state;
    check_held("ashikhmin-shirley-fresnel", ASF, held, 2e-2);
}

/* A Fresnel term entering the basis affinely (Rs of Ashikhmin-Shirley). */
static void test_held_fresnel(void **state)
{
    static const char *const held[] = {"Rs", NULL};
    (void)state;
    check_held("ashikhmin-shirley-fresnel", ASF, held, 2e-2);
}

/* F0 of a microfacet model, held (as by default) at a value that is not
 * the default, with the roughness and colours free. */
static void test_held_f0(void **state)
{
    static const char *const held[] = {"F0", NULL};
    (void)state;
    check_held("ggx", GGX, held, 2e-2);
}

/* A colour held away from the truth (cs = 0.05 against 0.30 .. 0.40, the
 * case of issue 14) in Ashikhmin-Shirley: every pipeline keeps it, and
 * auto reaches the optimum joint reaches from next to it (the exponent and
 * the diffuse colours compensate for the wrong colour). */
static void test_held_colour_off_truth(void **state)
{
    brdffit_model *model = make_model("ashikhmin-shirley");
    size_t n = brdffit_model_vector_size(model, NC), ks = param_index(model, "cs"), p, c, e;
    double truth[MAXV], start[MAXV], got[3][MAXV], cost[3];
    brdffit_grid *grid;
    (void)state;
    fx_vector(model, NC, AS, truth);
    grid = fx_grid_from_model(model, truth, NC, NULL, 0.0, 1);
    assert_non_null(grid);
    memcpy(start, truth, n * sizeof *start);
    for (c = 0; c < NC; c++) start[brdffit_model_vector_index(model, ks, c, NC)] = 0.05;
    for (p = 0; p < 3; p++) {
        brdffit_fit *fit = NULL;
        assert_int_equal(brdffit_fit_create(&fit, grid, model, NULL, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, PIPELINES[p]), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_set_fixed(fit, ks, 1), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_run(fit), BRDFFIT_OK);
        assert_int_equal(brdffit_fit_params(fit, got[p]), BRDFFIT_OK);
        assert_int_equal(
            brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost[p]),
            BRDFFIT_OK);
        for (c = 0; c < NC; c++)
            assert_true(got[p][brdffit_model_vector_index(model, ks, c, NC)] == 0.05);
        assert_true(cost[p] > 0.0); /* the held colour is wrong: no exact fit */
        brdffit_fit_destroy(fit);
    }
    /* auto's optimum is the global one: no worse than joint's from next to it */
    assert_true(cost[0] <= cost[1] * (1.0 + 1e-6));
    for (e = 0; e < n; e++) assert_close(got[0][e], got[1][e], 1e-4);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_held_shape),        cmocka_unit_test(test_held_colour),
        cmocka_unit_test(test_held_every_colour), cmocka_unit_test(test_held_fresnel),
        cmocka_unit_test(test_held_f0),           cmocka_unit_test(test_held_colour_off_truth),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
