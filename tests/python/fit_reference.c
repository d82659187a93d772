/* Reference fits for the Python binding's test (test_fit.py).
 *
 * Usage: python_fit_reference FILE.csv
 *
 * Writes a synthetic three-channel measurement (an Ashikhmin-Shirley
 * material with deterministic multiplicative noise) to FILE.csv in the
 * grid form of the CSV format, values printed with %.17g so that they
 * round-trip exactly, loads it back through brdffit_load_csv() and fits
 * it in the configurations below. For each configuration it prints
 *
 *     <config> params <p0> <p1> ...
 *     <config> std_errors <...>
 *     <config> errors <rms> <ngan> <cost>
 *     <config> run <iterations> <stop reason> <passes>
 *
 * with every number as %.17g. The Python test loads the same file, runs
 * the same configurations through the binding and compares. */
#include <stdio.h>
#include <stdlib.h>

#include "brdffit/brdffit.h"

#define PI 3.14159265358979323846
#define MAX_VEC 32

/* One deterministic value in [-1, 1) per call (64-bit LCG, top bits). */
static double noise(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / 4503599627370496.0 - 1.0;
}

static int eval_truth(const brdffit_model *model, double ti, double to, double po,
                      double *rgb)
{
    static const double truth[] = {90.0, 0.30, 0.20, 0.10, 0.40, 0.35, 0.30};
    double tir = ti * (PI / 180.0), pir = PI, tor = to * (PI / 180.0), por = po * (PI / 180.0);
    return brdffit_model_eval_angles(model, 1, &tir, &pir, &tor, &por, 3, truth, rgb, NULL,
                                     NULL) == BRDFFIT_OK;
}

/* The grid: theta_i 0..80 step 10, theta_o 0..80 step 5, phi_o 0..180 step 10. */
static int write_csv(const char *path)
{
    brdffit_model *model = NULL;
    unsigned long long state = 12345;
    FILE *f;
    int i, j, k, c, ok = 1;
    if (brdffit_model_create(&model, "ashikhmin-shirley", NULL, NULL) != BRDFFIT_OK) return 0;
    f = fopen(path, "w");
    if (f == NULL) {
        brdffit_model_destroy(model);
        return 0;
    }
    fprintf(f, "# synthetic Ashikhmin-Shirley material with 3%% noise\n");
    fprintf(f, "theta_i,theta_o,phi_o,r,g,b\n");
    for (i = 0; i <= 8 && ok; i++)
        for (j = 0; j <= 16 && ok; j++)
            for (k = 0; k <= 18 && ok; k++) {
                double rgb[3];
                ok = eval_truth(model, 10.0 * i, 5.0 * j, 10.0 * k, rgb);
                fprintf(f, "%d,%d,%d", 10 * i, 5 * j, 10 * k);
                for (c = 0; c < 3; c++) fprintf(f, ",%.17g", rgb[c] * (1.0 + 0.03 * noise(&state)));
                fprintf(f, "\n");
            }
    if (fclose(f) != 0) ok = 0;
    brdffit_model_destroy(model);
    return ok;
}

typedef struct config {
    const char *name;
    const char *model;
    int pipeline;
    double cap;          /* radians; 0 = default */
    int weighting;       /* -1 = default */
    double clearcoat;
    int threads;
    int max_iterations;  /* 0 = default */
    const double *start; /* NULL = model defaults */
    const char *fixed;   /* NULL, or a parameter to hold fixed */
} config;

static const double ASF_START[] = {60.0, 0.25, 0.2, 0.2, 0.2, 0.3, 0.3, 0.3};
static const double BP_START[] = {30.0, 0.2, 0.2, 0.2, 0.3, 0.3, 0.3};

static const config CONFIGS[] = {
    {"auto", "ashikhmin-shirley", BRDFFIT_PIPELINE_AUTO, 0.0, -1, 0.0, 1, 0, NULL, NULL},
    {"joint", "ashikhmin-shirley-fresnel", BRDFFIT_PIPELINE_JOINT, 60.0 * (PI / 180.0),
     BRDFFIT_WEIGHT_COSINE, 0.0, 1, 40, ASF_START, "Rs"},
    {"two-stage", "blinn-phong", BRDFFIT_PIPELINE_TWO_STAGE, 0.0, BRDFFIT_WEIGHT_SOLID_ANGLE,
     0.04, 3, 0, BP_START, NULL},
};

static void print_vector(const char *cfg, const char *what, const double *v, size_t n)
{
    size_t i;
    printf("%s %s", cfg, what);
    for (i = 0; i < n; i++) printf(" %.17g", v[i]);
    printf("\n");
}

static int set_options(brdffit_fit *fit, const brdffit_model *model, const config *c)
{
    int ok = brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, c->pipeline) == BRDFFIT_OK;
    if (c->cap > 0.0) ok = ok && brdffit_fit_set(fit, BRDFFIT_FIT_CAP, c->cap) == BRDFFIT_OK;
    if (c->weighting >= 0)
        ok = ok && brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, c->weighting) == BRDFFIT_OK;
    ok = ok && brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, c->clearcoat) == BRDFFIT_OK;
    ok = ok && brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, c->threads) == BRDFFIT_OK;
    if (c->max_iterations > 0)
        ok = ok && brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, c->max_iterations) ==
                       BRDFFIT_OK;
    if (c->start != NULL) ok = ok && brdffit_fit_set_start(fit, c->start) == BRDFFIT_OK;
    if (c->fixed != NULL) {
        size_t k;
        ok = ok && brdffit_model_param_find(model, c->fixed, &k) == BRDFFIT_OK;
        ok = ok && brdffit_fit_set_fixed(fit, k, 1) == BRDFFIT_OK;
    }
    return ok;
}

static int print_results(const brdffit_fit *fit, const char *cfg)
{
    double v[MAX_VEC], err[3];
    size_t n = brdffit_fit_param_count(fit), m;
    if (n > MAX_VEC || brdffit_fit_params(fit, v) != BRDFFIT_OK) return 0;
    print_vector(cfg, "params", v, n);
    if (brdffit_fit_std_errors(fit, v) != BRDFFIT_OK) return 0;
    print_vector(cfg, "std_errors", v, n);
    for (m = 0; m < 3; m++)
        if (brdffit_fit_error(fit, (brdffit_fit_metric)m, BRDFFIT_ALL_CHANNELS, &err[m]) !=
            BRDFFIT_OK)
            return 0;
    print_vector(cfg, "errors", err, 3);
    printf("%s run %zu %d %zu\n", cfg, brdffit_fit_iterations(fit),
           (int)brdffit_fit_stop_reason(fit), brdffit_fit_passes(fit));
    return 1;
}

static int run_config(const brdffit_grid *grid, const config *c)
{
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    brdffit_error err;
    int ok = 0;
    if (brdffit_model_create(&model, c->model, NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "%s: %s\n", c->name, err.message);
        return 0;
    }
    if (brdffit_fit_create(&fit, grid, model, NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "%s: %s\n", c->name, err.message);
    } else if (!set_options(fit, model, c) || brdffit_fit_run(fit) != BRDFFIT_OK) {
        fprintf(stderr, "%s: %s\n", c->name, brdffit_fit_message(fit));
    } else {
        ok = print_results(fit, c->name);
    }
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
    return ok;
}

int main(int argc, char **argv)
{
    brdffit_grid *grid = NULL;
    brdffit_error err;
    size_t i;
    int ok = 1;
    if (argc != 2) {
        fprintf(stderr, "usage: %s FILE.csv\n", argv[0]);
        return 2;
    }
    if (!write_csv(argv[1])) {
        fprintf(stderr, "cannot write %s\n", argv[1]);
        return 1;
    }
    if (brdffit_load_csv(&grid, argv[1], NULL, &err) != BRDFFIT_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    for (i = 0; i < sizeof CONFIGS / sizeof CONFIGS[0]; i++)
        ok = run_config(grid, &CONFIGS[i]) && ok;
    brdffit_grid_destroy(grid);
    return ok ? 0 : 1;
}
