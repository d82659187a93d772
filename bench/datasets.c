/* Synthetic measurements: see datasets.h. */
#include "datasets.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define BD_PI 3.14159265358979323846

/* ns; cd r g b; cs r g b */
static const double p1_params[] = {120.0, 0.30, 0.20, 0.10, 0.40, 0.35, 0.30};
/* m, F0; cd r g b; cs r g b */
static const double p2_params[] = {0.15, 0.04, 0.25, 0.12, 0.05, 0.6, 0.6, 0.6};

const char *bd_name(bd_dataset which)
{
    return which == BD_P1 ? "P1" : "P2";
}

const char *bd_model(bd_dataset which)
{
    return which == BD_P1 ? "ashikhmin-shirley" : "cook-torrance";
}

const double *bd_params(bd_dataset which)
{
    return which == BD_P1 ? p1_params : p2_params;
}

double bd_noise(bd_dataset which)
{
    return which == BD_P1 ? 0.0 : 0.01;
}

static void interleave_with_noise(const double *planar, size_t n, double noise, uint64_t seed,
                                  double *values)
{
    bh_rng rng;
    size_t s, c;
    bh_rng_seed(&rng, seed);
    for (s = 0; s < n; s++) {
        for (c = 0; c < BD_CHANNELS; c++) {
            double v = planar[c * n + s];
            if (noise > 0.0) v *= 1.0 + noise * bh_rng_normal(&rng);
            values[s * BD_CHANNELS + c] = v > 0.0 ? v : 0.0;
        }
    }
}

brdffit_status bd_generate(bd_dataset which, uint64_t seed, size_t n, const double *theta_i,
                           const double *phi_i, const double *theta_o, const double *phi_o,
                           double *values, brdffit_error *err)
{
    brdffit_model *model = NULL;
    double *planar = malloc(n * BD_CHANNELS * sizeof *planar);
    brdffit_status st = BRDFFIT_E_OUT_OF_MEMORY;
    if (planar != NULL) st = brdffit_model_create(&model, bd_model(which), NULL, err);
    if (st == BRDFFIT_OK)
        st = brdffit_model_eval_angles(model, n, theta_i, phi_i, theta_o, phi_o, BD_CHANNELS,
                                       bd_params(which), planar, NULL, err);
    if (st == BRDFFIT_OK) interleave_with_noise(planar, n, bd_noise(which), seed, values);
    brdffit_model_destroy(model);
    free(planar);
    return st;
}

size_t bd_axes_angles(const brdffit_axes *axes, double **angles)
{
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o, i, j, k, s = 0;
    double *a = malloc(4 * n * sizeof *a);
    *angles = a;
    if (a == NULL) return 0;
    for (i = 0; i < axes->n_theta_i; i++)
        for (j = 0; j < axes->n_theta_o; j++)
            for (k = 0; k < axes->n_phi_o; k++, s++) {
                a[s] = axes->theta_i[i];
                a[n + s] = BD_PI;
                a[2 * n + s] = axes->theta_o[j];
                a[3 * n + s] = axes->phi_o[k];
            }
    return n;
}

brdffit_status bd_default_grid(brdffit_grid **out, bd_dataset which, uint64_t seed,
                               const brdffit_allocator *alloc, brdffit_error *err)
{
    const brdffit_axes *axes = brdffit_axes_default();
    double *angles = NULL, *values = NULL;
    size_t n = bd_axes_angles(axes, &angles);
    brdffit_status st = BRDFFIT_E_OUT_OF_MEMORY;
    *out = NULL;
    if (n > 0) values = malloc(n * BD_CHANNELS * sizeof *values);
    if (values != NULL)
        st = bd_generate(which, seed, n, angles, angles + n, angles + 2 * n, angles + 3 * n, values,
                         err);
    if (st == BRDFFIT_OK)
        st = brdffit_grid_create_regular(out, axes, BD_CHANNELS, values, NULL, alloc, err);
    free(values);
    free(angles);
    return st;
}

/* ---- fits ------------------------------------------------------------------ */

static double thesis_value(const char *name, double fallback)
{
    if (strcmp(name, "ns") == 0) return 25.0;
    if (strcmp(name, "cd") == 0 || strcmp(name, "cs") == 0) return 0.2;
    return fallback;
}

brdffit_status bd_thesis_start(const brdffit_model *model, size_t nc, double *start)
{
    size_t k, c, n = brdffit_model_vector_size(model, nc);
    if (n == 0 || n > BD_MAX_PARAMS) return BRDFFIT_E_INVALID_ARGUMENT;
    BH_TRY(brdffit_model_default_params(model, nc, start));
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < nc; c++) {
            size_t e = brdffit_model_vector_index(model, k, c, nc);
            start[e] = thesis_value(info->name, start[e]);
        }
    }
    return BRDFFIT_OK;
}

const char *bd_pipeline_name(brdffit_pipeline p)
{
    switch (p) {
    case BRDFFIT_PIPELINE_AUTO: return "auto";
    case BRDFFIT_PIPELINE_JOINT: return "joint";
    case BRDFFIT_PIPELINE_TWO_STAGE: return "two-stage";
    }
    return "?";
}

static brdffit_status configure(brdffit_fit *fit, const bd_fit_job *job)
{
    BH_TRY(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, (double)job->pipeline));
    BH_TRY(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, (double)(job->threads ? job->threads : 1)));
    if (job->start != NULL) BH_TRY(brdffit_fit_set_start(fit, job->start));
    if (job->damping != NULL) BH_TRY(brdffit_fit_set_damping(fit, job->damping));
    /* always set: a zeroed job means the squares, not the library's default */
    BH_TRY(brdffit_fit_set(fit, BRDFFIT_FIT_OBJECTIVE, (double)job->objective));
    return BRDFFIT_OK;
}

static void collect(brdffit_fit *fit, bd_fit_result *res)
{
    res->iterations = brdffit_fit_iterations(fit);
    res->passes = brdffit_fit_passes(fit);
    res->stop = brdffit_fit_stop_reason(fit);
    res->n_params = brdffit_fit_param_count(fit);
    if (res->n_params > BD_MAX_PARAMS) res->n_params = BD_MAX_PARAMS;
    brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS, &res->cost);
    brdffit_fit_params(fit, res->params);
}

brdffit_status bd_fit_run(const bd_fit_job *job, bd_fit_result *res)
{
    brdffit_allocator a;
    brdffit_fit *fit = NULL;
    brdffit_error err;
    size_t calls0 = 0, live0 = 0;
    memset(res, 0, sizeof *res);
    if (job->counter != NULL) {
        a = bh_counter_allocator(job->counter);
        bh_counter_reset_peak(job->counter);
        calls0 = atomic_load(&job->counter->calls);
        live0 = atomic_load(&job->counter->live);
    }
    res->status = brdffit_fit_create(&fit, job->grid, job->model, job->counter ? &a : NULL, &err);
    if (res->status != BRDFFIT_OK) {
        snprintf(res->message, sizeof res->message, "%s", err.message);
        return res->status;
    }
    res->status = configure(fit, job);
    if (res->status == BRDFFIT_OK) res->status = brdffit_fit_run(fit);
    if (res->status == BRDFFIT_OK)
        collect(fit, res);
    else
        snprintf(res->message, sizeof res->message, "%s", brdffit_fit_message(fit));
    brdffit_fit_destroy(fit);
    if (job->counter != NULL) {
        res->peak_bytes = atomic_load(&job->counter->peak) - live0;
        res->alloc_calls = atomic_load(&job->counter->calls) - calls0;
        res->leaked = atomic_load(&job->counter->live) - live0;
    }
    return res->status;
}
