/* Auto against brute force: for every built-in model (with the Fresnel
 * term F0 of the microfacet models also freed) under every objective, the
 * auto pipeline's cost on data from other models, noiseless and noisy, is
 * no higher than the best of a brute-force search: a dense grid over every
 * free shape parameter (log-spaced over a logarithmic one's whole range,
 * evenly over a linear one's), each point followed by a joint
 * Levenberg-Marquardt polish of every parameter from it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_fixtures.h"
#include "test_support.h"

#define MAXV 64
#define NOBJ 4
#define MAXD 4

static const char *const OBJ_NAMES[NOBJ] = {"squares", "log", "cube-root", "relative"};

/* Auto may end a hair above the brute force's best: both stop at a
 * relative cost reduction of 1e-12 per LM iteration. Every model is held
 * to it: auto's further starts (lib/fit/lobe_starts.c) reach the optimum
 * of the two-lobe models on one-lobe data and of the coat models where
 * their coat vanishes or covers a rough base. */
#define TOLERANCE 1e-6

typedef struct source {
    const char *model;
    double v[6][8];
    double noise;
} source;

/* Two lobes and a diffuse term, noiseless; one broad anisotropy-free lobe
 * with 10 % noise. */
static const source SOURCES[] = {
    {"ggx-2", {{0.35}, {0.06}, {0.04}, {0.30, 0.20, 0.10}, {0.4, 0.3, 0.2}, {2.0, 1.5, 1.0}}, 0.0},
    {"ward-duer", {{0.15}, {0.25, 0.12, 0.05}, {0.5, 0.45, 0.4}}, 0.10},
};

static brdffit_model *make_model(const char *name)
{
    brdffit_model *model = NULL;
    assert_int_equal(brdffit_model_create(&model, name, NULL, NULL), BRDFFIT_OK);
    return model;
}

static double run_cost(brdffit_fit *fit)
{
    double cost;
    brdffit_status st = brdffit_fit_run(fit);
    if (st != BRDFFIT_OK) print_error("fit failed: %s\n", brdffit_fit_message(fit));
    assert_int_equal(st, BRDFFIT_OK);
    assert_int_equal(brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &cost),
                     BRDFFIT_OK);
    return cost;
}

/* The free shape parameters (shared, not linear, not held) of the model. */
static size_t shape_params(const brdffit_model *model, const int *freed, size_t *dims)
{
    size_t k, nd = 0;
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *p = brdffit_model_param(model, k);
        int fixed = (p->flags & BRDFFIT_PARAM_FIXED) && !freed[k];
        if (fixed || (p->flags & (BRDFFIT_PARAM_LINEAR | BRDFFIT_PARAM_PER_CHANNEL))) continue;
        if (nd < MAXD) dims[nd++] = k;
    }
    return nd;
}

/* Grid coordinate i of n over parameter p's range: log-spaced end to end
 * for a logarithmic one, cell centres for a linear one. */
static double coordinate(const brdffit_param_info *p, size_t i, size_t n)
{
    if (p->flags & BRDFFIT_PARAM_LOG_SCALE) /* exp(log(bound)) may miss it by an ulp */
        return fmin(fmax(exp(log(p->lower) + log(p->upper / p->lower) * (double)i /
                                                 (double)(n - 1)),
                         p->lower),
                    p->upper);
    return p->lower + (p->upper - p->lower) * ((double)i + 0.5) / (double)n;
}

static size_t points_per_dim(size_t nd)
{
    static const size_t full[MAXD + 1] = {1, 10, 5, 3, 2}, quick[MAXD + 1] = {1, 4, 2, 2, 1};
    return getenv("BRDFFIT_TEST_QUICK") ? quick[nd] : full[nd];
}

/* The lowest cost of joint fits from every point of the grid. */
static double brute_force(brdffit_fit *fit, const brdffit_model *model, size_t nc,
                          const size_t *dims, size_t nd)
{
    size_t per = points_per_dim(nd), total = 1, flat, d, k, c;
    double best = HUGE_VAL, start[MAXV];
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_JOINT),
                     BRDFFIT_OK);
    for (d = 0; d < nd; d++) total *= per;
    for (flat = 0; flat < total; flat++) {
        size_t rest = flat;
        for (k = 0; k < brdffit_model_param_count(model); k++)
            for (c = 0; c < nc; c++)
                start[brdffit_model_vector_index(model, k, c, nc)] =
                    brdffit_model_param(model, k)->start;
        for (d = 0; d < nd; d++, rest /= per)
            start[brdffit_model_vector_index(model, dims[d], 0, nc)] =
                coordinate(brdffit_model_param(model, dims[d]), rest % per, per);
        assert_int_equal(brdffit_fit_set_start(fit, start), BRDFFIT_OK);
        best = fmin(best, run_cost(fit));
    }
    assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, BRDFFIT_PIPELINE_AUTO),
                     BRDFFIT_OK);
    return best;
}

/* Index of parameter `name`, or the count when the model has none. */
static size_t param_index(const brdffit_model *model, const char *name)
{
    size_t k, n = brdffit_model_param_count(model);
    for (k = 0; k < n; k++)
        if (strcmp(brdffit_model_param(model, k)->name, name) == 0) return k;
    return n;
}

/* Worst ratio of auto's cost to the brute force's over the objectives. */
static int check_model(const char *name, int free_f0, brdffit_grid *const *grids,
                       size_t n_grids, double *worst_out)
{
    brdffit_model *model = make_model(name);
    size_t f0 = param_index(model, "F0"), dims[MAXD], nd, g, o;
    int freed[32] = {0}, ok = 1;
    size_t n_obj = getenv("BRDFFIT_TEST_QUICK") ? 2 : NOBJ;
    double worst = 0.0;
    *worst_out = 0.0;
    if (free_f0 && f0 == brdffit_model_param_count(model)) {
        brdffit_model_destroy(model);
        return 1;
    }
    if (free_f0) freed[f0] = 1;
    nd = shape_params(model, freed, dims);
    for (g = 0; g < n_grids; g++)
        for (o = 0; o < n_obj; o++) {
            brdffit_fit *fit = NULL;
            double cost, brute, ratio;
            assert_int_equal(brdffit_fit_create(&fit, grids[g], model, NULL, NULL), BRDFFIT_OK);
            assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)o), BRDFFIT_OK);
            if (free_f0) assert_int_equal(brdffit_fit_set_fixed(fit, f0, 0), BRDFFIT_OK);
            /* the optimum over the model's own bounds, as the joint fits see them */
            assert_int_equal(brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, 0), BRDFFIT_OK);
            cost = run_cost(fit);
            brute = brute_force(fit, model, 3, dims, nd);
            /* an exact fit: both at rounding level (the data are of order 1) */
            ratio = brute < 1e-20 ? (cost < 1e-20 ? 1.0 : HUGE_VAL) : cost / brute;
            printf("%-26s%s %-10s data %-10s auto %.9g brute %.9g ratio %.9f\n", name,
                   free_f0 ? " F0" : "   ", OBJ_NAMES[o], SOURCES[g + 2 - n_grids].model, cost, brute, ratio);
            if (!(ratio <= 1.0 + TOLERANCE)) {
                ok = 0;
                print_error("%s%s %s: auto %.12g above brute force %.12g\n", name,
                            free_f0 ? " (F0 free)" : "", OBJ_NAMES[o], cost, brute);
            }
            worst = fmax(worst, ratio);
            brdffit_fit_destroy(fit);
        }
    brdffit_model_destroy(model);
    *worst_out = worst;
    return ok;
}

static void test_every_model(void **state)
{
    double ti[9], to[13], po[12], p[MAXV];
    brdffit_axes ax = fx_small_axes(ti, to, po);
    brdffit_grid *grids[2];
    int ok = 1;
    size_t g, i, n_grids = getenv("BRDFFIT_TEST_QUICK") ? 1 : 2;
    (void)state;
    for (g = 0; g < 2; g++) {
        brdffit_model *src = make_model(SOURCES[g].model);
        fx_vector(src, 3, SOURCES[g].v, p);
        grids[g] = fx_grid_from_model(src, p, 3, &ax, SOURCES[g].noise, 11 + g);
        assert_non_null(grids[g]);
        brdffit_model_destroy(src);
    }
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        const char *name = brdffit_model_builtin_name(i), *only = getenv("BRDFFIT_TEST_MODEL");
        double w, wf;
        if (only != NULL && strcmp(only, name) != 0) continue; /* one model, when asked */
        ok &= check_model(name, 0, grids + 2 - n_grids, n_grids, &w);
        ok &= check_model(name, 1, grids + 2 - n_grids, n_grids, &wf);
        printf("worst ratio %-26s %.9f\n", name, w);
        if (wf > 0.0) printf("worst ratio %-26s %.9f (F0 free)\n", name, wf);
    }
    for (g = 0; g < 2; g++) brdffit_grid_destroy(grids[g]);
    /* every case is printed before the verdict */
    assert_true(ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
