/* Test problems for the optimizer; see optim_problems.h. */
#include "optim_problems.h"

#include <math.h>
#include <string.h>

/* --- Moré-Garbow-Hillstrom problems ------------------------------------------ */

brdffit_status optim_rosenbrock(const double *x, double *r, double *jac, void *user)
{
    (void)user;
    r[0] = 10.0 * (x[1] - x[0] * x[0]);
    r[1] = 1.0 - x[0];
    if (jac != NULL) {
        jac[0] = -20.0 * x[0];
        jac[1] = 10.0;
        jac[2] = -1.0;
        jac[3] = 0.0;
    }
    return BRDFFIT_OK;
}

brdffit_status optim_powell_singular(const double *x, double *r, double *jac, void *user)
{
    double s5 = sqrt(5.0), s10 = sqrt(10.0);
    double u = x[1] - 2.0 * x[2], v = x[0] - x[3];
    (void)user;
    r[0] = x[0] + 10.0 * x[1];
    r[1] = s5 * (x[2] - x[3]);
    r[2] = u * u;
    r[3] = s10 * v * v;
    if (jac != NULL) {
        static const double zero[16] = {0};
        memcpy(jac, zero, sizeof zero);
        jac[0] = 1.0;
        jac[1] = 10.0;
        jac[4 + 2] = s5;
        jac[4 + 3] = -s5;
        jac[8 + 1] = 2.0 * u;
        jac[8 + 2] = -4.0 * u;
        jac[12 + 0] = 2.0 * s10 * v;
        jac[12 + 3] = -2.0 * s10 * v;
    }
    return BRDFFIT_OK;
}

brdffit_status optim_freudenstein_roth(const double *x, double *r, double *jac, void *user)
{
    double y = x[1];
    (void)user;
    r[0] = -13.0 + x[0] + ((5.0 - y) * y - 2.0) * y;
    r[1] = -29.0 + x[0] + ((y + 1.0) * y - 14.0) * y;
    if (jac != NULL) {
        jac[0] = 1.0;
        jac[1] = 10.0 * y - 3.0 * y * y - 2.0;
        jac[2] = 1.0;
        jac[3] = 3.0 * y * y + 2.0 * y - 14.0;
    }
    return BRDFFIT_OK;
}

static const double meyer_y[16] = {34780.0, 28610.0, 23650.0, 19630.0, 16370.0, 13720.0,
                                   11540.0, 9744.0,  8261.0,  7030.0,  6005.0,  5147.0,
                                   4427.0,  3820.0,  3307.0,  2872.0};

brdffit_status optim_meyer(const double *x, double *r, double *jac, void *user)
{
    size_t i;
    (void)user;
    for (i = 0; i < 16; i++) {
        double t = 45.0 + 5.0 * (double)(i + 1), den = t + x[2];
        double e = exp(x[1] / den);
        r[i] = x[0] * e - meyer_y[i];
        if (jac != NULL) {
            jac[3 * i] = e;
            jac[3 * i + 1] = x[0] * e / den;
            jac[3 * i + 2] = -x[0] * e * x[1] / (den * den);
        }
    }
    return BRDFFIT_OK;
}

brdffit_status optim_box3d(const double *x, double *r, double *jac, void *user)
{
    size_t i;
    (void)user;
    for (i = 0; i < 10; i++) {
        double t = 0.1 * (double)(i + 1);
        double e1 = exp(-t * x[0]), e2 = exp(-t * x[1]), c = exp(-t) - exp(-10.0 * t);
        r[i] = e1 - e2 - x[2] * c;
        if (jac != NULL) {
            jac[3 * i] = -t * e1;
            jac[3 * i + 1] = t * e2;
            jac[3 * i + 2] = -c;
        }
    }
    return BRDFFIT_OK;
}

brdffit_status optim_jennrich_sampson(const double *x, double *r, double *jac, void *user)
{
    size_t i;
    (void)user;
    for (i = 0; i < 10; i++) {
        double k = (double)(i + 1), e1 = exp(k * x[0]), e2 = exp(k * x[1]);
        r[i] = 2.0 + 2.0 * k - (e1 + e2);
        if (jac != NULL) {
            jac[2 * i] = -k * e1;
            jac[2 * i + 1] = -k * e2;
        }
    }
    return BRDFFIT_OK;
}

static const optim_problem mgh[] = {
    {"rosenbrock", 2, 2, {-1.2, 1.0}, optim_rosenbrock},
    {"powell_singular", 4, 4, {3.0, -1.0, 0.0, 1.0}, optim_powell_singular},
    {"freudenstein_roth", 2, 2, {0.5, -2.0}, optim_freudenstein_roth},
    {"meyer", 3, 16, {0.02, 4000.0, 250.0}, optim_meyer},
    {"box3d", 3, 10, {0.0, 10.0, 20.0}, optim_box3d},
    {"jennrich_sampson", 2, 10, {0.3, 0.4}, optim_jennrich_sampson},
};

const optim_problem *optim_mgh_problems(size_t *count)
{
    *count = sizeof mgh / sizeof mgh[0];
    return mgh;
}

/* --- curve fits -------------------------------------------------------------------- */

double optim_uniform(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) * (1.0 / 9007199254740992.0);
}

/* Roughly normal, unit variance: the sum of 12 uniforms minus 6. */
static double gaussish(unsigned long long *state)
{
    double s = 0.0;
    int k;
    for (k = 0; k < 12; k++) s += optim_uniform(state);
    return s - 6.0;
}

static double exp_model(const double *p, double t)
{
    return p[0] * exp(-p[1] * t) + p[2];
}

void optim_make_exp_data(optim_fit_data *d)
{
    unsigned long long state = 12345;
    size_t i;
    memset(d, 0, sizeof *d);
    d->n = 40;
    d->truth[0] = 5.0;
    d->truth[1] = 0.7;
    d->truth[2] = 1.0;
    d->noise = 0.02;
    for (i = 0; i < d->n; i++) {
        d->t[i] = 0.25 * (double)i;
        d->y[i] = exp_model(d->truth, d->t[i]) + d->noise * gaussish(&state);
    }
}

brdffit_status optim_exp_fit(const double *x, double *r, double *jac, void *user)
{
    const optim_fit_data *d = user;
    size_t i;
    for (i = 0; i < d->n; i++) {
        double t = d->t[i], e = exp(-x[1] * t);
        r[i] = x[0] * e + x[2] - d->y[i];
        if (jac != NULL) {
            jac[3 * i] = e;
            jac[3 * i + 1] = -x[0] * t * e;
            jac[3 * i + 2] = 1.0;
        }
    }
    return BRDFFIT_OK;
}

static double rational_model(const double *p, double t)
{
    return (p[0] + p[1] * t) / (1.0 + p[2] * t + p[3] * t * t);
}

void optim_make_rational_data(optim_fit_data *d)
{
    unsigned long long state = 777;
    size_t i;
    memset(d, 0, sizeof *d);
    d->n = 50;
    d->truth[0] = 2.0;
    d->truth[1] = 5.0;
    d->truth[2] = 0.8;
    d->truth[3] = 0.3;
    d->noise = 0.01;
    for (i = 0; i < d->n; i++) {
        d->t[i] = 0.1 * (double)i;
        d->y[i] = rational_model(d->truth, d->t[i]) + d->noise * gaussish(&state);
    }
}

brdffit_status optim_rational_fit(const double *x, double *r, double *jac, void *user)
{
    const optim_fit_data *d = user;
    size_t i;
    for (i = 0; i < d->n; i++) {
        double t = d->t[i], num = x[0] + x[1] * t, den = 1.0 + x[2] * t + x[3] * t * t;
        r[i] = num / den - d->y[i];
        if (jac != NULL) {
            jac[4 * i] = 1.0 / den;
            jac[4 * i + 1] = t / den;
            jac[4 * i + 2] = -num * t / (den * den);
            jac[4 * i + 3] = -num * t * t / (den * den);
        }
    }
    return BRDFFIT_OK;
}

/* --- normal-equation adapter ------------------------------------------------------- */

void optim_normal_adapter_init(optim_normal_adapter *a, brdffit_residual_fn fn, void *user,
                               size_t n_rows, size_t n_params)
{
    memset(a, 0, sizeof *a);
    a->fn = fn;
    a->user = user;
    a->n_rows = n_rows;
    a->n_params = n_params;
}

brdffit_status optim_normal_adapter_fn(const double *x, double *cost, double *jtj, double *jtr,
                                       void *user)
{
    optim_normal_adapter *a = user;
    size_t i, j, k, n = a->n_rows, p = a->n_params;
    brdffit_status st;
    double c = 0.0;
    a->calls++;
    if (jtj != NULL) a->derivative_calls++;
    st = a->fn(x, a->r, jtj != NULL ? a->jac : NULL, a->user);
    if (st != BRDFFIT_OK) return st;
    for (i = 0; i < n; i++) c += a->r[i] * a->r[i];
    *cost = c;
    if (jtj == NULL) return BRDFFIT_OK;
    for (i = 0; i < n; i++) {
        const double *row = a->jac + i * p;
        for (j = 0; j < p; j++) {
            jtr[j] += row[j] * a->r[i];
            for (k = 0; k < p; k++) jtj[j * p + k] += row[j] * row[k];
        }
    }
    return BRDFFIT_OK;
}
