/* Test problems for the optimizer: part of the Moré-Garbow-Hillstrom set
 * (ACM TOMS 7, 1981) and two curve fits with data made from known
 * parameters, in residual form, plus an adapter that turns any of them
 * into the normal-equation form. */
#ifndef BRDFFIT_OPTIM_PROBLEMS_H
#define BRDFFIT_OPTIM_PROBLEMS_H

#include <stddef.h>

#include "brdffit/optim.h"

#define OPTIM_MAX_ROWS 64
#define OPTIM_MAX_PARAMS 8

/* Residual callbacks; user is unused except for the data fits. */
brdffit_status optim_rosenbrock(const double *x, double *r, double *jac, void *user);
brdffit_status optim_powell_singular(const double *x, double *r, double *jac, void *user);
brdffit_status optim_freudenstein_roth(const double *x, double *r, double *jac, void *user);
brdffit_status optim_meyer(const double *x, double *r, double *jac, void *user);
brdffit_status optim_box3d(const double *x, double *r, double *jac, void *user);
brdffit_status optim_jennrich_sampson(const double *x, double *r, double *jac, void *user);

/* Data made from known parameters plus deterministic noise. */
typedef struct optim_fit_data {
    size_t n;
    double t[OPTIM_MAX_ROWS], y[OPTIM_MAX_ROWS];
    double truth[OPTIM_MAX_PARAMS];
    double noise; /* standard deviation of the noise */
} optim_fit_data;

/* y = a exp(-b t) + c; 40 points, t in [0, 9.75]; a = 5, b = 0.7, c = 1. */
void optim_make_exp_data(optim_fit_data *d);
brdffit_status optim_exp_fit(const double *x, double *r, double *jac, void *user);

/* y = (a + b t) / (1 + c t + d t^2); 50 points, t in [0, 4.9];
 * a = 2, b = 5, c = 0.8, d = 0.3. */
void optim_make_rational_data(optim_fit_data *d);
brdffit_status optim_rational_fit(const double *x, double *r, double *jac, void *user);

/* Deterministic pseudo-random numbers in [0, 1). */
double optim_uniform(unsigned long long *state);

/* A residual problem seen through the normal-equation callback: sums
 * cost, J^T J and J^T r itself and counts the calls. */
typedef struct optim_normal_adapter {
    brdffit_residual_fn fn;
    void *user;
    size_t n_rows, n_params;
    size_t calls, derivative_calls;
    double r[OPTIM_MAX_ROWS];
    double jac[OPTIM_MAX_ROWS * OPTIM_MAX_PARAMS];
} optim_normal_adapter;

void optim_normal_adapter_init(optim_normal_adapter *a, brdffit_residual_fn fn, void *user,
                               size_t n_rows, size_t n_params);
brdffit_status optim_normal_adapter_fn(const double *x, double *cost, double *jtj, double *jtr,
                                       void *user);

/* A named problem with its standard start. */
typedef struct optim_problem {
    const char *name;
    size_t n_params, n_rows;
    double x0[OPTIM_MAX_PARAMS];
    brdffit_residual_fn fn;
} optim_problem;

/* The MGH problems above, in the order declared; *count receives 6. */
const optim_problem *optim_mgh_problems(size_t *count);

#endif
