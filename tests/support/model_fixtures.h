/* Shared helpers for the model tests: random parameter sets, the default
 * grid, and an independent finite-difference check of a model's Jacobian. */
#ifndef BRDFFIT_MODEL_FIXTURES_H
#define BRDFFIT_MODEL_FIXTURES_H

#include <stddef.h>
#include <stdint.h>

#include "brdffit/brdffit.h"

/* Deterministic uniform random numbers in [0, 1). */
double mf_uniform(uint64_t *state);

/* A regular grid on brdffit_axes_default() with nc channels, all values 0.
 * Returns NULL on failure. */
brdffit_grid *mf_default_grid(size_t nc);

/* A random parameter vector inside the parameter bounds, away from them
 * by more than two finite-difference steps: exponents log-uniform in
 * [1, 1e4] (Lafortune's n in [3, 1e4], where its lobe is smooth enough for
 * differences across base = 0), roughness log-uniform in [1e-3, 1],
 * bounded shared parameters uniform in [lower + 1%, upper - 1%], colours
 * uniform in [0.01, 1]. */
void mf_random_params(const brdffit_model *m, size_t nc, uint64_t *rng, double *x);

/* The worst relative error of the model's Jacobian on the grid against
 * central differences computed here, with the metric of
 * brdffit_model_check_jacobian() (differences within the rounding bound
 * of the numeric derivative do not count). Returns -1 when a per-channel
 * parameter changes another channel's values or an evaluation fails.
 * `raw` (may be NULL) receives the plain relative error
 * |a - n| / max(|n|, 1e-6 s) over the entries whose rounding bound is
 * below 1e-5 of that denominator. */
double mf_independent_jacobian_error(const brdffit_model *m, const brdffit_grid *grid,
                                     const double *x, double *raw);

#endif
