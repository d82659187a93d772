/* Synthetic measurements for the fitting tests: grids generated from a
 * model with known parameters, optionally with multiplicative noise. */
#ifndef BRDFFIT_FIT_FIXTURES_H
#define BRDFFIT_FIT_FIXTURES_H

#include <stddef.h>
#include <stdint.h>

#include "brdffit/brdffit.h"

/* Deterministic uniform random numbers in [0, 1). */
double fx_uniform(uint64_t *state);
/* Deterministic standard normal random numbers. */
double fx_normal(uint64_t *state);

/* A regular grid on `axes` (NULL = brdffit_axes_default()) with nc
 * channels holding model(params) times (1 + noise * N(0,1)), clipped at 0.
 * Returns NULL on failure (the test then fails). */
brdffit_grid *fx_grid_from_model(const brdffit_model *model, const double *params, size_t nc,
                                 const brdffit_axes *axes, double noise, uint64_t seed);

/* The same from a built-in model name and a parameter vector. */
brdffit_grid *fx_grid_from_named(const char *name, const double *params, size_t nc,
                                 const brdffit_axes *axes, double noise, uint64_t seed);

/* A small regular grid's axes, 9 x 13 x 12 samples (theta_i every 9
 * degrees, theta_o every 6.5, phi_o every pi/11), in the caller's arrays
 * of 9, 13 and 12 doubles. */
brdffit_axes fx_small_axes(double *ti, double *to, double *po);

/* Fill a model vector from per-parameter values: shared parameters take
 * values[k][0], per-channel ones values[k][c]. */
void fx_vector(const brdffit_model *model, size_t nc, const double values[][8], double *vec);

#endif
