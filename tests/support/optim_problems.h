/* Test problems for the optimizer: the least-squares problems of the
 * Moré-Garbow-Hillstrom set (ACM TOMS 7, 1981), all 35 with their minima
 * and six of them on their own, and two curve fits with data made from
 * known parameters, in residual form, plus an adapter that turns any of
 * them into the normal-equation form. */
#ifndef BRDFFIT_OPTIM_PROBLEMS_H
#define BRDFFIT_OPTIM_PROBLEMS_H

#include <stddef.h>

#include "brdffit/optim.h"

#define OPTIM_MAX_ROWS 100
#define OPTIM_MAX_PARAMS 12

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

/* A residual problem seen in changed coordinates x: the problem's own
 * parameters are b_j = scale_j x_j + shift_j, so its Jacobian's columns
 * are multiplied by scale_j (in place, so any number of rows works). */
typedef struct optim_changed {
    brdffit_residual_fn fn;
    void *user;
    size_t n_rows, n_params;
    double scale[OPTIM_MAX_PARAMS], shift[OPTIM_MAX_PARAMS];
} optim_changed;

/* The identity change of fn's n_params parameters. */
void optim_changed_init(optim_changed *c, brdffit_residual_fn fn, void *user, size_t n_rows,
                        size_t n_params);
/* Mixed magnitudes: the first parameter in units in which ref (its
 * certified value, or its start) is 1e6; ref 0 counts as 1. */
void optim_changed_mixed(optim_changed *c, double ref);
/* Through zero: every parameter shifted by the midpoint of from and to
 * (a start and a solution), so that each changes sign on the way. */
void optim_changed_through_zero(optim_changed *c, const double *from, const double *to);
/* x from b, and b from x. */
void optim_changed_from_problem(const optim_changed *c, const double *b, double *x);
void optim_changed_to_problem(const optim_changed *c, const double *x, double *b);
/* The residual callback in the changed coordinates; user is the
 * optim_changed. */
brdffit_status optim_changed_fn(const double *x, double *r, double *jac, void *user);

/* A named problem with its standard start; for the MGH set also its
 * number in the paper and its minima (sums of squares; an unused entry
 * is -1). */
typedef struct optim_problem {
    const char *name;
    size_t n_params, n_rows;
    double x0[OPTIM_MAX_PARAMS];
    brdffit_residual_fn fn;
    int number;
    double minima[2];
} optim_problem;

/* A zero minimum counts as reached below this cost. */
#define OPTIM_ZERO_COST 1e-10

/* Six MGH problems (those above), in the order declared; *count
 * receives 6. */
const optim_problem *optim_mgh_problems(size_t *count);

/* The whole least-squares set of Moré, Garbow and Hillstrom (1981): the 35
 * problems in the paper's order, at the dimensions and starts given
 * there (variable dimensions: n = 10, Watson n = 6, extended Powell
 * n = 12, Chebyquad n = 8, the linear functions n = 5, m = 10; Gulf
 * m = 99, Brown-Dennis m = 20, Biggs m = 13). Call fn with the
 * problem itself as user: the variable dimensions come from it.
 * *count receives 35. */
const optim_problem *optim_mgh_set(size_t *count);

/* Whether cost is one of pb's minima: within 1e-6 relative of a
 * non-zero one, or below OPTIM_ZERO_COST for a zero one. */
int optim_mgh_solved(const optim_problem *pb, double cost);

#endif
