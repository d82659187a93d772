/* The 27 NIST StRD nonlinear regression problems (Statistical Reference
 * Datasets, NIST Information Technology Laboratory; public domain): data
 * (nist_data.c), both certified starts, the certified parameters and
 * residual sum of squares, and each model with its analytic gradient. */
#ifndef BRDFFIT_NIST_PROBLEMS_H
#define BRDFFIT_NIST_PROBLEMS_H

#include <stddef.h>

#include "brdffit/optim.h"

#define NIST_MAX_PARAMS 9

/* f(b; x) at one observation (x[0], and x[1] for Nelson); grad, when not
 * NULL, receives df/db (n_params values). */
typedef double (*nist_model_fn)(const double *b, const double *x, double *grad);

typedef struct nist_problem {
    const char *name;
    size_t n_params, n_obs;
    const double *data; /* stride values per observation, y first */
    size_t stride;      /* 1: y alone, x = 1, 2, ...; 2: y, x; 3: y, x1, x2 */
    int log_response;   /* the model fits log(y) (Nelson) */
    nist_model_fn model;
    double start[2][NIST_MAX_PARAMS];
    double certified[NIST_MAX_PARAMS];
    double certified_rss;
} nist_problem;

/* The observations (nist_data.c): the published number of observations
 * times the values per observation. */
extern const double nist_misra1a_data[14 * 2];
extern const double nist_chwirut2_data[54 * 2];
extern const double nist_chwirut1_data[214 * 2];
extern const double nist_lanczos3_data[24 * 2];
extern const double nist_lanczos1_data[24 * 2];
extern const double nist_lanczos2_data[24 * 2];
extern const double nist_gauss1_y[250 * 1];
extern const double nist_gauss2_y[250 * 1];
extern const double nist_danwood_data[6 * 2];
extern const double nist_kirby2_data[151 * 2];
extern const double nist_hahn1_data[236 * 2];
extern const double nist_nelson_data[128 * 3];
extern const double nist_mgh17_data[33 * 2];
extern const double nist_gauss3_y[250 * 1];
extern const double nist_roszman1_data[25 * 2];
extern const double nist_enso_y[168 * 1];
extern const double nist_mgh09_data[11 * 2];
extern const double nist_thurber_data[37 * 2];
extern const double nist_boxbod_data[6 * 2];
extern const double nist_rat42_data[9 * 2];
extern const double nist_mgh10_data[16 * 2];
extern const double nist_eckerle4_data[35 * 2];
extern const double nist_rat43_data[15 * 2];
extern const double nist_bennett5_data[154 * 2];

/* The problems in NIST's order (lower, average, higher difficulty);
 * *count receives 27. */
const nist_problem *nist_problems(size_t *count);

/* Observation i: the response (y, or log y) and the predictors. */
double nist_response(const nist_problem *p, size_t i, double x[2]);

/* Residual callback: r_i = f(b; x_i) - response_i; user is the problem. */
brdffit_status nist_residuals(const double *b, double *r, double *jac, void *user);

/* Log relative error of a value against the certified one: -log10 of the
 * relative error (absolute when the certified value is 0), capped at 15. */
double nist_lre(double value, double certified);

#endif
