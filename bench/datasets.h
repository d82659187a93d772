/* Synthetic measurements shared by the bench programs.
 *
 * P1: the simplified Ashikhmin-Shirley model (4.28) with ns = 120,
 *     cd = (0.30, 0.20, 0.10), cs = (0.40, 0.35, 0.30); no noise.
 * P2: a different model: Lambert cd = (0.25, 0.12, 0.05) plus a
 *     Cook-Torrance Beckmann lobe m = 0.15, F0 = 0.04, cs = (0.6, 0.6, 0.6)
 *     (the built-in "cook-torrance" model), times (1 + 0.01 N(0, 1)) per
 *     value: 1 % multiplicative noise from a fixed seed.
 * Both on the thesis's default axes (19 x 37 x 36 samples, 3 channels). */
#ifndef BRDFFIT_BENCH_DATASETS_H
#define BRDFFIT_BENCH_DATASETS_H

#include <stddef.h>
#include <stdint.h>

#include <brdffit/brdffit.h>

#include "harness.h"

typedef enum bd_dataset { BD_P1 = 0, BD_P2 = 1 } bd_dataset;

#define BD_CHANNELS 3
#define BD_SEED UINT64_C(20170601)

/* "P1" or "P2". */
const char *bd_name(bd_dataset which);
/* The generating model's name and its parameter vector (3 channels). */
const char *bd_model(bd_dataset which);
const double *bd_params(bd_dataset which);
/* Relative noise of the data set (0 or 0.01). */
double bd_noise(bd_dataset which);

/* Fill `values` (n * 3, interleaved as the grid constructors take them)
 * with the data set's values at the given directions; `seed` drives the
 * noise. */
brdffit_status bd_generate(bd_dataset which, uint64_t seed, size_t n, const double *theta_i,
                           const double *phi_i, const double *theta_o, const double *phi_o,
                           double *values, brdffit_error *err);

/* A regular grid on brdffit_axes_default() holding the data set. */
brdffit_status bd_default_grid(brdffit_grid **out, bd_dataset which, uint64_t seed,
                               const brdffit_allocator *alloc, brdffit_error *err);

/* Angles of every sample of a regular grid on `axes` (phi_i = pi), in
 * sample order; four malloc'ed arrays of n_samples in *angles (theta_i,
 * phi_i, theta_o, phi_o, one block). Returns the sample count, 0 on failure. */
size_t bd_axes_angles(const brdffit_axes *axes, double **angles);

#endif /* BRDFFIT_BENCH_DATASETS_H */

/* ---- fits ------------------------------------------------------------------ */

#define BD_MAX_PARAMS 32

/* The thesis's start values: ns = 25, every colour cd, cs = 0.2, anything
 * else (Rs of the Fresnel form) at the model's default. `start` holds
 * brdffit_model_vector_size(model, nc) values (<= BD_MAX_PARAMS). */
brdffit_status bd_thesis_start(const brdffit_model *model, size_t nc, double *start);

/* One fit: grid and model borrowed; start NULL = the model's defaults. */
typedef struct bd_fit_job {
    const brdffit_grid *grid;
    const brdffit_model *model;
    brdffit_pipeline pipeline;
    const double *start;
    size_t threads;                 /* BRDFFIT_FIT_THREADS */
    bh_counter *counter;            /* NULL: the default allocator */
    const brdffit_damping *damping; /* NULL: the default policy */
    brdffit_objective objective;    /* BRDFFIT_FIT_OBJECTIVE; 0 (zeroed job): the squares, whatever
                                     * the library's default, so figures stay comparable */
} bd_fit_job;

typedef struct bd_fit_result {
    brdffit_status status;
    char message[256];
    size_t iterations, passes, n_params;
    brdffit_stop_reason stop;
    double cost; /* BRDFFIT_METRIC_COST */
    double params[BD_MAX_PARAMS];
    size_t peak_bytes;  /* peak live bytes of the fit's allocator (create .. destroy) */
    size_t alloc_calls; /* allocations made by the fit */
    size_t leaked;      /* bytes still live after destroy */
} bd_fit_result;

/* Create, configure, run and destroy a fit. */
brdffit_status bd_fit_run(const bd_fit_job *job, bd_fit_result *res);

/* "auto", "joint", "two-stage". */
const char *bd_pipeline_name(brdffit_pipeline p);
