/* The cost of physical plausibility (BRDFFIT_FIT_PLAUSIBLE, docs/fitting.md):
 * the auto fit of the bundled sample (data/sample-carpaint.csv, default
 * cap; the squares objective unless --objective says otherwise, the
 * objective of the figures in docs/fitting.md, whatever the library's
 * default) per model at plausibility 0 (the reference), 1 (the
 * default) and 2, median of repeated runs taken in turn (0, 1, 2, 0, ...)
 * in the same run, with the ratios to 0; and for the default, the largest
 * directional albedo over 0, 30, 50, 65, 75, 85 degrees of each colour's
 * own term (every other colour 0) of the result, by
 * brdffit_model_albedo(): at most 1 when the bounds hold.
 *
 *   bench_plausible [--repeats=N] [--filter=MODEL] [--objective=NAME]
 *
 * Public API only, so it also builds against an older library. Prints
 * markdown rows on stdout. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <brdffit/brdffit.h>

#include "harness.h"

#ifndef BENCH_SOURCE_DIR
#define BENCH_SOURCE_DIR "."
#endif

#define PI 3.14159265358979323846
#define MAXV 64
#define NC 3

static const char *const OBJECTIVES[] = {"squares", "log", "cube-root", "relative"};

/* One auto fit at plausibility `level`: its time (ms), NAN on failure. */
static double fit_ms(const brdffit_grid *grid, const brdffit_model *model, int objective, int level,
                     double *p)
{
    brdffit_fit *fit = NULL;
    uint64_t t0;
    double ms = NAN;
    if (brdffit_fit_create(&fit, grid, model, NULL, NULL) != BRDFFIT_OK) return NAN;
    brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, objective);
    brdffit_fit_set(fit, BRDFFIT_FIT_PLAUSIBLE, level);
    t0 = bh_now_ns();
    if (brdffit_fit_run(fit) == BRDFFIT_OK && brdffit_fit_params(fit, p) == BRDFFIT_OK)
        ms = 1e-6 * (double)(bh_now_ns() - t0);
    brdffit_fit_destroy(fit);
    return ms;
}

/* The largest albedo over the angles and channels of any single colour's
 * term of the model at p; its declared index into *which. */
static double worst_term(const brdffit_model *model, const double *p, size_t *which)
{
    static const double deg[6] = {0.0, 30.0, 50.0, 65.0, 75.0, 85.0};
    double v[MAXV], ti[6], a[6 * NC], worst = 0.0;
    size_t n = brdffit_model_param_count(model), nv = brdffit_model_vector_size(model, NC);
    size_t keep, k, c, t;
    for (t = 0; t < 6; t++) ti[t] = deg[t] * PI / 180.0;
    *which = n;
    for (keep = 0; keep < n; keep++) {
        if (!(brdffit_model_param(model, keep)->flags & BRDFFIT_PARAM_LINEAR)) continue;
        memcpy(v, p, nv * sizeof *v);
        for (k = 0; k < n; k++)
            if (k != keep && (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_LINEAR))
                for (c = 0; c < NC; c++) v[brdffit_model_vector_index(model, k, c, NC)] = 0.0;
        if (brdffit_model_albedo(model, v, NC, ti, 6, 0, a, NULL) != BRDFFIT_OK) return NAN;
        for (t = 0; t < 6 * NC; t++)
            if (a[t] > worst) {
                worst = a[t];
                *which = keep;
            }
    }
    return worst;
}

static void one_model(const brdffit_grid *grid, const char *name, int objective, size_t repeats)
{
    brdffit_model *model = NULL;
    double t[3][64], med[3], p[MAXV], top;
    size_t r, which;
    int level;
    if (brdffit_model_create(&model, name, NULL, NULL) != BRDFFIT_OK) return;
    for (r = 0; r < repeats; r++)
        for (level = 0; level < 3; level++) t[level][r] = fit_ms(grid, model, objective, level, p);
    for (level = 0; level < 3; level++) {
        bh_stats st;
        bh_stats_from(t[level], repeats, &st);
        med[level] = st.median_ns; /* the times are in ms */
    }
    fit_ms(grid, model, objective, 1, p);
    top = worst_term(model, p, &which);
    printf("| %s | %.1f ms | %.1f ms (%.2fx) | %.1f ms (%.2fx) | %.4f (%s) |\n", name, med[0],
           med[1], med[1] / med[0], med[2], med[2] / med[0], top,
           which < brdffit_model_param_count(model) ? brdffit_model_param(model, which)->name
                                                    : "-");
    fflush(stdout);
    brdffit_model_destroy(model);
}

int main(int argc, char **argv)
{
    static const char *const models[] = {
        "ashikhmin-shirley", "phong", "blinn-phong", "cook-torrance", "ggx", "ward", "ggx-2",
        "lafortune"};
    const char *filter = NULL;
    size_t repeats = 5, i;
    brdffit_grid *sample = NULL;
    int a, objective = 0, o;
    for (a = 1; a < argc; a++) {
        if (strncmp(argv[a], "--repeats=", 10) == 0)
            repeats = (size_t)atoi(argv[a] + 10);
        else if (strncmp(argv[a], "--filter=", 9) == 0)
            filter = argv[a] + 9;
        else if (strncmp(argv[a], "--objective=", 12) == 0) {
            for (o = 0; o < 4 && strcmp(argv[a] + 12, OBJECTIVES[o]) != 0; o++) continue;
            if (o == 4) {
                fprintf(stderr, "--objective is squares, log, cube-root or relative\n");
                return 2;
            }
            objective = o;
        } else {
            fprintf(stderr, "usage: %s [--repeats=N] [--filter=MODEL] [--objective=NAME]\n",
                    argv[0]);
            return 2;
        }
    }
    if (repeats < 1 || repeats > 64) repeats = 5;
    if (brdffit_load_csv(&sample, BENCH_SOURCE_DIR "/data/sample-carpaint.csv", NULL, NULL) !=
        BRDFFIT_OK) {
        fprintf(stderr, "cannot load the bundled sample\n");
        return 1;
    }
    printf("auto fit of the bundled sample (default cap, %s objective) per plausibility level, "
           "median of %zu runs taken in turn, 1 thread; largest term albedo of the level-1 "
           "result\n\n"
           "| model | 0 | 1 (default) | 2 | largest term albedo at 1 |\n|---|---|---|---|---|\n",
           OBJECTIVES[objective], repeats);
    for (i = 0; i < sizeof models / sizeof models[0]; i++)
        if (filter == NULL || strcmp(filter, models[i]) == 0)
            one_model(sample, models[i], objective, repeats);
    brdffit_grid_destroy(sample);
    return 0;
}
